//! The network of a scene, built as data ([`super::syntax`]): the grid's constants (per
//! obstacle as arrays indexed by its id), the variables, the functions of
//! [`super::scene_functions`], the `Robot` template and the `Obstacle(id)` template
//! instantiated once per obstacle, and the violation the safety query excludes. The module
//! docs of `uppaal` describe the network; the order here is the order it is printed.

use super::scene_functions::{functions, hit};
use super::syntax::{
    Decl, Edge, Expr, Kind, Location, Network, Op, Param, Stmt, Template, add, and, bin, call,
    elem, int, mul, n, not, or, sub,
};
use super::{SceneGrid, printer::SEED_QUERY};
use crate::core::num::Exact;
use crate::core::scene::SceneParams;
use crate::crosscheck::explore::scene::SceneSpeeds;
use crate::crosscheck::explore::show_exact;

/// Side of an occupancy interval as the network stores it: the lane is not occupied.
pub(super) const SIDE_NONE: i64 = 0;
/// The obstacle was ahead when the interval began (the measure is the gap).
pub(super) const SIDE_AHEAD: i64 = 1;
/// The obstacle was beside or behind (the measure is −gap).
pub(super) const SIDE_BEHIND: i64 = 2;

/// Builds the network of a scene's grid (names and the speed sets go into the comments).
pub(super) fn scene_network(
    name: &str,
    params: &SceneParams<Exact>,
    grid: &SceneGrid,
    speeds: &SceneSpeeds,
) -> Network {
    let mut declarations = constants(name, params, grid, speeds);
    declarations.extend(variables(grid));
    declarations.extend(functions(grid));
    let n_obstacles = grid.obstacles.len();
    Network {
        header: header(name, params, grid, speeds),
        declarations,
        templates: vec![
            robot_template(),
            obstacle_template(n_obstacles, grid.speeds_max()),
        ],
        system_comment: "One robot; one Obstacle process per obstacle (id = 0..N-1, the scene's \
                         order)."
            .into(),
        violation: violation(n_obstacles),
        query_comment: query_comment(),
    }
}

/// `--speeds` as the scene explorer reads it: every obstacle's set, by name.
fn speed_sets(params: &SceneParams<Exact>, speeds: &SceneSpeeds) -> String {
    params
        .obstacles
        .iter()
        .zip(speeds.sets())
        .map(|(o, s)| {
            let list: Vec<String> = s.speeds().iter().map(show_exact).collect();
            format!("{:?} {{{}}}", o.name, list.join(", "))
        })
        .collect::<Vec<_>>()
        .join("; ")
}

fn header(name: &str, params: &SceneParams<Exact>, g: &SceneGrid, speeds: &SceneSpeeds) -> String {
    format!(
        "safereach export of scene \"{name}\": its finite model (obstacle speeds in m/s: {sets})\n\
         as UPPAAL timed automata on an exact integer grid.\n\
         Scaling (exact for this scene, nothing is rounded):\n\
         - time: 1 model time unit = 1 control period = {dt} s;\n\
         - distance: 1 unit = 1/{d} m (positions, gaps, thresholds, goal, rear gap);\n\
         - speed: units per period: 1 = 1/({d} * {dt}) m/s;\n\
         - the reaction radius enters as floor(rho * {d}) = {rho}, the same condition for integer gaps;\n\
         - the sensing range is left out: it is at least rho, and every guard reads only gaps <= rho.\n\
         An obstacle whose position is a range [min, max] starts at either end (as the explorer).\n\
         Reference answer: the scene explorer on the same finite model, safereach explore SCENE\n\
         with the same speeds option as export-uppaal (it needs no UPPAAL).",
        sets = speed_sets(params, speeds),
        dt = show_exact(&params.robot.dt),
        d = g.scale,
        rho = g.rho,
    )
}

fn constant(name: &'static str, value: i64, note: &str) -> Decl {
    Decl::Const {
        name,
        value,
        boolean: false,
        note: note.to_string(),
    }
}

fn flag(name: &'static str, value: bool, note: &str) -> Decl {
    Decl::Const {
        name,
        value: i64::from(value),
        boolean: true,
        note: note.to_string(),
    }
}

fn array(name: &'static str, len: &'static str, values: Vec<i64>, note: &str) -> Decl {
    Decl::ConstArray {
        name,
        len,
        values,
        note: note.to_string(),
    }
}

/// The grid's constants, the robot's and then the obstacles' (arrays indexed by id).
fn constants(
    name: &str,
    params: &SceneParams<Exact>,
    g: &SceneGrid,
    speeds: &SceneSpeeds,
) -> Vec<Decl> {
    let lmin = *g.lanes.first().expect("a scene has lane 0");
    let lmax = *g.lanes.last().expect("a scene has lane 0");
    let lane_ok: Vec<i64> = (lmin - 1..=lmax + 1)
        .map(|l| i64::from(g.lanes.contains(&l)))
        .collect();
    let nw = g.speeds_max();
    let wset: Vec<i64> = g
        .obstacles
        .iter()
        .flat_map(|o| (0..nw).map(|s| o.speeds.get(s).copied().unwrap_or(0)))
        .collect();
    let starts: Vec<i64> = g
        .obstacles
        .iter()
        .flat_map(|o| [o.starts[0], *o.starts.last().expect("a start")])
        .collect();
    let (periods, rear) = g.lane_change.unwrap_or((0, 0));
    let per = |f: &dyn Fn(&super::ObstacleGrid) -> i64| g.obstacles.iter().map(f).collect();
    vec![
        Decl::Comment(format!(
            "Scene \"{name}\" on the integer grid: 1 distance unit = 1/{} m, 1 time unit = {} s,\n\
             speeds in distance units per period. Exact: see the file's header comment.\n\
             Obstacle speed sets (m/s): {}",
            g.scale,
            show_exact(&params.robot.dt),
            speed_sets(params, speeds)
        )),
        constant("N", g.obstacles.len() as i64, "number of obstacles"),
        Decl::Typedef {
            name: "id_t",
            lo: "0",
            hi: "N - 1",
            note: "an obstacle's index".into(),
        },
        constant("L", g.latency as i64, "observation latency (periods)"),
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
        constant("VA", g.v_a, "assumed obstacle speed bound V_a * dt"),
        constant("RHO", g.rho, "reaction radius floor(rho)"),
        constant("BUFFER", g.buffer, "danger buffer"),
        constant(
            "CLEARANCE",
            g.clearance,
            "collision: moving with separation <= CLEARANCE",
        ),
        flag(
            "WRONG_ASSUMPTION_BRAKE",
            g.wrong_assumption_brake,
            "brake on seeing a moving obstacle faster than V_a",
        ),
        flag(
            "LANE_CHANGE",
            g.lane_change.is_some(),
            "the controller may change lanes on danger",
        ),
        constant("P", periods as i64, "periods a lane change lasts"),
        constant(
            "REAR",
            rear,
            "a lane is free unless an obstacle in it is observed in [-REAR, RHO]",
        ),
        flag("HAS_GOAL", g.goal.is_some(), "the robot has a destination"),
        constant("GOAL", g.goal.unwrap_or(0), "destination x (0: none)"),
        constant("LMIN", i64::from(lmin), "lowest lane"),
        constant("LMAX", i64::from(lmax), "highest lane"),
        array(
            "LANEOK",
            "LMAX - LMIN + 3",
            lane_ok,
            "LANEOK[l - LMIN + 1]: lane l exists (for l in LMIN-1..LMAX+1)",
        ),
        array(
            "OLANE",
            "N",
            per(&|o| i64::from(o.lane)),
            "each obstacle's lane",
        ),
        array(
            "STATIC",
            "N",
            per(&|o| i64::from(o.is_static)),
            "known to the robot as static",
        ),
        array(
            "VI",
            "N",
            per(&|o| if o.is_static { 0 } else { g.v_a }),
            "speed the controller assumes for it: VA, or 0 when static",
        ),
        array(
            "NSTART",
            "N",
            per(&|o| o.starts.len() as i64),
            "its starts: 1, or 2 for the ends of a position range",
        ),
        array(
            "START",
            "2 * N",
            starts,
            "START[2 * id + s]: its x at t = 0",
        ),
        array(
            "NW",
            "N",
            per(&|o| o.speeds.len() as i64),
            "number of speeds in its set",
        ),
        constant("NWMAX", nw as i64, "most speeds of any obstacle"),
        array(
            "WSET",
            "N * NWMAX",
            wset,
            "WSET[id * NWMAX + s]: its speeds (units per period), ascending",
        ),
        constant("WMAX", g.w_max(), "fastest obstacle speed"),
        constant("GMIN", g.gap_min, "lowest gap a run reaches before it ends"),
        constant("GMAX", g.gap_max, "farthest start"),
        constant("SMIN", g.sep_min(), "lowest separation share"),
        constant("SMAX", g.sep_max(), "highest separation share"),
        constant("XRMAX", g.xr_max, "farthest robot position (with a goal)"),
    ]
}

fn var(
    name: &'static str,
    range: Option<(&'static str, &'static str, i64, i64)>,
    len: Option<(&str, usize)>,
    note: &str,
) -> Decl {
    Decl::Var {
        name,
        range,
        len: len.map(|(t, c)| (t.to_string(), c)),
        init: 0,
        note: note.to_string(),
    }
}

/// The variables: whose turn it is, the robot (speed, position with a goal, lanes), and per
/// obstacle its gap, speed, observation history, occupancy side and last separation share.
fn variables(g: &SceneGrid) -> Vec<Decl> {
    let n_obs = g.obstacles.len();
    let hist = n_obs * (g.latency + 1);
    let l = g.latency as i64;
    let (periods, _) = g.lane_change.unwrap_or((0, 0));
    let lmin = i64::from(*g.lanes.first().expect("lane 0"));
    let lmax = i64::from(*g.lanes.last().expect("lane 0"));
    let gap = Some(("GMIN", "GMAX", g.gap_min, g.gap_max));
    let mut out = vec![
        var(
            "turn",
            Some(("0", "N + 1", 0, n_obs as i64 + 1)),
            None,
            "0: the robot decides; id + 1: obstacle id picks its speed; N + 1: the period may end",
        ),
        var(
            "k",
            Some(("0", "L", 0, l)),
            None,
            "periods started, counted up to L",
        ),
        var("v", Some(("0", "VMAX", 0, g.v_max)), None, "robot speed"),
    ];
    if g.goal.is_some() {
        out.push(var(
            "xr",
            Some(("0", "XRMAX", 0, g.xr_max)),
            None,
            "robot position x_r (read only by the destination guard)",
        ));
    }
    out.extend([
        var(
            "lane",
            Some(("LMIN", "LMAX", lmin, lmax)),
            None,
            "the robot's lane, or the lane it is changing into",
        ),
        var(
            "leaving",
            Some(("LMIN", "LMAX", lmin, lmax)),
            None,
            "during a lane change: the lane it leaves",
        ),
        var(
            "changing",
            Some(("0", "P", 0, periods as i64)),
            None,
            "periods the lane change still lasts (0: none under way)",
        ),
        var("gap", gap, Some(("N", n_obs)), "obstacle x - robot x"),
        var(
            "w",
            Some(("0", "WMAX", 0, g.w_max())),
            Some(("N", n_obs)),
            "its speed over the current period",
        ),
        var(
            "gapAt",
            gap,
            Some(("N * (L + 1)", hist)),
            "gapAt[id * (L + 1) + j]: its gap at the start of the period j periods ago (RHO + 1: beyond RHO)",
        ),
        var(
            "fastAt",
            None,
            Some(("N * (L + 1)", hist)),
            "fastAt[id * (L + 1) + j]: faster than V_a in the period that ended j periods ago (kept only with a gap in (0, RHO])",
        ),
        var(
            "side",
            Some(("0", "2", SIDE_NONE, SIDE_BEHIND)),
            Some(("N", n_obs)),
            "its lane's occupancy interval: 0 not occupied, 1 began with it ahead, 2 beside or behind",
        ),
        var(
            "share",
            None,
            Some(("N", n_obs)),
            "the last period had moving instants in its lane",
        ),
        var(
            "sep",
            Some(("SMIN", "SMAX", g.sep_min(), g.sep_max())),
            Some(("N", n_obs)),
            "the least separation over them (gap if ahead, -gap if beside or behind)",
        ),
        var(
            "attained",
            None,
            Some(("N", n_obs)),
            "that least separation is attained (not only approached at a rest instant)",
        ),
    ]);
    out
}

/// The violation for obstacle `i` with its index written out (the query names no function).
fn violation(n_obstacles: usize) -> Expr {
    (0..n_obstacles)
        .map(|i| hit(int(i as i64)))
        .reduce(or)
        .expect("a scene has an obstacle")
}

fn query_comment() -> String {
    format!(
        "Passive safety per obstacle (docs/semantics.md 11.6): never a moving instant in an\n\
         obstacle's lane with separation <= clearance, the separation being its gap when it was\n\
         ahead as the robot entered the lane (sigma = +1) and minus its gap when it was beside or\n\
         behind (sigma = -1). Each period stores, per obstacle, the least separation over its\n\
         moving instants (sep), whether it had any (share) and whether the least is attained\n\
         (at a rest instant it is only approached: < CLEARANCE then).\n\
         The seed paper's form, for N obstacles on lanes y at positions x:\n  {SEED_QUERY}"
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

fn robot_template() -> Template {
    const IDLE: usize = 0;
    const ACC: usize = 1;
    const DRIVE: usize = 2;
    const BRAKE: usize = 3;
    const STOP: usize = 4;
    let loc = |name, invariant, kind, xy| Location {
        name,
        invariant,
        kind,
        xy,
    };
    let period = Some("x <= 1");
    let turn_is = |t: Expr| bin(Op::Eq, n("turn"), t);
    let done = Stmt::Set("turn", int(1));
    let decide = |guard: Expr| and(turn_is(int(0)), and(not(call("collided")), guard));
    let live = |g: Expr| decide(and(not(call("settled")), g));
    let go = and(not(call("swerve")), not(call("brakeNow")));
    let keep = |m: usize| Edge {
        guard: Some(live(go.clone())),
        update: vec![done.clone()],
        ..edge(m, m)
    };
    let swerve = |m: usize| Edge {
        guard: Some(live(call("swerve"))),
        update: vec![Stmt::Call("beginChange", vec![]), done.clone()],
        ..edge(m, m)
    };
    let to_brake = |m: usize| Edge {
        guard: Some(live(call("brakeNow"))),
        update: vec![done.clone()],
        ..edge(m, BRAKE)
    };
    let mv = |from: usize, to: usize, guard: Option<Expr>, f: &'static str| {
        let end = turn_is(add(n("N"), int(1)));
        Edge {
            guard: Some(guard.map_or(end.clone(), |g| and(end, g))),
            clock_guard: Some("x == 1"),
            update: vec![Stmt::Call(f, vec![])],
            clock_reset: Some("x = 0"),
            ..edge(from, to)
        }
    };
    Template {
        name: "Robot",
        param: None,
        declaration: "clock x;",
        locations: vec![
            loc("Idle", None, Kind::Committed, (-400, 0)),
            loc("Accelerate", period, Kind::Normal, (-150, 0)),
            loc("Drive", period, Kind::Normal, (150, 0)),
            loc("Brake", period, Kind::Normal, (150, 250)),
            loc("Stop", None, Kind::Normal, (-150, 250)),
        ],
        init: IDLE,
        edges: vec![
            edge(IDLE, ACC),
            keep(ACC),
            swerve(ACC),
            to_brake(ACC),
            keep(DRIVE),
            swerve(DRIVE),
            to_brake(DRIVE),
            Edge {
                guard: Some(and(turn_is(int(0)), not(call("collided")))),
                update: vec![done],
                ..edge(BRAKE, BRAKE)
            },
            mv(
                ACC,
                ACC,
                Some(bin(Op::Gt, sub(n("VMAX"), n("v")), n("ACC"))),
                "accelerate",
            ),
            mv(
                ACC,
                DRIVE,
                Some(bin(Op::Le, sub(n("VMAX"), n("v")), n("ACC"))),
                "reachTopSpeed",
            ),
            mv(DRIVE, DRIVE, None, "drive"),
            mv(BRAKE, BRAKE, Some(bin(Op::Gt, n("v"), n("BRK"))), "brake"),
            mv(BRAKE, STOP, Some(bin(Op::Le, n("v"), n("BRK"))), "stop"),
        ],
    }
}

fn obstacle_template(count: usize, speeds_max: usize) -> Template {
    const INIT: usize = 0;
    const WAIT: usize = 1;
    let id = || n("id");
    Template {
        name: "Obstacle",
        param: Some(Param {
            name: "id",
            ty: "id_t",
            count,
        }),
        declaration: "",
        locations: vec![
            Location {
                name: "Init",
                invariant: None,
                kind: Kind::Committed,
                xy: (-300, 0),
            },
            Location {
                name: "Wait",
                invariant: None,
                kind: Kind::Normal,
                xy: (0, 0),
            },
        ],
        init: INIT,
        edges: vec![
            Edge {
                select: Some(("s", "1", 1)),
                guard: Some(bin(Op::Lt, n("s"), elem("NSTART", id()))),
                update: vec![Stmt::Call("initialise", vec![id(), n("s")])],
                ..edge(INIT, WAIT)
            },
            Edge {
                select: Some(("s", "NWMAX - 1", speeds_max as i64 - 1)),
                guard: Some(and(
                    bin(Op::Eq, n("turn"), add(id(), int(1))),
                    bin(Op::Lt, n("s"), elem("NW", id())),
                )),
                update: vec![
                    Stmt::SetElem("w", id(), elem("WSET", add(mul(id(), n("NWMAX")), n("s")))),
                    Stmt::Set("turn", add(n("turn"), int(1))),
                ],
                ..edge(WAIT, WAIT)
            },
        ],
    }
}
