//! Safety per obstacle (DESIGN.md §1.1, "Safety"), computed exactly, step by step.
//!
//! For obstacle i, only the instants at which the robot moves (v > 0) and occupies lane ℓ_i
//! count. They fall into occupancy intervals (maximal, closed: lane 0 from t = 0, a target
//! lane from the start of the change into it, a lane left until the change out of it ends).
//! When an interval begins with the obstacle ahead (gap > 0), the measure over it is the gap;
//! otherwise (beside or behind) it is −gap. sep_i is the infimum of the measure; a collision
//! is an instant with measure ≤ clearance.
//!
//! Within a step the gap never grows (the robot moves forward, the obstacle towards −x) and
//! while the robot moves it strictly falls. So over a step's moving instants the gap's
//! infimum is at their end (the step's end, or the rest instant, where v = 0 and it is not
//! attained) and −gap's at their start (the step's start, not attained when v = 0 there:
//! only at t = 0). An unattained infimum is a collision only when it is below the clearance.

use crate::core::num::Scalar;

/// Which way an occupancy interval measures separation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// The obstacle was ahead when the interval began: the measure is the gap.
    Ahead,
    /// The obstacle was beside or behind: the measure is −gap.
    Behind,
}

impl Side {
    /// The side of an interval beginning with gap `gap`.
    pub fn of<N: Scalar>(gap: &N) -> Side {
        if *gap > N::zero() {
            Side::Ahead
        } else {
            Side::Behind
        }
    }
}

/// One step's share of an obstacle's safety.
#[derive(Clone, Debug, PartialEq)]
pub struct StepSafety<N> {
    /// Infimum of the measure over the step's moving instants.
    pub sep: N,
    /// Some moving instant of the step has measure ≤ clearance.
    pub collision: bool,
}

/// How the robot moved in a step, as safety needs it.
#[derive(Clone, Debug)]
pub struct MovingSpan<'a, N> {
    /// The robot's speed at the step start.
    pub start_speed: &'a N,
    /// It came to rest inside the step (its last moving instant is open).
    pub came_to_rest: bool,
}

/// The step's share of safety for an obstacle whose lane the robot occupies throughout the
/// step and in which it moves: `gap_start` at the step start, `gap_low` at the end of its
/// moving instants (rest instant or step end).
pub fn step_safety<N: Scalar>(
    side: Side,
    clearance: &N,
    gap_start: &N,
    gap_low: &N,
    span: &MovingSpan<'_, N>,
) -> StepSafety<N> {
    let (sep, attained) = match side {
        Side::Ahead => (gap_low.clone(), !span.came_to_rest),
        Side::Behind => (-gap_start.clone(), *span.start_speed > N::zero()),
    };
    let collision = if attained {
        sep <= *clearance
    } else {
        sep < *clearance
    };
    StepSafety { sep, collision }
}
