//! The checks of what the model says beyond its premises (ModelPlex's three monitors,
//! DESIGN.md §3): that what was observed can be explained by the model
//! (`observation_inconsistent`, `observation_dropout`), that the robot did what the certified
//! controller does (`controller_reaction`, `robot_envelope`), and safety itself
//! (`collision`). Every certificate's monitor runs them.
//!
//! Their rows (unit, relation, reasons) are [`PremiseCheck`]s like the premises'; the checks
//! themselves are in `obstacle.rs` (`observation_inconsistent`), `controller.rs`
//! (`controller_reaction`, `robot_envelope`, `observation_dropout`), `motion.rs`
//! (`robot_motion`) and `collision.rs` (`collision`).

use super::{Carried, PremiseCheck};

/// A check of the model beyond its premises (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BehaviourCheck {
    /// The speed a sample states and the speed its positions imply differ by more than
    /// observation noise allows (σ_w + 2σ_g/Δt, plus rounding).
    ObservationInconsistent,
    /// An obstacle last observed inside the reaction area was missing from the next instant.
    ObservationDropout,
    /// The robot was neither braking nor at rest (nor, in a scene, changing lanes) at the
    /// instant its controller had an observation that showed danger or a wrong assumption.
    ControllerReaction,
    /// The robot's speed above v_max, or its acceleration between instants above a.
    RobotEnvelope,
    /// The robot's displacement between instants is not one its speeds, its mode and the
    /// certified dynamics allow (it moved while reporting speed 0, or farther or less far
    /// than its speeds explain).
    RobotMotion,
    /// The robot moved with an obstacle at a separation ≤ clearance: a collision, the
    /// gravest event, whatever the premises say.
    Collision,
}

impl BehaviourCheck {
    /// Every behaviour check, in output order.
    pub const ALL: [BehaviourCheck; 6] = [
        BehaviourCheck::ObservationInconsistent,
        BehaviourCheck::ObservationDropout,
        BehaviourCheck::ControllerReaction,
        BehaviourCheck::RobotEnvelope,
        BehaviourCheck::RobotMotion,
        BehaviourCheck::Collision,
    ];

    /// The stable name.
    pub const fn name(self) -> &'static str {
        match self {
            BehaviourCheck::ObservationInconsistent => "observation_inconsistent",
            BehaviourCheck::ObservationDropout => "observation_dropout",
            BehaviourCheck::ControllerReaction => "controller_reaction",
            BehaviourCheck::RobotEnvelope => "robot_envelope",
            BehaviourCheck::RobotMotion => "robot_motion",
            BehaviourCheck::Collision => "collision",
        }
    }

    /// Its row: unit, relation and reasons.
    pub(crate) fn row(self) -> &'static PremiseCheck {
        match self {
            BehaviourCheck::ObservationInconsistent => &OBSERVATION_INCONSISTENT,
            BehaviourCheck::ObservationDropout => &OBSERVATION_DROPOUT,
            BehaviourCheck::ControllerReaction => &CONTROLLER_REACTION,
            BehaviourCheck::RobotEnvelope => &ROBOT_ENVELOPE,
            BehaviourCheck::RobotMotion => &super::motion::ROBOT_MOTION,
            BehaviourCheck::Collision => &COLLISION,
        }
    }
}

/// `observation_inconsistent`: |stated − estimated speed| against σ_w + 2σ_g/Δt (m/s).
const OBSERVATION_INCONSISTENT: PremiseCheck = PremiseCheck {
    unit: "m/s",
    relation: ">",
    positive: false,
    not_checked: "no obstacle with obstacle_v was seen at two successive instants",
    not_monitored: speed_not_stated,
};

/// `observation_dropout`: the last gap seen of an obstacle that went missing, against ρ (m).
const OBSERVATION_DROPOUT: PremiseCheck = PremiseCheck {
    unit: "m",
    relation: "<=",
    positive: false,
    not_checked: "no obstacle was seen inside the reaction area",
    not_monitored: super::always_monitored,
};

/// `controller_reaction`: the observed gap that showed danger, against the distance at which
/// the controller must react, min(ρ, d(v)) (m).
const CONTROLLER_REACTION: PremiseCheck = PremiseCheck {
    unit: "m",
    relation: "<=",
    positive: false,
    not_checked: "no observation showed danger or a wrong assumption",
    not_monitored: mode_not_stated,
};

/// `robot_envelope`: the robot's speed against v_max, or its acceleration against a; the
/// event's detail says which (the two have different units, so none is given here).
const ROBOT_ENVELOPE: PremiseCheck = PremiseCheck {
    unit: "",
    relation: ">",
    positive: false,
    not_checked: "no instant",
    not_monitored: super::always_monitored,
};

/// `collision`: separation ≤ clearance while the robot moves, at an instant or within the
/// step before it (m).
const COLLISION: PremiseCheck = PremiseCheck {
    unit: "m",
    relation: "<=",
    positive: false,
    not_checked: "the robot never moved with an obstacle in a lane it occupies",
    not_monitored: super::always_monitored,
};

fn speed_not_stated(carried: Carried) -> Option<&'static str> {
    (!carried.obstacle_speed).then_some(
        "no sample carried obstacle_v, so stated speeds cannot be compared with positions",
    )
}

fn mode_not_stated(carried: Carried) -> Option<&'static str> {
    (!carried.mode)
        .then_some("no sample carried robot_mode, so what the controller did cannot be recognised")
}
