//! The finite model as UPPAAL timed automata, on an exact integer grid.
//!
//! The seed paper modelled its robot and obstacle as UPPAAL timed automata and checked a
//! TCTL safety query. [`export`] writes the same finite model the explorer ([`crate::crosscheck::explore`])
//! searches — the problem plus a finite obstacle speed set — as a UPPAAL network (XML) and the
//! passive-safety query (`.q`), for users who own UPPAAL. UPPAAL is not available here; the
//! explorer with the same `--speeds` is the reference for what UPPAAL answers.
//!
//! # The integer grid (exact, no rounding)
//!
//! UPPAAL has bounded 32-bit integers and no rationals. The export picks one scale D (grid
//! units per metre) and writes every quantity as an integer:
//!
//! - time: one model time unit is one control period dt (the obstacle's clock `x`);
//! - distances (gap, thresholds): metres × D;
//! - speeds: distance per period, metres/second × dt × D; accelerations: the speed change per
//!   period, a·dt²·D and b·dt²·D.
//!
//! D is the least common multiple of the denominators of every quantity the model's integer
//! arithmetic produces: the initial gap, clearance, buffer, v_max·dt, V_a·dt, a·dt²/2, b·dt²/2,
//! each obstacle speed × dt, the distance of the step in which the robot reaches v_max, and
//! for every speed the robot can brake from, the distance it and each obstacle speed cover in
//! the last, partial braking period. With that D every position the model reaches is an
//! integer and every division in the model is exact — the grid model is the rational model
//! scaled by D, behaviour for behaviour. The reaction radius is the one number that need not
//! be on the grid: `observed ≤ ρ` is written `observed ≤ ⌊ρ·D⌋`, which is the same condition
//! for an integer `observed`. The collision-danger guard o ≤ d_coll(v) is multiplied out
//! (`(o − BUFFER)·BRK ≤ v·v + VA·v` for the paper's rule), so it needs no division at all.
//! When the scaled numbers or the guard's products do not fit UPPAAL's 32-bit `int`, the
//! export refuses ([`UppaalError::Grid`]) rather than round.
//!
//! # The network
//!
//! - `Robot`: Idle → Accelerate → Drive → Brake → Stop, the seed's robot automaton. At each
//!   period's start (channel `decide`) it evaluates `collisionDanger() || wrongAssumption()`
//!   on its delayed observation and moves to Brake or stays; at the period's end (channel
//!   `advance`) it moves by the exact distance of its mode.
//! - `Obstacle`: Init → Idle ⇄ Move, the seed's obstacle automaton. Init stores the initial
//!   gap; from Idle it selects its speed for the period from the set (`decide!`), and Move
//!   lasts one time unit (`advance!` at x == 1).
//! - Variables: the gap (not absolute positions — only the gap matters, as in the explorer,
//!   and absolute positions would only multiply UPPAAL's states), the robot's speed, the
//!   obstacle's speed in the current period (cleared at its end), the last L+1 gaps and
//!   whether each of the last L+1 periods' obstacle speed exceeded V_a (all the latency
//!   needs: the speed is only ever compared with V_a), and the gap at the instant the robot
//!   came to rest.
//! - Query: `A[] not ((v > 0 && gap <= CLEARANCE) || (rested && restGap < CLEARANCE))` —
//!   never moving with gap ≤ clearance; a robot that comes to rest inside a period is judged
//!   by its gap at that instant (< clearance), exactly as [`crate::core::semantics::World::step`].
//!   The network stops (the obstacle blocks) once the query is violated, which keeps every
//!   variable in its declared range.
//!
//! # Checking the export without UPPAAL
//!
//! The model is built as data — declarations, functions as small syntax trees, templates and
//! edges — and printed from that data. [`explore_grid`] runs the *same data* through an
//! interpreter of UPPAAL's semantics for this network (the clock only spaces `decide` and
//! `advance` one time unit apart, so it is left out), checking on every evaluation that
//! integers stay 32-bit, assignments stay in their declared ranges (UPPAAL aborts otherwise)
//! and every division is exact. Tests hold its verdict, shortest collision period and
//! minimum separation against the explorer's.

use std::collections::{BTreeSet, HashMap, HashSet, VecDeque};
use std::fmt::Write as _;

use dashu_int::ops::Gcd;
use dashu_int::{IBig, UBig};

use crate::core::model::{DangerRule, Params, Problem};
use crate::core::num::Exact;
use crate::core::semantics::{Mode, RobotState, robot_motion};
use crate::crosscheck::explore::{ExploreVerdict, Options, SpeedSet, show_exact};

/// Most drive-profile speeds (control periods to reach v_max, plus one) the export enumerates.
pub const MAX_PROFILE: usize = 100_000;

/// Largest value of UPPAAL's `int` (32-bit).
pub const INT_MAX: i64 = i32::MAX as i64;

/// Why a problem cannot be exported, or the exported network cannot be explored.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum UppaalError {
    /// No exact integer grid fits UPPAAL's 32-bit integers.
    #[error("no exact UPPAAL integer grid: {0}")]
    Grid(String),
    /// The network would abort in UPPAAL (a value out of its declared range, an overflow) or
    /// divide inexactly — a bug in the export, reported rather than hidden.
    #[error("the exported network fails when run: {0}")]
    Run(String),
    /// The options are unusable.
    #[error("{0}")]
    Options(String),
}

// ---------------------------------------------------------------------------------------------
// The grid
// ---------------------------------------------------------------------------------------------

/// The problem's numbers on the integer grid.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Grid {
    /// D: grid units per metre.
    pub scale: UBig,
    /// Latency L in periods.
    pub latency: usize,
    /// Initial gap, g0·D.
    pub g0: i64,
    /// v_max·dt·D.
    pub v_max: i64,
    /// a·dt²·D (speed gained per period while accelerating).
    pub acc: i64,
    /// b·dt²·D (speed lost per period while braking).
    pub brk: i64,
    /// V_a·dt·D.
    pub v_a: i64,
    /// ⌊ρ·D⌋.
    pub rho: i64,
    /// buffer·D.
    pub buffer: i64,
    /// clearance·D.
    pub clearance: i64,
    /// Obstacle speeds × dt·D, ascending.
    pub speeds: Vec<i64>,
    /// Lowest value a gap variable can take.
    pub gap_min: i64,
    /// The danger rule.
    pub rule: DangerRule,
    /// Whether the wrong-assumption guard is on.
    pub wrong_assumption_brake: bool,
}

fn lcm(a: &UBig, b: &UBig) -> UBig {
    let g = a.gcd(b);
    a / &g * b
}

fn to_int(x: &Exact, what: &str) -> Result<i64, UppaalError> {
    let n: IBig = x.numerator().clone();
    let v = i64::try_from(&n).ok().filter(|v| v.abs() <= INT_MAX);
    v.ok_or_else(|| {
        UppaalError::Grid(format!(
            "{what} is {n} grid units, beyond UPPAAL's 32-bit int (at most {INT_MAX})"
        ))
    })
}

impl Grid {
    /// The exact grid of a (validated) problem with obstacle speeds `speeds`.
    pub fn new(problem: &Problem, speeds: &SpeedSet) -> Result<Grid, UppaalError> {
        let p: Params<Exact> = problem.params();
        let two = Exact::from(2);
        let dt = p.dt.clone();
        // The drive profile's speeds: every speed the robot can brake from.
        let mut drive = vec![Exact::ZERO];
        let mut state = RobotState {
            position: Exact::ZERO,
            speed: Exact::ZERO,
            mode: Mode::Accelerate,
        };
        while state.speed < p.v_max {
            if drive.len() > MAX_PROFILE {
                return Err(UppaalError::Grid(format!(
                    "the robot needs more than {MAX_PROFILE} control periods to reach top speed"
                )));
            }
            state = robot_motion(&p, &state).end;
            drive.push(state.speed.clone());
        }
        let mut need: Vec<Exact> = vec![
            p.g0.clone(),
            p.clearance.clone(),
            p.buffer.clone(),
            p.v_max.clone() * dt.clone(),
            p.V_a.clone() * dt.clone(),
            p.a.clone() * dt.clone() * dt.clone() / two.clone(),
            p.b.clone() * dt.clone() * dt.clone() / two.clone(),
        ];
        need.extend(speeds.speeds().iter().map(|w| w.clone() * dt.clone()));
        // The period in which the robot reaches v_max: v_max·dt − (v_max − u)²/(2a).
        let before_top = drive[drive.len() - 2].clone();
        let gap_to_top = p.v_max.clone() - before_top;
        need.push(gap_to_top.clone() * gap_to_top / (two.clone() * p.a.clone()));
        // The last, partial braking period from every speed the robot can brake from.
        let bdt = p.b.clone() * dt.clone();
        let mut last: BTreeSet<Exact> = BTreeSet::new();
        for u in drive.iter().filter(|u| **u > Exact::ZERO) {
            let periods = Exact::from((u.clone() / bdt.clone()).ceil());
            last.insert(u.clone() - (periods - Exact::ONE) * bdt.clone());
        }
        for r in &last {
            need.push(r.clone() * r.clone() / (two.clone() * p.b.clone()));
            for w in speeds.speeds() {
                need.push(w.clone() * r.clone() / p.b.clone());
            }
        }
        let scale = need.iter().fold(UBig::ONE, |d, x| lcm(&d, x.denominator()));
        let d = Exact::from(scale.clone());
        let on_grid = |x: Exact| x * d.clone();
        let g0 = to_int(&on_grid(p.g0.clone()), "the initial gap")?;
        let v_max = to_int(&on_grid(p.v_max.clone() * dt.clone()), "v_max·dt")?;
        let acc = to_int(&on_grid(p.a.clone() * dt.clone() * dt.clone()), "a·dt²")?;
        let brk = to_int(&on_grid(bdt.clone() * dt.clone()), "b·dt²")?;
        let v_a = to_int(&on_grid(p.V_a.clone() * dt.clone()), "V_a·dt")?;
        let rho_exact = Exact::from(on_grid(p.rho.clone()).floor());
        let rho = to_int(&rho_exact, "the reaction radius")?;
        let buffer = to_int(&on_grid(p.buffer.clone()), "the buffer")?;
        let clearance = to_int(&on_grid(p.clearance.clone()), "the clearance")?;
        let speeds_int = speeds
            .speeds()
            .iter()
            .map(|w| to_int(&on_grid(w.clone() * dt.clone()), "an obstacle speed"))
            .collect::<Result<Vec<_>, _>>()?;
        let w_max = *speeds_int.last().expect("a speed set is nonempty");
        let gap_min = 0.min(clearance - v_max - w_max);
        let grid = Grid {
            scale,
            latency: p.L,
            g0,
            v_max,
            acc,
            brk,
            v_a,
            rho,
            buffer,
            clearance,
            speeds: speeds_int,
            gap_min,
            rule: p.rule,
            wrong_assumption_brake: p.wrong_assumption_brake,
        };
        grid.check_products()?;
        Ok(grid)
    }

    /// The largest obstacle speed on the grid.
    pub fn w_max(&self) -> i64 {
        *self.speeds.last().expect("a speed set is nonempty")
    }

    /// Every product the model's functions compute must fit a 32-bit int.
    fn check_products(&self) -> Result<(), UppaalError> {
        let factor = if self.rule == DangerRule::Kinematic {
            2
        } else {
            1
        };
        let span = (self.g0 + self.buffer).max(self.buffer - self.gap_min);
        let checks: [(&str, i128); 6] = [
            (
                "the danger guard's left side (observed gap - BUFFER)·BRK",
                i128::from(factor) * i128::from(span) * i128::from(self.brk),
            ),
            (
                "the danger guard's right side v·v + VA·v",
                i128::from(self.v_max) * i128::from(self.v_max)
                    + i128::from(factor) * i128::from(self.v_a) * i128::from(self.v_max),
            ),
            (
                "the rest gap's v·(2·w + v)",
                i128::from(self.brk) * (2 * i128::from(self.w_max()) + i128::from(self.brk)),
            ),
            (
                "the top-speed step's (VMAX - v)²",
                i128::from(self.acc) * i128::from(self.acc),
            ),
            (
                "a gap plus a period's travel",
                i128::from(self.g0) + i128::from(self.v_max) + i128::from(self.w_max()),
            ),
            ("2·ACC, 2·BRK", 2 * i128::from(self.acc.max(self.brk))),
        ];
        for (what, value) in checks {
            if value > i128::from(INT_MAX) {
                return Err(UppaalError::Grid(format!(
                    "with 1 unit = 1/{} m, {what} reaches {value}, beyond UPPAAL's 32-bit int \
                     (at most {INT_MAX}); use fewer or rounder speeds, or rounder problem numbers",
                    self.scale
                )));
            }
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------------------------
// The model as data: expressions, statements, functions, templates
// ---------------------------------------------------------------------------------------------

/// A binary operator of UPPAAL's expression language.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/` (the interpreter requires it to be exact)
    Div,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
    /// `==`
    Eq,
    /// `&&`
    And,
    /// `||`
    Or,
}

impl Op {
    fn text(self) -> &'static str {
        match self {
            Op::Add => "+",
            Op::Sub => "-",
            Op::Mul => "*",
            Op::Div => "/",
            Op::Lt => "<",
            Op::Le => "<=",
            Op::Gt => ">",
            Op::Ge => ">=",
            Op::Eq => "==",
            Op::And => "&&",
            Op::Or => "||",
        }
    }

    fn precedence(self) -> u8 {
        match self {
            Op::Or => 1,
            Op::And => 2,
            Op::Eq => 3,
            Op::Lt | Op::Le | Op::Gt | Op::Ge => 4,
            Op::Add | Op::Sub => 5,
            Op::Mul | Op::Div => 6,
        }
    }
}

/// An expression of UPPAAL's C-like language (the subset the export uses).
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    /// An integer literal.
    Int(i64),
    /// `true` / `false`.
    Bool(bool),
    /// A constant, variable, parameter or local.
    Name(&'static str),
    /// `a[i]`.
    Elem(&'static str, Box<Expr>),
    /// `f(args)`.
    Call(&'static str, Vec<Expr>),
    /// `!e`.
    Not(Box<Expr>),
    /// `a op b`.
    Bin(Op, Box<Expr>, Box<Expr>),
}

/// A statement of a function body (or of an edge's update list).
#[derive(Clone, Debug, PartialEq)]
pub enum Stmt {
    /// `name = e;`
    Set(&'static str, Expr),
    /// `name[i] = e;`
    SetElem(&'static str, Expr, Expr),
    /// `f(args);`
    Call(&'static str, Vec<Expr>),
    /// `if (c) { … } else { … }`
    If(Expr, Vec<Stmt>, Vec<Stmt>),
    /// `return e;`
    Return(Expr),
    /// `for (var = from; var > 0; var--) { … }` (`down`) or
    /// `for (var = from; var <= to; var++) { … }`.
    For {
        /// The loop variable (a local).
        var: &'static str,
        /// Its first value.
        from: Expr,
        /// Counting down to 1 (`None`) or up to this bound inclusive.
        up_to: Option<Expr>,
        /// The body.
        body: Vec<Stmt>,
    },
}

/// A function's return type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ty {
    /// `bool`
    Bool,
    /// `int`
    Int,
    /// `void`
    Void,
}

/// A function of the global declarations.
#[derive(Clone, Debug, PartialEq)]
pub struct Function {
    /// Comment printed above it.
    pub doc: String,
    /// Return type.
    pub ret: Ty,
    /// Name.
    pub name: &'static str,
    /// Parameters (all `int`).
    pub params: Vec<&'static str>,
    /// Local `int` variables.
    pub locals: Vec<&'static str>,
    /// Body.
    pub body: Vec<Stmt>,
}

/// A global declaration.
#[derive(Clone, Debug, PartialEq)]
pub enum Decl {
    /// A comment line (or lines).
    Comment(String),
    /// `const int NAME = v;` (or `const bool`).
    Const {
        /// Name.
        name: &'static str,
        /// Value.
        value: i64,
        /// Declared `bool`.
        boolean: bool,
        /// Trailing comment.
        note: String,
    },
    /// `const int NAME[N] = {…};`
    ConstArray {
        /// Name.
        name: &'static str,
        /// Values.
        values: Vec<i64>,
        /// Trailing comment.
        note: String,
    },
    /// `int[lo,hi] name = init;` or `bool name = init;` or an array of them.
    Var {
        /// Name.
        name: &'static str,
        /// Range as printed (constant names) and as numbers; `None`: `bool`.
        range: Option<(&'static str, &'static str, i64, i64)>,
        /// Array length, if an array.
        len: Option<(String, usize)>,
        /// Initial value (every element).
        init: i64,
        /// Trailing comment.
        note: String,
    },
    /// `chan a, b;`
    Chans(Vec<&'static str>),
    /// A function.
    Func(Function),
}

/// How a location delays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Time may pass (subject to its invariant).
    Normal,
    /// No delay.
    Urgent,
    /// No delay, and the next transition must leave a committed location.
    Committed,
}

/// A location of a template.
#[derive(Clone, Debug, PartialEq)]
pub struct Location {
    /// Name (UPPAAL identifier).
    pub name: &'static str,
    /// Clock invariant (printed; clocks are not interpreted).
    pub invariant: Option<&'static str>,
    /// Delay kind.
    pub kind: Kind,
    /// Position in UPPAAL's editor.
    pub xy: (i32, i32),
}

/// Direction of a synchronisation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dir {
    /// `c!`
    Send,
    /// `c?`
    Receive,
}

/// An edge of a template.
#[derive(Clone, Debug, PartialEq)]
pub struct Edge {
    /// Source location (index).
    pub source: usize,
    /// Target location (index).
    pub target: usize,
    /// `name : int[0, hi]` where hi is printed as given and interpreted as the number.
    pub select: Option<(&'static str, &'static str, i64)>,
    /// Data guard (interpreted).
    pub guard: Option<Expr>,
    /// Clock guard (printed only).
    pub clock_guard: Option<&'static str>,
    /// Synchronisation.
    pub sync: Option<(&'static str, Dir)>,
    /// Updates (interpreted).
    pub update: Vec<Stmt>,
    /// Clock resets (printed only).
    pub clock_reset: Option<&'static str>,
}

/// A template (one process: templates have no parameters and are instantiated once).
#[derive(Clone, Debug, PartialEq)]
pub struct Template {
    /// Name, also the process name.
    pub name: &'static str,
    /// Local declarations (clocks only).
    pub declaration: &'static str,
    /// Locations.
    pub locations: Vec<Location>,
    /// Initial location (index).
    pub init: usize,
    /// Edges.
    pub edges: Vec<Edge>,
}

/// The network: global declarations, templates and the safety query.
#[derive(Clone, Debug, PartialEq)]
pub struct Network {
    /// Header comment of the file.
    pub header: String,
    /// Global declarations.
    pub declarations: Vec<Decl>,
    /// Templates, each instantiated once.
    pub templates: Vec<Template>,
    /// The violation the safety query excludes (`A[] not violation`).
    pub violation: Expr,
}

/// An exported model.
#[derive(Clone, Debug)]
pub struct UppaalModel {
    /// The grid.
    pub grid: Grid,
    /// The network as data.
    pub network: Network,
    /// The UPPAAL XML file.
    pub xml: String,
    /// The query file.
    pub query: String,
}

// Shorthands for building expressions.
fn n(name: &'static str) -> Expr {
    Expr::Name(name)
}
fn int(v: i64) -> Expr {
    Expr::Int(v)
}
fn call(f: &'static str) -> Expr {
    Expr::Call(f, vec![])
}
fn elem(a: &'static str, i: Expr) -> Expr {
    Expr::Elem(a, Box::new(i))
}
fn bin(op: Op, a: Expr, b: Expr) -> Expr {
    Expr::Bin(op, Box::new(a), Box::new(b))
}
fn add(a: Expr, b: Expr) -> Expr {
    bin(Op::Add, a, b)
}
fn sub(a: Expr, b: Expr) -> Expr {
    bin(Op::Sub, a, b)
}
fn mul(a: Expr, b: Expr) -> Expr {
    bin(Op::Mul, a, b)
}
fn div(a: Expr, b: Expr) -> Expr {
    bin(Op::Div, a, b)
}
fn and(a: Expr, b: Expr) -> Expr {
    bin(Op::And, a, b)
}
fn or(a: Expr, b: Expr) -> Expr {
    bin(Op::Or, a, b)
}
fn not(a: Expr) -> Expr {
    Expr::Not(Box::new(a))
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

/// Builds the network of a grid (the problem's name goes into the header).
fn network(problem: &Problem, grid: &Grid, speeds: &SpeedSet) -> Network {
    let g = grid;
    let dt = problem.robot.control_period;
    let header = format!(
        "safereach export of problem \"{name}\": the finite model (obstacle speeds {speeds} m/s)\n\
         as UPPAAL timed automata on an exact integer grid.\n\
         Scaling (exact for this problem, nothing is rounded):\n\
         - time: 1 model time unit = 1 control period = {dt} s;\n\
         - distance: 1 unit = 1/{d} m (gap, thresholds, clearance);\n\
         - speed: units per period: 1 = 1/({d} * {dt}) m/s;\n\
         - the reaction radius enters as floor(rho * {d}) = {rho}, the same condition for integer gaps.\n\
         Reference answer: the explorer on the same finite model, safereach explore PROBLEM\n\
         with the speed list {list} (UPPAAL is not needed for it).",
        name = problem.name,
        d = g.scale,
        rho = g.rho,
        list = speeds
            .speeds()
            .iter()
            .map(show_exact)
            .collect::<Vec<_>>()
            .join(","),
    );
    let l = g.latency as i64;
    let mut d = vec![
        Decl::Comment(format!(
            "Problem \"{}\" on the integer grid: 1 distance unit = 1/{} m, 1 time unit = {} s,\n\
             speeds in distance units per period. Exact: see the file's header comment.\n\
             Reference answer: safereach explore PROBLEM --speeds {}",
            problem.name,
            g.scale,
            dt,
            speeds
                .speeds()
                .iter()
                .map(show_exact)
                .collect::<Vec<_>>()
                .join(",")
        )),
        constant("L", l, "observation latency (periods)"),
        constant("G0", g.g0, "initial gap"),
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
        Decl::Var {
            name: "gap",
            range: Some(("GMIN", "G0", g.gap_min, g.g0)),
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
            range: Some(("GMIN", "G0", g.gap_min, g.g0)),
            len: Some(("L + 1".into(), g.latency + 1)),
            init: 0,
            note: "gapAt[j]: gap at the start of the period j periods ago".into(),
        },
        Decl::Var {
            name: "fastAt",
            range: None,
            len: Some(("L + 1".into(), g.latency + 1)),
            init: 0,
            note:
                "fastAt[j]: the obstacle was faster than V_a in the period that ended j periods ago"
                    .into(),
        },
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
            range: Some(("GMIN", "G0", g.gap_min, g.g0)),
            len: None,
            init: 0,
            note: "gap at the instant the robot came to rest".into(),
        },
    ];
    let observed_gap = call("observedGap");
    let danger = match g.rule {
        DangerRule::Paper => and(
            call("inArea"),
            bin(
                Op::Le,
                mul(sub(observed_gap.clone(), n("BUFFER")), n("BRK")),
                add(mul(n("v"), n("v")), mul(n("VA"), n("v"))),
            ),
        ),
        DangerRule::Kinematic => and(
            call("inArea"),
            bin(
                Op::Le,
                mul(
                    mul(int(2), sub(observed_gap.clone(), n("BUFFER"))),
                    n("BRK"),
                ),
                add(mul(n("v"), n("v")), mul(mul(int(2), n("VA")), n("v"))),
            ),
        ),
        DangerRule::Area => call("inArea"),
    };
    let danger_doc = match g.rule {
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
    d.extend([
        func(
            "The robot sees the gap L periods ago (and the obstacle speed of the period\n\
             before that; 0 before the first period) once L periods have passed.",
            Ty::Bool,
            "observing",
            &[],
            &[],
            vec![Stmt::Return(bin(Op::Ge, n("k"), n("L")))],
        ),
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
        func(
            "In the reaction area: 0 < observed gap <= rho.",
            Ty::Bool,
            "inArea",
            &[],
            &[],
            vec![Stmt::Return(and(
                and(call("observing"), bin(Op::Gt, observed_gap.clone(), int(0))),
                bin(Op::Le, observed_gap.clone(), n("RHO")),
            ))],
        ),
        func(
            danger_doc,
            Ty::Bool,
            "collisionDanger",
            &[],
            &[],
            vec![Stmt::Return(danger)],
        ),
        func(
            "Wrong assumption: an obstacle in the area seen faster than V_a.",
            Ty::Bool,
            "wrongAssumption",
            &[],
            &[],
            vec![Stmt::Return(and(
                and(n("WRONG_ASSUMPTION_BRAKE"), call("inArea")),
                call("observedFast"),
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
        func(
            "Obstacle.Init: store the initial gap.",
            Ty::Void,
            "initialise",
            &[],
            &["j"],
            vec![
                Stmt::Set("gap", n("G0")),
                Stmt::For {
                    var: "j",
                    from: int(0),
                    up_to: Some(n("L")),
                    body: vec![Stmt::SetElem("gapAt", n("j"), n("G0"))],
                },
            ],
        ),
        func(
            "End of a period: the robot moved dx and ends at speed vEnd, the obstacle moved w;\n\
             shift the observation history (w is cleared: it is chosen anew each period).",
            Ty::Void,
            "endPeriod",
            &["dx", "vEnd"],
            &["j"],
            vec![
                Stmt::Set("gap", sub(sub(n("gap"), n("dx")), n("w"))),
                Stmt::Set("v", n("vEnd")),
                Stmt::For {
                    var: "j",
                    from: n("L"),
                    up_to: None,
                    body: vec![
                        Stmt::SetElem("gapAt", n("j"), elem("gapAt", sub(n("j"), int(1)))),
                        Stmt::SetElem("fastAt", n("j"), elem("fastAt", sub(n("j"), int(1)))),
                    ],
                },
                Stmt::SetElem("gapAt", int(0), n("gap")),
                Stmt::SetElem("fastAt", int(0), bin(Op::Gt, n("w"), n("VA"))),
                Stmt::Set("w", int(0)),
                Stmt::If(
                    bin(Op::Lt, n("k"), n("L")),
                    vec![Stmt::Set("k", add(n("k"), int(1)))],
                    vec![],
                ),
            ],
        ),
        func(
            "Accelerate for a whole period: distance v + ACC/2.",
            Ty::Void,
            "accelerate",
            &[],
            &[],
            vec![Stmt::Call(
                "endPeriod",
                vec![add(n("v"), div(n("ACC"), int(2))), add(n("v"), n("ACC"))],
            )],
        ),
        func(
            "Reach VMAX inside the period, then cruise: distance VMAX - (VMAX - v)^2/(2*ACC).",
            Ty::Void,
            "reachTopSpeed",
            &[],
            &[],
            vec![Stmt::Call(
                "endPeriod",
                vec![
                    sub(
                        n("VMAX"),
                        div(
                            mul(sub(n("VMAX"), n("v")), sub(n("VMAX"), n("v"))),
                            mul(int(2), n("ACC")),
                        ),
                    ),
                    n("VMAX"),
                ],
            )],
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
            "Brake for a whole period: distance v - BRK/2.",
            Ty::Void,
            "brake",
            &[],
            &[],
            vec![Stmt::Call(
                "endPeriod",
                vec![sub(n("v"), div(n("BRK"), int(2))), sub(n("v"), n("BRK"))],
            )],
        ),
        func(
            "Come to rest after v/BRK of the period, having moved v^2/(2*BRK) while the\n\
             obstacle moved w*v/BRK: the gap at that instant is recorded.",
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
                                    mul(int(2), n("BRK")),
                                ),
                            ),
                        ),
                    ],
                    vec![],
                ),
                Stmt::Call(
                    "endPeriod",
                    vec![div(mul(n("v"), n("v")), mul(int(2), n("BRK"))), int(0)],
                ),
            ],
        ),
    ]);
    Network {
        header,
        declarations: d,
        templates: vec![robot_template(), obstacle_template(g.speeds.len() as i64)],
        violation: violation(),
    }
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

fn brake_guard() -> Expr {
    or(call("collisionDanger"), call("wrongAssumption"))
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
    let loc = |name, kind, xy| Location {
        name,
        invariant: None,
        kind,
        xy,
    };
    let decide = Some(("decide", Dir::Receive));
    let advance = Some(("advance", Dir::Receive));
    let keep = |from: usize| Edge {
        guard: Some(not(brake_guard())),
        sync: decide,
        ..edge(from, from)
    };
    let to_brake = |from: usize| Edge {
        guard: Some(brake_guard()),
        sync: decide,
        ..edge(from, BRAKE)
    };
    let mv = |from: usize, to: usize, guard: Option<Expr>, f: &'static str| Edge {
        guard,
        sync: advance,
        update: vec![Stmt::Call(f, vec![])],
        ..edge(from, to)
    };
    Template {
        name: "Robot",
        declaration: "",
        locations: vec![
            loc("Idle", Kind::Committed, (-400, 0)),
            loc("Accelerate", Kind::Normal, (-150, 0)),
            loc("Drive", Kind::Normal, (150, 0)),
            loc("Brake", Kind::Normal, (150, 250)),
            loc("Stop", Kind::Normal, (-150, 250)),
        ],
        init: IDLE,
        edges: vec![
            edge(IDLE, ACC),
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

fn obstacle_template(nw: i64) -> Template {
    const INIT: usize = 0;
    const IDLE: usize = 1;
    const MOVE: usize = 2;
    Template {
        name: "Obstacle",
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
            Edge {
                update: vec![Stmt::Call("initialise", vec![])],
                ..edge(INIT, IDLE)
            },
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

// ---------------------------------------------------------------------------------------------
// Printing
// ---------------------------------------------------------------------------------------------

fn show_expr(e: &Expr) -> String {
    fn go(e: &Expr, out: &mut String) {
        match e {
            Expr::Int(v) => {
                let _ = write!(out, "{v}");
            }
            Expr::Bool(b) => out.push_str(if *b { "true" } else { "false" }),
            Expr::Name(x) => out.push_str(x),
            Expr::Elem(a, i) => {
                out.push_str(a);
                out.push('[');
                go(i, out);
                out.push(']');
            }
            Expr::Call(f, args) => {
                out.push_str(f);
                out.push('(');
                for (i, a) in args.iter().enumerate() {
                    if i > 0 {
                        out.push_str(", ");
                    }
                    go(a, out);
                }
                out.push(')');
            }
            Expr::Not(a) => {
                out.push('!');
                paren(a, 7, false, out);
            }
            Expr::Bin(op, a, b) => {
                paren(a, op.precedence(), false, out);
                let _ = write!(out, " {} ", op.text());
                paren(b, op.precedence(), true, out);
            }
        }
    }
    fn paren(e: &Expr, outer: u8, right: bool, out: &mut String) {
        let inner = match e {
            Expr::Bin(op, ..) => op.precedence(),
            _ => 8,
        };
        // `&&` inside `||` is parenthesised for the reader, not for the parser.
        let clarity = outer == Op::Or.precedence() && inner == Op::And.precedence();
        if inner < outer || (right && inner == outer) || clarity {
            out.push('(');
            go(e, out);
            out.push(')');
        } else {
            go(e, out);
        }
    }
    let mut s = String::new();
    go(e, &mut s);
    s
}

fn show_stmt(s: &Stmt, indent: usize, out: &mut String) {
    let pad = "    ".repeat(indent);
    match s {
        Stmt::Set(x, e) => {
            let _ = writeln!(out, "{pad}{x} = {};", show_expr(e));
        }
        Stmt::SetElem(x, i, e) => {
            let _ = writeln!(out, "{pad}{x}[{}] = {};", show_expr(i), show_expr(e));
        }
        Stmt::Call(f, args) => {
            let _ = writeln!(out, "{pad}{};", show_expr(&Expr::Call(f, args.clone())));
        }
        Stmt::Return(e) => {
            let _ = writeln!(out, "{pad}return {};", show_expr(e));
        }
        Stmt::If(c, then, other) => {
            let _ = writeln!(out, "{pad}if ({}) {{", show_expr(c));
            for t in then {
                show_stmt(t, indent + 1, out);
            }
            if other.is_empty() {
                let _ = writeln!(out, "{pad}}}");
            } else {
                let _ = writeln!(out, "{pad}}} else {{");
                for t in other {
                    show_stmt(t, indent + 1, out);
                }
                let _ = writeln!(out, "{pad}}}");
            }
        }
        Stmt::For {
            var,
            from,
            up_to,
            body,
        } => {
            let head = match up_to {
                Some(to) => format!(
                    "for ({var} = {}; {var} <= {}; {var}++)",
                    show_expr(from),
                    show_expr(to)
                ),
                None => format!("for ({var} = {}; {var} > 0; {var}--)", show_expr(from)),
            };
            let _ = writeln!(out, "{pad}{head} {{");
            for t in body {
                show_stmt(t, indent + 1, out);
            }
            let _ = writeln!(out, "{pad}}}");
        }
    }
}

fn comment_lines(text: &str, out: &mut String) {
    for line in text.lines() {
        let _ = writeln!(out, "// {line}");
    }
}

/// The global declarations as UPPAAL text.
pub fn declarations_text(net: &Network) -> String {
    let mut out = String::new();
    for d in &net.declarations {
        match d {
            Decl::Comment(c) => {
                comment_lines(c, &mut out);
                out.push('\n');
            }
            Decl::Const {
                name,
                value,
                boolean,
                note,
            } => {
                let value = if *boolean {
                    (if *value != 0 { "true" } else { "false" }).to_string()
                } else {
                    value.to_string()
                };
                let ty = if *boolean { "bool" } else { "int" };
                let _ = writeln!(out, "const {ty} {name} = {value};  // {note}");
            }
            Decl::ConstArray { name, values, note } => {
                let list: Vec<String> = values.iter().map(i64::to_string).collect();
                let _ = writeln!(
                    out,
                    "const int {name}[NW] = {{{}}};  // {note}",
                    list.join(", ")
                );
            }
            Decl::Var {
                name,
                range,
                len,
                init,
                note,
            } => {
                let ty = match range {
                    Some((lo, hi, ..)) => format!("int[{lo},{hi}]"),
                    None => "bool".to_string(),
                };
                let show_init = |v: i64| match range {
                    None => (if v != 0 { "true" } else { "false" }).to_string(),
                    Some(_) => v.to_string(),
                };
                match len {
                    None => {
                        let _ = writeln!(out, "{ty} {name} = {};  // {note}", show_init(*init));
                    }
                    Some((text, count)) => {
                        let list: Vec<String> = (0..*count).map(|_| show_init(*init)).collect();
                        let _ = writeln!(
                            out,
                            "{ty} {name}[{text}] = {{{}}};  // {note}",
                            list.join(", ")
                        );
                    }
                }
            }
            Decl::Chans(names) => {
                let _ = writeln!(
                    out,
                    "chan {};  // decide: a period starts; advance: it ends",
                    names.join(", ")
                );
            }
            Decl::Func(f) => {
                out.push('\n');
                if !f.doc.is_empty() {
                    comment_lines(&f.doc, &mut out);
                }
                let ret = match f.ret {
                    Ty::Bool => "bool",
                    Ty::Int => "int",
                    Ty::Void => "void",
                };
                let params: Vec<String> = f.params.iter().map(|p| format!("int {p}")).collect();
                let _ = writeln!(out, "{ret} {}({}) {{", f.name, params.join(", "));
                for l in &f.locals {
                    let _ = writeln!(out, "    int {l};");
                }
                for s in &f.body {
                    show_stmt(s, 1, &mut out);
                }
                out.push_str("}\n");
            }
        }
    }
    out
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn updates_text(e: &Edge) -> Option<String> {
    let mut parts: Vec<String> = e
        .update
        .iter()
        .map(|s| {
            let mut t = String::new();
            show_stmt(s, 0, &mut t);
            t.trim().trim_end_matches(';').to_string()
        })
        .collect();
    if let Some(r) = e.clock_reset {
        parts.push(r.to_string());
    }
    (!parts.is_empty()).then(|| parts.join(", "))
}

fn guard_text(e: &Edge) -> Option<String> {
    match (&e.clock_guard, &e.guard) {
        (None, None) => None,
        (Some(c), None) => Some(c.to_string()),
        (None, Some(g)) => Some(show_expr(g)),
        (Some(c), Some(g)) => Some(format!("{c} && ({})", show_expr(g))),
    }
}

/// The safety query (`A[] not violation`).
pub fn query_formula(net: &Network) -> String {
    format!("A[] not ({})", show_expr(&net.violation))
}

const SEED_QUERY: &str = "A[] forall (i:int[0,N-1]) R.y == obstacles[i].y and obstacles[i].x > R.x \
                          and (obstacles[i].x - R.x <= 1) imply R.v == 0";

fn query_comment() -> String {
    format!(
        "Passive safety: the robot is never moving with gap <= clearance. A robot that comes\n\
         to rest inside a period is judged by its gap at that instant (restGap < CLEARANCE).\n\
         The seed paper's form, for N obstacles on lanes y at positions x:\n  {SEED_QUERY}\n\
         Its moving part in this model's variables (one obstacle, on the robot's lane):\n  \
         A[] (gap <= CLEARANCE imply v == 0)"
    )
}

/// The model as UPPAAL XML.
pub fn xml_text(net: &Network) -> String {
    let mut out = String::new();
    out.push_str("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n");
    out.push_str(
        "<!DOCTYPE nta PUBLIC '-//Uppaal Team//DTD Flat System 1.1//EN' \
         'http://www.it.uu.se/research/group/darts/uppaal/flat-1_2.dtd'>\n",
    );
    let _ = writeln!(out, "<!--\n{}\n-->", net.header.replace("--", "- -"));
    out.push_str("<nta>\n");
    let _ = writeln!(
        out,
        "  <declaration>{}</declaration>",
        xml_escape(&declarations_text(net))
    );
    for t in &net.templates {
        out.push_str("  <template>\n");
        let _ = writeln!(out, "    <name>{}</name>", t.name);
        if !t.declaration.is_empty() {
            let _ = writeln!(
                out,
                "    <declaration>{}</declaration>",
                xml_escape(t.declaration)
            );
        }
        for (i, l) in t.locations.iter().enumerate() {
            let _ = writeln!(
                out,
                "    <location id=\"{}\" x=\"{}\" y=\"{}\">",
                location_id(net, t, i),
                l.xy.0,
                l.xy.1
            );
            let _ = writeln!(
                out,
                "      <name x=\"{}\" y=\"{}\">{}</name>",
                l.xy.0 - 20,
                l.xy.1 - 30,
                l.name
            );
            if let Some(inv) = l.invariant {
                let _ = writeln!(
                    out,
                    "      <label kind=\"invariant\" x=\"{}\" y=\"{}\">{}</label>",
                    l.xy.0 - 20,
                    l.xy.1 + 15,
                    xml_escape(inv)
                );
            }
            match l.kind {
                Kind::Normal => {}
                Kind::Urgent => out.push_str("      <urgent/>\n"),
                Kind::Committed => out.push_str("      <committed/>\n"),
            }
            out.push_str("    </location>\n");
        }
        let _ = writeln!(out, "    <init ref=\"{}\"/>", location_id(net, t, t.init));
        for e in &t.edges {
            out.push_str("    <transition>\n");
            let _ = writeln!(
                out,
                "      <source ref=\"{}\"/>",
                location_id(net, t, e.source)
            );
            let _ = writeln!(
                out,
                "      <target ref=\"{}\"/>",
                location_id(net, t, e.target)
            );
            if let Some((name, hi, _)) = e.select {
                let _ = writeln!(
                    out,
                    "      <label kind=\"select\">{name} : int[0, {}]</label>",
                    xml_escape(hi)
                );
            }
            if let Some(g) = guard_text(e) {
                let _ = writeln!(
                    out,
                    "      <label kind=\"guard\">{}</label>",
                    xml_escape(&g)
                );
            }
            if let Some((c, dir)) = e.sync {
                let mark = if dir == Dir::Send { '!' } else { '?' };
                let _ = writeln!(
                    out,
                    "      <label kind=\"synchronisation\">{c}{mark}</label>"
                );
            }
            if let Some(u) = updates_text(e) {
                let _ = writeln!(
                    out,
                    "      <label kind=\"assignment\">{}</label>",
                    xml_escape(&u)
                );
            }
            out.push_str("    </transition>\n");
        }
        out.push_str("  </template>\n");
    }
    let names: Vec<&str> = net.templates.iter().map(|t| t.name).collect();
    let _ = writeln!(
        out,
        "  <system>// One robot, one obstacle on its lane.\nsystem {};</system>",
        names.join(", ")
    );
    out.push_str("  <queries>\n    <query>\n");
    let _ = writeln!(
        out,
        "      <formula>{}</formula>",
        xml_escape(&query_formula(net))
    );
    let _ = writeln!(
        out,
        "      <comment>{}</comment>",
        xml_escape(&query_comment())
    );
    out.push_str("    </query>\n  </queries>\n</nta>\n");
    out
}

fn location_id(net: &Network, t: &Template, i: usize) -> String {
    let before: usize = net
        .templates
        .iter()
        .take_while(|o| o.name != t.name)
        .map(|o| o.locations.len())
        .sum();
    format!("id{}", before + i)
}

/// The query file (UPPAAL's `.q` format: comments and one formula).
pub fn query_text(net: &Network) -> String {
    format!("/*\n{}\n*/\n{}\n", query_comment(), query_formula(net))
}

/// Exports a (validated) problem with obstacle speeds from `speeds`.
pub fn export(problem: &Problem, speeds: &SpeedSet) -> Result<UppaalModel, UppaalError> {
    let grid = Grid::new(problem, speeds)?;
    let network = network(problem, &grid, speeds);
    let xml = xml_text(&network);
    let query = query_text(&network);
    Ok(UppaalModel {
        grid,
        network,
        xml,
        query,
    })
}

// ---------------------------------------------------------------------------------------------
// The interpreter
// ---------------------------------------------------------------------------------------------

/// Storage of one global variable in the flat state vector.
#[derive(Clone, Debug)]
struct Slot {
    offset: usize,
    len: Option<usize>,
    lo: i64,
    hi: i64,
}

/// Constants, variable layout and functions of a network, for evaluation.
struct Machine<'a> {
    consts: HashMap<&'static str, i64>,
    const_arrays: HashMap<&'static str, &'a [i64]>,
    slots: HashMap<&'static str, Slot>,
    funcs: HashMap<&'static str, &'a Function>,
    init: Vec<i64>,
}

type Frame = Vec<(&'static str, i64)>;

enum Flow {
    Next,
    Return(i64),
}

fn fail<T>(msg: String) -> Result<T, UppaalError> {
    Err(UppaalError::Run(msg))
}

fn int32(v: i64, what: &dyn Fn() -> String) -> Result<i64, UppaalError> {
    if v.abs() > INT_MAX {
        return fail(format!("{} overflows a 32-bit int ({v})", what()));
    }
    Ok(v)
}

impl<'a> Machine<'a> {
    fn new(net: &'a Network) -> Machine<'a> {
        let mut m = Machine {
            consts: HashMap::new(),
            const_arrays: HashMap::new(),
            slots: HashMap::new(),
            funcs: HashMap::new(),
            init: Vec::new(),
        };
        for d in &net.declarations {
            match d {
                Decl::Const { name, value, .. } => {
                    m.consts.insert(name, *value);
                }
                Decl::ConstArray { name, values, .. } => {
                    m.const_arrays.insert(name, values);
                }
                Decl::Var {
                    name,
                    range,
                    len,
                    init,
                    ..
                } => {
                    let (lo, hi) = range.map_or((0, 1), |(_, _, lo, hi)| (lo, hi));
                    let count = len.as_ref().map(|(_, c)| *c);
                    m.slots.insert(
                        name,
                        Slot {
                            offset: m.init.len(),
                            len: count,
                            lo,
                            hi,
                        },
                    );
                    m.init
                        .extend(std::iter::repeat_n(*init, count.unwrap_or(1)));
                }
                Decl::Func(f) => {
                    m.funcs.insert(f.name, f);
                }
                Decl::Comment(_) | Decl::Chans(_) => {}
            }
        }
        m
    }

    fn lookup(&self, name: &str, frame: &Frame, vars: &[i64]) -> Result<i64, UppaalError> {
        if let Some((_, v)) = frame.iter().rev().find(|(x, _)| *x == name) {
            return Ok(*v);
        }
        if let Some(s) = self.slots.get(name) {
            if s.len.is_some() {
                return fail(format!("array {name} used as a scalar"));
            }
            return Ok(vars[s.offset]);
        }
        match self.consts.get(name) {
            Some(v) => Ok(*v),
            None => fail(format!("unknown name {name}")),
        }
    }

    fn element(&self, name: &str, i: i64, vars: &[i64]) -> Result<i64, UppaalError> {
        if let Some(values) = self.const_arrays.get(name) {
            return usize::try_from(i)
                .ok()
                .and_then(|i| values.get(i).copied())
                .map_or_else(|| fail(format!("{name}[{i}] out of bounds")), Ok);
        }
        let s = self
            .slots
            .get(name)
            .ok_or_else(|| UppaalError::Run(format!("unknown array {name}")))?;
        let len = s.len.unwrap_or(0) as i64;
        if i < 0 || i >= len {
            return fail(format!("{name}[{i}] out of bounds (length {len})"));
        }
        Ok(vars[s.offset + i as usize])
    }

    fn eval(&self, e: &Expr, frame: &Frame, vars: &mut [i64]) -> Result<i64, UppaalError> {
        Ok(match e {
            Expr::Int(v) => *v,
            Expr::Bool(b) => i64::from(*b),
            Expr::Name(x) => self.lookup(x, frame, vars)?,
            Expr::Elem(a, i) => {
                let i = self.eval(i, frame, vars)?;
                self.element(a, i, vars)?
            }
            Expr::Call(f, args) => {
                let mut values = Vec::with_capacity(args.len());
                for a in args {
                    values.push(self.eval(a, frame, vars)?);
                }
                self.call(f, &values, vars)?
            }
            Expr::Not(a) => i64::from(self.eval(a, frame, vars)? == 0),
            Expr::Bin(Op::And, a, b) => {
                i64::from(self.eval(a, frame, vars)? != 0 && self.eval(b, frame, vars)? != 0)
            }
            Expr::Bin(Op::Or, a, b) => {
                i64::from(self.eval(a, frame, vars)? != 0 || self.eval(b, frame, vars)? != 0)
            }
            Expr::Bin(op, a, b) => {
                let x = self.eval(a, frame, vars)?;
                let y = self.eval(b, frame, vars)?;
                let what = || show_expr(e);
                match op {
                    Op::Add => int32(x + y, &what)?,
                    Op::Sub => int32(x - y, &what)?,
                    Op::Mul => int32(x * y, &what)?,
                    Op::Div => {
                        if y == 0 {
                            return fail(format!("{} divides by zero", what()));
                        }
                        if x % y != 0 {
                            return fail(format!(
                                "{} = {x}/{y} is not exact: the grid would round",
                                what()
                            ));
                        }
                        x / y
                    }
                    Op::Lt => i64::from(x < y),
                    Op::Le => i64::from(x <= y),
                    Op::Gt => i64::from(x > y),
                    Op::Ge => i64::from(x >= y),
                    Op::Eq => i64::from(x == y),
                    Op::And | Op::Or => unreachable!("handled above"),
                }
            }
        })
    }

    fn call(&self, f: &str, args: &[i64], vars: &mut [i64]) -> Result<i64, UppaalError> {
        let func = self
            .funcs
            .get(f)
            .ok_or_else(|| UppaalError::Run(format!("unknown function {f}")))?;
        if func.params.len() != args.len() {
            return fail(format!("{f} called with {} arguments", args.len()));
        }
        let mut frame: Frame = func
            .params
            .iter()
            .copied()
            .zip(args.iter().copied())
            .collect();
        frame.extend(func.locals.iter().map(|l| (*l, 0)));
        match self.exec_all(&func.body, &mut frame, vars)? {
            Flow::Return(v) => Ok(v),
            Flow::Next if func.ret == Ty::Void => Ok(0),
            Flow::Next => fail(format!("{f} ends without returning a value")),
        }
    }

    fn assign(
        &self,
        name: &str,
        index: Option<i64>,
        value: i64,
        frame: &mut Frame,
        vars: &mut [i64],
    ) -> Result<(), UppaalError> {
        if index.is_none()
            && let Some(slot) = frame.iter_mut().rev().find(|(x, _)| *x == name)
        {
            slot.1 = int32(value, &|| name.to_string())?;
            return Ok(());
        }
        let s = self
            .slots
            .get(name)
            .ok_or_else(|| UppaalError::Run(format!("assignment to {name}, not a variable")))?;
        let at = match (index, s.len) {
            (None, None) => s.offset,
            (Some(i), Some(len)) if i >= 0 && (i as usize) < len => s.offset + i as usize,
            _ => return fail(format!("bad assignment to {name}[{index:?}]")),
        };
        if value < s.lo || value > s.hi {
            return fail(format!(
                "{name} = {value} is outside its declared range [{}, {}] (UPPAAL aborts)",
                s.lo, s.hi
            ));
        }
        vars[at] = value;
        Ok(())
    }

    fn exec_all(
        &self,
        body: &[Stmt],
        frame: &mut Frame,
        vars: &mut [i64],
    ) -> Result<Flow, UppaalError> {
        for s in body {
            if let Flow::Return(v) = self.exec(s, frame, vars)? {
                return Ok(Flow::Return(v));
            }
        }
        Ok(Flow::Next)
    }

    fn exec(&self, s: &Stmt, frame: &mut Frame, vars: &mut [i64]) -> Result<Flow, UppaalError> {
        match s {
            Stmt::Set(x, e) => {
                let v = self.eval(e, frame, vars)?;
                self.assign(x, None, v, frame, vars)?;
            }
            Stmt::SetElem(x, i, e) => {
                let i = self.eval(i, frame, vars)?;
                let v = self.eval(e, frame, vars)?;
                self.assign(x, Some(i), v, frame, vars)?;
            }
            Stmt::Call(f, args) => {
                self.eval(&Expr::Call(f, args.clone()), frame, vars)?;
            }
            Stmt::If(c, then, other) => {
                let branch = if self.eval(c, frame, vars)? != 0 {
                    then
                } else {
                    other
                };
                return self.exec_all(branch, frame, vars);
            }
            Stmt::Return(e) => return Ok(Flow::Return(self.eval(e, frame, vars)?)),
            Stmt::For {
                var,
                from,
                up_to,
                body,
            } => {
                let start = self.eval(from, frame, vars)?;
                self.assign(var, None, start, frame, vars)?;
                loop {
                    let j = self.lookup(var, frame, vars)?;
                    let go_on = match up_to {
                        Some(to) => j <= self.eval(to, frame, vars)?,
                        None => j > 0,
                    };
                    if !go_on {
                        break;
                    }
                    if let Flow::Return(v) = self.exec_all(body, frame, vars)? {
                        return Ok(Flow::Return(v));
                    }
                    let step = if up_to.is_some() { 1 } else { -1 };
                    self.assign(var, None, j + step, frame, vars)?;
                }
            }
        }
        Ok(Flow::Next)
    }

    fn truth(
        &self,
        e: &Option<Expr>,
        frame: &Frame,
        vars: &mut [i64],
    ) -> Result<bool, UppaalError> {
        match e {
            None => Ok(true),
            Some(e) => Ok(self.eval(e, frame, vars)? != 0),
        }
    }

    fn update(&self, e: &Edge, frame: &mut Frame, vars: &mut [i64]) -> Result<(), UppaalError> {
        for s in &e.update {
            self.exec(s, frame, vars)?;
        }
        Ok(())
    }
}

/// A state of the network: one location per template, then every variable.
type NetState = (Vec<usize>, Vec<i64>);

/// The successors of a network state (UPPAAL's action transitions; see the module docs on
/// clocks), each with whether it ends a period (an `advance` synchronisation).
fn successors(
    net: &Network,
    m: &Machine<'_>,
    state: &NetState,
) -> Result<Vec<(NetState, bool)>, UppaalError> {
    let (locs, vars) = state;
    let mut out = Vec::new();
    let committed: Vec<bool> = net
        .templates
        .iter()
        .zip(locs)
        .map(|(t, &l)| t.locations[l].kind == Kind::Committed)
        .collect();
    let any_committed = committed.iter().any(|c| *c);
    // Internal edges.
    for (ti, t) in net.templates.iter().enumerate() {
        if any_committed && !committed[ti] {
            continue;
        }
        for e in t
            .edges
            .iter()
            .filter(|e| e.source == locs[ti] && e.sync.is_none())
        {
            let mut vars = vars.clone();
            let mut frame = Frame::new();
            if m.truth(&e.guard, &frame, &mut vars)? {
                m.update(e, &mut frame, &mut vars)?;
                let mut locs = locs.clone();
                locs[ti] = e.target;
                out.push(((locs, vars), false));
            }
        }
    }
    // Binary synchronisations: sender's update first, then the receiver's.
    for (si, st) in net.templates.iter().enumerate() {
        for se in st.edges.iter().filter(|e| e.source == locs[si]) {
            let Some((chan, Dir::Send)) = se.sync else {
                continue;
            };
            let choices = match se.select {
                Some((name, _, hi)) => (0..=hi).map(|v| vec![(name, v)]).collect(),
                None => vec![Frame::new()],
            };
            for choice in choices {
                for (ri, rt) in net.templates.iter().enumerate() {
                    if ri == si || (any_committed && !committed[si] && !committed[ri]) {
                        continue;
                    }
                    for re in rt
                        .edges
                        .iter()
                        .filter(|e| e.source == locs[ri] && e.sync == Some((chan, Dir::Receive)))
                    {
                        let mut vars = vars.clone();
                        let mut sframe = choice.clone();
                        if !m.truth(&se.guard, &sframe, &mut vars)?
                            || !m.truth(&re.guard, &Frame::new(), &mut vars)?
                        {
                            continue;
                        }
                        m.update(se, &mut sframe, &mut vars)?;
                        m.update(re, &mut Frame::new(), &mut vars)?;
                        let mut locs = locs.clone();
                        locs[si] = se.target;
                        locs[ri] = re.target;
                        out.push(((locs, vars), chan == "advance"));
                    }
                }
            }
        }
    }
    Ok(out)
}

/// What the interpreter found in the exported network.
#[derive(Clone, Debug, PartialEq)]
pub struct GridExploration {
    /// `collision` iff a reachable state violates the query; `safe` iff none does and the
    /// search completed; else `inconclusive`.
    pub verdict: ExploreVerdict,
    /// Every reachable state was visited.
    pub complete: bool,
    /// Distinct network states (locations and all variables).
    pub states: usize,
    /// Least `restGap` over reachable states where the robot rested (grid units).
    pub min_separation_grid: Option<i64>,
    /// The same in metres, exactly.
    pub min_separation: Option<Exact>,
    /// Periods (`advance` synchronisations) on a shortest path to a violating state.
    pub collision_period: Option<usize>,
}

/// Explores every reachable state of an exported network breadth first, by interpreting its
/// declarations, functions and edges (the data the XML is printed from).
pub fn explore_grid(
    model: &UppaalModel,
    options: &Options,
) -> Result<GridExploration, UppaalError> {
    if options.max_states == 0 {
        return Err(UppaalError::Options(
            "--max-states must be at least 1".into(),
        ));
    }
    let net = &model.network;
    let m = Machine::new(net);
    let rested = m.slots["rested"].offset;
    let rest_gap = m.slots["restGap"].offset;
    let init: NetState = (
        net.templates.iter().map(|t| t.init).collect(),
        m.init.clone(),
    );
    let mut seen: HashSet<NetState> = HashSet::new();
    seen.insert(init.clone());
    let mut queue: VecDeque<(NetState, usize)> = VecDeque::from([(init, 0)]);
    let mut complete = true;
    let mut min_rest: Option<i64> = None;
    let mut collision_period = None;
    while let Some((state, periods)) = queue.pop_front() {
        let mut vars = state.1.clone();
        if m.eval(&net.violation, &Frame::new(), &mut vars)? != 0 && collision_period.is_none() {
            collision_period = Some(periods);
        }
        if vars[rested] != 0 {
            min_rest = Some(min_rest.map_or(vars[rest_gap], |x| x.min(vars[rest_gap])));
        }
        for (next, advanced) in successors(net, &m, &state)? {
            if seen.contains(&next) {
                continue;
            }
            if seen.len() >= options.max_states {
                complete = false;
                queue.clear();
                break;
            }
            seen.insert(next.clone());
            queue.push_back((next, periods + usize::from(advanced)));
        }
    }
    let verdict = if collision_period.is_some() {
        ExploreVerdict::Collision
    } else if complete {
        ExploreVerdict::Safe
    } else {
        ExploreVerdict::Inconclusive
    };
    let d = Exact::from(model.grid.scale.clone());
    Ok(GridExploration {
        verdict,
        complete,
        states: seen.len(),
        min_separation_grid: min_rest,
        min_separation: min_rest.map(|g| Exact::from(g) / d),
        collision_period,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expressions_print_with_the_parentheses_c_needs() {
        let e = sub(n("a"), sub(n("b"), n("c")));
        assert_eq!(show_expr(&e), "a - (b - c)");
        let e = mul(add(n("a"), n("b")), n("c"));
        assert_eq!(show_expr(&e), "(a + b) * c");
        let e = div(mul(n("a"), n("b")), mul(int(2), n("c")));
        assert_eq!(show_expr(&e), "a * b / (2 * c)");
        let e = not(or(n("a"), and(n("b"), n("c"))));
        assert_eq!(show_expr(&e), "!(a || (b && c))");
        let e = bin(Op::Le, sub(n("o"), n("B")), add(n("x"), n("y")));
        assert_eq!(show_expr(&e), "o - B <= x + y");
    }
}
