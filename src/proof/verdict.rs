//! What an analysis concludes and what `check` re-derives: the three-valued verdict, and the
//! worst-case witness with the tolerances its replay is held to.

use serde::{Deserialize, Serialize};

use crate::core::simulate::TraceRow;
use crate::proof::schedule::Piece;
use crate::proof::witness_runs::ModeSegment;

/// A witness must replay to within this of its piece's optimum (m).
pub const REPLAY_TOLERANCE: f64 = 1e-6;
/// A witness's trace rows must match their exact replay to within this (m, s, m/s).
pub const TRACE_TOLERANCE: f64 = 1e-9;

/// Whether a stated trace row matches its exact replay's: modes equal, every number within
/// [`TRACE_TOLERANCE`].
pub fn rows_match(replayed: &TraceRow, stated: &TraceRow) -> bool {
    let close = |a: f64, b: f64| (a - b).abs() <= TRACE_TOLERANCE;
    let (a, b) = (replayed, stated);
    a.robot_mode == b.robot_mode
        && close(a.t, b.t)
        && close(a.robot_position, b.robot_position)
        && close(a.robot_speed, b.robot_speed)
        && close(a.obstacle_position, b.obstacle_position)
        && close(a.obstacle_speed, b.obstacle_speed)
        && close(a.gap, b.gap)
}

/// The three-valued answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "lowercase")]
pub enum Verdict {
    /// Rigorous lower bound on s* above the clearance.
    Certified,
    /// A concrete behaviour collides (replayed exactly).
    Refuted,
    /// Neither.
    Inconclusive,
}

impl Verdict {
    /// The word used in output.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Certified => "certified",
            Verdict::Refuted => "refuted",
            Verdict::Inconclusive => "inconclusive",
        }
    }
}

/// A concrete worst-case behaviour, replayed exactly.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct Witness {
    /// The piece it comes from.
    pub piece: Piece,
    /// For a merged piece, the number of whole steps the behaviour is shifted by.
    pub shift: usize,
    /// Margin its strict rows were kept inside (m).
    pub margin: f64,
    /// The obstacle's speed in each control period (after the last: W); stored in files as
    /// constant-speed segments ([`crate::proof::witness_runs::SpeedSegment`]).
    pub obstacle_speeds: crate::proof::witness_runs::Speeds,
    /// The robot's mode over the run, as segments of periods (`check` holds them to the
    /// replay).
    pub robot_modes: Vec<ModeSegment>,
    /// Occlusion, for a piece first seen inside the area at its early entry *or before*:
    /// the period whose observation first shows the obstacle (hidden before it). Other
    /// pieces fix it themselves ([`aim`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub first_seen: Option<usize>,
    /// The replay collides.
    pub collides: bool,
    /// Gap when the robot came to rest (None: it never stopped before colliding).
    pub separation: Option<f64>,
    /// One row at every period start plus the instant the robot came to rest: written only
    /// when asked (`certify --steps`, which replays the witness period by period for them),
    /// since it grows with the horizon; empty in the analyser's witness. `check` compares
    /// it with the replay when present.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub steps: Vec<TraceRow>,
}

impl Witness {
    /// The period from which the environment lets the robot react (its schedule's brake
    /// step; None for a pass-through, which never lets it): with noisy sensing the replay
    /// picks each observation's error by it ([`crate::core::simulate::run_reacting_at`]).
    pub fn react_at(&self) -> Option<usize> {
        self.aim().react_at
    }

    /// What the environment aims at in its replay: [`Witness::react_at`], and for a piece
    /// first seen late (occlusion) the obstacle hidden until then.
    pub fn aim(&self) -> crate::core::simulate::Aim {
        aim(&self.piece, self.shift, self.first_seen)
    }
}

/// What the environment aims at when it replays a behaviour of `piece` shifted by `shift`
/// steps: it lets the robot react from the brake step (never, for a pass-through), and for a
/// piece first seen late (occlusion) hides the obstacle until its sighting: `first_seen` if
/// given, else the piece's entry (a detected twin) or brake step.
pub fn aim(piece: &Piece, shift: usize, first_seen: Option<usize>) -> crate::core::simulate::Aim {
    let t = piece.brake + shift;
    let sighting = || first_seen.unwrap_or_else(|| piece.entry.map_or(t, |e| e + shift));
    crate::core::simulate::Aim {
        react_at: piece.has_objective().then_some(t),
        hidden_until: if piece.detected { sighting() } else { 0 },
    }
}
