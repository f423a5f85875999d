//! A number or a range chosen adversarially: an obstacle's initial x in a scene, the initial
//! gap of a problem (`initial_gap = [8.0, 12.0]`).

use serde::{Deserialize, Serialize};

/// An initial position or gap: a number, or a range `[min, max]` whose every point the
/// environment may choose (the analysis covers them all).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(untagged)]
pub enum Position {
    /// Exactly here (m).
    At(f64),
    /// Anywhere in [min, max] (m).
    Range(f64, f64),
}

impl Position {
    /// The nearest possible value (m).
    pub fn min(&self) -> f64 {
        match *self {
            Position::At(x) => x,
            Position::Range(lo, _) => lo,
        }
    }

    /// The farthest possible value (m).
    pub fn max(&self) -> f64 {
        match *self {
            Position::At(x) => x,
            Position::Range(_, hi) => hi,
        }
    }

    /// Whether it is a range rather than one number (a range `[x, x]` is a range).
    pub fn is_range(&self) -> bool {
        matches!(self, Position::Range(..))
    }
}
