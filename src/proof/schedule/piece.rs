//! Schedule pieces: how a piece's schedule ends and which behaviours one piece stands for.

use serde::{Deserialize, Serialize};

/// How a piece's schedule ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum Ending {
    /// Brakes at T on collision danger.
    Danger,
    /// Brakes at T on seeing the obstacle faster than V_a.
    WrongAssumption,
    /// Never brakes: the observed gap jumps from outside the area to ≤ 0 at T.
    PassThrough,
    /// In a scene: the robot brakes at T for another reason (another obstacle fired, or
    /// the destination) while this obstacle fired at no step before T. Only schedule rows;
    /// the objective is this obstacle's gap when the robot rests.
    Bystander,
}

/// One schedule piece: a set of behaviours whose worst case is one linear program.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct Piece {
    /// First step whose observation is in the reaction area (only with the
    /// wrong-assumption guard active).
    pub entry: Option<usize>,
    /// The step T at whose start the robot brakes (pass-through: first observation ≤ 0).
    pub brake: usize,
    /// Why the schedule ends at T.
    pub ending: Ending,
    /// Stands for this piece and all its shifts by whole steps (T+j, E+j for j ≥ 0).
    pub merged: bool,
    /// The obstacle entered the area at `entry` *or earlier*: every entry E ≤ T−2 has the
    /// same rows from step T−2 on, so one piece stands for all of them.
    #[serde(default)]
    pub early: bool,
    /// Occlusion: the obstacle was hidden at every earlier step and is first seen at T, at
    /// a true gap ≥ d_det (`sensing.first_detection_gap`); no schedule rows before T.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub detected: bool,
}

impl Piece {
    /// The single piece a merged piece stands for at brake step `t` (its shift by
    /// t − brake), or None when `t` is not one of its shifts. An unmerged piece stands only
    /// for itself.
    pub fn shifted_to(&self, t: usize) -> Option<Piece> {
        let j = t.checked_sub(self.brake)?;
        if j > 0 && !self.merged {
            return None;
        }
        Some(Piece {
            brake: t,
            entry: self.entry.map(|e| e + j),
            merged: false,
            ..*self
        })
    }

    /// Whether the piece's objective is a separation (else it is a feasibility question).
    pub fn has_objective(&self) -> bool {
        self.ending != Ending::PassThrough
    }

    /// The piece in words, for messages: "braking on danger at step 253 (and every later
    /// shift)".
    pub fn describe(&self) -> String {
        let mut s = format!(
            "{} at step {}",
            match self.ending {
                Ending::Danger => "braking on danger",
                Ending::WrongAssumption => "braking on a wrong assumption",
                Ending::PassThrough => "passing through without braking",
                Ending::Bystander => "braking for another reason",
            },
            self.brake
        );
        if let Some(e) = self.entry {
            let when = if self.early { "by" } else { "at" };
            s += &format!(", in the area {when} step {e}");
        }
        if self.detected {
            s += if self.entry.is_some() {
                ", first seen in the area"
            } else {
                ", first seen then"
            };
        }
        if self.merged {
            s += " (and every later shift)";
        }
        s
    }
}
