//! Safety itself (`collision`, docs/semantics.md §6 and §11.6): the robot never moves at a
//! separation ≤ clearance from an obstacle in a lane it occupies — at an instant, and within
//! the step before it.
//!
//! **At an instant** where the robot moves (`robot_v` > 0) the separation is the sample's.
//!
//! **Within the step.** Samples are instants; the robot moves in between. A robot that comes
//! to rest within the step did so at a gap the next sample does not show, and the gap at the
//! rest sample may already be negative (it collided while still moving). The step is checked
//! with the worst motion the premises allow, given what the two samples show:
//!
//! - the robot may have moved until [`Motion::until`]: the step's end, or, braking at b or
//!   harder from v₀ (as its positions confirm), t₀ + v₀/b. It is never beyond the position the
//!   next sample shows (it does not move backwards), and its position says that it moved
//!   ([`Motion::moved`]), whatever speed it reports;
//! - the obstacle moves monotonically between its two positions (the model's obstacle,
//!   Lemma 2) and approaches at up to its bound W (W_i for a scene's obstacle; a static one
//!   not at all): until the robot stops it may have come as near as y₀ − W·(until − t₀), but
//!   not nearer than where the next sample shows it. Where the two positions are farther
//!   apart than W allows (an `obstacle_speed` violation) only the nearer position bounds it.
//!
//! For an obstacle ahead the least separation is then max(min(y₀, y₁), y₀ − W·(until − t₀))
//! − x₁. A receding obstacle (y₁ > y₀, outside the model) may have stood at y₀ until the robot
//! reached x₁. For one beside or behind, the separation −gap only grows while both move as
//! the model's do; the least is at the robot's first moving instant, so a robot that sets off
//! from rest beside an obstacle is checked against its gap at the step's start. The noise is
//! taken in the robot's favour as everywhere in `collision`: a collision is reported when
//! every true separation within σ_g of the worst one is one. Because the worst obstacle of the
//! step is itself a behaviour of the model (its speeds in the step do not change what the
//! controller saw), a run of the model never has a worst step separation below s*: the
//! certified runs still raise nothing.

use super::{Motion, rounding};
use crate::monitor::event::{Detail, Violation};
use crate::monitor::{Check, Monitor, RELATIVE_TOLERANCE, Sample, Track};

impl Monitor {
    /// `collision` for the sample of an obstacle in a lane the robot occupies, on the side
    /// `ahead` (the separation is the gap, else minus the gap), the obstacle's speed bound
    /// `w`: at the instant when the robot moves, and over the step before it when it moved
    /// there (see the module docs).
    #[inline(always)]
    pub(in crate::monitor) fn check_separation(
        &mut self,
        s: &Sample,
        track: &Track,
        ahead: bool,
        w: f64,
    ) {
        let gap = s.obstacle_x - s.robot_x;
        if s.robot_v > 0.0 {
            // The usual case, an obstacle ahead that came no farther away: the gap is lowest
            // at the sample. Otherwise the step may hold a lower separation.
            let plain = if ahead {
                s.obstacle_x <= track.x || !track.seen
            } else {
                !self.motion.from_rest
            };
            if plain || track.ahead.is_none() {
                self.check_collision(s, if ahead { gap } else { -gap }, 0.0);
                return;
            }
        } else if !self.motion.moved || (track.seen && track.ahead.is_none()) {
            // At rest all step long, or not in the obstacle's lane at its last sample.
            return;
        }
        self.check_step(s, track, ahead, gap, w);
    }

    /// `collision` over the step: the least separation the premises allow while the robot
    /// moved (out of line: only a robot that stopped within the step, set off from rest or
    /// has an obstacle receding comes here).
    #[cold]
    #[inline(never)]
    fn check_step(&mut self, s: &Sample, track: &Track, ahead: bool, gap: f64, w: f64) {
        let Motion { until, .. } = self.motion;
        let until = if s.robot_v > 0.0 { s.t } else { until };
        let (y0, t0, y1) = (track.x, track.t, s.obstacle_x);
        let (separation, slack) = if !track.seen {
            // Nothing is known of it before: it was no nearer than it is now, if ahead.
            (if ahead { gap } else { f64::INFINITY }, 0.0)
        } else if ahead {
            let span = s.t - t0;
            let noise = 2.0 * self.bounds.observation_noise;
            let within =
                y0 - y1 <= w * span + noise + rounding(y0, y1) + w * (RELATIVE_TOLERANCE * span);
            let nearest = if within {
                y0 - w * (until - t0)
            } else {
                f64::NEG_INFINITY
            };
            let slack = rounding(y0, s.robot_x) + w * rounding(t0, until);
            (y0.min(y1).max(nearest) - s.robot_x, slack)
        } else {
            let at_start = if self.motion.from_rest && track.instant + 1 == self.instant {
                -track.gap
            } else {
                f64::INFINITY
            };
            let now = if s.robot_v > 0.0 { -gap } else { f64::INFINITY };
            (now.min(at_start), rounding(track.gap, 0.0))
        };
        if separation.is_finite() {
            self.check_collision_with(s, separation, slack, Some(Detail::WithinStep));
        }
    }

    /// `collision` at `separation` (the sample's, or the least of the step before it) with
    /// `extra` rounding of how it was derived.
    #[inline(always)]
    fn check_collision(&mut self, s: &Sample, separation: f64, extra: f64) {
        self.check_collision_with(s, separation, extra, None);
    }

    /// `collision`: the robot moves at `separation` ≤ clearance, less the rounding error of
    /// the gap (and `extra`) and the observation noise σ_g (taken in the robot's favour: a
    /// collision is reported only when every true gap the observation allows is one; so a
    /// full-precision trace of a safe run, or one with noise within σ_g, raises nothing).
    #[inline(always)]
    fn check_collision_with(
        &mut self,
        s: &Sample,
        separation: f64,
        extra: f64,
        detail: Option<Detail>,
    ) {
        let clearance = self.rule.clearance;
        self.count_with_slack(Check::Collision, separation - clearance, s.t);
        let slack = RELATIVE_TOLERANCE * clearance
            + rounding(s.obstacle_x, s.robot_x)
            + extra
            + self.bounds.observation_noise;
        if separation <= clearance - slack {
            let mut v = Violation::at(Check::Collision, s)
                .observed(separation)
                .bound(clearance);
            v.detail = detail;
            self.raise(v);
        }
    }
}
