//! The runtime monitor: checks, sample by sample, that the premises a certificate was proved
//! under still hold on the running robot (DESIGN.md §3).
//!
//! A certificate says "passively safe, *provided that* obstacles move at most at W, the robot
//! brakes at least at b, the controller runs every dt, …". Nothing in the proof protects the
//! robot once one of those premises fails, so the monitor watches them on the live trace and
//! says the moment one breaks, with the action `brake`: enter the passive safe state (stop;
//! being hit while standing still is not the robot's fault).
//!
//! # Using it
//!
//! [`Monitor::new`] takes a certificate, runs [`certificate::check`] on it (an invalid
//! certificate is never monitored against), refuses certificates whose verdict is not
//! `certified` (their premises holding would guarantee nothing) and reads the bounds from the
//! certificate's premises. Then [`Monitor::observe`] takes one [`Sample`] at a time and
//! returns an [`Outcome`]: the standing [`Verdict`] and the [`Event`]s this sample raised.
//!
//! ```
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! # let cert_json = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/seed.cert.json");
//! use safereach::proof::certificate::Certificate;
//! use safereach::monitor::{Monitor, Sample, Verdict};
//! use safereach::core::semantics::Mode;
//!
//! // The seed's certificate: obstacles no faster than W = 0.15 m/s.
//! let text = std::fs::read_to_string(cert_json)?;
//! let cert: Certificate = serde_json::from_str(&text)?;
//! let mut monitor = Monitor::new(&cert)?;
//! let sample = Sample {
//!     t: 12.3,
//!     robot_x: 2.1,
//!     robot_v: 0.2,
//!     robot_mode: Some(Mode::Drive),
//!     obstacle_id: 0,
//!     obstacle_x: 9.4,
//!     obstacle_v: Some(0.25),
//!     obstacle_t: None,
//! };
//! let outcome = monitor.observe(&sample);
//! for event in outcome.events {
//!     eprintln!("{event}"); // obstacle_speed observed 0.25 m/s > bound 0.15 m/s -> brake
//! }
//! if outcome.verdict == Verdict::Violated {
//!     // command the passive safe state: brake to a stop
//! }
//! assert_eq!(outcome.verdict, Verdict::Violated);
//! # Ok(()) }
//! ```
//!
//! It is built for a robot's control loop: `observe` does no I/O, never panics and never
//! allocates (the events of a sample live in a small buffer inside the monitor, which the
//! returned [`Outcome`] borrows). Memory is constant per obstacle: one small record in a table
//! indexed by the obstacle's integer id, so ids should be small and dense (0, 1, 2, …);
//! [`Monitor::with_max_obstacles`] sizes the table once, up front, for a loop that must
//! never allocate. Text traces are read by [`trace`], which maps textual ids to integers.
//!
//! # What is checked
//!
//! Each check has a stable name ([`Check`]), used as `premise` in events:
//!
//! | name | violated when | observed | bound |
//! | --- | --- | --- | --- |
//! | `obstacle_speed` | the obstacle's speed towards the robot exceeds its bound: `obstacle_v` above W + σ_w, or the speed estimated from its previous position above W + 2σ_g/Δt (across a dropout over the whole gap: a reappearing obstacle must have been able to get there); a static obstacle stated faster than σ_w | speed (m/s) | W |
//! | `braking_deceleration` | after a sample in mode `brake` with the robot moving, the robot is still moving at the next instant and slowed by less than b_min·Δt | (v₀ − v₁)/Δt (m/s²) | b_min |
//! | `control_period` | two successive instants are more than dt apart (an obstacle missing from an instant is a dropout, below) | Δt (s) | dt |
//! | `latency` | (samples with `obstacle_t` only) the observation is older than L periods: (t − obstacle_t)/dt > L | age (periods) | L |
//! | `first_detection_gap` | an obstacle is first seen at a gap obstacle_x − robot_x below ρ − σ_g (it appeared inside the reaction radius) | gap (m) | ρ |
//! | `observation_noise`, `speed_noise` | never by themselves (errors need the true positions, which a trace of observations does not carry); σ_g and σ_w widen the other checks | | σ |
//!
//! and the model's behaviour checks (ModelPlex's controller and safety monitors):
//!
//! | name | violated when |
//! | --- | --- |
//! | `observation_inconsistent` | a stated speed and the speed from the obstacle's last two positions differ by more than σ_w + 2σ_g/Δt (plus rounding) |
//! | `observation_dropout` | an obstacle last seen inside the reaction area is missing from a later instant |
//! | `controller_reaction` | (with `robot_mode`) the robot is not braking (in scenes: nor changing lanes or out of the obstacle's lane) at the instant its observation shows danger for every gap within σ_g, or a wrong assumption |
//! | `robot_envelope` | the robot's speed above v_max, or its acceleration above a, beyond the stated tolerance |
//! | `robot_motion` | the robot's displacement between instants beyond the most, or below the least, that its two speeds, its mode and a, b, v_max allow (a robot in `stop` or `idle` does not move) |
//! | `collision` | the robot moving with a gap ≤ clearance (noise in the robot's favour), at an instant or, with the worst motion the premises allow, within the step before it (it moved, by its speed or its positions, and came to rest): the gravest event, reported even when every premise held |
//!
//! and four fail-safe checks on the input itself; a sample that fails one is reported and
//! otherwise ignored (it changes no state), and the monitor goes on:
//!
//! | name | violated when |
//! | --- | --- |
//! | `malformed_sample` | the input could not be read as a sample (reported by the reader through [`Monitor::malformed`]), an obstacle id beyond the table, or a sample whose robot state differs from the first sample of the same instant |
//! | `non_finite` | a number is NaN or infinite |
//! | `time_backwards` | t is earlier than the current instant (observed t, bound the instant's t) |
//! | `duplicate_sample` | the same obstacle twice at the same instant (observed: its t) |
//!
//! **Instants.** Samples with equal `t` form one instant: the robot's control step, at which
//! it sees several obstacles. Within an instant obstacles come in any order, each at most once,
//! all with the same robot state; instants come in order of increasing `t`.
//! Robot checks (`control_period` between instants, `braking_deceleration`,
//! `robot_envelope`, `robot_motion`) run on the first sample of each instant, obstacle checks
//! on every sample.
//!
//! An obstacle is checked against ρ at its first sighting only. One that drops out of the
//! trace while outside the reaction area is fine; inside it, the missed instant is an
//! `observation_dropout`. Robot-only instants (no obstacle in view) are [`RobotSample`]s.
//!
//! **Tolerances.** A value the trace states (`obstacle_v`) is compared with its bound exactly.
//! Values the monitor derives by subtraction and division (an estimated speed, a
//! deceleration, a time step, a gap, an observation age) carry the rounding error of the
//! numbers they come from; they are compared with the bound widened by
//! [`RELATIVE_TOLERANCE`] (one part in 10⁹) of the bound plus the worst-case rounding error
//! of the computation, 8ε·(|a₀| + |a₁|)/Δ for a difference of a₀ and a₁ over Δ (ε the machine
//! epsilon). An estimated speed is further widened by 2σ/Δt, the most that observation noise
//! σ (the certificate's `observation_noise`) can add. So a trace written with full
//! precision (as `simulate --trace` does) never raises a false alarm, and a physically
//! meaningful violation is never hidden. A trace that rounds positions (to a millimetre,
//! say) carries an error the certificate did not allow for (σ = 0): give `obstacle_v`, or
//! expect estimated speeds to be flagged.
//!
//! After the first violation the verdict stays [`Verdict::Violated`] (the robot may not have
//! obeyed), but every later violation is still reported.
//!
//! # Scene certificates
//!
//! [`Monitor::for_scene`] (or [`Monitor::for_certificate_file`], either kind) monitors a
//! [`SceneCertificate`](crate::proof::scene_certificate::SceneCertificate): it runs
//! [`check_scene`](crate::proof::scene_check::check_scene), requires `certified`, and checks
//! the premises per obstacle. A trace obstacle matched to one of the scene's obstacles by
//! name ([`Monitor::identify`]; [`Monitor::observe_decoded`] does it for text traces) is
//! checked against that obstacle's own W_i, and must stay in its certified lane
//! (`obstacle_lane`); a static one must not move at all (`static_obstacle`: its stated speed
//! and the speed its positions imply, either way, at most what observation noise allows).
//! Any other tracked object is checked against the scene's largest moving bound (the
//! premises' W), in any lane. A scene monitor also checks safety itself: `collision`, the
//! robot moving at a separation ≤ clearance from an obstacle in a lane it occupies. Lanes
//! come with [`Monitor::observe_in_lanes`] ([`Lanes`]); without them every obstacle counts
//! as in the robot's lane. A single-obstacle certificate's monitor runs none of these
//! checks, and its output is as it always was.
//!
//! | name | violated when | observed | bound |
//! | --- | --- | --- | --- |
//! | `static_obstacle` | a static obstacle's \|speed\| exceeds 2σ/Δt (stated: exactly; estimated: plus rounding) | \|speed\| (m/s) | 2σ/Δt |
//! | `obstacle_lane` | a named obstacle's `obstacle_lane` differs from its certified lane | lane | certified lane |
//! | `collision` | `robot_v` > 0 and the separation (the gap, or minus the gap for an obstacle beside or behind when the robot entered its lane) ≤ clearance, less rounding | separation (m) | clearance |
//!
//! # Planar certificates
//!
//! [`planar::PlanarMonitor`] monitors a planar certificate's premises on traces in the plane
//! (robot and obstacle centres), with the same [`Event`]s and [`Summary`] (its `plane` part
//! added) and the planar checks [`PlaneCheck`]; `Monitor` refuses planar certificates
//! ([`MonitorError::Planar`]).
//!
//! # Where things are
//!
//! The premises are the certificate's typed list,
//! [`PremiseKind`](crate::proof::premise::PremiseKind); each is checked in `check/` by the
//! file of its idea (`obstacle.rs`, `timing.rs`, `braking.rs`; the fail-safe checks in
//! `input.rs`), next to its row of units and reasons. Every per-check table is indexed by
//! [`Check::index`]. Adding a premise is its variant in `proof/premise.rs`, its field in
//! [`Bounds`], and its check. Events are built with a small `Violation` builder
//! (`event.rs`); the end-of-trace [`Summary`] is in `summary.rs`; text traces are read by
//! [`trace`].

use crate::core::model::{Params, Problem};
use crate::core::semantics::Mode;
use crate::proof::certificate::{self, Certificate};
use crate::proof::premise::Premise;
use crate::proof::verdict;

#[cfg(feature = "bag")]
pub mod bag;
mod check;
mod event;
mod field;
mod lanes;
pub mod planar;
mod region;
mod scene;
mod summary;
pub mod trace;

pub use check::{BehaviourCheck, Bounds, Check, FailSafe, PlaneCheck, SceneCheck};
use check::{Carried, Fast, Motion};
use event::Violation;
pub use event::{Action, Detail, Event, Outcome, Verdict};
pub use field::Field;
pub use lanes::Lanes;
pub use region::{RegionPoint, planar_region_certificate};
use scene::SceneAssumptions;
pub use summary::{
    CertifiedObstacleSummary, CheckSummary, FailSafeSummary, Margin, PremiseSummary,
    SceneCheckSummary, SceneSummary, Status, Summary,
};

/// An obstacle's number: an index into the monitor's table (keep them small and dense).
pub type ObstacleId = u32;

/// Relative widening of a bound for values the monitor derives by arithmetic.
pub const RELATIVE_TOLERANCE: f64 = 1e-9;

/// The table size [`Monitor::new`] allows: obstacle ids must be below this.
pub const DEFAULT_MAX_OBSTACLES: u32 = 1 << 16;

/// Most events one sample's [`Outcome`] lists. A dozen checks can fail on one sample, and a
/// new instant can find several obstacles missing; events beyond this are still counted
/// (and the first violation kept), only not listed.
pub const MAX_EVENTS_PER_SAMPLE: usize = 16;

/// The obstacle id of a robot-only sample inside the monitor (never an index into its
/// table; events of such a sample have no obstacle).
pub(crate) const ROBOT_ONLY: ObstacleId = ObstacleId::MAX;

/// One line of a trace: the robot and one obstacle at an instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Time (s).
    pub t: f64,
    /// Robot position along its lane (m).
    pub robot_x: f64,
    /// Robot speed (m/s).
    pub robot_v: f64,
    /// The robot's mode from this instant on, if the trace records it.
    pub robot_mode: Option<Mode>,
    /// Which obstacle (an index into the monitor's table).
    pub obstacle_id: ObstacleId,
    /// Observed obstacle position along the robot's lane (m); gap = obstacle_x − robot_x.
    pub obstacle_x: f64,
    /// Observed obstacle speed towards the robot over the period that ends at `t` (m/s);
    /// `None`: the monitor estimates it from successive positions.
    pub obstacle_v: Option<f64>,
    /// Time at which `obstacle_x` was observed (s); when present, latency is checked and
    /// speeds are estimated over observation times.
    pub obstacle_t: Option<f64>,
}

/// A trace line with the robot only: an instant at which no obstacle was observed (its
/// obstacle cells empty).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RobotSample {
    /// Time (s).
    pub t: f64,
    /// Robot position along its lane (m).
    pub robot_x: f64,
    /// Robot speed (m/s).
    pub robot_v: f64,
    /// The robot's mode from this instant on, if the trace records it.
    pub robot_mode: Option<Mode>,
}

impl RobotSample {
    /// As a [`Sample`] whose obstacle is [`ROBOT_ONLY`] (for the checks of the robot).
    fn as_sample(&self) -> Sample {
        Sample {
            t: self.t,
            robot_x: self.robot_x,
            robot_v: self.robot_v,
            robot_mode: self.robot_mode,
            obstacle_id: ROBOT_ONLY,
            obstacle_x: 0.0,
            obstacle_v: None,
            obstacle_t: None,
        }
    }
}

/// Why a certificate cannot be monitored against.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MonitorError {
    /// The certificate fails `check` (the reason is part of the message, not a `source`).
    #[error("the certificate does not verify: {0}")]
    Invalid(certificate::Invalid),
    /// The certificate is valid but does not certify safety: its premises holding would
    /// guarantee nothing.
    #[error(
        "the certificate's verdict is {}, not certified: there is no safety proof whose premises could be monitored",
        .0.as_str()
    )]
    NotCertified(verdict::Verdict),
    /// A premise the monitor needs is not in the certificate.
    #[error("the certificate lists no `{0}` premise")]
    MissingPremise(&'static str),
    /// A premise's bound is unusable (non-finite, negative, or a zero control period).
    #[error("premise `{name}` has an unusable bound {bound}")]
    BadBound {
        /// The premise.
        name: &'static str,
        /// Its bound.
        bound: f64,
    },
    /// A region map cannot be monitored as asked (no certified box chosen, or a controller
    /// value missing or outside the box).
    #[error("{0}")]
    Region(String),
    /// A planar certificate given to the line's monitor: [`planar::PlanarMonitor`] checks
    /// those.
    #[error(
        "the certificate is for a planar problem: its traces are checked by the planar monitor (monitor::planar::PlanarMonitor)"
    )]
    Planar,
}

/// Refuses a verdict other than `certified`: its premises holding would guarantee nothing.
fn require_certified(verdict: verdict::Verdict) -> Result<(), MonitorError> {
    if verdict == verdict::Verdict::Certified {
        Ok(())
    } else {
        Err(MonitorError::NotCertified(verdict))
    }
}

impl From<certificate::Invalid> for MonitorError {
    fn from(e: certificate::Invalid) -> Self {
        MonitorError::Invalid(e)
    }
}

/// What the monitor remembers about one obstacle.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Track {
    /// Seen at least once.
    seen: bool,
    /// The last sample had `obstacle_t`.
    has_obs_t: bool,
    /// Instant number of its last sample.
    instant: u64,
    /// Time of its last sample.
    t: f64,
    /// Observation time of its last sample (if `has_obs_t`).
    obs_t: f64,
    /// Position at its last sample.
    x: f64,
    /// The scene certificate's obstacle it is, once [`Monitor::identify`] matched it: its
    /// index + 1 (non-zero, so that the record stays as small as before scenes).
    certified: Option<std::num::NonZeroU32>,
    /// [`Monitor::identify`] has looked its name up.
    named: bool,
    /// Whether it was ahead of the robot (gap > 0) when its lane last became one the robot
    /// occupies (`None`: the robot is not in its lane); the side `collision` measures from.
    ahead: Option<bool>,
    /// Its last observation was inside the reaction area, 0 < gap ≤ ρ (`observation_dropout`
    /// if the next instant comes without it).
    in_area: bool,
    /// Gap at its last observation (m).
    gap: f64,
}

impl Track {
    /// Index of the scene obstacle it was matched to.
    #[inline]
    pub(crate) fn certified_index(&self) -> Option<usize> {
        self.certified.map(|i| i.get() as usize - 1)
    }
}

/// The robot's state at the current instant.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RobotAt {
    t: f64,
    x: f64,
    v: f64,
    mode: Option<Mode>,
}

/// What the certified controller and robot are: the numbers the controller and safety checks
/// use, read from the certificate's problem (or scene).
#[derive(Clone, Debug)]
pub(crate) struct Rule {
    /// The controller for moving obstacles (v_max, a, b, L, ρ, V_a, the danger rule, …).
    pub(crate) moving: Params<f64>,
    /// The same with V_a = 0: the danger rule for a scene's static obstacles.
    pub(crate) fixed: Params<f64>,
    /// `collision`: a separation at most this while moving (m).
    pub(crate) clearance: f64,
}

impl Rule {
    /// The rule of a single-obstacle problem.
    fn of_problem(problem: &Problem) -> Rule {
        let moving: Params<f64> = problem.params();
        let mut fixed = moving.clone();
        fixed.V_a = 0.0;
        Rule {
            clearance: problem.robot.clearance,
            moving,
            fixed,
        }
    }
}

/// A reaction the controller owes: an observation showed danger (or a wrong assumption), and
/// the robot must be braking by the instant the controller has that observation.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Reaction {
    /// The time by which the controller has the observation (s).
    due: f64,
    /// Whose observation it was.
    obstacle: ObstacleId,
    /// The observed gap (m) and the distance within which it is danger (m).
    gap: f64,
    bound: f64,
    /// The obstacle's lane, when known: a robot that left that lane has reacted.
    lane: Option<i32>,
    /// It was a wrong assumption (an obstacle faster than V_a), not danger.
    wrong: bool,
}

/// The runtime monitor for one certificate (see the module docs).
#[derive(Clone, Debug)]
pub struct Monitor {
    bounds: Bounds,
    /// What the per-sample checks derive from `bounds`, computed once.
    fast: Fast,
    /// The certified controller and robot.
    rule: Rule,
    /// min(ρ, d(v)) at the current instant's robot speed: for moving obstacles, and for a
    /// scene's static ones (m).
    reaction_distance: [f64; 2],
    /// The robot speed `reaction_distance` was computed for (NaN: none yet).
    reaction_speed: f64,
    /// The earliest reaction owed, if any.
    reaction: Option<Reaction>,
    /// Obstacles seen inside the reaction area at the current instant, at the previous one,
    /// and how many of the previous one's have been seen again at the current one.
    area_now: u32,
    area_previous: u32,
    area_previous_seen: u32,
    /// The smallest slack of each check so far, by [`Check::index`].
    margins: [Margin; Check::COUNT],
    /// What a scene certificate assumed of each of its obstacles (`None`: a single-obstacle
    /// certificate, monitored exactly as before scenes existed).
    scene: Option<SceneAssumptions>,
    /// Obstacle ids must be below this.
    max_obstacles: u32,
    obstacles: Vec<Track>,
    /// The current instant, once there is one.
    robot: Option<RobotAt>,
    /// What the robot's motion over the step that ended at the current instant showed.
    motion: Motion,
    /// The robot's lanes at the current instant (`robot`, `leaving`), as far as its samples
    /// state them; kept by a scene certificate's monitor only.
    robot_lanes: Lanes,
    /// Number of the current instant (0-based).
    instant: u64,
    samples: u64,
    distinct_obstacles: u64,
    /// Evaluations of each check, by [`Check::index`].
    checks: [u64; Check::COUNT],
    /// Violations of each check, by [`Check::index`].
    violations: [u64; Check::COUNT],
    /// Accepted samples (those that reached the checks), robot-only ones included.
    accepted: u64,
    first: Option<Event>,
    /// What the samples carried so far.
    carried: Carried,
    events: [Event; MAX_EVENTS_PER_SAMPLE],
    n_events: usize,
}

const NO_EVENT: Event = Event {
    sample: 0,
    t: None,
    obstacle_id: None,
    check: Check::MalformedSample,
    observed: None,
    bound: None,
    action: Action::Brake,
    detail: None,
};

impl Monitor {
    /// A monitor for `cert`: runs [`certificate::check`], requires the verdict `certified`,
    /// reads the bounds from the premises. Obstacle ids must be below
    /// [`DEFAULT_MAX_OBSTACLES`]; the table grows (allocates) on a new largest id.
    pub fn new(cert: &Certificate) -> Result<Monitor, MonitorError> {
        Self::build(cert, DEFAULT_MAX_OBSTACLES, 0)
    }

    /// A monitor whose obstacle table is allocated once, for ids `0..max_obstacles`: it never
    /// allocates again. A sample with a larger id is `malformed_sample`.
    pub fn with_max_obstacles(
        cert: &Certificate,
        max_obstacles: u32,
    ) -> Result<Monitor, MonitorError> {
        Self::build(cert, max_obstacles, max_obstacles as usize)
    }

    fn build(
        cert: &Certificate,
        max_obstacles: u32,
        reserve: usize,
    ) -> Result<Monitor, MonitorError> {
        let report = certificate::check(cert)?;
        require_certified(report.verdict)?;
        let bounds = Bounds::from_premises(&cert.premises)?;
        let rule = Rule::of_problem(&cert.problem);
        Ok(Self::with_bounds(
            bounds,
            rule,
            None,
            max_obstacles,
            reserve,
        ))
    }

    /// A monitor for `problem` as if it had been certified under `premises`, without a
    /// certificate: **no proof is checked**, so the caller vouches that a proof exists (it is
    /// for experiments and tests, e.g. premises with observation noise before the analyser
    /// certifies noisy problems). The bounds come from `premises` as from a certificate's;
    /// the controller, v_max, a and the clearance from `problem`.
    pub fn for_premises(problem: &Problem, premises: &[Premise]) -> Result<Monitor, MonitorError> {
        let bounds = Bounds::from_premises(premises)?;
        let rule = Rule::of_problem(problem);
        Ok(Self::with_bounds(
            bounds,
            rule,
            None,
            DEFAULT_MAX_OBSTACLES,
            0,
        ))
    }

    /// A monitor for checked bounds (and a scene's assumptions), before any sample.
    fn with_bounds(
        bounds: Bounds,
        rule: Rule,
        scene: Option<SceneAssumptions>,
        max_obstacles: u32,
        reserve: usize,
    ) -> Monitor {
        Monitor {
            fast: Fast::of(&bounds),
            bounds,
            reaction_distance: [0.0; 2],
            reaction_speed: f64::NAN,
            reaction: None,
            area_now: 0,
            area_previous: 0,
            area_previous_seen: 0,
            margins: [Margin::NONE; Check::COUNT],
            rule,
            scene,
            max_obstacles,
            obstacles: vec![Track::default(); reserve],
            robot: None,
            motion: Motion::NONE,
            robot_lanes: Lanes::UNKNOWN,
            instant: 0,
            samples: 0,
            distinct_obstacles: 0,
            checks: [0; Check::COUNT],
            violations: [0; Check::COUNT],
            accepted: 0,
            first: None,
            carried: Carried::default(),
            events: [NO_EVENT; MAX_EVENTS_PER_SAMPLE],
            n_events: 0,
        }
    }

    /// The bounds being checked.
    pub fn bounds(&self) -> &Bounds {
        &self.bounds
    }

    /// The standing verdict.
    pub fn verdict(&self) -> Verdict {
        if self.first.is_some() {
            Verdict::Violated
        } else {
            Verdict::Held
        }
    }

    /// The first violation, if any.
    pub fn first_violation(&self) -> Option<&Event> {
        self.first.as_ref()
    }

    /// Samples fed so far (malformed ones included).
    pub fn samples(&self) -> u64 {
        self.samples
    }

    /// Violations of `check` so far.
    pub fn violations(&self, check: Check) -> u64 {
        self.violations[check.index()]
    }

    /// Times `check` was evaluated so far.
    pub fn checks(&self, check: Check) -> u64 {
        self.checks[check.index()]
    }

    /// The events of the last sample.
    pub fn events(&self) -> &[Event] {
        &self.events[..self.n_events]
    }

    fn outcome(&self) -> Outcome<'_> {
        Outcome {
            verdict: self.verdict(),
            events: &self.events[..self.n_events],
        }
    }

    /// Counts an evaluation of `check`.
    #[inline]
    fn count(&mut self, check: Check) {
        self.checks[check.index()] += 1;
    }

    /// Counts an evaluation of `check` whose slack (how far the observed value is from
    /// breaking the bound, in the check's unit) was `slack`, at the current sample of time
    /// `t`; keeps the smallest.
    #[inline(always)]
    fn count_with_slack(&mut self, check: Check, slack: f64, t: f64) {
        let i = check.index();
        self.checks[i] += 1;
        if slack < self.margins[i].slack {
            self.margins[i] = Margin {
                slack,
                t,
                sample: self.samples - 1,
            };
        }
    }

    /// Whether any sample reached the checks (an empty trace, or one of only unreadable
    /// lines, checked nothing).
    pub fn checked_anything(&self) -> bool {
        self.accepted > 0
    }

    /// Records a violation of the current sample.
    #[cold]
    #[inline(never)]
    fn raise(&mut self, violation: Violation) {
        let event = violation.event(self.samples - 1);
        self.violations[violation.check.index()] += 1;
        if !violation.check.is_fail_safe() {
            self.count_for_certified(violation.obstacle_id);
        }
        if self.first.is_none() {
            self.first = Some(event);
        }
        // Beyond the buffer an event is counted, not listed (see MAX_EVENTS_PER_SAMPLE).
        if let Some(slot) = self.events.get_mut(self.n_events) {
            *slot = event;
            self.n_events += 1;
        }
    }

    /// Records input that could not be read as a sample (a `malformed_sample`, or with
    /// [`Detail::NonFinite`] a `non_finite` one); `t` is the sample's time if it was read.
    /// It counts as a sample and changes no other state.
    pub fn malformed(&mut self, t: Option<f64>, detail: Detail) -> Outcome<'_> {
        self.n_events = 0;
        self.samples += 1;
        let check = match detail {
            Detail::NonFinite(_) => Check::NonFinite,
            _ => Check::MalformedSample,
        };
        self.count(check);
        let t = t.filter(|t| t.is_finite());
        self.raise(Violation::of_input(check, t, None).detail(detail));
        self.outcome()
    }

    /// Checks one sample (see the module docs for the checks and their order: fail-safe
    /// checks first, which reject the sample; then, on the first sample of an instant,
    /// `control_period` between instants and `braking_deceleration`; then the obstacle's
    /// `first_detection_gap` or its own `control_period`, `latency`, `obstacle_speed` — or
    /// `static_obstacle` for a scene's static obstacle — and under a scene certificate
    /// `obstacle_lane` and `collision`).
    ///
    /// No I/O, no allocation (except growing the table of [`Monitor::new`] on a new largest
    /// obstacle id), no panic. The sample states no lanes; see [`Monitor::observe_in_lanes`].
    pub fn observe(&mut self, s: &Sample) -> Outcome<'_> {
        if self.scene.is_some() {
            self.observe_with::<true>(s, Lanes::UNKNOWN);
        } else {
            self.observe_with::<false>(s, Lanes::UNKNOWN);
        }
        self.outcome()
    }

    /// Checks `samples` in order, exactly as [`Monitor::observe`] one at a time would, and
    /// calls `on_event(i, event)` for each event that `samples[i]` raised. Returns the
    /// verdict after the last sample. For a robot that logs or receives its samples in
    /// blocks (a bag, a message with several detections): the per-call work — the choice
    /// between a scene's and a single obstacle's checks, the return of an [`Outcome`] — is
    /// done once per block, not per sample. No I/O, no allocation, no panic, as `observe`.
    pub fn observe_all(
        &mut self,
        samples: &[Sample],
        on_event: impl FnMut(usize, &Event),
    ) -> Verdict {
        if self.scene.is_some() {
            self.observe_all_with::<true>(samples, on_event)
        } else {
            self.observe_all_with::<false>(samples, on_event)
        }
    }

    fn observe_all_with<const SCENE: bool>(
        &mut self,
        samples: &[Sample],
        mut on_event: impl FnMut(usize, &Event),
    ) -> Verdict {
        for (i, s) in samples.iter().enumerate() {
            self.observe_with::<SCENE>(s, Lanes::UNKNOWN);
            for event in &self.events[..self.n_events] {
                on_event(i, event);
            }
        }
        self.verdict()
    }

    /// [`Monitor::observe`] for a sample of a scene trace, which states `lanes`: the robot's
    /// (part of its state at the instant, like its mode) and the obstacle's. A scene
    /// certificate's monitor uses them in `obstacle_lane` and `collision`, and rejects a
    /// sample whose robot lanes differ from its instant's; a single-obstacle certificate's
    /// ignores them.
    pub fn observe_in_lanes(&mut self, s: &Sample, lanes: Lanes) -> Outcome<'_> {
        if self.scene.is_some() {
            self.observe_with::<true>(s, lanes);
        } else {
            self.observe_with::<false>(s, lanes);
        }
        self.outcome()
    }

    /// The body of [`Monitor::observe`] and [`Monitor::observe_in_lanes`], in two copies: a
    /// scene certificate's (`SCENE`), and a single obstacle's, which runs exactly the checks
    /// it ran before scenes existed and pays nothing for them.
    #[inline(always)]
    fn observe_with<const SCENE: bool>(&mut self, s: &Sample, lanes: Lanes) {
        self.n_events = 0;
        self.samples += 1;
        // Fail safe: reject what cannot be trusted, before it touches any state.
        let Some(track) = self.admit(s) else {
            return;
        };
        match self.robot {
            Some(r) if s.t <= r.t => {
                if !self.join_instant::<SCENE>(s, lanes, r, Some(&track)) {
                    return;
                }
            }
            previous => self.start_instant::<SCENE>(previous, s, lanes),
        }
        self.accepted += 1;
        self.carried.mode |= s.robot_mode.is_some();
        self.check_obstacle::<SCENE>(s, lanes, &track);
    }

    /// Checks a robot-only sample: an instant at which no obstacle was observed. It counts
    /// as an instant (for `control_period`, `braking_deceleration`, `robot_envelope`,
    /// `controller_reaction` and `observation_dropout`); `lanes` are the robot's, as in
    /// [`Monitor::observe_in_lanes`]. No allocation, no panic.
    pub fn observe_robot(&mut self, r: &RobotSample, lanes: Lanes) -> Outcome<'_> {
        if self.scene.is_some() {
            self.observe_robot_with::<true>(r, lanes)
        } else {
            self.observe_robot_with::<false>(r, lanes)
        }
    }

    fn observe_robot_with<const SCENE: bool>(
        &mut self,
        r: &RobotSample,
        lanes: Lanes,
    ) -> Outcome<'_> {
        self.n_events = 0;
        self.samples += 1;
        let s = r.as_sample();
        if !self.admit_robot(&s) {
            return self.outcome();
        }
        match self.robot {
            Some(current) if s.t <= current.t => {
                if !self.join_instant::<SCENE>(&s, lanes, current, None) {
                    return self.outcome();
                }
            }
            previous => self.start_instant::<SCENE>(previous, &s, lanes),
        }
        self.accepted += 1;
        self.carried.mode |= s.robot_mode.is_some();
        self.outcome()
    }

    /// The first sample of a new instant: the robot's checks over the step from the previous
    /// instant (`control_period`, `braking_deceleration`), then the robot's new state.
    #[inline(always)]
    fn start_instant<const SCENE: bool>(
        &mut self,
        previous: Option<RobotAt>,
        s: &Sample,
        lanes: Lanes,
    ) {
        if let Some(r) = previous {
            self.check_period(r.t, s);
            let braked = self.check_braking(&r, s);
            let accelerated = self.check_acceleration(&r, s);
            self.check_motion(&r, s, braked, accelerated);
            self.check_dropouts(s);
            self.instant += 1;
        }
        self.robot = Some(RobotAt {
            t: s.t,
            x: s.robot_x,
            v: s.robot_v,
            mode: s.robot_mode,
        });
        if SCENE {
            self.robot_lanes = Lanes {
                obstacle: None,
                ..lanes
            };
        }
        self.check_top_speed(s);
        self.set_reaction_distance(s.robot_v);
        self.check_reaction_due::<SCENE>(s);
    }

    /// The obstacle's checks: `first_detection_gap` at its first sighting; `latency`;
    /// `obstacle_speed` and `observation_inconsistent` (or `static_obstacle`); under a scene
    /// certificate `obstacle_lane`; `collision`; whether it shows danger
    /// (`controller_reaction`). Then its record.
    #[inline(always)]
    fn check_obstacle<const SCENE: bool>(&mut self, s: &Sample, lanes: Lanes, track: &Track) {
        if !track.seen {
            self.distinct_obstacles += 1;
            self.check_first_sighting(s);
        } else if track.in_area && track.instant + 1 == self.instant {
            self.area_previous_seen += 1;
        }
        if let Some(obs_t) = s.obstacle_t {
            self.carried.observation_time = true;
            self.check_latency(s, obs_t);
        }
        self.carried.obstacle_speed |= s.obstacle_v.is_some();
        let (speed, view, fixed) = if SCENE {
            let certified = self.certified(track);
            let fixed = certified.is_some_and(|o| o.is_static);
            let speed = if fixed {
                self.check_static(s, track)
            } else {
                self.check_obstacle_speed(s, track, certified)
            };
            (speed, self.check_lanes(s, lanes, track, certified), fixed)
        } else {
            let speed = self.check_obstacle_speed(s, track, None);
            (speed, self.check_collision_ahead(s, track), false)
        };
        let gap = s.obstacle_x - s.robot_x;
        let in_area = gap > 0.0 && gap <= self.rule.moving.rho;
        self.area_now += u32::from(in_area);
        if view.relevant {
            self.check_danger(s, gap, speed.slowest, view.lane, fixed);
        }
        let ahead = view.ahead;
        let keep_reference = speed.keep_reference;
        let slot = &mut self.obstacles[s.obstacle_id as usize];
        slot.seen = true;
        slot.instant = self.instant;
        slot.t = s.t;
        slot.in_area = in_area;
        slot.gap = gap;
        slot.ahead = ahead;
        if !keep_reference {
            slot.x = s.obstacle_x;
            slot.has_obs_t = s.obstacle_t.is_some();
            slot.obs_t = s.obstacle_t.unwrap_or(0.0);
        }
    }
}
