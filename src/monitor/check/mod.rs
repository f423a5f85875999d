//! The monitor's checks, one idea per file: what it checks ([`Check`]: the certificate's
//! premises, the fail-safe checks on the input, and the checks a scene certificate adds),
//! the bounds it checks them against ([`Bounds`]), and how each premise is checked.
//!
//! Every per-check table of the monitor (counters of evaluations and violations, units,
//! reasons for "not checked" and "not monitored") is indexed by [`Check::index`], which for
//! a premise is its [`PremiseKind::index`]: adding a premise is its variant in
//! `proof/premise.rs`, its bound in [`Bounds`], and its check here — a [`PremiseCheck`] row
//! and the function that evaluates it, in the file of its idea:
//!
//! - `obstacle.rs`: what the environment does (`obstacle_speed`, per obstacle under a scene
//!   certificate, `first_detection_gap`, `observation_noise`, and `static_obstacle`);
//! - `timing.rs`: when the controller runs and what it sees (`control_period`, `latency`);
//! - `braking.rs`: what the robot does (`braking_deceleration`);
//! - `motion.rs`: whether the robot moved as its speeds say (`robot_motion`);
//! - `collision.rs`: safety itself (`collision`), at an instant and within the step before;
//! - `input.rs`: the fail-safe checks on the input and the instant a sample belongs to;
//! - `scene.rs`: the checks a scene certificate adds ([`SceneCheck`]), evaluated in
//!   `obstacle.rs` and `lanes.rs` (`obstacle_lane`, `collision`).

use std::fmt;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::MonitorError;
use crate::proof::premise::{Premise, PremiseKind};

mod behaviour;
mod braking;
mod collision;
mod controller;
mod input;
mod lanes;
mod motion;
mod obstacle;
mod plane;
mod scene;
mod timing;

pub use behaviour::BehaviourCheck;
pub(in crate::monitor) use braking::deceleration;
pub(in crate::monitor) use motion::{Motion, StepRange};
pub use plane::PlaneCheck;
pub use scene::SceneCheck;

/// Rounding error of one derived quantity, in units of its operands' magnitude.
pub(in crate::monitor) const ROUNDING: f64 = 8.0 * f64::EPSILON;

/// The slack of `x0 − x1` (or of a rate `(x0 − x1)/d`) due to rounding in its operands.
#[inline]
pub(in crate::monitor) fn rounding(x0: f64, x1: f64) -> f64 {
    ROUNDING * (x0.abs() + x1.abs())
}

/// A fail-safe check on the input itself (not a premise of the certificate).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FailSafe {
    /// The input is not a readable sample.
    MalformedSample,
    /// A number is NaN or infinite.
    NonFinite,
    /// Time went backwards.
    TimeBackwards,
    /// The same obstacle twice at one instant.
    DuplicateSample,
}

impl FailSafe {
    /// Every fail-safe check, in output order.
    pub const ALL: [FailSafe; 4] = [
        FailSafe::MalformedSample,
        FailSafe::NonFinite,
        FailSafe::TimeBackwards,
        FailSafe::DuplicateSample,
    ];

    /// The stable name.
    pub const fn name(self) -> &'static str {
        match self {
            FailSafe::MalformedSample => "malformed_sample",
            FailSafe::NonFinite => "non_finite",
            FailSafe::TimeBackwards => "time_backwards",
            FailSafe::DuplicateSample => "duplicate_sample",
        }
    }
}

/// What the monitor checks: the certificate's premises, the fail-safe checks on the input,
/// and the checks a scene certificate adds. The names are stable (they appear in output as
/// `premise`).
///
/// The associated constants (`Check::ObstacleSpeed`, …, `Check::Collision`) name every check
/// directly.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Check {
    /// A premise of the certificate.
    Premise(PremiseKind),
    /// A fail-safe check on the input.
    FailSafe(FailSafe),
    /// A check of what the model says beyond its premises: that observations can be
    /// explained by it, that the controller did what the certified one does, and safety
    /// itself (every certificate's monitor runs them).
    Behaviour(BehaviourCheck),
    /// A check a scene certificate adds (only a scene certificate's monitor runs them).
    Scene(SceneCheck),
    /// A check a planar certificate adds (only a planar certificate's monitor runs them).
    Plane(PlaneCheck),
}

#[allow(non_upper_case_globals)]
impl Check {
    /// Obstacle speed towards the robot ≤ W.
    pub const ObstacleSpeed: Check = Check::Premise(PremiseKind::ObstacleSpeed);
    /// Deceleration while braking ≥ b.
    pub const BrakingDeceleration: Check = Check::Premise(PremiseKind::BrakingDeceleration);
    /// Time between instants ≤ dt.
    pub const ControlPeriod: Check = Check::Premise(PremiseKind::ControlPeriod);
    /// Observation age ≤ L control periods.
    pub const Latency: Check = Check::Premise(PremiseKind::Latency);
    /// A new obstacle is first seen at a gap ≥ ρ.
    pub const FirstDetectionGap: Check = Check::Premise(PremiseKind::FirstDetectionGap);
    /// Observation error ≤ σ (not monitorable from a trace).
    pub const ObservationNoise: Check = Check::Premise(PremiseKind::ObservationNoise);
    /// The input is not a readable sample.
    pub const MalformedSample: Check = Check::FailSafe(FailSafe::MalformedSample);
    /// A number is NaN or infinite.
    pub const NonFinite: Check = Check::FailSafe(FailSafe::NonFinite);
    /// Time went backwards.
    pub const TimeBackwards: Check = Check::FailSafe(FailSafe::TimeBackwards);
    /// The same obstacle twice at one instant.
    pub const DuplicateSample: Check = Check::FailSafe(FailSafe::DuplicateSample);
    /// A static obstacle moved.
    pub const StaticObstacle: Check = Check::Scene(SceneCheck::StaticObstacle);
    /// A named obstacle outside its certified lane.
    pub const ObstacleLane: Check = Check::Scene(SceneCheck::ObstacleLane);
    /// Reported obstacle speed and positions disagree beyond the noise.
    pub const ObservationInconsistent: Check =
        Check::Behaviour(BehaviourCheck::ObservationInconsistent);
    /// An obstacle inside the reaction area went unobserved for an instant.
    pub const ObservationDropout: Check = Check::Behaviour(BehaviourCheck::ObservationDropout);
    /// The robot did not brake when its observation showed danger.
    pub const ControllerReaction: Check = Check::Behaviour(BehaviourCheck::ControllerReaction);
    /// The robot's speed or acceleration beyond the certified v_max or a.
    pub const RobotEnvelope: Check = Check::Behaviour(BehaviourCheck::RobotEnvelope);
    /// The robot's displacement is not one its speeds and mode allow.
    pub const RobotMotion: Check = Check::Behaviour(BehaviourCheck::RobotMotion);
    /// The robot moved at a separation ≤ clearance from an obstacle of its lane.
    pub const Collision: Check = Check::Behaviour(BehaviourCheck::Collision);
    /// The robot's centre off its certified path.
    pub const RobotPath: Check = Check::Plane(PlaneCheck::RobotPath);
    /// An obstacle first seen where it could not have come from its start.
    pub const ObstacleStart: Check = Check::Plane(PlaneCheck::ObstacleStart);
    /// An obstacle outside its certified region.
    pub const ObstacleRegion: Check = Check::Plane(PlaneCheck::ObstacleRegion);
    /// An object the certificate has no obstacle for.
    pub const UncertifiedObstacle: Check = Check::Plane(PlaneCheck::UncertifiedObstacle);
}

impl Check {
    /// How many checks there are: the size of the monitor's counters.
    pub const COUNT: usize = PremiseKind::COUNT
        + FailSafe::ALL.len()
        + BehaviourCheck::ALL.len()
        + SceneCheck::ALL.len()
        + PlaneCheck::ALL.len();

    /// Every check: the premises in the certificate's order, then the fail-safe ones, then
    /// the behaviour, scene and planar checks.
    pub const ALL: [Check; Check::COUNT] = {
        const FIRST_BEHAVIOUR: usize = PremiseKind::COUNT + FailSafe::ALL.len();
        const FIRST_SCENE: usize = FIRST_BEHAVIOUR + BehaviourCheck::ALL.len();
        const FIRST_PLANE: usize = FIRST_SCENE + SceneCheck::ALL.len();
        let mut all = [Check::MalformedSample; Check::COUNT];
        let mut i = 0;
        while i < Check::COUNT {
            all[i] = if i < PremiseKind::COUNT {
                Check::Premise(PremiseKind::ALL[i])
            } else if i < FIRST_BEHAVIOUR {
                Check::FailSafe(FailSafe::ALL[i - PremiseKind::COUNT])
            } else if i < FIRST_SCENE {
                Check::Behaviour(BehaviourCheck::ALL[i - FIRST_BEHAVIOUR])
            } else if i < FIRST_PLANE {
                Check::Scene(SceneCheck::ALL[i - FIRST_SCENE])
            } else {
                Check::Plane(PlaneCheck::ALL[i - FIRST_PLANE])
            };
            i += 1;
        }
        all
    };

    /// The certificate's premises, in its order.
    pub const PREMISES: [Check; PremiseKind::COUNT] = {
        let mut all = [Check::MalformedSample; PremiseKind::COUNT];
        let mut i = 0;
        while i < PremiseKind::COUNT {
            all[i] = Check::Premise(PremiseKind::ALL[i]);
            i += 1;
        }
        all
    };

    /// The fail-safe checks on the input.
    pub const FAIL_SAFE: [Check; FailSafe::ALL.len()] = [
        Check::MalformedSample,
        Check::NonFinite,
        Check::TimeBackwards,
        Check::DuplicateSample,
    ];

    /// The checks of what the model says beyond its premises.
    pub const BEHAVIOUR: [Check; BehaviourCheck::ALL.len()] = [
        Check::ObservationInconsistent,
        Check::ObservationDropout,
        Check::ControllerReaction,
        Check::RobotEnvelope,
        Check::RobotMotion,
        Check::Collision,
    ];

    /// The checks a scene certificate adds.
    pub const SCENE: [Check; SceneCheck::ALL.len()] = [Check::StaticObstacle, Check::ObstacleLane];

    /// The checks a planar certificate adds.
    pub const PLANE: [Check; PlaneCheck::ALL.len()] = [
        Check::RobotPath,
        Check::ObstacleStart,
        Check::ObstacleRegion,
        Check::UncertifiedObstacle,
    ];

    /// The stable name.
    pub const fn as_str(self) -> &'static str {
        match self {
            Check::Premise(kind) => kind.name(),
            Check::FailSafe(f) => f.name(),
            Check::Behaviour(c) => c.name(),
            Check::Scene(c) => c.name(),
            Check::Plane(c) => c.name(),
        }
    }

    /// The check named `name`.
    pub fn from_name(name: &str) -> Option<Check> {
        Check::ALL.into_iter().find(|c| c.as_str() == name)
    }

    /// Whether this is a fail-safe check on the input rather than a certificate premise.
    pub fn is_fail_safe(self) -> bool {
        matches!(self, Check::FailSafe(_))
    }

    /// The premise checked, if this is one.
    pub fn premise(self) -> Option<PremiseKind> {
        match self {
            Check::Premise(kind) => Some(kind),
            Check::FailSafe(_) | Check::Behaviour(_) | Check::Scene(_) | Check::Plane(_) => None,
        }
    }

    /// The scene check, if this is one.
    pub fn scene(self) -> Option<SceneCheck> {
        match self {
            Check::Scene(c) => Some(c),
            Check::Premise(_) | Check::FailSafe(_) | Check::Behaviour(_) | Check::Plane(_) => None,
        }
    }

    /// The unit of its observed value and bound (empty when it has none).
    pub fn unit(self) -> &'static str {
        match self {
            Check::Premise(kind) => PremiseCheck::of(kind).unit,
            Check::FailSafe(FailSafe::TimeBackwards | FailSafe::DuplicateSample) => "s",
            Check::FailSafe(FailSafe::MalformedSample | FailSafe::NonFinite) => "",
            Check::Behaviour(c) => c.row().unit,
            Check::Scene(c) => c.row().unit,
            Check::Plane(c) => c.row().unit,
        }
    }

    /// How observed and bound compare when violated: `>` (above the bound), `<`, `<=`
    /// (`collision`) or `!=` (`obstacle_lane`).
    pub fn relation(self) -> &'static str {
        match self {
            Check::Premise(kind) => PremiseCheck::of(kind).relation,
            Check::FailSafe(FailSafe::TimeBackwards) => "<",
            Check::FailSafe(_) => ">",
            Check::Behaviour(c) => c.row().relation,
            Check::Scene(c) => c.row().relation,
            Check::Plane(c) => c.row().relation,
        }
    }

    /// Its index in [`Check::ALL`]: the index into the monitor's per-check tables.
    #[inline]
    pub const fn index(self) -> usize {
        match self {
            Check::Premise(kind) => kind.index(),
            Check::FailSafe(f) => PremiseKind::COUNT + f as usize,
            Check::Behaviour(c) => PremiseKind::COUNT + FailSafe::ALL.len() + c as usize,
            Check::Scene(c) => {
                PremiseKind::COUNT + FailSafe::ALL.len() + BehaviourCheck::ALL.len() + c as usize
            }
            Check::Plane(c) => {
                PremiseKind::COUNT
                    + FailSafe::ALL.len()
                    + BehaviourCheck::ALL.len()
                    + SceneCheck::ALL.len()
                    + c as usize
            }
        }
    }
}

impl From<PremiseKind> for Check {
    fn from(kind: PremiseKind) -> Check {
        Check::Premise(kind)
    }
}

impl fmt::Display for Check {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl Serialize for Check {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

#[cfg(feature = "schema")]
impl schemars::JsonSchema for Check {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "Check".into()
    }

    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        let names: Vec<&str> = Check::ALL.iter().map(|c| c.as_str()).collect();
        schemars::json_schema!({
            "description": "A check of the monitor: a premise of the certificate, a fail-safe check of the input, a behaviour of the robot, a scene's or a planar certificate's check.",
            "type": "string",
            "enum": names,
        })
    }
}

impl<'de> Deserialize<'de> for Check {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Check, D::Error> {
        let name = String::deserialize(d)?;
        Check::from_name(&name)
            .ok_or_else(|| serde::de::Error::custom(format!("unknown check `{name}`")))
    }
}

/// What the trace carried, which decides whether some premises can be monitored at all.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Carried {
    /// Some sample had `robot_mode`.
    pub(crate) mode: bool,
    /// Some sample had `obstacle_t`.
    pub(crate) observation_time: bool,
    /// Some sample had `obstacle_lane`.
    pub(crate) obstacle_lane: bool,
    /// Some sample had `obstacle_v`.
    pub(crate) obstacle_speed: bool,
}

/// How the monitor treats one premise (or scene check): its row in the per-check table.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PremiseCheck {
    /// Unit of observed values and the bound in events.
    pub(crate) unit: &'static str,
    /// Violated when observed is above (`>`) or below (`<`) the bound.
    pub(crate) relation: &'static str,
    /// Whether a bound of 0 is unusable (not only a negative one).
    pub(crate) positive: bool,
    /// Why it was not checked, when no sample gave the opportunity.
    pub(crate) not_checked: &'static str,
    /// Why it cannot be monitored on a trace that carried this (`None`: it can).
    pub(crate) not_monitored: fn(Carried) -> Option<&'static str>,
}

/// For premises every trace can monitor.
fn always_monitored(_: Carried) -> Option<&'static str> {
    None
}

impl PremiseCheck {
    /// The row of `kind`.
    pub(crate) fn of(kind: PremiseKind) -> &'static PremiseCheck {
        match kind {
            PremiseKind::ObstacleSpeed => &obstacle::OBSTACLE_SPEED,
            PremiseKind::BrakingDeceleration => &braking::BRAKING_DECELERATION,
            PremiseKind::ControlPeriod => &timing::CONTROL_PERIOD,
            PremiseKind::Latency => &timing::LATENCY,
            PremiseKind::FirstDetectionGap => &obstacle::FIRST_DETECTION_GAP,
            PremiseKind::ObservationNoise => &obstacle::OBSERVATION_NOISE,
            PremiseKind::SpeedNoise => &obstacle::SPEED_NOISE,
        }
    }
}

/// Numbers the per-sample checks derive from the bounds, computed once: each exactly as the
/// check would compute it per sample (the same operations in the same order), so verdicts,
/// observed values and margins are bit for bit what they were.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Fast {
    /// W + σ_w: the bound of a stated speed (m/s).
    pub(crate) stated_speed: f64,
    /// W + W·[`RELATIVE_TOLERANCE`](super::RELATIVE_TOLERANCE): an estimated speed at most
    /// this is within its bound whatever its slack (m/s).
    pub(crate) estimated_speed: f64,
    /// 2σ_g (m).
    pub(crate) noise: f64,
    /// The last span 2σ_g was divided by (NaN: none), and the quotient.
    pub(crate) noise_span: f64,
    pub(crate) noise_per_span: f64,
}

impl Fast {
    /// The numbers for `bounds`.
    pub(crate) fn of(bounds: &Bounds) -> Fast {
        let w = bounds.obstacle_speed;
        Fast {
            stated_speed: w + bounds.speed_noise,
            estimated_speed: w + super::RELATIVE_TOLERANCE * w,
            noise: 2.0 * bounds.observation_noise,
            noise_span: f64::NAN,
            noise_per_span: f64::NAN,
        }
    }
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
    /// σ_g (m).
    pub observation_noise: f64,
    /// σ_w (m/s); 0 when the certificate lists no `speed_noise` premise.
    pub speed_noise: f64,
}

impl Bounds {
    /// The bound of `check` (`None` for the fail-safe checks).
    pub fn of(&self, check: Check) -> Option<f64> {
        Some(match check.premise()? {
            PremiseKind::ObstacleSpeed => self.obstacle_speed,
            PremiseKind::BrakingDeceleration => self.braking_deceleration,
            PremiseKind::ControlPeriod => self.control_period,
            PremiseKind::Latency => self.latency,
            PremiseKind::FirstDetectionGap => self.first_detection_gap,
            PremiseKind::ObservationNoise => self.observation_noise,
            PremiseKind::SpeedNoise => self.speed_noise,
        })
    }

    /// The bounds of `premises` (the first of each kind), each finite and not negative (and
    /// positive where the check needs it, as for the control period). `speed_noise` may be
    /// absent: a certificate that does not list it was proved with exact speeds (σ_w = 0).
    pub fn from_premises(premises: &[Premise]) -> Result<Bounds, MonitorError> {
        let mut table: [Option<f64>; PremiseKind::COUNT] = [None; PremiseKind::COUNT];
        for p in premises {
            table[p.name.index()].get_or_insert(p.bound);
        }
        if table[PremiseKind::SpeedNoise.index()].is_none() {
            table[PremiseKind::SpeedNoise.index()] = Some(0.0);
        }
        let bound = |kind: PremiseKind| -> Result<f64, MonitorError> {
            let name = kind.name();
            let bound = table[kind.index()].ok_or(MonitorError::MissingPremise(name))?;
            let positive = PremiseCheck::of(kind).positive;
            if bound.is_finite() && bound >= 0.0 && (!positive || bound > 0.0) {
                Ok(bound)
            } else {
                Err(MonitorError::BadBound { name, bound })
            }
        };
        Ok(Bounds {
            obstacle_speed: bound(PremiseKind::ObstacleSpeed)?,
            braking_deceleration: bound(PremiseKind::BrakingDeceleration)?,
            control_period: bound(PremiseKind::ControlPeriod)?,
            latency: bound(PremiseKind::Latency)?,
            first_detection_gap: bound(PremiseKind::FirstDetectionGap)?,
            observation_noise: bound(PremiseKind::ObservationNoise)?,
            speed_noise: bound(PremiseKind::SpeedNoise)?,
        })
    }
}
