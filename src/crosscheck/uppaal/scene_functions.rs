//! The functions of a scene's network (docs/semantics.md §11, in the order the step function
//! `SceneWorld::step` applies it): what the robot observes of obstacle `i`, the guards of
//! §11.4 (`collisionDanger`, `wrongAssumption`, `nearDestination`, the lane-change time test
//! and `otherLaneSafe`, here `laneFree`), when nothing can happen any more (`settled`), the
//! violation, the end of a period (every obstacle's gap, occupancy side of §11.6, separation
//! share and observation history) and the robot's motion. Every guard is multiplied out:
//! no division, so nothing is rounded.

use super::SceneGrid;
use super::scene_network::{SIDE_AHEAD, SIDE_BEHIND, SIDE_NONE};
use super::syntax::{
    Decl, Expr, Function, Op, Stmt, Ty, add, and, bin, call, div, elem, int, mul, n, not, or, sub,
};
use crate::core::model::DangerRule;

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

fn call1(f: &'static str, a: Expr) -> Expr {
    Expr::Call(f, vec![a])
}

fn ret(e: Expr) -> Stmt {
    Stmt::Return(e)
}

/// `for (i = 0; i <= N - 1; i++) { body }`.
fn each_obstacle(body: Vec<Stmt>) -> Stmt {
    Stmt::For {
        var: "i",
        from: int(0),
        up_to: Some(sub(n("N"), int(1))),
        body,
    }
}

/// `if (c) { return v; }`.
fn return_if(c: Expr, v: bool) -> Stmt {
    Stmt::If(c, vec![ret(Expr::Bool(v))], vec![])
}

fn eq(a: Expr, b: Expr) -> Expr {
    bin(Op::Eq, a, b)
}

/// Index `i * (L + 1) + j` of obstacle i's history arrays.
fn hist(i: Expr, j: Expr) -> Expr {
    add(mul(i, add(n("L"), int(1))), j)
}

/// Obstacle `i`'s violation: a share with separation below the clearance, or at it when
/// attained.
pub(super) fn hit(i: Expr) -> Expr {
    and(
        elem("share", i.clone()),
        or(
            bin(Op::Lt, elem("sep", i.clone()), n("CLEARANCE")),
            and(
                elem("attained", i.clone()),
                bin(Op::Le, elem("sep", i), n("CLEARANCE")),
            ),
        ),
    )
}

/// Every function of the network, in the order printed.
pub(super) fn functions(g: &SceneGrid) -> Vec<Decl> {
    let mut out = observation_functions();
    out.extend(guard_functions(g));
    out.extend(lane_functions());
    out.extend(end_functions());
    out.extend(period_functions(g.goal.is_some()));
    out.push(forget_function());
    out.extend(motion_functions());
    out
}

fn observation_functions() -> Vec<Decl> {
    let i = || n("i");
    vec![
        func(
            "The robot sees every obstacle's gap L periods ago (and its speed in the period\n\
             before that; 0 before the first period) once L periods have passed. The sensing\n\
             range needs no test: it is at least RHO, and every guard reads only gaps <= RHO.",
            Ty::Bool,
            "observing",
            &[],
            &[],
            vec![ret(bin(Op::Ge, n("k"), n("L")))],
        ),
        func(
            "",
            Ty::Int,
            "observedGap",
            &["i"],
            &[],
            vec![ret(elem("gapAt", hist(i(), n("L"))))],
        ),
        func(
            "The observed speed matters only as faster than V_a or not.",
            Ty::Bool,
            "observedFast",
            &["i"],
            &[],
            vec![ret(elem("fastAt", hist(i(), n("L"))))],
        ),
        func(
            "Lane l exists (LANEOK is padded: l may be one beyond the outermost lanes).",
            Ty::Bool,
            "hasLane",
            &["l"],
            &[],
            vec![ret(bin(
                Op::Eq,
                elem("LANEOK", add(sub(n("l"), n("LMIN")), int(1))),
                int(1),
            ))],
        ),
        func(
            "The robot occupies lane l: its lane, and during a lane change the lane it leaves.",
            Ty::Bool,
            "occupies",
            &["l"],
            &[],
            vec![ret(or(
                eq(n("lane"), n("l")),
                and(bin(Op::Gt, n("changing"), int(0)), eq(n("leaving"), n("l"))),
            ))],
        ),
        func(
            "Relevant: in the robot's (target) lane and observed in its reaction area (0, RHO].",
            Ty::Bool,
            "relevant",
            &["i"],
            &[],
            vec![ret(and(
                and(call("observing"), eq(elem("OLANE", i()), n("lane"))),
                and(
                    bin(Op::Gt, call1("observedGap", i()), int(0)),
                    bin(Op::Le, call1("observedGap", i()), n("RHO")),
                ),
            ))],
        ),
    ]
}

/// `dangerous(i)` under the danger rule, multiplied out; VI[i] is V_a for a moving obstacle
/// and 0 for a static one (d_static).
fn dangerous(rule: DangerRule) -> Decl {
    let i = || n("i");
    let o = || call1("observedGap", i());
    let vi = || elem("VI", i());
    let (test, doc) = match rule {
        DangerRule::Paper => (
            Some(bin(
                Op::Le,
                mul(sub(o(), n("BUFFER")), n("BRK")),
                add(mul(n("v"), n("v")), mul(vi(), n("v"))),
            )),
            "Danger (the seed's rule): a relevant obstacle observed at o <= d_i(v) =\n\
             v*t_b + V_i*t_b + buffer, t_b = v/b, V_i = V_a (moving) or 0 (static: d_static).\n\
             On the grid d_i = (v*v + VI[i]*v)/BRK + BUFFER; multiplied out:",
        ),
        DangerRule::Kinematic => (
            Some(bin(
                Op::Le,
                mul(mul(int(2), sub(o(), n("BUFFER"))), n("BRK")),
                add(mul(n("v"), n("v")), mul(mul(int(2), vi()), n("v"))),
            )),
            "Danger (kinematic rule): a relevant obstacle observed at o <= d_i(v) =\n\
             v^2/(2b) + V_i*v/b + buffer, V_i = V_a (moving) or 0 (static: d_static).\n\
             On the grid d_i = (v*v + 2*VI[i]*v)/(2*BRK) + BUFFER; multiplied out:",
        ),
        DangerRule::Area => (
            None,
            "Danger (area rule): d_i is infinite, every relevant obstacle is dangerous.",
        ),
    };
    let body = match test {
        Some(t) => and(call1("relevant", i()), t),
        None => call1("relevant", i()),
    };
    func(doc, Ty::Bool, "dangerous", &["i"], &[], vec![ret(body)])
}

fn guard_functions(g: &SceneGrid) -> Vec<Decl> {
    let i = || n("i");
    let destination = if g.goal.is_some() {
        vec![ret(bin(
            Op::Le,
            mul(mul(int(2), n("BRK")), sub(n("GOAL"), n("xr"))),
            mul(n("v"), n("v")),
        ))]
    } else {
        vec![ret(Expr::Bool(false))]
    };
    vec![
        dangerous(g.rule),
        func(
            "Collision danger: some relevant obstacle is dangerous.",
            Ty::Bool,
            "collisionDanger",
            &[],
            &["i"],
            vec![
                each_obstacle(vec![return_if(call1("dangerous", i()), true)]),
                ret(Expr::Bool(false)),
            ],
        ),
        func(
            "Wrong assumption: a relevant moving obstacle seen faster than V_a.",
            Ty::Bool,
            "wrongAssumption",
            &[],
            &["i"],
            vec![
                each_obstacle(vec![return_if(
                    and(
                        and(n("WRONG_ASSUMPTION_BRAKE"), call1("relevant", i())),
                        and(eq(elem("STATIC", i()), int(0)), call1("observedFast", i())),
                    ),
                    true,
                )]),
                ret(Expr::Bool(false)),
            ],
        ),
        func(
            "Destination (the seed's nearDestination): braking now would bring the robot to\n\
             rest at the goal or beyond, x + v^2/(2b) >= goal; on the grid, multiplied out,\n\
             2*BRK*(GOAL - xr) <= v*v. It reads only the robot's own state.",
            Ty::Bool,
            "nearDestination",
            &[],
            &[],
            destination,
        ),
    ]
}

fn lane_functions() -> Vec<Decl> {
    let i = || n("i");
    let o = || call1("observedGap", i());
    let d_lc = add(mul(add(n("v"), elem("VI", i())), n("P")), n("BUFFER"));
    let lane_plus = add(n("lane"), int(1));
    let lane_minus = sub(n("lane"), int(1));
    vec![
        func(
            "Time to change lanes: every dangerous obstacle is observed beyond\n\
             d_lc = (v + V_i)*P*dt + buffer, on the grid (v + VI[i])*P + BUFFER.",
            Ty::Bool,
            "inTime",
            &[],
            &["i"],
            vec![
                each_obstacle(vec![return_if(
                    and(call1("dangerous", i()), bin(Op::Le, o(), d_lc)),
                    false,
                )]),
                ret(Expr::Bool(true)),
            ],
        ),
        func(
            "The seed's otherLaneSafe: lane l exists and no obstacle in it is observed at a\n\
             gap in [-REAR, RHO].",
            Ty::Bool,
            "laneFree",
            &["l"],
            &["i"],
            vec![
                return_if(not(call1("hasLane", n("l"))), false),
                each_obstacle(vec![return_if(
                    and(
                        and(eq(elem("OLANE", i()), n("l")), call("observing")),
                        and(
                            bin(Op::Ge, add(o(), n("REAR")), int(0)),
                            bin(Op::Le, o(), n("RHO")),
                        ),
                    ),
                    false,
                )]),
                ret(Expr::Bool(true)),
            ],
        ),
        func(
            "Danger answered by a lane change: lane changes on, none under way, no wrong\n\
             assumption and no destination, in time, and lane+1 or lane-1 free.",
            Ty::Bool,
            "swerve",
            &[],
            &[],
            vec![ret(and(
                and(
                    and(n("LANE_CHANGE"), eq(n("changing"), int(0))),
                    and(call("collisionDanger"), not(call("wrongAssumption"))),
                ),
                and(
                    and(not(call("nearDestination")), call("inTime")),
                    or(
                        call1("laneFree", lane_plus.clone()),
                        call1("laneFree", lane_minus.clone()),
                    ),
                ),
            ))],
        ),
        func(
            "Brake: wrong assumption, destination, or danger no lane change answers.",
            Ty::Bool,
            "brakeNow",
            &[],
            &[],
            vec![ret(and(
                or(
                    or(call("collisionDanger"), call("wrongAssumption")),
                    call("nearDestination"),
                ),
                not(call("swerve")),
            ))],
        ),
        func(
            "Begin a lane change into lane+1 if free, else lane-1; it lasts P periods.",
            Ty::Void,
            "beginChange",
            &[],
            &[],
            vec![
                Stmt::Set("leaving", n("lane")),
                Stmt::Set("changing", n("P")),
                Stmt::If(
                    call1("laneFree", lane_plus.clone()),
                    vec![Stmt::Set("lane", lane_plus)],
                    vec![Stmt::Set("lane", lane_minus)],
                ),
            ],
        ),
    ]
}

fn end_functions() -> Vec<Decl> {
    let i = || n("i");
    let behind = || call1("behind", i());
    let side = || elem("side", i());
    vec![
        func(
            "Obstacle i is beside or behind in the robot's occupancy interval of its lane\n\
             (or would be, were the interval to begin now).",
            Ty::Bool,
            "behind",
            &["i"],
            &[],
            vec![ret(or(
                eq(side(), int(SIDE_BEHIND)),
                and(
                    eq(side(), int(SIDE_NONE)),
                    bin(Op::Le, elem("gap", i()), int(0)),
                ),
            ))],
        ),
        func(
            "Nothing can happen any more (no goal, the robot accelerating or driving): every\n\
             obstacle of its lane was observed at a gap <= 0 and is beside or behind, and so is\n\
             every obstacle of a lane it still occupies. No guard fires again and no\n\
             separation falls; the run ends.",
            Ty::Bool,
            "settled",
            &[],
            &["i"],
            vec![
                return_if(n("HAS_GOAL"), false),
                each_obstacle(vec![Stmt::If(
                    eq(elem("OLANE", i()), n("lane")),
                    vec![return_if(
                        not(and(
                            and(
                                call("observing"),
                                bin(Op::Le, call1("observedGap", i()), int(0)),
                            ),
                            behind(),
                        )),
                        false,
                    )],
                    vec![return_if(
                        and(call1("occupies", elem("OLANE", i())), not(behind())),
                        false,
                    )],
                )]),
                ret(Expr::Bool(true)),
            ],
        ),
        func(
            "The violation the safety query excludes (per obstacle, docs/semantics.md 11.6).",
            Ty::Bool,
            "collided",
            &[],
            &["i"],
            vec![
                each_obstacle(vec![return_if(hit(i()), true)]),
                ret(Expr::Bool(false)),
            ],
        ),
    ]
}

/// The separation share of obstacle i in a period the robot moves in its lane.
fn share_statements() -> Vec<Stmt> {
    let i = || n("i");
    let gap = || elem("gap", i());
    let rest_gap = sub(
        gap(),
        div(
            mul(n("v"), add(mul(int(2), elem("w", i())), n("v"))),
            mul(int(2), n("BRK")),
        ),
    );
    vec![
        Stmt::SetElem("share", i(), Expr::Bool(true)),
        Stmt::If(
            eq(elem("side", i()), int(SIDE_AHEAD)),
            vec![Stmt::If(
                bin(Op::Gt, n("rest"), int(0)),
                vec![Stmt::SetElem("sep", i(), rest_gap)],
                vec![
                    Stmt::SetElem("sep", i(), sub(sub(gap(), n("dx")), elem("w", i()))),
                    Stmt::SetElem("attained", i(), Expr::Bool(true)),
                ],
            )],
            vec![
                Stmt::SetElem("sep", i(), sub(int(0), gap())),
                Stmt::SetElem("attained", i(), bin(Op::Gt, n("v"), int(0))),
            ],
        ),
    ]
}

fn period_functions(has_goal: bool) -> Vec<Decl> {
    let i = || n("i");
    let j = || n("j");
    let side_at_start = Stmt::If(
        call1("occupies", elem("OLANE", i())),
        vec![Stmt::If(
            eq(elem("side", i()), int(SIDE_NONE)),
            vec![Stmt::If(
                bin(Op::Gt, elem("gap", i()), int(0)),
                vec![Stmt::SetElem("side", i(), int(SIDE_AHEAD))],
                vec![Stmt::SetElem("side", i(), int(SIDE_BEHIND))],
            )],
            vec![],
        )],
        vec![Stmt::SetElem("side", i(), int(SIDE_NONE))],
    );
    let mut per_obstacle = vec![
        Stmt::SetElem("share", i(), Expr::Bool(false)),
        Stmt::SetElem("sep", i(), int(0)),
        Stmt::SetElem("attained", i(), Expr::Bool(false)),
        side_at_start,
        Stmt::If(
            and(
                bin(Op::Gt, n("moving"), int(0)),
                bin(Op::Gt, elem("side", i()), int(SIDE_NONE)),
            ),
            share_statements(),
            vec![],
        ),
        Stmt::For {
            var: "j",
            from: n("L"),
            up_to: None,
            body: vec![
                Stmt::SetElem(
                    "gapAt",
                    hist(i(), j()),
                    elem("gapAt", sub(hist(i(), j()), int(1))),
                ),
                Stmt::SetElem(
                    "fastAt",
                    hist(i(), j()),
                    elem("fastAt", sub(hist(i(), j()), int(1))),
                ),
            ],
        },
    ];
    per_obstacle.extend([
        Stmt::SetElem(
            "gap",
            i(),
            sub(sub(elem("gap", i()), n("dx")), elem("w", i())),
        ),
        Stmt::If(
            bin(Op::Gt, elem("gap", i()), n("RHO")),
            vec![Stmt::SetElem(
                "gapAt",
                hist(i(), int(0)),
                add(n("RHO"), int(1)),
            )],
            vec![Stmt::SetElem("gapAt", hist(i(), int(0)), elem("gap", i()))],
        ),
        // Read only together with this gap, and only when it is in (0, RHO].
        Stmt::SetElem(
            "fastAt",
            hist(i(), int(0)),
            and(
                bin(Op::Gt, elem("w", i()), n("VA")),
                and(
                    bin(Op::Gt, elem("gap", i()), int(0)),
                    bin(Op::Le, elem("gap", i()), n("RHO")),
                ),
            ),
        ),
        Stmt::SetElem("w", i(), int(0)),
    ]);
    let mut body = vec![each_obstacle(per_obstacle), Stmt::Set("v", n("vEnd"))];
    if has_goal {
        body.push(Stmt::Set("xr", add(n("xr"), n("dx"))));
    }
    body.extend([
        Stmt::If(
            bin(Op::Gt, n("changing"), int(0)),
            vec![Stmt::Set("changing", sub(n("changing"), int(1)))],
            vec![],
        ),
        Stmt::If(
            bin(Op::Lt, n("k"), n("L")),
            vec![Stmt::Set("k", add(n("k"), int(1)))],
            vec![],
        ),
        Stmt::Set("turn", int(0)),
    ]);
    vec![
        func(
            "Obstacle(id).Init: obstacle i starts at START[2*i + s]. Its history remembers\n\
             a gap beyond RHO as RHO + 1: no guard tells such gaps apart (relevance and the\n\
             free-lane test ask for gaps <= RHO, settled for gaps <= 0), and UPPAAL then\n\
             need not either. Likewise a speed is remembered as faster than V_a only when the\n\
             gap observed with it is in (0, RHO]: only then does wrongAssumption read it.",
            Ty::Void,
            "initialise",
            &["i", "s"],
            &["j"],
            vec![
                Stmt::SetElem("gap", i(), elem("START", add(mul(int(2), i()), n("s")))),
                Stmt::For {
                    var: "j",
                    from: int(0),
                    up_to: Some(n("L")),
                    body: vec![Stmt::If(
                        bin(Op::Gt, elem("gap", i()), n("RHO")),
                        vec![Stmt::SetElem(
                            "gapAt",
                            hist(i(), j()),
                            add(n("RHO"), int(1)),
                        )],
                        vec![Stmt::SetElem("gapAt", hist(i(), j()), elem("gap", i()))],
                    )],
                },
            ],
        ),
        func(
            "End of a period: the robot moved dx (moving > 0: it moved at all; rest > 0: it\n\
             came to rest inside the period) and ends at speed vEnd; obstacle i moved w[i].\n\
             Per obstacle: the occupancy side (set as the robot enters its lane, from the gap\n\
             at the period's start), the period's separation share, the observation history.",
            Ty::Void,
            "endPeriod",
            &["dx", "vEnd", "moving", "rest"],
            &["i", "j"],
            body,
        ),
    ]
}

/// `forget()`: the observation history cleared to one value. Called at the end of every
/// braking period: Brake latches and no guard reads the history again, so braking states that
/// differ only in it have the same futures (UPPAAL then stores one of them).
fn forget_function() -> Decl {
    let at = || hist(n("i"), n("j"));
    func(
        "Braking latches: no guard reads the observation history again, so it is cleared\n\
         (states that differ only in it have the same futures).",
        Ty::Void,
        "forget",
        &[],
        &["i", "j"],
        vec![each_obstacle(vec![Stmt::For {
            var: "j",
            from: int(0),
            up_to: Some(n("L")),
            body: vec![
                Stmt::SetElem("gapAt", at(), int(0)),
                Stmt::SetElem("fastAt", at(), Expr::Bool(false)),
            ],
        }])],
    )
}

fn motion_functions() -> Vec<Decl> {
    let end = |dx: Expr, v_end: Expr, moving: i64, rest: i64| {
        Stmt::Call("endPeriod", vec![dx, v_end, int(moving), int(rest)])
    };
    vec![
        func(
            "Accelerate for a whole period: distance v + ACC/2.",
            Ty::Void,
            "accelerate",
            &[],
            &[],
            vec![end(
                add(n("v"), div(n("ACC"), int(2))),
                add(n("v"), n("ACC")),
                1,
                0,
            )],
        ),
        func(
            "Reach VMAX inside the period, then cruise: distance VMAX - (VMAX - v)^2/(2*ACC).",
            Ty::Void,
            "reachTopSpeed",
            &[],
            &[],
            vec![end(
                sub(
                    n("VMAX"),
                    div(
                        mul(sub(n("VMAX"), n("v")), sub(n("VMAX"), n("v"))),
                        mul(int(2), n("ACC")),
                    ),
                ),
                n("VMAX"),
                1,
                0,
            )],
        ),
        func(
            "Cruise at VMAX.",
            Ty::Void,
            "drive",
            &[],
            &[],
            vec![end(n("VMAX"), n("VMAX"), 1, 0)],
        ),
        func(
            "Brake for a whole period: distance v - BRK/2.",
            Ty::Void,
            "brake",
            &[],
            &[],
            vec![
                end(
                    sub(n("v"), div(n("BRK"), int(2))),
                    sub(n("v"), n("BRK")),
                    1,
                    0,
                ),
                Stmt::Call("forget", vec![]),
            ],
        ),
        func(
            "Come to rest after v/BRK of the period, having moved v^2/(2*BRK) (a robot that\n\
             brakes at rest does not move at all).",
            Ty::Void,
            "stop",
            &[],
            &[],
            vec![
                Stmt::If(
                    bin(Op::Gt, n("v"), int(0)),
                    vec![end(
                        div(mul(n("v"), n("v")), mul(int(2), n("BRK"))),
                        int(0),
                        1,
                        1,
                    )],
                    vec![end(int(0), int(0), 0, 0)],
                ),
                Stmt::Call("forget", vec![]),
            ],
        ),
    ]
}
