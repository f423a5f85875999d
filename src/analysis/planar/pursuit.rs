//! Pursuit witnesses: behaviours built without the bound, for where the bound is loose and
//! its leaves' optima are no guide (docs/reductions.md §11.8). One obstacle runs at the
//! robot — each step towards where the robot's centre will be at the step's end — first at
//! a *stalking* speed (standing still, or V_a − σ_w, a hair less, which the
//! wrong-assumption guard does not read as too fast), then from a switch step on at full
//! speed W; when occlusion is possible it may also hide until first seen. Every other obstacle stands at its start. Each
//! candidate is replayed exactly; the least replay wins, and is an upper bound on s* like
//! any behaviour's.
//!
//! Velocities are chosen in floats and made exact on a 10⁻⁹ m/s grid (so that positions
//! keep small denominators through a long replay), then checked exactly against W and the
//! region; a step that would leave the region slides along one axis or halves, and a
//! candidate the problem still refuses is dropped.

use crate::core::num::{Exact, exact_decimal};
use crate::core::planar::{
    ObstacleBehaviour, PlanarBehaviour, PlanarParams, PlanarReplay, Start, StepChoice,
};
use crate::core::plane::point::Point;

use super::witness::Witness;

/// How many steps apart the switch steps are tried first; the best is then refined step by
/// step within this distance.
const SWITCH_STRIDE: usize = 4;

/// At most this many switch steps in the first pass over a long horizon.
const SWITCHES: usize = 64;

/// The least pursuit witness over every moving, free-direction obstacle of `params`, each
/// replayed for at most `steps` periods.
pub fn pursuit_witness(params: &PlanarParams, steps: usize) -> Option<Witness> {
    let mut best: Option<Witness> = None;
    for i in 0..params.obstacles.len() {
        let o = &params.obstacles[i];
        if o.direction.is_some() || o.max_speed == Exact::ZERO {
            continue;
        }
        for w in pursue(params, i, steps) {
            if better(&w, best.as_ref()) {
                best = Some(w);
            }
        }
    }
    best
}

fn better(w: &Witness, than: Option<&Witness>) -> bool {
    match (w.upper(), than.and_then(Witness::upper)) {
        (None, _) => false,
        (Some(_), None) => true,
        (Some(u), Some(b)) => u < b,
    }
}

/// Obstacle `i`'s best candidates: per hiding choice, the best switch step.
fn pursue(params: &PlanarParams, i: usize, steps: usize) -> Vec<Witness> {
    let m = &params.motion;
    let w = params.obstacles[i].max_speed.to_f64().value();
    let stalk = ((m.V_a.to_f64().value() - m.sigma_w.to_f64().value()) * (1.0 - 1e-6)).min(w);
    let hides: &[bool] = if params.sensing.first_detection.is_some() {
        &[false, true]
    } else {
        &[false]
    };
    let mut out = Vec::new();
    for (&hide, stalk) in hides.iter().flat_map(|h| [(h, 0.0), (h, stalk)]) {
        let mut best: Option<(usize, Witness)> = None;
        let mut tried = std::collections::BTreeSet::new();
        let mut try_switch = |switch: usize, best: &mut Option<(usize, Witness)>| {
            if switch > steps || !tried.insert(switch) {
                return;
            }
            if let Some(found) = candidate(params, i, stalk.max(0.0), switch, hide, steps)
                && better(&found, best.as_ref().map(|(_, b)| b))
            {
                *best = Some((switch, found));
            }
        };
        // Every candidate replays up to `steps` steps: a long horizon gets a coarser first
        // pass, so the work stays near SWITCHES · steps, not steps² / SWITCH_STRIDE.
        let stride = SWITCH_STRIDE.max(steps.div_ceil(SWITCHES));
        for switch in (0..=steps).step_by(stride) {
            try_switch(switch, &mut best);
        }
        // Then around the best, by halving the distance down to single steps.
        let mut reach = stride;
        while reach > SWITCH_STRIDE {
            reach = reach.div_ceil(2);
            if let Some((s, _)) = &best {
                let s = *s;
                try_switch(s.saturating_sub(reach), &mut best);
                try_switch(s + reach, &mut best);
            }
        }
        if let Some((s, _)) = &best {
            let s = *s;
            for switch in s.saturating_sub(SWITCH_STRIDE - 1)..=s + SWITCH_STRIDE - 1 {
                if switch != s {
                    try_switch(switch, &mut best);
                }
            }
        }
        out.extend(best.map(|(_, w)| w));
    }
    out
}

/// One pursuit: stalking speed until `switch`, then W.
fn candidate(
    params: &PlanarParams,
    i: usize,
    stalk: f64,
    switch: usize,
    hide: bool,
    steps: usize,
) -> Option<Witness> {
    let starts: Vec<Point> = params
        .obstacles
        .iter()
        .map(|o| match &o.start {
            Start::At(p) => p.clone(),
            Start::Box { min, max } => Point::new(
                (&min.x + &max.x) / Exact::from(2),
                (&min.y + &max.y) / Exact::from(2),
            ),
        })
        .collect();
    let mut hides = vec![false; starts.len()];
    hides[i] = hide;
    let mut replay = PlanarReplay::new(params, &starts, &hides).ok()?;
    let obstacle = &params.obstacles[i];
    let w = obstacle.max_speed.to_f64().value();
    let dt = params.motion.dt.to_f64().value();
    let mut velocities = Vec::new();
    while replay.k() < steps && !replay.stopped() {
        let k = replay.k();
        // Where the robot will be at this step's end: its motion in step k does not depend
        // on what the obstacles do in it (the guards read observation k − L).
        let aim = replay.robot_centre_after(&still(starts.len())).to_f64();
        let here = replay.centre(i).to_f64();
        let speed = if k < switch { stalk } else { w };
        let v = towards(here, aim, speed, dt, &obstacle.max_speed);
        let v = within_region(params, i, replay.centre(i), v, &params.motion.dt);
        let mut choices = still(starts.len());
        choices[i] = StepChoice::moving(v.clone());
        replay.step(&choices).ok()?;
        velocities.push(v);
    }
    let mut behaviour = PlanarBehaviour {
        obstacles: starts
            .iter()
            .map(|s| ObstacleBehaviour::moving(s.clone(), Vec::new()))
            .collect(),
    };
    behaviour.obstacles[i].velocities = velocities;
    behaviour.obstacles[i].hide = hide;
    Some(Witness {
        behaviour,
        run: replay.finish(),
    })
}

fn still(n: usize) -> Vec<StepChoice> {
    vec![StepChoice::moving(Point::origin()); n]
}

/// The velocity of norm at most `speed` (and W, exactly) from `here` towards `aim`, not
/// overshooting it within the step, on the 10⁻⁹ grid.
fn towards(here: (f64, f64), aim: (f64, f64), speed: f64, dt: f64, w: &Exact) -> Point {
    let (dx, dy) = (aim.0 - here.0, aim.1 - here.1);
    let d = dx.hypot(dy);
    if !(d.is_finite() && d > 0.0) {
        return Point::origin();
    }
    let s = speed.min(d / dt);
    let mut scale = 1.0 - 1e-9;
    let w2 = w * w;
    for _ in 0..8 {
        let v = grid_point(dx / d * s * scale, dy / d * s * scale);
        if v.norm_squared() <= w2 {
            return v;
        }
        scale *= 1.0 - 1e-6;
    }
    Point::origin()
}

fn grid_point(x: f64, y: f64) -> Point {
    let g = |v: f64| exact_decimal((v * 1e9).round() / 1e9);
    Point::new(g(x), g(y))
}

/// `v`, or its part along one of the region's edges (sliding along the boundary it meets),
/// or a fraction of it, so that a step of obstacle `i` from `here` stays inside its region
/// (zero when nothing does). Edges, not the frame's axes: the choice must not depend on
/// how the problem's frame is turned (tests/it/planar_rotation.rs).
fn within_region(params: &PlanarParams, i: usize, here: &Point, v: Point, dt: &Exact) -> Point {
    let Some(region) = &params.obstacles[i].region else {
        return v;
    };
    let inside = |u: &Point| region.contains(&(here + &(u * dt)));
    if inside(&v) {
        return v;
    }
    let corners = region.vertices();
    let along_edges = (0..corners.len()).map(|k| {
        let e = &corners[(k + 1) % corners.len()] - &corners[k];
        &e * &(v.dot(&e) / e.norm_squared())
    });
    if let Some(best) = along_edges.filter(inside).max_by_key(Point::norm_squared) {
        return best;
    }
    let mut u = v;
    for _ in 0..20 {
        u = &u * &(Exact::ONE / Exact::from(2));
        if inside(&u) {
            return u;
        }
    }
    Point::origin()
}
