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
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! use safereach::proof::certificate::Certificate;
//! use safereach::monitor::{Monitor, Sample, Verdict};
//! use safereach::core::semantics::Mode;
//!
//! let text = std::fs::read_to_string("cert.json")?;
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
//!     eprintln!("{event}"); // obstacle_speed observed 0.25 m/s > bound 0.2 m/s -> brake
//! }
//! if outcome.verdict == Verdict::Violated {
//!     // command the passive safe state: brake to a stop
//! }
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
//! | `obstacle_speed` | the obstacle's speed towards the robot exceeds W: `obstacle_v` when the sample has it, else estimated from this and the obstacle's previous position | speed (m/s) | W |
//! | `braking_deceleration` | after a sample in mode `brake` with the robot moving, the robot is still moving at the next instant and slowed by less than b·Δt | (v₀ − v₁)/Δt (m/s²) | b |
//! | `control_period` | two successive instants, or two successive samples of one obstacle that missed an instant in between, are more than dt apart | Δt (s) | dt |
//! | `latency` | (samples with `obstacle_t` only) the observation is older than L periods: (t − obstacle_t)/dt > L | age (periods) | L |
//! | `first_detection_gap` | an obstacle is first seen at a gap obstacle_x − robot_x below ρ (it appeared inside the reaction radius) | gap (m) | ρ |
//! | `observation_noise` | never: not monitored (observation errors need the true positions, which a trace of observations does not carry) | | σ |
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
//! Robot checks (`control_period` between instants, `braking_deceleration`) run on the first
//! sample of each instant, obstacle checks on every sample.
//!
//! An obstacle is checked against ρ at its first sighting only; one that drops out of the
//! trace for an instant or more is reported under `control_period` when it comes back (the
//! controller went without an observation of it for longer than dt).
//!
//! **Tolerances.** A value the trace states (`obstacle_v`) is compared with its bound exactly.
//! Values the monitor derives by subtraction and division (an estimated speed, a
//! deceleration, a time step, a gap, an observation age) carry the rounding error of the
//! numbers they come from; they are compared with the bound widened by
//! [`RELATIVE_TOLERANCE`] (one part in 10⁹) of the bound plus the worst-case rounding error
//! of the computation, 8ε·(|a₀| + |a₁|)/Δ for a difference of a₀ and a₁ over Δ (ε the machine
//! epsilon). An estimated speed is further widened by 2σ/Δt, the most that observation noise
//! σ (the certificate's `observation_noise`, 0 so far) can add. So a trace written with full
//! precision (as `simulate --trace` does) never raises a false alarm, and a physically
//! meaningful violation is never hidden. A trace that rounds positions (to a millimetre,
//! say) carries an error the certificate did not allow for (σ = 0): give `obstacle_v`, or
//! expect estimated speeds to be flagged.
//!
//! After the first violation the verdict stays [`Verdict::Violated`] (the robot may not have
//! obeyed), but every later violation is still reported.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::core::semantics::Mode;
use crate::proof::certificate::{self, Certificate};
use crate::proof::verdict;

pub mod trace;

/// An obstacle's number: an index into the monitor's table (keep them small and dense).
pub type ObstacleId = u32;

/// Relative widening of a bound for values the monitor derives by arithmetic.
pub const RELATIVE_TOLERANCE: f64 = 1e-9;

/// Rounding error of one derived quantity, in units of its operands' magnitude.
const ROUNDING: f64 = 8.0 * f64::EPSILON;

/// The table size [`Monitor::new`] allows: obstacle ids must be below this.
pub const DEFAULT_MAX_OBSTACLES: u32 = 1 << 16;

/// Most events one sample can raise (five can coincide; see [`Monitor::observe`]).
pub const MAX_EVENTS_PER_SAMPLE: usize = 8;

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

/// A column of a trace.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Field {
    /// `t`
    T,
    /// `robot_x`
    RobotX,
    /// `robot_v`
    RobotV,
    /// `robot_mode`
    RobotMode,
    /// `obstacle_id`
    ObstacleId,
    /// `obstacle_x`
    ObstacleX,
    /// `obstacle_v`
    ObstacleV,
    /// `obstacle_t`
    ObstacleT,
}

impl Field {
    /// Every column, required ones first.
    pub const ALL: [Field; 8] = [
        Field::T,
        Field::RobotX,
        Field::RobotV,
        Field::ObstacleId,
        Field::ObstacleX,
        Field::ObstacleV,
        Field::RobotMode,
        Field::ObstacleT,
    ];

    /// The column's name in traces.
    pub fn as_str(self) -> &'static str {
        match self {
            Field::T => "t",
            Field::RobotX => "robot_x",
            Field::RobotV => "robot_v",
            Field::RobotMode => "robot_mode",
            Field::ObstacleId => "obstacle_id",
            Field::ObstacleX => "obstacle_x",
            Field::ObstacleV => "obstacle_v",
            Field::ObstacleT => "obstacle_t",
        }
    }

    /// The column named `name`.
    pub fn from_name(name: &[u8]) -> Option<Field> {
        Field::ALL
            .into_iter()
            .find(|f| f.as_str().as_bytes() == name)
    }

    /// Whether every sample must have it.
    pub fn required(self) -> bool {
        matches!(
            self,
            Field::T | Field::RobotX | Field::RobotV | Field::ObstacleId | Field::ObstacleX
        )
    }
}

impl fmt::Display for Field {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// What the monitor checks: the certificate's premises, then the fail-safe checks on the
/// input. The names are stable (they appear in output as `premise`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Check {
    /// Obstacle speed towards the robot ≤ W.
    ObstacleSpeed,
    /// Deceleration while braking ≥ b.
    BrakingDeceleration,
    /// Time between instants ≤ dt.
    ControlPeriod,
    /// Observation age ≤ L control periods.
    Latency,
    /// A new obstacle is first seen at a gap ≥ ρ.
    FirstDetectionGap,
    /// Observation error ≤ σ (not monitorable from a trace).
    ObservationNoise,
    /// The input is not a readable sample.
    MalformedSample,
    /// A number is NaN or infinite.
    NonFinite,
    /// Time went backwards.
    TimeBackwards,
    /// The same obstacle twice at one instant.
    DuplicateSample,
}

impl Check {
    /// Every check: the six premises in the certificate's order, then the fail-safe ones.
    pub const ALL: [Check; 10] = [
        Check::ObstacleSpeed,
        Check::BrakingDeceleration,
        Check::ControlPeriod,
        Check::Latency,
        Check::FirstDetectionGap,
        Check::ObservationNoise,
        Check::MalformedSample,
        Check::NonFinite,
        Check::TimeBackwards,
        Check::DuplicateSample,
    ];

    /// The certificate's premises, in its order.
    pub const PREMISES: [Check; 6] = [
        Check::ObstacleSpeed,
        Check::BrakingDeceleration,
        Check::ControlPeriod,
        Check::Latency,
        Check::FirstDetectionGap,
        Check::ObservationNoise,
    ];

    /// The fail-safe checks on the input.
    pub const FAIL_SAFE: [Check; 4] = [
        Check::MalformedSample,
        Check::NonFinite,
        Check::TimeBackwards,
        Check::DuplicateSample,
    ];

    /// The stable name.
    pub fn as_str(self) -> &'static str {
        match self {
            Check::ObstacleSpeed => "obstacle_speed",
            Check::BrakingDeceleration => "braking_deceleration",
            Check::ControlPeriod => "control_period",
            Check::Latency => "latency",
            Check::FirstDetectionGap => "first_detection_gap",
            Check::ObservationNoise => "observation_noise",
            Check::MalformedSample => "malformed_sample",
            Check::NonFinite => "non_finite",
            Check::TimeBackwards => "time_backwards",
            Check::DuplicateSample => "duplicate_sample",
        }
    }

    /// The check named `name`.
    pub fn from_name(name: &str) -> Option<Check> {
        Check::ALL.into_iter().find(|c| c.as_str() == name)
    }

    /// Whether this is a fail-safe check on the input rather than a certificate premise.
    pub fn is_fail_safe(self) -> bool {
        Check::FAIL_SAFE.contains(&self)
    }

    /// The unit of its observed value and bound (empty when it has none).
    pub fn unit(self) -> &'static str {
        match self {
            Check::ObstacleSpeed => "m/s",
            Check::BrakingDeceleration => "m/s^2",
            Check::ControlPeriod | Check::TimeBackwards | Check::DuplicateSample => "s",
            Check::Latency => "periods",
            Check::FirstDetectionGap | Check::ObservationNoise => "m",
            Check::MalformedSample | Check::NonFinite => "",
        }
    }

    /// How observed and bound compare when violated: `>` (above the bound) or `<`.
    pub fn relation(self) -> &'static str {
        match self {
            Check::BrakingDeceleration | Check::FirstDetectionGap | Check::TimeBackwards => "<",
            _ => ">",
        }
    }

    fn index(self) -> usize {
        self as usize
    }
}

impl fmt::Display for Check {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// What a violation asks the robot to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Action {
    /// Enter the passive safe state: brake to a stop.
    Brake,
}

impl Action {
    /// The word used in output.
    pub fn as_str(self) -> &'static str {
        match self {
            Action::Brake => "brake",
        }
    }
}

/// Why a sample was malformed or non-finite, without allocating.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Detail {
    /// The value of this field is NaN or infinite (or JSON `null` in a required field).
    NonFinite(Field),
    /// The obstacle id is beyond the monitor's table.
    ObstacleIdOutOfRange {
        /// Ids must be below this.
        limit: u32,
    },
    /// A new obstacle, but the reader's table of obstacle ids is full.
    TooManyObstacles {
        /// Most obstacles a trace may have.
        limit: u32,
    },
    /// The robot's position, speed or mode differs from the first sample of the same instant.
    RobotStateDiffers,
    /// A required field is missing.
    MissingField(Field),
    /// A field is not a number.
    BadNumber(Field),
    /// `robot_mode` is not one of idle, accelerate, drive, brake, stop.
    BadMode,
    /// `obstacle_id` is neither a string nor an integer.
    BadId,
    /// A CSV row with a different number of fields than the header.
    FieldCount {
        /// Fields in the row.
        found: u32,
        /// Columns in the header.
        expected: u32,
    },
    /// The CSV header lacks a required column.
    MissingColumn(Field),
    /// The CSV header names a column twice.
    DuplicateColumn(Field),
    /// A CSV data line with no usable header before it.
    NoHeader,
    /// A line longer than the reader accepts.
    LineTooLong {
        /// Longest accepted line (bytes).
        limit: u32,
    },
    /// A CSV syntax error (quoting).
    Csv(&'static str),
    /// A JSON syntax error.
    Json(&'static str),
    /// A JSON object with the same key twice.
    DuplicateKey(Field),
}

impl fmt::Display for Detail {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Detail::NonFinite(field) => write!(f, "{field} is not a finite number"),
            Detail::ObstacleIdOutOfRange { limit } => {
                write!(
                    f,
                    "obstacle id beyond the monitor's table (ids must be < {limit})"
                )
            }
            Detail::TooManyObstacles { limit } => {
                write!(f, "more than {limit} distinct obstacle ids")
            }
            Detail::RobotStateDiffers => f.write_str(
                "robot state differs from the first sample of the same instant (same t)",
            ),
            Detail::MissingField(field) => write!(f, "{field} is missing"),
            Detail::BadNumber(field) => write!(f, "{field} is not a number"),
            Detail::BadMode => {
                f.write_str("robot_mode is not one of idle, accelerate, drive, brake, stop")
            }
            Detail::BadId => f.write_str("obstacle_id is neither a string nor an integer"),
            Detail::FieldCount { found, expected } => {
                write!(f, "{found} fields, but the header has {expected} columns")
            }
            Detail::MissingColumn(field) => {
                write!(
                    f,
                    "the header has no column {field} (required: t, robot_x, robot_v, obstacle_id, obstacle_x)"
                )
            }
            Detail::DuplicateColumn(field) => write!(f, "the header names {field} twice"),
            Detail::NoHeader => f.write_str("no usable CSV header before this line"),
            Detail::LineTooLong { limit } => write!(f, "line longer than {limit} bytes"),
            Detail::Csv(what) => write!(f, "not a CSV row: {what}"),
            Detail::Json(what) => write!(f, "not a JSON sample: {what}"),
            Detail::DuplicateKey(field) => write!(f, "key {field} given twice"),
        }
    }
}

/// A violation: which check failed at which sample, by how much, and what to do.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Event {
    /// Index of the sample that raised it (0-based count of samples fed to the monitor,
    /// malformed ones included).
    pub sample: u64,
    /// Time of the sample (s); `None` when it could not be read.
    pub t: Option<f64>,
    /// The obstacle of the sample, when known.
    pub obstacle_id: Option<ObstacleId>,
    /// The check that failed.
    #[serde(rename = "premise")]
    pub check: Check,
    /// The observed value (in [`Check::unit`]); `None` for malformed and non-finite input.
    pub observed: Option<f64>,
    /// The bound it broke.
    pub bound: Option<f64>,
    /// What the robot must do.
    pub action: Action,
    /// For malformed and non-finite input: what is wrong.
    #[serde(serialize_with = "serialize_detail")]
    pub detail: Option<Detail>,
}

fn serialize_detail<S: serde::Serializer>(d: &Option<Detail>, s: S) -> Result<S::Ok, S::Error> {
    match d {
        Some(d) => s.collect_str(d),
        None => s.serialize_none(),
    }
}

impl fmt::Display for Event {
    /// `premise observed X > bound Y unit -> brake`, or `premise: detail -> brake`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.check)?;
        if let (Some(o), Some(b)) = (self.observed, self.bound) {
            let unit = self.check.unit();
            let sep = if unit.is_empty() { "" } else { " " };
            write!(
                f,
                " observed {o}{sep}{unit} {} bound {b}{sep}{unit}",
                self.check.relation()
            )?;
        } else if let Some(o) = self.observed {
            write!(f, " observed {o} {}", self.check.unit())?;
        }
        if let Some(d) = &self.detail {
            write!(f, ": {d}")?;
        }
        write!(f, " -> {}", self.action.as_str())
    }
}

/// The standing verdict.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Every premise has held on every sample so far.
    Held,
    /// Some sample violated a premise (latched: it never returns to `Held`).
    Violated,
}

impl Verdict {
    /// The word used in output.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Held => "held",
            Verdict::Violated => "violated",
        }
    }
}

/// What one sample produced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome<'a> {
    /// The standing verdict after this sample.
    pub verdict: Verdict,
    /// The violations this sample raised (usually none), in the order the checks ran.
    pub events: &'a [Event],
}

/// The bounds the monitor checks, read from a certificate's premises.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// W (m/s).
    pub obstacle_speed: f64,
    /// b (m/s²).
    pub braking_deceleration: f64,
    /// dt (s).
    pub control_period: f64,
    /// L (control periods).
    pub latency: f64,
    /// ρ (m).
    pub first_detection_gap: f64,
    /// σ (m).
    pub observation_noise: f64,
}

impl Bounds {
    /// The bound of `check` (`None` for the fail-safe checks).
    pub fn of(&self, check: Check) -> Option<f64> {
        match check {
            Check::ObstacleSpeed => Some(self.obstacle_speed),
            Check::BrakingDeceleration => Some(self.braking_deceleration),
            Check::ControlPeriod => Some(self.control_period),
            Check::Latency => Some(self.latency),
            Check::FirstDetectionGap => Some(self.first_detection_gap),
            Check::ObservationNoise => Some(self.observation_noise),
            _ => None,
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
}

impl From<certificate::Invalid> for MonitorError {
    fn from(e: certificate::Invalid) -> Self {
        MonitorError::Invalid(e)
    }
}

/// What the monitor remembers about one obstacle.
#[derive(Clone, Copy, Debug, Default)]
struct Track {
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
}

/// The robot's state at the current instant.
#[derive(Clone, Copy, Debug)]
struct RobotAt {
    t: f64,
    x: f64,
    v: f64,
    mode: Option<Mode>,
}

/// The runtime monitor for one certificate (see the module docs).
#[derive(Clone, Debug)]
pub struct Monitor {
    bounds: Bounds,
    /// Obstacle ids must be below this.
    max_obstacles: u32,
    obstacles: Vec<Track>,
    /// The current instant, once there is one.
    robot: Option<RobotAt>,
    /// Number of the current instant (0-based).
    instant: u64,
    samples: u64,
    distinct_obstacles: u64,
    checks: [u64; 10],
    violations: [u64; 10],
    first: Option<Event>,
    saw_mode: bool,
    saw_obs_t: bool,
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

/// The slack of `x0 − x1` (or of a rate `(x0 − x1)/d`) due to rounding in its operands.
#[inline]
fn rounding(x0: f64, x1: f64) -> f64 {
    ROUNDING * (x0.abs() + x1.abs())
}

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
        if report.verdict != verdict::Verdict::Certified {
            return Err(MonitorError::NotCertified(report.verdict));
        }
        let bound = |check: Check| -> Result<f64, MonitorError> {
            let name = check.as_str();
            let p = cert
                .premises
                .iter()
                .find(|p| p.name == name)
                .ok_or(MonitorError::MissingPremise(name))?;
            let ok = p.bound.is_finite()
                && p.bound >= 0.0
                && (check != Check::ControlPeriod || p.bound > 0.0);
            if ok {
                Ok(p.bound)
            } else {
                Err(MonitorError::BadBound {
                    name,
                    bound: p.bound,
                })
            }
        };
        let bounds = Bounds {
            obstacle_speed: bound(Check::ObstacleSpeed)?,
            braking_deceleration: bound(Check::BrakingDeceleration)?,
            control_period: bound(Check::ControlPeriod)?,
            latency: bound(Check::Latency)?,
            first_detection_gap: bound(Check::FirstDetectionGap)?,
            observation_noise: bound(Check::ObservationNoise)?,
        };
        Ok(Monitor {
            bounds,
            max_obstacles,
            obstacles: vec![Track::default(); reserve],
            robot: None,
            instant: 0,
            samples: 0,
            distinct_obstacles: 0,
            checks: [0; 10],
            violations: [0; 10],
            first: None,
            saw_mode: false,
            saw_obs_t: false,
            events: [NO_EVENT; MAX_EVENTS_PER_SAMPLE],
            n_events: 0,
        })
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

    #[inline]
    fn check(&mut self, check: Check) {
        self.checks[check.index()] += 1;
    }

    /// The control-period premise between two observation times of obstacle `id`.
    fn check_period(&mut self, from: f64, to: f64, id: u32) {
        let dt = self.bounds.control_period;
        let step = to - from;
        self.check(Check::ControlPeriod);
        if step > dt + RELATIVE_TOLERANCE * dt + rounding(from, to) {
            self.raise(
                Check::ControlPeriod,
                Some(to),
                Some(id),
                Some(step),
                Some(dt),
                None,
            );
        }
    }

    #[cold]
    #[inline(never)]
    fn raise(
        &mut self,
        check: Check,
        t: Option<f64>,
        obstacle_id: Option<ObstacleId>,
        observed: Option<f64>,
        bound: Option<f64>,
        detail: Option<Detail>,
    ) {
        let event = Event {
            sample: self.samples - 1,
            t,
            obstacle_id,
            check,
            observed,
            bound,
            action: Action::Brake,
            detail,
        };
        self.violations[check.index()] += 1;
        if self.first.is_none() {
            self.first = Some(event);
        }
        // At most five checks can fail on one sample, so this never drops an event.
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
        self.check(check);
        self.raise(
            check,
            t.filter(|t| t.is_finite()),
            None,
            None,
            None,
            Some(detail),
        );
        self.outcome()
    }

    /// Checks one sample (see the module docs for the checks and their order: fail-safe
    /// checks first, which reject the sample; then, on the first sample of an instant,
    /// `control_period` between instants and `braking_deceleration`; then the obstacle's
    /// `first_detection_gap` or its own `control_period`, `latency`, `obstacle_speed`).
    ///
    /// No I/O, no allocation (except growing the table of [`Monitor::new`] on a new largest
    /// obstacle id), no panic.
    pub fn observe(&mut self, s: &Sample) -> Outcome<'_> {
        self.n_events = 0;
        self.samples += 1;
        let id = s.obstacle_id;
        // Fail safe: reject what cannot be trusted, before it touches any state.
        if let Some(field) = non_finite(s) {
            self.check(Check::NonFinite);
            let t = Some(s.t).filter(|t| t.is_finite());
            self.raise(
                Check::NonFinite,
                t,
                Some(id),
                None,
                None,
                Some(Detail::NonFinite(field)),
            );
            return self.outcome();
        }
        if id >= self.max_obstacles {
            self.check(Check::MalformedSample);
            let detail = Detail::ObstacleIdOutOfRange {
                limit: self.max_obstacles,
            };
            self.raise(
                Check::MalformedSample,
                Some(s.t),
                Some(id),
                None,
                None,
                Some(detail),
            );
            return self.outcome();
        }
        let idx = id as usize;
        if idx >= self.obstacles.len() {
            self.obstacles.resize(idx + 1, Track::default());
        }
        let track = self.obstacles[idx];
        let dt = self.bounds.control_period;
        match self.robot {
            Some(r) if s.t < r.t => {
                self.raise(
                    Check::TimeBackwards,
                    Some(s.t),
                    Some(id),
                    Some(s.t),
                    Some(r.t),
                    None,
                );
                return self.outcome();
            }
            Some(r) if s.t == r.t => {
                if track.seen && track.instant == self.instant {
                    self.raise(
                        Check::DuplicateSample,
                        Some(s.t),
                        Some(id),
                        Some(s.t),
                        None,
                        None,
                    );
                    return self.outcome();
                }
                let mode_differs = matches!((r.mode, s.robot_mode), (Some(a), Some(m)) if a != m);
                if r.x != s.robot_x || r.v != s.robot_v || mode_differs {
                    self.check(Check::MalformedSample);
                    self.raise(
                        Check::MalformedSample,
                        Some(s.t),
                        Some(id),
                        None,
                        None,
                        Some(Detail::RobotStateDiffers),
                    );
                    return self.outcome();
                }
                if r.mode.is_none() && s.robot_mode.is_some() {
                    self.robot = Some(RobotAt {
                        mode: s.robot_mode,
                        ..r
                    });
                }
            }
            previous => {
                // The first sample of a new instant: the robot's checks.
                if let Some(r) = previous {
                    let step = s.t - r.t;
                    self.check_period(r.t, s.t, id);
                    if r.mode == Some(Mode::Brake) && r.v > 0.0 {
                        self.check(Check::BrakingDeceleration);
                        // A robot at rest at the next instant decelerated fast enough (it may
                        // have stopped inside the step); one still moving must have slowed by
                        // at least b over the step.
                        if s.robot_v > 0.0 {
                            let bb = self.bounds.braking_deceleration;
                            let decel = (r.v - s.robot_v) / step;
                            let slack = RELATIVE_TOLERANCE * bb
                                + (rounding(r.v, s.robot_v) + bb * rounding(r.t, s.t)) / step;
                            if decel < bb - slack {
                                self.raise(
                                    Check::BrakingDeceleration,
                                    Some(s.t),
                                    Some(id),
                                    Some(decel),
                                    Some(bb),
                                    None,
                                );
                            }
                        }
                    }
                    self.instant += 1;
                }
                self.robot = Some(RobotAt {
                    t: s.t,
                    x: s.robot_x,
                    v: s.robot_v,
                    mode: s.robot_mode,
                });
            }
        }
        self.saw_mode |= s.robot_mode.is_some();
        // The obstacle's checks.
        if !track.seen {
            self.distinct_obstacles += 1;
            self.check(Check::FirstDetectionGap);
            let rho = self.bounds.first_detection_gap;
            let gap = s.obstacle_x - s.robot_x;
            if gap < rho - RELATIVE_TOLERANCE * rho - rounding(s.obstacle_x, s.robot_x) {
                self.raise(
                    Check::FirstDetectionGap,
                    Some(s.t),
                    Some(id),
                    Some(gap),
                    Some(rho),
                    None,
                );
            }
        } else if track.instant + 1 < self.instant {
            // It missed at least one instant: its own observations are a period apart.
            self.check_period(track.t, s.t, id);
        }
        if let Some(obs_t) = s.obstacle_t {
            self.saw_obs_t = true;
            self.check(Check::Latency);
            let age = (s.t - obs_t) / dt;
            let l = self.bounds.latency;
            if age > l + RELATIVE_TOLERANCE * l.max(1.0) + rounding(s.t, obs_t) / dt {
                self.raise(
                    Check::Latency,
                    Some(s.t),
                    Some(id),
                    Some(age),
                    Some(l),
                    None,
                );
            }
        }
        let w = self.bounds.obstacle_speed;
        let mut keep_reference = false;
        match s.obstacle_v {
            Some(v) => {
                self.check(Check::ObstacleSpeed);
                if v > w {
                    self.raise(
                        Check::ObstacleSpeed,
                        Some(s.t),
                        Some(id),
                        Some(v),
                        Some(w),
                        None,
                    );
                }
            }
            None if track.seen => {
                let (t0, t1) = match s.obstacle_t {
                    Some(o) if track.has_obs_t => (track.obs_t, o),
                    _ => (track.t, s.t),
                };
                let span = t1 - t0;
                if span > 0.0 {
                    self.check(Check::ObstacleSpeed);
                    let speed = (track.x - s.obstacle_x) / span;
                    let slack = RELATIVE_TOLERANCE * w
                        + (2.0 * self.bounds.observation_noise
                            + rounding(track.x, s.obstacle_x)
                            + speed.abs() * rounding(t0, t1))
                            / span;
                    if speed > w + slack {
                        self.raise(
                            Check::ObstacleSpeed,
                            Some(s.t),
                            Some(id),
                            Some(speed),
                            Some(w),
                            None,
                        );
                    }
                } else {
                    // The same observation again: estimate later from the older one.
                    keep_reference = true;
                }
            }
            None => {}
        }
        let slot = &mut self.obstacles[idx];
        slot.seen = true;
        slot.instant = self.instant;
        slot.t = s.t;
        if !keep_reference {
            slot.x = s.obstacle_x;
            slot.has_obs_t = s.obstacle_t.is_some();
            slot.obs_t = s.obstacle_t.unwrap_or(0.0);
        }
        self.outcome()
    }

    /// The summary so far: counts, the first violation and the status of every premise.
    pub fn summary(&self) -> Summary {
        let premises = Check::PREMISES
            .into_iter()
            .map(|c| {
                let checks = self.checks(c);
                let violations = self.violations(c);
                let not_monitored = match c {
                    Check::ObservationNoise => Some(
                        "observation errors need the true positions, which a trace of \
                         observations does not carry",
                    ),
                    Check::Latency if !self.saw_obs_t => Some(
                        "no sample carried obstacle_t (the time the observation was taken); \
                         add that column to check latency",
                    ),
                    Check::BrakingDeceleration if !self.saw_mode => {
                        Some("no sample carried robot_mode, so braking cannot be recognised")
                    }
                    _ => None,
                };
                let not_checked = match c {
                    Check::ObstacleSpeed => {
                        "no sample had obstacle_v and no obstacle was seen twice"
                    }
                    Check::BrakingDeceleration => "the robot never braked while moving",
                    Check::ControlPeriod => "fewer than two instants",
                    Check::FirstDetectionGap => "no obstacle was seen",
                    _ => "no sample gave the opportunity",
                };
                let (status, reason) = if violations > 0 {
                    (Status::Violated, None)
                } else if let Some(r) = not_monitored {
                    (Status::NotMonitored, Some(r.to_string()))
                } else if checks == 0 {
                    (Status::NotChecked, Some(not_checked.to_string()))
                } else {
                    (Status::Held, None)
                };
                PremiseSummary {
                    premise: c,
                    status,
                    bound: self.bounds.of(c).unwrap_or(0.0),
                    unit: c.unit().to_string(),
                    checks,
                    violations,
                    reason,
                }
            })
            .collect();
        let fail_safe = Check::FAIL_SAFE
            .into_iter()
            .map(|c| FailSafeSummary {
                check: c,
                violations: self.violations(c),
            })
            .collect();
        Summary {
            verdict: self.verdict(),
            samples: self.samples,
            instants: if self.robot.is_some() {
                self.instant + 1
            } else {
                0
            },
            obstacles: self.distinct_obstacles,
            violations: self.violations.iter().sum(),
            first_violation: self.first,
            premises,
            fail_safe,
        }
    }
}

/// The first non-finite field of a sample.
#[inline]
fn non_finite(s: &Sample) -> Option<Field> {
    let all = s.t.is_finite()
        & s.robot_x.is_finite()
        & s.robot_v.is_finite()
        & s.obstacle_x.is_finite()
        & s.obstacle_v.is_none_or(f64::is_finite)
        & s.obstacle_t.is_none_or(f64::is_finite);
    if all {
        return None;
    }
    [
        (Field::T, s.t),
        (Field::RobotX, s.robot_x),
        (Field::RobotV, s.robot_v),
        (Field::ObstacleX, s.obstacle_x),
        (Field::ObstacleV, s.obstacle_v.unwrap_or(0.0)),
        (Field::ObstacleT, s.obstacle_t.unwrap_or(0.0)),
    ]
    .into_iter()
    .find(|(_, x)| !x.is_finite())
    .map(|(f, _)| f)
}

/// How a premise fared.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Checked at least once, never violated.
    Held,
    /// Violated at least once.
    Violated,
    /// Monitored, but no sample gave the opportunity (e.g. the robot never braked).
    NotChecked,
    /// Cannot be checked from these samples (see the reason).
    NotMonitored,
}

impl Status {
    /// The words used in output.
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Held => "held",
            Status::Violated => "violated",
            Status::NotChecked => "not checked",
            Status::NotMonitored => "not monitored",
        }
    }
}

/// One premise in a [`Summary`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PremiseSummary {
    /// The premise.
    pub premise: Check,
    /// How it fared.
    pub status: Status,
    /// Its bound.
    pub bound: f64,
    /// The bound's unit.
    pub unit: String,
    /// Times it was evaluated.
    pub checks: u64,
    /// Times it was violated.
    pub violations: u64,
    /// Why it was not checked or not monitored.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

/// One fail-safe check in a [`Summary`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FailSafeSummary {
    /// The check.
    pub check: Check,
    /// Times it was violated.
    pub violations: u64,
}

/// What the monitor saw, at the end of a trace (or at any moment).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// The standing verdict.
    pub verdict: Verdict,
    /// Samples fed (malformed ones included).
    pub samples: u64,
    /// Distinct instants (values of `t`) among the accepted samples.
    pub instants: u64,
    /// Distinct obstacles among the accepted samples.
    pub obstacles: u64,
    /// Violations of all checks.
    pub violations: u64,
    /// The first violation.
    pub first_violation: Option<Event>,
    /// The certificate's six premises, in its order.
    pub premises: Vec<PremiseSummary>,
    /// The fail-safe checks on the input.
    pub fail_safe: Vec<FailSafeSummary>,
}
