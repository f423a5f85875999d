//! Witnesses: concrete behaviours built from the least leaf's optimum and replayed exactly
//! (`core::planar::run`), so that every upper bound on s* is a behaviour's own separation.
//!
//! The leaf's point holds the obstacle's start P, its centre X at the anchor instant and Y
//! at the leaf's first instant. Candidates for the worst obstacle:
//! - *through the anchor*: P → X at constant velocity until the anchor instant, then
//!   towards Y and on, each leg slowed by a factor 1 − δ for a few small δ (the optimum
//!   sits on the guard's threshold, where the guard fires: a hair slower it does not);
//!   when the first leg recedes from the robot (it may: speed is a norm, and the robot
//!   catches up), slowing brings X nearer the robot, so X is instead moved a few small
//!   distances ε directly away from the robot's centre at the anchor instant;
//! - *straight*: from P at full speed towards Y (along its direction, if fixed), all along.
//!
//! Every other obstacle stands at its start. A candidate the problem does not allow
//! (rounding put it outside its region or box) is dropped; the least replay wins.

use crate::core::num::{Exact, exact_decimal};
use crate::core::planar::{
    ObstacleBehaviour, PlanarBehaviour, PlanarObstacle, PlanarParams, PlanarRun, Start, run,
};
use crate::core::plane::direction::RationalDirection;
use crate::core::plane::point::Point;
use crate::proof::planar::trajectory::{BrakeTrajectory, DriveProfile};

use super::lower_bound::WorstLeaf;

/// A replayed behaviour: the adversary's choice and what it does to the robot.
#[derive(Clone, Debug)]
pub struct Witness {
    /// The behaviour.
    pub behaviour: PlanarBehaviour,
    /// Its exact replay.
    pub run: PlanarRun,
}

impl Witness {
    /// The least separation of its replay, from above (exact).
    pub fn upper(&self) -> Option<Exact> {
        self.run.closest().map(|(_, s)| s.upper)
    }
}

/// The least replayed candidate built from `worst`, replayed until the robot has had
/// time to rest after the leaf's instants.
pub fn witness(params: &PlanarParams, worst: &WorstLeaf) -> Option<Witness> {
    witness_untried(params, worst, &mut Vec::new())
}

/// [`witness`], skipping the candidates in `tried` (neighbouring leaves often build the
/// same behaviours; a replay is the costly part) and adding the new ones to it, each
/// with the number of steps it is replayed for.
pub fn witness_untried(
    params: &PlanarParams,
    worst: &WorstLeaf,
    tried: &mut Vec<(PlanarBehaviour, usize)>,
) -> Option<Witness> {
    let steps = steps_after(params, &worst.to);
    let mut best: Option<Witness> = None;
    for behaviour in candidates(params, worst) {
        let key = (behaviour, steps);
        if tried.contains(&key) {
            continue;
        }
        tried.push(key.clone());
        let behaviour = key.0;
        let Ok(run) = run(params, &behaviour, steps) else {
            continue;
        };
        let found = Witness { behaviour, run };
        let better = match (&best, found.upper()) {
            (_, None) => false,
            (None, Some(_)) => true,
            (Some(b), Some(u)) => b.upper().is_none_or(|bu| u < bu),
        };
        if better {
            best = Some(found);
        }
    }
    best
}

fn candidates(params: &PlanarParams, worst: &WorstLeaf) -> Vec<PlanarBehaviour> {
    let i = worst.obstacle;
    let obstacle = &params.obstacles[i];
    let dt = &params.motion.dt;
    let p = &worst.point;
    if p.len() < 7 {
        return Vec::new();
    }
    let start = match &obstacle.start {
        Start::At(q) => q.clone(),
        Start::Box { min, max } => clamp(&Point::decimal(p[1], p[2]), min, max),
    };
    let x = Point::decimal(p[3], p[4]);
    let y = Point::decimal(p[5], p[6]);
    let at = worst.from.clone();
    let anchor = worst
        .anchor_instant
        .map(|j| Exact::from(j) * dt)
        .unwrap_or(Exact::ZERO);
    let mut out = Vec::new();
    // Slowing the first leg moves X back towards P: away from the robot when the obstacle
    // approaches it, towards the robot when it recedes. A receding X is pushed out instead.
    let away = outward(params, &anchor, &x);
    let recedes = away
        .as_ref()
        .is_some_and(|a| (&x - &start).dot(a) > Exact::ZERO);
    let variants: Vec<(Exact, Point)> = match away {
        Some(away) if recedes => [0.0, 1e-9, 1e-8, 1e-7, 1e-5, 1e-3]
            .map(|e| (Exact::ONE, &x + &(&away * &exact_decimal(e))))
            .into(),
        _ => [0.0, 1e-9, 1e-7, 1e-5, 1e-3]
            .map(|d| (Exact::ONE - exact_decimal(d), x.clone()))
            .into(),
    };
    for (slow, x) in variants {
        let mut velocities = Vec::new();
        let steps_at = |t: &Exact| (t / dt).ceil().try_into().unwrap_or(0usize);
        let first = leg(obstacle, &start, &x, &anchor).map(|u| &u * &slow);
        let second = leg(obstacle, &x, &y, &(&at - &anchor)).map(|u| &u * &slow);
        let (Some(first), Some(second)) = (first, second) else {
            continue;
        };
        let k_anchor = steps_at(&anchor);
        let k_at = steps_at(&at).max(k_anchor) + 1;
        // A step that holds the anchor instant inside it would mix the legs; the anchor
        // instant is a step start (j·dt), so the legs meet there exactly.
        for k in 0..k_at + 1 {
            velocities.push(if k < k_anchor {
                first.clone()
            } else {
                second.clone()
            });
        }
        // And on, at full speed along the second leg's heading.
        if let Some(on) = full_speed(obstacle, &second) {
            velocities.extend(std::iter::repeat_n(on, steps_after(params, &at)));
        }
        out.push(with_others(
            params,
            i,
            ObstacleBehaviour::moving(start.clone(), velocities),
        ));
    }
    if let Some(u) = full_speed(obstacle, &(&y - &start)) {
        let n = steps_after(params, &Exact::ZERO);
        out.push(with_others(
            params,
            i,
            ObstacleBehaviour::moving(start.clone(), vec![u; n]),
        ));
    }
    out
}

/// A unit vector (to about 10⁻⁹) from the robot's centre at the instant `t` (on its drive
/// profile) towards `x`; None when `x` is that centre.
fn outward(params: &PlanarParams, t: &Exact, x: &Point) -> Option<Point> {
    let goal = params.path_ends.then(|| params.path.length());
    let mut profile = DriveProfile::new(params.motion.clone(), goal);
    let centre = BrakeTrajectory::new(&mut profile, None).centre_at(&mut profile, &params.path, t);
    let delta = Exact::ONE / Exact::from(1_000_000_000);
    RationalDirection::near(&(x - &centre), &delta)
        .ok()
        .map(|d| d.unit().clone())
}

/// The constant velocity from `a` to `b` in time `t` (zero when t = 0), within the bound
/// exactly (scaled down if the solver's rounding asks for more), along a fixed direction's
/// line if the obstacle has one.
fn leg(obstacle: &PlanarObstacle, a: &Point, b: &Point, t: &Exact) -> Option<Point> {
    if *t <= Exact::ZERO {
        return Some(Point::origin());
    }
    let d = b - a;
    let u = match &obstacle.direction {
        Some(dir) => {
            let w = dir.unit().dot(&d) / t;
            let w = if w < Exact::ZERO { Exact::ZERO } else { w };
            let w = if w > obstacle.max_speed {
                obstacle.max_speed.clone()
            } else {
                w
            };
            dir.unit() * &w
        }
        None => &d * &(Exact::ONE / t),
    };
    within_bound(obstacle, u)
}

/// `u` scaled down, if needed, so that ‖u‖ ≤ W holds exactly.
fn within_bound(obstacle: &PlanarObstacle, u: Point) -> Option<Point> {
    let w2 = &obstacle.max_speed * &obstacle.max_speed;
    if u.norm_squared() <= w2 {
        return Some(u);
    }
    let (ux, uy) = u.to_f64();
    let norm = ux.hypot(uy);
    if !norm.is_finite() || norm == 0.0 {
        return None;
    }
    let factor = exact_decimal(obstacle.max_speed.to_f64().value() / norm * (1.0 - 1e-12));
    let scaled = &u * &factor;
    (scaled.norm_squared() <= w2).then_some(scaled)
}

/// Full speed W along `towards` (a fixed direction: W·d when `towards` has d·towards ≥ 0).
fn full_speed(obstacle: &PlanarObstacle, towards: &Point) -> Option<Point> {
    let w = &obstacle.max_speed;
    match &obstacle.direction {
        Some(d) => (d.unit().dot(towards) >= Exact::ZERO).then(|| d.unit() * w),
        None => {
            let delta = Exact::ONE / Exact::from(1_000_000_000);
            let unit = RationalDirection::near(towards, &delta).ok()?;
            Some(unit.unit() * w)
        }
    }
}

/// Enough steps past `t` for the robot to brake to rest from any speed, plus margin.
pub(super) fn steps_after(params: &PlanarParams, t: &Exact) -> usize {
    let m = &params.motion;
    let span = t + &m.v_max / &m.b_min + &m.dt * Exact::from(4 + 2 * m.L);
    (span / &m.dt).ceil().try_into().unwrap_or(0)
}

fn clamp(p: &Point, min: &Point, max: &Point) -> Point {
    let c = |v: &Exact, lo: &Exact, hi: &Exact| {
        if v < lo {
            lo.clone()
        } else if v > hi {
            hi.clone()
        } else {
            v.clone()
        }
    };
    Point::new(c(&p.x, &min.x, &max.x), c(&p.y, &min.y, &max.y))
}

/// The behaviour where obstacle `i` does `this` and every other stands at its start.
fn with_others(params: &PlanarParams, i: usize, this: ObstacleBehaviour) -> PlanarBehaviour {
    let obstacles = params
        .obstacles
        .iter()
        .enumerate()
        .map(|(k, o)| {
            if k == i {
                this.clone()
            } else {
                let start = match &o.start {
                    Start::At(q) => q.clone(),
                    Start::Box { min, .. } => min.clone(),
                };
                ObstacleBehaviour::moving(start, Vec::new())
            }
        })
        .collect();
    PlanarBehaviour { obstacles }
}
