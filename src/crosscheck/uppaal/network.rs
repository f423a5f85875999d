//! The network of a problem, built as data ([`super::syntax`]): the global declarations
//! (the grid's constants, the variables, and the functions the edges call — guards first,
//! then the period's bookkeeping and the robot's motion), the `Robot` and `Obstacle`
//! templates, and the violation the safety query excludes. The module docs of `uppaal`
//! describe the network; the order of the declarations here is the order they are printed.

use super::Grid;
use super::printer::SEED_QUERY;
use super::syntax::{
    Decl, Dir, Edge, Expr, Function, Kind, Location, Network, Op, Stmt, Template, Ty, add, and,
    bin, call, div, elem, int, mul, n, not, or, sub,
};
use crate::core::model::{DangerRule, Problem};
use crate::crosscheck::explore::{SpeedSet, show_exact};

/// Builds the network of a grid (the problem's name goes into the header).
pub(super) fn network(problem: &Problem, grid: &Grid, speeds: &SpeedSet) -> Network {
    let mut declarations = constants(problem, grid, speeds);
    declarations.extend(variables(grid));
    declarations.extend(guard_functions(grid));
    declarations.extend(occlusion_functions(grid));
    declarations.extend(period_functions(grid));
    declarations.extend(motion_functions(plant_brake(grid)));
    Network {
        header: header(problem, grid, speeds),
        declarations,
        templates: vec![robot_template(grid), obstacle_template(grid)],
        system_comment: "One robot, one obstacle on its lane.".into(),
        violation: violation(),
        query_comment: query_comment(),
    }
}

/// The speed set as the explorer's `--speeds` list.
fn speed_list(speeds: &SpeedSet) -> String {
    speeds
        .speeds()
        .iter()
        .map(show_exact)
        .collect::<Vec<_>>()
        .join(",")
}

/// The explorer's `--starts` for a range of initial gaps (nothing for a single start).
fn starts_option(g: &Grid) -> String {
    if g.starts.len() > 1 {
        format!(" --starts {}", g.starts.len())
    } else {
        String::new()
    }
}

/// The name of the gap variables' upper bound: the initial gap, or the largest start.
fn gap_top(g: &Grid) -> &'static str {
    if g.starts.len() > 1 { "G0MAX" } else { "G0" }
}

/// The file's header comment: the scaling, and where the reference answer comes from.
fn header(problem: &Problem, g: &Grid, speeds: &SpeedSet) -> String {
    let dt = problem.robot.control_period;
    format!(
        "safereach export of problem \"{name}\": the finite model (obstacle speeds {speeds} m/s)\n\
         as UPPAAL timed automata on an exact integer grid.\n\
         Scaling (exact for this problem, nothing is rounded):\n\
         - time: 1 model time unit = 1 control period = {dt} s;\n\
         - distance: 1 unit = 1/{d} m (gap, thresholds, clearance);\n\
         - speed: units per period: 1 = 1/({d} * {dt}) m/s;\n\
         - the reaction radius enters as floor(rho * {d}) = {rho}, the same condition for integer gaps.\n\
         Reference answer: the explorer on the same finite model, safereach explore PROBLEM\n\
         with the speed list {list}{starts} (UPPAAL is not needed for it).",
        name = problem.name,
        d = g.scale,
        rho = g.rho,
        list = speed_list(speeds),
        starts = starts_option(g),
    )
}

/// The grid's constants (with the comment above them) and the channels.
fn constants(problem: &Problem, g: &Grid, speeds: &SpeedSet) -> Vec<Decl> {
    let dt = problem.robot.control_period;
    let mut out = vec![
        Decl::Comment(format!(
            "Problem \"{}\" on the integer grid: 1 distance unit = 1/{} m, 1 time unit = {} s,\n\
             speeds in distance units per period. Exact: see the file's header comment.\n\
             Reference answer: safereach explore PROBLEM --speeds {}{}",
            problem.name,
            g.scale,
            dt,
            speed_list(speeds),
            starts_option(g)
        )),
        constant("L", g.latency as i64, "observation latency (periods)"),
    ];
    if g.starts.len() > 1 {
        out.extend([
            constant(
                "NSTART",
                g.starts.len() as i64,
                "number of initial gaps (the explorer's starts in the range)",
            ),
            Decl::ConstArray {
                name: "GSTART",
                len: "NSTART",
                values: g.starts.clone(),
                note: "initial gaps, ascending: the environment picks one".into(),
            },
            constant("G0MAX", g.g0, "largest initial gap"),
        ]);
    } else {
        out.push(constant("G0", g.g0, "initial gap"));
    }
    out.extend([
        constant("VMAX", g.v_max, "top speed v_max * dt"),
        constant(
            "ACC",
            g.acc,
            "speed gained per period while accelerating, a * dt^2",
        ),
        constant(
            "BRK",
            g.brk,
            "speed lost per period while braking, b * dt^2",
        ),
    ]);
    if g.brk_min != g.brk {
        out.push(constant(
            "BRKMIN",
            g.brk_min,
            "speed the plant loses per period while braking, b_min * dt^2 (BRK stays in d_coll)",
        ));
    }
    if g.v0 != 0 {
        out.push(constant("V0", g.v0, "the robot's speed at t = 0, v0 * dt"));
    }
    if let Some(d) = g.d_det {
        out.push(constant(
            "DDET",
            d,
            "occlusion: the obstacle is first seen at a true gap >= DDET",
        ));
    }
    if noisy(g) {
        out.extend([
            constant(
                "SG",
                g.sigma_g,
                "gap noise: an observed gap is off by at most SG",
            ),
            constant(
                "SW",
                g.sigma_w,
                "speed noise: a measured speed is off by at most SW (sigma_w * dt)",
            ),
        ]);
    }
    out.extend([
        constant("VA", g.v_a, "assumed obstacle speed bound V_a * dt"),
        constant("RHO", g.rho, "reaction radius floor(rho)"),
        constant("BUFFER", g.buffer, "danger buffer"),
        constant(
            "CLEARANCE",
            g.clearance,
            "collision: moving with gap <= CLEARANCE",
        ),
        Decl::Const {
            name: "WRONG_ASSUMPTION_BRAKE",
            value: i64::from(g.wrong_assumption_brake),
            boolean: true,
            note: "brake on seeing the obstacle faster than V_a".into(),
        },
        constant("NW", g.speeds.len() as i64, "number of obstacle speeds"),
        Decl::ConstArray {
            name: "WSET",
            len: "NW",
            values: g.speeds.clone(),
            note: "obstacle speeds (units per period), ascending".into(),
        },
        constant("WMAX", g.w_max(), "fastest obstacle speed"),
        constant(
            "GMIN",
            g.gap_min,
            "lowest gap reachable before the network stops",
        ),
        Decl::Chans(vec!["decide", "advance"]),
    ]);
    out
}

/// The name of the plant's braking constant: `BRKMIN` when the plant may brake weaker than
/// the controller's b, else `BRK`.
fn plant_brake(g: &Grid) -> &'static str {
    if g.brk_min != g.brk { "BRKMIN" } else { "BRK" }
}

/// The variables: the gap, the speeds, the observation history, the rest.
fn variables(g: &Grid) -> Vec<Decl> {
    let l = g.latency as i64;
    let top = gap_top(g);
    let mut out = vec![
        Decl::Var {
            name: "gap",
            range: Some(("GMIN", top, g.gap_min, g.g0)),
            len: None,
            init: 0,
            note: "obstacle position - robot position (set by Obstacle.Init)".into(),
        },
        Decl::Var {
            name: "v",
            range: Some(("0", "VMAX", 0, g.v_max)),
            len: None,
            init: 0,
            note: "robot speed".into(),
        },
        Decl::Var {
            name: "w",
            range: Some(("0", "WMAX", 0, g.w_max())),
            len: None,
            init: 0,
            note: "obstacle speed over the current period".into(),
        },
        Decl::Var {
            name: "gapAt",
            range: Some(("GMIN", top, g.gap_min, g.g0)),
            len: Some(("L + 1".into(), g.latency + 1)),
            init: 0,
            note: "gapAt[j]: gap at the start of the period j periods ago".into(),
        },
        Decl::Var {
            name: "fastAt",
            range: None,
            len: Some(("L + 1".into(), g.latency + 1)),
            init: 0,
            note: if noisy(g) {
                "fastAt[j]: the speed of the period that ended j periods ago can be measured above V_a"
                    .into()
            } else {
                "fastAt[j]: the obstacle was faster than V_a in the period that ended j periods ago"
                    .into()
            },
        },
    ];
    if g.d_det.is_some() {
        out.push(Decl::Var {
            name: "seen",
            range: None,
            len: None,
            init: 0,
            note: "occlusion: the obstacle has been seen (it stays seen)".into(),
        });
    }
    if noisy(g) {
        out.push(Decl::Var {
            name: "slowAt",
            range: None,
            len: Some(("L + 1".into(), g.latency + 1)),
            init: 1,
            note: "slowAt[j]: ... can be measured at or below V_a (0 before the first period)"
                .into(),
        });
    }
    out.extend([
        Decl::Var {
            name: "k",
            range: Some(("0", "L", 0, l)),
            len: None,
            init: 0,
            note: "periods started, counted up to L".into(),
        },
        Decl::Var {
            name: "rested",
            range: None,
            len: None,
            init: 0,
            note: "the robot came to rest after moving".into(),
        },
        Decl::Var {
            name: "restGap",
            range: Some(("GMIN", top, g.gap_min, g.g0)),
            len: None,
            init: 0,
            note: "gap at the instant the robot came to rest".into(),
        },
    ]);
    out
}

/// Sensing noise: the guards take the observation error's index `e` (module docs of
/// `uppaal`, "Sensing noise").
fn noisy(g: &Grid) -> bool {
    g.sigma_g != 0 || g.sigma_w != 0
}

/// The argument list of a guard function: `(e)` with noise, else `()`.
fn err_args(g: &Grid) -> Vec<Expr> {
    if noisy(g) { vec![n("e")] } else { vec![] }
}

/// The parameter list of a guard function: `(int e)` with noise, else `()`.
fn err_params(g: &Grid) -> &'static [&'static str] {
    if noisy(g) { &["e"] } else { &[] }
}

/// `f()` or `f(e)`.
fn guard_call(g: &Grid, f: &'static str) -> Expr {
    Expr::Call(f, err_args(g))
}

/// The observed gap and speed: exact, or with noise the error the index `e` picks.
fn observation_functions(g: &Grid) -> Vec<Decl> {
    if !noisy(g) {
        return vec![
            func(
                "",
                Ty::Int,
                "observedGap",
                &[],
                &[],
                vec![Stmt::Return(elem("gapAt", n("L")))],
            ),
            func(
                "The observed speed matters only as faster than V_a or not.",
                Ty::Bool,
                "observedFast",
                &[],
                &[],
                vec![Stmt::Return(elem("fastAt", n("L")))],
            ),
        ];
    }
    let truth = || elem("gapAt", n("L"));
    let low = || sub(truth(), n("SG"));
    let high = || add(truth(), n("SG"));
    let is = |v: i64| bin(Op::Eq, n("e"), int(v));
    vec![
        func(
            "Sensing noise: the environment picks the observation's error within +-SG (gap)\n\
             and +-SW (speed); the robot's decide edge selects it as e in [0, 5]. e mod 3\n\
             picks the gap: 0 the lowest it can be seen at, 1 the highest, 2 the lowest\n\
             positive one (the highest if none is positive). These three realise every\n\
             outcome of the guard that some error in the whole interval allows (the guard\n\
             fires on a gap above 0 and at most its threshold, else it is quiet).",
            Ty::Int,
            "observedGap",
            &["e"],
            &[],
            vec![
                Stmt::If(or(is(0), is(3)), vec![Stmt::Return(low())], vec![]),
                Stmt::If(or(is(1), is(4)), vec![Stmt::Return(high())], vec![]),
                Stmt::If(
                    bin(Op::Ge, low(), int(1)),
                    vec![Stmt::Return(low())],
                    vec![],
                ),
                Stmt::If(
                    bin(Op::Ge, high(), int(1)),
                    vec![Stmt::Return(int(1))],
                    vec![],
                ),
                Stmt::Return(high()),
            ],
        ),
        func(
            "The measured speed, against V_a: e >= 3 shows it faster than V_a if some error\n\
             can, else (or if no error can show it at or below V_a) as the errors allow.",
            Ty::Bool,
            "observedFast",
            &["e"],
            &[],
            vec![Stmt::Return(or(
                and(bin(Op::Ge, n("e"), int(3)), elem("fastAt", n("L"))),
                not(elem("slowAt", n("L"))),
            ))],
        ),
    ]
}

/// The guard functions: what the robot observes, the danger and wrong-assumption guards,
/// and the violation.
fn guard_functions(g: &Grid) -> Vec<Decl> {
    let observed_gap = guard_call(g, "observedGap");
    let params = err_params(g);
    let mut out = vec![func(
        "The robot sees the gap L periods ago (and the obstacle speed of the period\n\
         before that; 0 before the first period) once L periods have passed.",
        Ty::Bool,
        "observing",
        &[],
        &[],
        vec![Stmt::Return(bin(Op::Ge, n("k"), n("L")))],
    )];
    out.extend(observation_functions(g));
    out.extend([
        func(
            "In the reaction area: 0 < observed gap <= rho.",
            Ty::Bool,
            "inArea",
            params,
            &[],
            vec![Stmt::Return(and(
                and(call("observing"), bin(Op::Gt, observed_gap.clone(), int(0))),
                bin(Op::Le, observed_gap, n("RHO")),
            ))],
        ),
        collision_danger(g),
        func(
            "Wrong assumption: an obstacle in the area seen faster than V_a.",
            Ty::Bool,
            "wrongAssumption",
            params,
            &[],
            vec![Stmt::Return(and(
                and(n("WRONG_ASSUMPTION_BRAKE"), guard_call(g, "inArea")),
                guard_call(g, "observedFast"),
            ))],
        ),
        func(
            "The violation the safety query excludes: moving with gap <= clearance, or come\n\
             to rest (inside a period) with a gap below the clearance.",
            Ty::Bool,
            "collided",
            &[],
            &[],
            vec![Stmt::Return(violation())],
        ),
    ]);
    out
}

/// Occlusion: whether the obstacle is seen at this decision, and whether a period would
/// end with it hidden for good (none for a problem without occlusion).
fn occlusion_functions(g: &Grid) -> Vec<Decl> {
    if g.d_det.is_none() {
        return vec![];
    }
    // The observation the robot makes after the period: of the current gap (L = 0), else
    // of the gap the history moves to index L. Before L it is the start, still in gapAt.
    let next = if g.latency == 0 {
        sub(sub(n("gap"), n("dx")), n("w"))
    } else {
        elem("gapAt", sub(n("L"), int(1)))
    };
    vec![
        func(
            "Occlusion: the obstacle is seen at this decision if it was seen before, or if the\n\
             environment shows it now, which it may at an observation of a true gap >= DDET.",
            Ty::Bool,
            "shown",
            &[],
            &[],
            vec![Stmt::Return(or(
                n("seen"),
                and(
                    call("observing"),
                    bin(Op::Ge, elem("gapAt", n("L")), n("DDET")),
                ),
            ))],
        ),
        func(
            "A period of travel dx that would leave the obstacle hidden with no sighting left:\n\
             the next observation shows a true gap < DDET (gaps never grow). No behaviour goes\n\
             there (its first sighting came too late), so the robot's advance is blocked.",
            Ty::Bool,
            "lostAfter",
            &["dx"],
            &[],
            vec![Stmt::Return(and(
                not(n("seen")),
                bin(Op::Lt, next, n("DDET")),
            ))],
        ),
    ]
}

/// `collisionDanger()` under the problem's danger rule, multiplied out (no division).
fn collision_danger(g: &Grid) -> Decl {
    let rule = g.rule;
    let observed_gap = guard_call(g, "observedGap");
    let in_area = guard_call(g, "inArea");
    let danger = match rule {
        DangerRule::Paper => and(
            in_area,
            bin(
                Op::Le,
                mul(sub(observed_gap.clone(), n("BUFFER")), n("BRK")),
                add(mul(n("v"), n("v")), mul(n("VA"), n("v"))),
            ),
        ),
        DangerRule::Kinematic => and(
            in_area,
            bin(
                Op::Le,
                mul(
                    mul(int(2), sub(observed_gap.clone(), n("BUFFER"))),
                    n("BRK"),
                ),
                add(mul(n("v"), n("v")), mul(mul(int(2), n("VA")), n("v"))),
            ),
        ),
        DangerRule::Area => in_area,
    };

    let danger_doc = match rule {
        DangerRule::Paper => {
            "Collision danger (the seed's rule): the observed gap o is in the area and\n\
             o <= d_coll(v) = v*t_b + V_a*t_b + buffer with t_b = v/b. On the grid,\n\
             t_b = v/BRK periods, so d_coll = (v*v + VA*v)/BRK + BUFFER; multiplied out:"
        }
        DangerRule::Kinematic => {
            "Collision danger (kinematic rule): the observed gap o is in the area and\n\
             o <= d_coll(v) = v^2/(2b) + V_a*v/b + buffer. On the grid\n\
             d_coll = (v*v + 2*VA*v)/(2*BRK) + BUFFER; multiplied out:"
        }
        DangerRule::Area => {
            "Collision danger (area rule): d_coll is infinite, the robot brakes on seeing\n\
             the obstacle in its reaction area."
        }
    };
    func(
        danger_doc,
        Ty::Bool,
        "collisionDanger",
        err_params(g),
        &[],
        vec![Stmt::Return(danger)],
    )
}

/// The period's bookkeeping: the initial gap, and the end of a period (the gap, the speed,
/// the shifted observation history).
fn period_functions(g: &Grid) -> Vec<Decl> {
    // A range's start is the environment's choice on Obstacle.Init, passed in as g0.
    let (start, params): (_, &[&'static str]) = if g.starts.len() > 1 {
        (n("g0"), &["g0"])
    } else {
        (n("G0"), &[])
    };
    let mut init = vec![Stmt::Set("gap", start.clone())];
    let what = if g.starts.len() > 1 {
        "the initial gap g0 it picked"
    } else {
        "the initial gap"
    };
    let mut init_doc = format!("Obstacle.Init: store {what}.");
    if g.v0 != 0 {
        // Here rather than on the robot's first edge: the two committed first edges may
        // fire in either order, and a moving robot must not meet the gap's placeholder 0.
        init.push(Stmt::Set("v", n("V0")));
        init_doc = format!("Obstacle.Init: store {what} and the robot's initial speed.");
    }
    init.push(Stmt::For {
        var: "j",
        from: int(0),
        up_to: Some(n("L")),
        body: vec![Stmt::SetElem("gapAt", n("j"), start)],
    });
    let mut shift = vec![
        Stmt::SetElem("gapAt", n("j"), elem("gapAt", sub(n("j"), int(1)))),
        Stmt::SetElem("fastAt", n("j"), elem("fastAt", sub(n("j"), int(1)))),
    ];
    let mut fast = bin(Op::Gt, n("w"), n("VA"));
    let mut measured = vec![];
    if noisy(g) {
        shift.push(Stmt::SetElem(
            "slowAt",
            n("j"),
            elem("slowAt", sub(n("j"), int(1))),
        ));
        fast = bin(Op::Gt, add(n("w"), n("SW")), n("VA"));
        measured.push(Stmt::SetElem(
            "slowAt",
            int(0),
            bin(Op::Le, sub(n("w"), n("SW")), n("VA")),
        ));
    }
    let mut end = vec![
        Stmt::Set("gap", sub(sub(n("gap"), n("dx")), n("w"))),
        Stmt::Set("v", n("vEnd")),
        Stmt::For {
            var: "j",
            from: n("L"),
            up_to: None,
            body: shift,
        },
        Stmt::SetElem("gapAt", int(0), n("gap")),
        Stmt::SetElem("fastAt", int(0), fast),
    ];
    end.extend(measured);
    end.extend([
        Stmt::Set("w", int(0)),
        Stmt::If(
            bin(Op::Lt, n("k"), n("L")),
            vec![Stmt::Set("k", add(n("k"), int(1)))],
            vec![],
        ),
    ]);
    vec![
        func(&init_doc, Ty::Void, "initialise", params, &["j"], init),
        func(
            "End of a period: the robot moved dx and ends at speed vEnd, the obstacle moved w;\n\
             shift the observation history (w is cleared: it is chosen anew each period).",
            Ty::Void,
            "endPeriod",
            &["dx", "vEnd"],
            &["j"],
            end,
        ),
    ]
}

/// The distance the robot covers in a whole period of acceleration: v + ACC/2.
fn accelerate_dx() -> Expr {
    add(n("v"), div(n("ACC"), int(2)))
}

/// The distance of the period in which it reaches VMAX: VMAX - (VMAX - v)^2/(2*ACC).
fn top_speed_dx() -> Expr {
    sub(
        n("VMAX"),
        div(
            mul(sub(n("VMAX"), n("v")), sub(n("VMAX"), n("v"))),
            mul(int(2), n("ACC")),
        ),
    )
}

/// The robot's motion over one period, one function per mode (each ends the period).
/// `brk` names the plant's braking constant (`BRK`, or `BRKMIN` when it is weaker).
fn motion_functions(brk: &'static str) -> Vec<Decl> {
    let brake_doc = if brk == "BRK" {
        "Brake for a whole period: distance v - BRK/2."
    } else {
        "Brake for a whole period at the plant's b_min: distance v - BRKMIN/2."
    };
    vec![
        func(
            "Accelerate for a whole period: distance v + ACC/2.",
            Ty::Void,
            "accelerate",
            &[],
            &[],
            vec![Stmt::Call(
                "endPeriod",
                vec![accelerate_dx(), add(n("v"), n("ACC"))],
            )],
        ),
        func(
            "Reach VMAX inside the period, then cruise: distance VMAX - (VMAX - v)^2/(2*ACC).",
            Ty::Void,
            "reachTopSpeed",
            &[],
            &[],
            vec![Stmt::Call("endPeriod", vec![top_speed_dx(), n("VMAX")])],
        ),
        func(
            "Cruise at VMAX.",
            Ty::Void,
            "drive",
            &[],
            &[],
            vec![Stmt::Call("endPeriod", vec![n("VMAX"), n("VMAX")])],
        ),
        func(
            brake_doc,
            Ty::Void,
            "brake",
            &[],
            &[],
            vec![Stmt::Call(
                "endPeriod",
                vec![sub(n("v"), div(n(brk), int(2))), sub(n("v"), n(brk))],
            )],
        ),
        stop_function(brk),
    ]
}

/// `stop()`: the robot comes to rest inside the period; the gap at that instant is kept.
fn stop_function(brk: &'static str) -> Decl {
    let doc = if brk == "BRK" {
        "Come to rest after v/BRK of the period, having moved v^2/(2*BRK) while the\n\
         obstacle moved w*v/BRK: the gap at that instant is recorded."
    } else {
        "Come to rest after v/BRKMIN of the period (the plant brakes at b_min), having\n\
         moved v^2/(2*BRKMIN) while the obstacle moved w*v/BRKMIN: the gap at that instant\n\
         is recorded."
    };
    func(
        doc,
        Ty::Void,
        "stop",
        &[],
        &[],
        vec![
            Stmt::If(
                bin(Op::Gt, n("v"), int(0)),
                vec![
                    Stmt::Set("rested", Expr::Bool(true)),
                    Stmt::Set(
                        "restGap",
                        sub(
                            n("gap"),
                            div(
                                mul(n("v"), add(mul(int(2), n("w")), n("v"))),
                                mul(int(2), n(brk)),
                            ),
                        ),
                    ),
                ],
                vec![],
            ),
            Stmt::Call(
                "endPeriod",
                vec![div(mul(n("v"), n("v")), mul(int(2), n(brk))), int(0)],
            ),
        ],
    )
}

fn func(
    doc: &str,
    ret: Ty,
    name: &'static str,
    params: &[&'static str],
    locals: &[&'static str],
    body: Vec<Stmt>,
) -> Decl {
    Decl::Func(Function {
        doc: doc.to_string(),
        ret,
        name,
        params: params.to_vec(),
        locals: locals.to_vec(),
        body,
    })
}

fn constant(name: &'static str, value: i64, note: &str) -> Decl {
    Decl::Const {
        name,
        value,
        boolean: false,
        note: note.to_string(),
    }
}

/// The query's comment: passive safety in this model's variables, and the seed's form.
fn query_comment() -> String {
    format!(
        "Passive safety: the robot is never moving with gap <= clearance. A robot that comes\n\
         to rest inside a period is judged by its gap at that instant (restGap < CLEARANCE).\n\
         The seed paper's form, for N obstacles on lanes y at positions x:\n  {SEED_QUERY}\n\
         Its moving part in this model's variables (one obstacle, on the robot's lane):\n  \
         A[] (gap <= CLEARANCE imply v == 0)"
    )
}

/// `(v > 0 && gap <= CLEARANCE) || (rested && restGap < CLEARANCE)`.
fn violation() -> Expr {
    or(
        and(
            bin(Op::Gt, n("v"), int(0)),
            bin(Op::Le, n("gap"), n("CLEARANCE")),
        ),
        and(n("rested"), bin(Op::Lt, n("restGap"), n("CLEARANCE"))),
    )
}

fn brake_guard(g: &Grid) -> Expr {
    or(
        guard_call(g, "collisionDanger"),
        guard_call(g, "wrongAssumption"),
    )
}

fn edge(source: usize, target: usize) -> Edge {
    Edge {
        source,
        target,
        select: None,
        guard: None,
        clock_guard: None,
        sync: None,
        update: vec![],
        clock_reset: None,
    }
}

fn robot_template(g: &Grid) -> Template {
    const IDLE: usize = 0;
    const ACC: usize = 1;
    const DRIVE: usize = 2;
    const BRAKE: usize = 3;
    const STOP: usize = 4;
    let brk = plant_brake(g);
    let loc = |name, kind, xy| Location {
        name,
        invariant: None,
        kind,
        xy,
    };
    let decide = Some(("decide", Dir::Receive));
    let advance = Some(("advance", Dir::Receive));
    // With noise the observation's error is selected on the decide edge (its index e).
    let select = noisy(g).then_some(("e", "5", 5));
    // Occlusion: the guard is evaluated only when the obstacle is shown, which marks it seen.
    let occluded = g.d_det.is_some();
    let shown = |guard: Expr| {
        if occluded {
            and(call("shown"), guard)
        } else {
            guard
        }
    };
    let mark = || {
        if occluded {
            vec![Stmt::Set("seen", Expr::Bool(true))]
        } else {
            vec![]
        }
    };
    let keep = |from: usize| Edge {
        select,
        guard: Some(shown(not(brake_guard(g)))),
        sync: decide,
        update: mark(),
        ..edge(from, from)
    };
    let to_brake = |from: usize| Edge {
        select,
        guard: Some(shown(brake_guard(g))),
        sync: decide,
        update: mark(),
        ..edge(from, BRAKE)
    };
    // Occlusion: the obstacle stays hidden (nothing is observed, no guard fires).
    let hidden = |from: usize| Edge {
        guard: Some(not(n("seen"))),
        sync: decide,
        ..edge(from, from)
    };
    // Occlusion: a period of travel dx must not leave the obstacle hidden for good.
    let admissible = |guard: Option<Expr>, dx: Expr| {
        if !occluded {
            return guard;
        }
        let ok = not(Expr::Call("lostAfter", vec![dx]));
        Some(match guard {
            Some(g) => and(g, ok),
            None => ok,
        })
    };
    let mv = |from: usize, to: usize, guard: Option<Expr>, f: &'static str| Edge {
        guard,
        sync: advance,
        update: vec![Stmt::Call(f, vec![])],
        ..edge(from, to)
    };
    Template {
        name: "Robot",
        param: None,
        declaration: "",
        locations: vec![
            loc("Idle", Kind::Committed, (-400, 0)),
            loc("Accelerate", Kind::Normal, (-150, 0)),
            loc("Drive", Kind::Normal, (150, 0)),
            loc("Brake", Kind::Normal, (150, 250)),
            loc("Stop", Kind::Normal, (-150, 250)),
        ],
        init: IDLE,
        edges: [
            vec![
                // The robot starts in Drive at top speed, else in Accelerate
                // (RobotState::initial).
                edge(IDLE, if g.v0 >= g.v_max { DRIVE } else { ACC }),
            ],
            if occluded {
                vec![hidden(ACC), hidden(DRIVE)]
            } else {
                vec![]
            },
            vec![
                keep(ACC),
                to_brake(ACC),
                keep(DRIVE),
                to_brake(DRIVE),
                Edge {
                    sync: decide,
                    ..edge(BRAKE, BRAKE)
                },
                mv(
                    ACC,
                    ACC,
                    admissible(
                        Some(bin(Op::Gt, sub(n("VMAX"), n("v")), n("ACC"))),
                        accelerate_dx(),
                    ),
                    "accelerate",
                ),
                mv(
                    ACC,
                    DRIVE,
                    admissible(
                        Some(bin(Op::Le, sub(n("VMAX"), n("v")), n("ACC"))),
                        top_speed_dx(),
                    ),
                    "reachTopSpeed",
                ),
                mv(DRIVE, DRIVE, admissible(None, n("VMAX")), "drive"),
                mv(BRAKE, BRAKE, Some(bin(Op::Gt, n("v"), n(brk))), "brake"),
                mv(BRAKE, STOP, Some(bin(Op::Le, n("v"), n(brk))), "stop"),
            ],
        ]
        .concat(),
    }
}

fn obstacle_template(g: &Grid) -> Template {
    let nw = g.speeds.len() as i64;
    // A range: the environment picks the start, one of the explorer's.
    // Occlusion: a start below DDET can never be seen, so no behaviour starts there.
    let seeable = |start: Expr| g.d_det.is_some().then(|| bin(Op::Ge, start, n("DDET")));
    let init = if g.starts.len() > 1 {
        Edge {
            select: Some(("s", "NSTART - 1", g.starts.len() as i64 - 1)),
            guard: seeable(elem("GSTART", n("s"))),
            update: vec![Stmt::Call("initialise", vec![elem("GSTART", n("s"))])],
            ..edge(INIT, IDLE)
        }
    } else {
        Edge {
            guard: seeable(n("G0")),
            update: vec![Stmt::Call("initialise", vec![])],
            ..edge(INIT, IDLE)
        }
    };
    const INIT: usize = 0;
    const IDLE: usize = 1;
    const MOVE: usize = 2;
    Template {
        name: "Obstacle",
        param: None,
        declaration: "clock x;",
        locations: vec![
            Location {
                name: "Init",
                invariant: None,
                kind: Kind::Committed,
                xy: (-300, 0),
            },
            Location {
                name: "Idle",
                invariant: None,
                kind: Kind::Urgent,
                xy: (0, 0),
            },
            Location {
                name: "Move",
                invariant: Some("x <= 1"),
                kind: Kind::Normal,
                xy: (300, 0),
            },
        ],
        init: INIT,
        edges: vec![
            init,
            Edge {
                select: Some(("i", "NW - 1", nw - 1)),
                guard: Some(not(call("collided"))),
                sync: Some(("decide", Dir::Send)),
                update: vec![Stmt::Set("w", elem("WSET", n("i")))],
                ..edge(IDLE, MOVE)
            },
            Edge {
                clock_guard: Some("x == 1"),
                sync: Some(("advance", Dir::Send)),
                clock_reset: Some("x = 0"),
                ..edge(MOVE, IDLE)
            },
        ],
    }
}
