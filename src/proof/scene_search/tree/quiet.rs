//! The steps at which nothing can happen: the stretch before the controller might react,
//! jumped in one go (Lemma R7), the run in which no guard can fire again (a leaf), and the
//! step at which the destination fires.

use crate::core::num::Scalar;
use crate::core::rational::Rational;
use crate::core::scene::SceneParams;
use crate::core::scene::lateral::Lateral;
use crate::core::semantics::danger_distance;
use crate::proof::scene_search::sense::Sense;

use super::{Node, Profile};

/// The first step after `node.k` at which the controller might do anything but go on, when
/// it can be told without branching: no obstacle of the robot's lane can be shown where a
/// guard reads it before then (observed gaps fall no faster than the robot's travel plus
/// W_i per period), and the destination does not fire before it. Where only danger can
/// fire ([`only_danger_fires`]) that is within min(ρ, d_i(v)), else within ρ: an obstacle
/// in the area but not dangerous moves nothing (`scene_guard`). Lane changes need danger,
/// so none begins before it either; obstacles of other lanes are read only for lane
/// changes. None when the robot might react now.
#[allow(clippy::too_many_arguments)]
pub(super) fn quiet_until(
    p: &SceneParams<Rational>,
    sense: &Sense,
    profile: &mut Profile,
    node: &Node,
    lateral: &Lateral,
    goal_step: Option<usize>,
    horizon: usize,
) -> Option<usize> {
    let k = node.k;
    let l = p.robot.L;
    let mut next = goal_step.unwrap_or(horizon + 1).min(horizon + 1);
    if k < l {
        // From step L on a lane without obstacles has nothing left to decide.
        next = next.min(l);
    }
    if next <= k {
        return None;
    }
    for (i, o) in p.obstacles.iter().enumerate() {
        if o.lane != lateral.lane {
            continue;
        }
        let chain = &node.chains[i];
        let first = k.saturating_sub(l).max(chain.last_step());
        let lowest = chain.reach_at(chain.last_step()).lo?.at;
        let guarded = only_danger_fires(p, sense, i);
        // First n ≥ first with lowest − W·dt·(n − last) − P_n ≤ θ_n (monotone in n: the
        // left side falls, θ_n = ρ or min(ρ, d(v_{n+L})) grows with the robot's speed).
        let near = |n: usize, profile: &mut Profile| {
            let fall = chain.w_max().clone()
                * p.robot.dt.clone()
                * Rational::int((n - chain.last_step()) as i64);
            // Some error shows it within θ_n iff its true gap is ≤ θ_n + σ_g.
            let gap =
                lowest.clone() - fall - profile.at(p, n).position.clone() - sense.sigma_g.clone();
            // θ_n ≤ ρ: beyond ρ there is no need to ask for d_i.
            gap <= p.robot.rho
                && (!guarded || gap <= fires_within(p, i, &profile.at(p, n + l).speed))
        };
        if near(first, profile) {
            return None;
        }
        // Only steps k' = n + L < next matter.
        let last = match next.checked_sub(l + 1) {
            Some(last) if last > first => last,
            _ => continue,
        };
        if !near(last, profile) {
            continue;
        }
        // near(lo) is false, near(hi) true: bisect for the first near step.
        let (mut lo, mut hi) = (first, last);
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if near(mid, profile) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        next = next.min(hi + l);
    }
    (next > k).then_some(next)
}

/// Whether obstacle i, seen within ρ, can move the controller only by danger: it is never
/// seen faster than V_a (static, the guard off, or W_i + σ_w ≤ V_a) and no occlusion
/// decides its sight at a read (a read of a hidden obstacle is a choice of the run).
fn only_danger_fires(p: &SceneParams<Rational>, sense: &Sense, i: usize) -> bool {
    let o = &p.obstacles[i];
    let wrong = p.robot.wrong_assumption_brake
        && !o.is_static
        && o.max_speed.clone() + sense.sigma_w.clone() > p.robot.V_a;
    sense.d_det.is_none() && !wrong
}

/// min(ρ, d_i(v)): the largest shown gap at which obstacle i is dangerous to a robot at
/// speed v (ρ under the area rule).
fn fires_within(p: &SceneParams<Rational>, i: usize, v: &Rational) -> Rational {
    match danger_distance(p.controller_for(i), v) {
        Some(d) if d < p.robot.rho => d,
        _ => p.robot.rho.clone(),
    }
}

/// Whether no guard can fire again at or after this step: every obstacle of the lane the
/// robot is in (or moving into) is already at a true gap ≤ −σ_g whatever it did, so it is
/// shown at a gap ≤ 0 whatever the error (true gaps never grow), and there is no goal.
pub(super) fn nothing_left(
    p: &SceneParams<Rational>,
    sense: &Sense,
    profile: &mut Profile,
    node: &Node,
    lateral: &Lateral,
    n: usize,
) -> bool {
    let seen_at = profile.at(p, n).position.clone();
    p.obstacles.iter().enumerate().all(|(i, o)| {
        o.lane != lateral.lane
            || node.chains[i]
                .reach_at(n.max(node.chains[i].last_step()))
                .hi
                .is_some_and(|h| h.at <= seen_at.clone() - sense.sigma_g.clone())
    })
}

/// G: the first step at whose start the robot, driving on, has x + v²/(2b) ≥ goal (None:
/// no goal, or not within the horizon).
pub(super) fn goal_step(
    p: &SceneParams<Rational>,
    profile: &mut Profile,
    horizon: usize,
) -> Option<usize> {
    let goal = p.goal.as_ref()?;
    let two_b = Rational::int(2) * p.robot.b.clone();
    (0..=horizon).find(|&k| {
        let s = profile.at(p, k);
        s.position.clone() + s.speed.clone() * s.speed.clone() / two_b.clone() >= *goal
    })
}
