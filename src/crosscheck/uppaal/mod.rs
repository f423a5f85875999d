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
//!   period, a·dt²·D, b·dt²·D (the controller's b, in d_coll) and b_min·dt²·D (the plant's
//!   braking, `BRKMIN`, written only when b_min < b).
//!
//! D is the least common multiple of the denominators of every quantity the model's integer
//! arithmetic produces: the initial gap (every start of a range), σ_g, σ_w·dt, d_det,
//! clearance, buffer, v_max·dt, v0·dt, V_a·dt, a·dt²/2, b·dt²/2, b_min·dt²/2, each obstacle
//! speed × dt, the distance of the step in which the robot reaches v_max (none when it
//! starts at v_max), and for every speed the robot can brake from (v0, then one per period
//! until v_max), the distance it and each obstacle speed cover in the last, partial braking
//! period at b_min; with gap noise, D is then multiplied by the least factor that makes every
//! positive guard threshold a whole unit ("Sensing noise" below). With that D every position
//! the model reaches is an integer and every division in the model is exact — the grid
//! model is the rational model scaled by D, behaviour for behaviour. The reaction radius is
//! the one number that need not be on the grid: `observed ≤ ρ` is written
//! `observed ≤ ⌊ρ·D⌋`, which is the same condition for an integer `observed`. The collision-danger guard o ≤ d_coll(v) is multiplied out
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
//!
//!   *Weaker brakes and a moving start* (docs/semantics.md §12). The danger distance keeps
//!   the controller's `BRK`; the plant brakes at `BRKMIN` = b_min·dt²·D (`brake()`,
//!   `stop()` and the Brake edges' guards), the worst case of [b_min, b] that every engine
//!   takes. A robot with `V0` = v0·dt·D > 0 leaves Idle for Accelerate, or for Drive when
//!   v0 = v_max (`RobotState::initial`); `v = V0` is set by the obstacle's `initialise()`,
//!   not on the robot's first edge, because the two committed first edges fire in either
//!   order and a moving robot must never meet the gap's placeholder 0. Neither constant is
//!   written when the setting is at its default, so those exports are unchanged.
//! - `Obstacle`: Init → Idle ⇄ Move, the seed's obstacle automaton. Init stores the initial
//!   gap; from Idle it selects its speed for the period from the set (`decide!`), and Move
//!   lasts one time unit (`advance!` at x == 1).
//!
//!   *A range of initial gaps* is exported as the explorer's finite set of starts
//!   ([`export_with_starts`], `--starts N`, default 5: N evenly spaced gaps, both ends
//!   included, taken from [`crate::crosscheck::explore::FiniteModel::with_starts`] itself):
//!   `GSTART[NSTART]` on the grid (each start's denominator goes into D), and Init's edge
//!   selects one (`select s : int[0, NSTART - 1]`, `initialise(GSTART[s])`) — the
//!   environment's first choice, as the explorer's init states are. The gap variables are
//!   bounded by the largest start, `G0MAX`. Like the explorer, the network covers exactly
//!   these starts, not the points between.
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
//! # Sensing noise: three gaps and two speed readings realise every error's outcome
//!
//! With `[sensing] gap_noise` σ_g or `speed_noise` σ_w (docs/semantics.md §12) each
//! observation is off by an error the environment picks within ±σ. The grid takes
//! `SG` = σ_g·D and `SW` = σ_w·dt·D (their denominators go into D). The history keeps, per
//! period, whether its speed can be measured above V_a (`fastAt`: w + SW > VA) and at or
//! below it (`slowAt`: w − SW ≤ VA; the speed before the first period is 0 exactly, so
//! `slowAt` starts true and `fastAt` false). The robot's decide edges select the error
//! `e : int[0, 5]`, and every guard reads the observation `e` picks: `observedGap(e)` is,
//! for e mod 3 = 0, 1, 2, the lowest gap the noise allows, l = g − SG, the highest,
//! h = g + SG, or the lowest positive one, max(l, min(1, h)); `observedFast(e)` is "fast"
//! for e ≥ 3 if some error shows the speed above V_a, and "fast" whenever none shows it at or
//! below (one of the two always can). The selected index lives only on the edge: nothing
//! of it is stored.
//!
//! *Claim.* For each robot speed v and true observation (g, w), the guard outcomes these six
//! errors give are exactly the outcomes some real error in [−σ_g, σ_g] × [−σ_w, σ_w] gives —
//! the explorer's `(fire, quiet)` (`explore::observe::choices`) — so the network's runs are
//! the explorer's runs, and its reachable (gap, speed, history) states the same.
//!
//! *Proof.* The guard fires on an observed gap o and speed s iff 0 < o ≤ T, with T = ρ if s
//! is seen above V_a (and the wrong-assumption guard is on) and T = θ(v) = min(ρ, d_coll(v))
//! otherwise; whether s is seen above V_a depends only on the speed error, and both bits
//! the noise allows are among the selected ones. *Fire:* some real o ∈ [l, h] lies in
//! (0, T] iff h > 0, l ≤ T and T > 0. On the grid g, SG — hence l, h — are integers, and
//! the network's comparisons are exact for integer o (o ≤ ⌊ρ·D⌋ ⟺ o ≤ ρ·D, and
//! d_coll is multiplied out). The least positive integer in [l, h], max(l, min(1, h)) when
//! h ≥ 1, fires iff some integer of [l, h] does (the firing set is an interval starting
//! above 0), and some integer of [l, h] lies in (0, T] iff the real condition holds
//! provided every positive threshold T is at least one unit: if l ≥ 1 both say l ≤ T; if
//! l ≤ 0 both say h ≥ 1 and T ≥ 1 (⟺ T > 0). So the grid is refined (D multiplied by
//! ⌈1/(T·D)⌉) until ρ and every positive d_coll(v) over the drive profile are at least one
//! unit — d_coll is nondecreasing in v, and the robot only ever decides at profile speeds.
//! *Quiet:* o ≤ 0, or o > T' (T' = θ(v) if s can be seen at or below V_a, else ρ); some real
//! o ∈ [l, h] does this iff l ≤ 0 or h > T', and for the integer h, h > T' ⟺ h > ⌊T'⌋, so
//! l and h (with the slow bit if allowed) realise it. ∎
//!
//! Without noise, nothing of this is written (no `SG`, `SW`, `slowAt`, select or
//! parameter), so those exports are unchanged.
//!
//! # Occlusion: the first sighting as a choice, lost behaviours blocked
//!
//! With `first_detection_gap` d_det (`DDET` = d_det·D on the grid) the obstacle may stay
//! hidden for any prefix of the observations and is first seen at an observation of a true
//! gap ≥ d_det (docs/semantics.md §12). The network keeps one bit, `seen`. In Accelerate and
//! Drive the robot's decide edges are: *hidden* (`!seen`: nothing is observed, no guard
//! fires), and keep / brake guarded by `shown() && …`, where `shown()` is `seen`, or an
//! observation exists whose true gap `gapAt[L]` is ≥ `DDET` (the environment shows the
//! obstacle now); both set `seen`. These are the explorer's choices at a state: stay
//! hidden, or (where its `may_show` holds) be first seen, then the guard on that
//! observation; once seen, the guard as without occlusion.
//!
//! The explorer leaves out *lost* states — hidden, and no observation to come can show a true
//! gap ≥ d_det — and the steps into them: no behaviour goes through them (docs of
//! `explore`). Gaps never grow, so the first observation to come decides it: after a period
//! that is the one made at the next decision, of `gapAt[L − 1]` (L ≥ 1; the start while
//! fewer than L periods have passed, since the history is initialised with it) or of the
//! gap at the period's end, `gap − dx − w` (L = 0). `lostAfter(dx)` tests exactly that, and
//! the robot's advance edges in Accelerate and Drive (the only modes a hidden obstacle
//! leaves the robot in) are guarded by `!lostAfter(dx)` with their own travel dx, so the
//! network never enters a lost state: the step into it is not taken, and a violation there
//! is never reached. Likewise Init's edge takes only starts ≥ `DDET` (a start below it is
//! lost from the outset). A state the network does reach is on a behaviour of the explorer
//! (its continuation showing the obstacle at the next admissible observation), so the
//! reachable violations, rest gaps and shortest collision periods are the explorer's.
//! Blocking leaves the network in Move with no `advance` partner (a time-lock, not a
//! violation): UPPAAL's `A[]` query is unaffected, and the deadlock is not a behaviour.
//!
//! # Scenes: the seed's whole network
//!
//! [`export_scene`] writes a scene (docs/semantics.md §11) with each obstacle's finite speed
//! set ([`SceneSpeeds`], read from `--speeds` as the scene explorer
//! [`crate::crosscheck::explore::scene`] reads it) as the seed's network of one robot and an
//! array of obstacles:
//!
//! - `Obstacle(const id_t id)`: one template instantiated per obstacle (`typedef int[0, N-1]
//!   id_t`). Init selects its start (its position, or either end of a position range, as the
//!   explorer samples a range); then each period, at its turn, it selects its speed from its
//!   own set `WSET[id * NWMAX + s]` (a static obstacle's set is {0}).
//! - `Robot`: the seed's modes. Each period it decides first (turn 0): `brakeNow()` → Brake,
//!   `swerve()` → `beginChange()` (the lane change of §11.4: lane changes on, none under way,
//!   danger, no wrong assumption, no destination, every dangerous obstacle beyond
//!   d_lc = (v + V_i)·P·dt + buffer, and `laneFree(lane + 1)` else `laneFree(lane - 1)`, the
//!   seed's `otherLaneSafe` with the rear gap), else it keeps its mode; then the obstacles pick
//!   their speeds in id order (turns 1..N); at the period's end (turn N + 1, clock `x == 1`)
//!   it moves, which ends the period for every obstacle (`endPeriod`). A period is a clock
//!   reset, for the interpreter as for UPPAAL. Brake latches; a lane change completes after P
//!   periods (`changing` counts down), braking or not.
//! - Guards, per obstacle i, all multiplied out (no division): `relevant(i)` (its lane is the
//!   robot's (target) lane, observed gap in (0, RHO]); `dangerous(i)` with d_coll for a moving
//!   obstacle and d_static (V_a replaced by `VI[i]` = 0) for a static one; `wrongAssumption()`
//!   (a relevant moving obstacle seen faster than V_a); `nearDestination()`
//!   (`2·BRK·(GOAL − xr) ≤ v·v`). The sensing range needs no test: it is at least ρ, and
//!   every guard reads only gaps ≤ ρ (§11.3).
//! - Safety (§11.6): per obstacle, `side[i]` is the side of the robot's occupancy interval of
//!   its lane (set from the gap as the robot enters the lane, cleared when it leaves), and
//!   every period stores its share: `sep[i]` is the least separation over the period's moving
//!   instants in that lane (the gap at their end when the obstacle was ahead, minus the gap at
//!   the period's start when beside or behind), `attained[i]` whether that least is attained
//!   (not at a rest instant, not at a start at rest). The query excludes, for each obstacle
//!   written out, `share[i] && (sep[i] < CLEARANCE || attained[i] && sep[i] <= CLEARANCE)`.
//!   These are exactly the shares of `SceneWorld::step`.
//! - The network stops (the robot's decision is blocked) at a violation, at rest (Stop), and
//!   when nothing can happen any more (`settled()`, as `SceneWorld::settled`): every run then
//!   ends within the scene explorer's horizon, which bounds the gaps' declared range.
//!
//! **Positions.** The network keeps per-obstacle gaps, as the single-obstacle one does, and the
//! robot's absolute position `xr` only when the scene has a goal. Every guard, the free-lane
//! test and safety read gaps; only the destination guard reads x_r. Absolute obstacle positions
//! would add a subtraction to every test and nothing else, and an `xr` without a goal would
//! only split states that have the same future (the scene explorer drops x_r then, too).
//!
//! **Exact reductions inside the network**, so that UPPAAL's state space shrinks as well: the
//! observation history remembers a gap beyond ρ as ρ + 1 and a speed as faster than V_a only
//! with a gap in (0, ρ] (no guard reads more), and it is cleared once the robot brakes (no
//! guard is evaluated again). The intermediate states of a period (after the robot's decision
//! and each obstacle's choice) remain: on the tests' scenes the network has 4 to 20 times the
//! scene explorer's states.
//!
//! The grid ([`SceneGrid`]) is the single-obstacle grid's construction extended to every
//! obstacle's starts and speeds, the goal and the rear gap; d_lc and the destination guard are
//! products of grid numbers. Numbers or products beyond 32 bits are refused
//! ([`UppaalError::Grid`]).
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
//!
//! # Where things are
//!
//! - `grid`: the exact integer grid (the scale D and the problem's numbers on it);
//! - `syntax`: the network as data — expressions, statements, functions, declarations,
//!   templates;
//! - `network`: a problem's network built as that data: constants, variables, the guard and
//!   motion functions, the `Robot` and `Obstacle` automata, the query's violation;
//! - `printer`: the data printed as UPPAAL's XML and `.q` query;
//! - `machine`: evaluation of the declarations, expressions and statements, with UPPAAL's
//!   range and overflow checks;
//! - `interpreter`: the network's transitions (templates instantiated per parameter value)
//!   and the breadth-first search over them;
//! - `scene_grid`, `scene_network`, `scene_functions`: a scene's grid, its network (constants,
//!   variables, templates, the query) and its functions (guards, safety, period's end,
//!   motion);
//! - `scene_interpreter`: the scene network run by the interpreter ([`explore_scene_grid`]),
//!   held equal to the scene explorer by tests/it/scene_uppaal.rs.

mod grid;
mod interpreter;
mod machine;
mod network;
mod printer;
mod scene_functions;
mod scene_grid;
mod scene_interpreter;
mod scene_network;
mod syntax;

pub use grid::Grid;
pub use interpreter::{GridExploration, explore_grid};
pub use printer::{declarations_text, query_formula, query_text, xml_text};
pub use scene_grid::{ObstacleGrid, SceneGrid};
pub use scene_interpreter::{SceneGridExploration, explore_scene_grid};
pub use syntax::{
    Decl, Dir, Edge, Expr, Function, Kind, Location, Network, Op, Param, Stmt, Template, Ty,
};

use crate::core::model::Problem;
use crate::core::num::Exact;
use crate::core::scene::Scene;
use crate::crosscheck::explore::scene::SceneSpeeds;
use crate::crosscheck::explore::{DEFAULT_STARTS, SpeedSet};

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

/// Exports a (validated) problem with obstacle speeds from `speeds` (and for a range of
/// initial gaps, the explorer's default starts).
pub fn export(problem: &Problem, speeds: &SpeedSet) -> Result<UppaalModel, UppaalError> {
    export_with_starts(problem, speeds, DEFAULT_STARTS)
}

/// As [`export`], with `starts` evenly spaced starts in a range of initial gaps, both ends
/// included: the set `explore --starts` explores (a single initial gap is its only start).
pub fn export_with_starts(
    problem: &Problem,
    speeds: &SpeedSet,
    starts: usize,
) -> Result<UppaalModel, UppaalError> {
    let grid = Grid::with_starts(problem, speeds, starts)?;
    let network = network::network(problem, &grid, speeds);
    let xml = xml_text(&network);
    let query = query_text(&network);
    Ok(UppaalModel {
        grid,
        network,
        xml,
        query,
    })
}

/// An exported scene.
#[derive(Clone, Debug)]
pub struct SceneUppaalModel {
    /// The grid.
    pub grid: SceneGrid,
    /// The network as data.
    pub network: Network,
    /// The UPPAAL XML file.
    pub xml: String,
    /// The query file.
    pub query: String,
}

/// Exports a (validated) scene with each obstacle's speeds from `speeds` (as the scene
/// explorer reads `--speeds`).
pub fn export_scene(scene: &Scene, speeds: &SceneSpeeds) -> Result<SceneUppaalModel, UppaalError> {
    let params = scene.params::<Exact>();
    if params.robot.noisy() || params.robot.d_det.is_some() {
        return Err(UppaalError::Grid(
            "the scene export models exact observations of obstacles visible from the start; \
             the [sensing] settings are not exported yet"
                .into(),
        ));
    }
    let grid = SceneGrid::new(&params, speeds)?;
    let network = scene_network::scene_network(&scene.name, &params, &grid, speeds);
    let xml = xml_text(&network);
    let query = query_text(&network);
    Ok(SceneUppaalModel {
        grid,
        network,
        xml,
        query,
    })
}
