//! Random planar runs (issue 36, item 4): obstacles that keep a random heading and speed
//! and change them now and then, replayed exactly (`core::planar::PlanarReplay`). A
//! falsifier, not a proof: a collision it finds is a real behaviour's (exact replay); no
//! collision in N runs proves nothing.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::core::num::{Exact, exact_decimal};
use crate::core::planar::{
    ObstacleBehaviour, PlanarBehaviour, PlanarParams, PlanarReplay, Separation, Start, StepChoice,
};
use crate::core::plane::direction::RationalDirection;
use crate::core::plane::point::Point;

/// The most control periods one random run takes (it ends earlier when the robot rests).
pub const MAX_RUN_STEPS: usize = 3000;

/// The chance per step that an obstacle picks a new heading and speed.
const TURN_CHANCE: f64 = 0.2;

/// What the random runs found.
#[derive(Clone, Debug)]
pub struct PlanarMonteCarlo {
    /// Runs made.
    pub runs: usize,
    /// Runs with a collision while the robot moved (exact replay).
    pub collisions: usize,
    /// The run that came closest: its seed, behaviour and least separation.
    pub closest: Option<ClosestRun>,
}

/// The run that came closest.
#[derive(Clone, Debug)]
pub struct ClosestRun {
    /// Its seed.
    pub seed: u64,
    /// The obstacle that came closest.
    pub obstacle: usize,
    /// Its least separation (exact bracket) and when.
    pub separation: Separation,
    /// What every obstacle did.
    pub behaviour: PlanarBehaviour,
    /// Whether it collided.
    pub collided: bool,
}

/// `runs` random runs of `params`, run i seeded `seed + i`, each at most `steps` control
/// periods (it ends earlier when the robot rests).
pub fn planar_monte_carlo(
    params: &PlanarParams,
    runs: usize,
    seed: u64,
    steps: usize,
) -> PlanarMonteCarlo {
    let clearance = &params.motion.clearance;
    let results: Vec<ClosestRun> = (0..runs)
        .into_par_iter()
        .filter_map(|i| random_run(params, seed.wrapping_add(i as u64), steps, clearance))
        .collect();
    let collisions = results.iter().filter(|r| r.collided).count();
    let closest = results
        .into_iter()
        .min_by(|a, b| a.separation.upper.cmp(&b.separation.upper));
    PlanarMonteCarlo {
        runs,
        collisions,
        closest,
    }
}

/// One random run seeded `seed`, at most `steps` periods, judged against `clearance` (None:
/// the random starts or choices are not a behaviour of the problem, or no obstacle).
pub fn random_run(
    params: &PlanarParams,
    seed: u64,
    steps: usize,
    clearance: &Exact,
) -> Option<ClosestRun> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let starts: Vec<Point> = params
        .obstacles
        .iter()
        .map(|o| match &o.start {
            Start::At(p) => p.clone(),
            Start::Box { min, max } => Point::new(
                between(&mut rng, &min.x, &max.x),
                between(&mut rng, &min.y, &max.y),
            ),
        })
        .collect();
    let hides: Vec<bool> = params
        .obstacles
        .iter()
        .map(|_| params.sensing.first_detection.is_some() && rng.random_bool(0.5))
        .collect();
    let mut replay = PlanarReplay::new(params, &starts, &hides).ok()?;
    let mut velocities: Vec<Vec<Point>> = vec![Vec::new(); params.obstacles.len()];
    let mut current: Vec<Point> = params
        .obstacles
        .iter()
        .map(|o| random_velocity(&mut rng, o))
        .collect();
    while replay.k() < steps && !replay.stopped() {
        let mut choices = Vec::with_capacity(current.len());
        for (i, o) in params.obstacles.iter().enumerate() {
            if rng.random_bool(TURN_CHANCE) {
                current[i] = random_velocity(&mut rng, o);
            }
            let mut u = current[i].clone();
            if let Some(q) = &o.region {
                // Stay inside the region: a step that would leave it is spent standing.
                let next = &replay.centre(i).clone() + &(&u * &params.motion.dt);
                if !q.contains(&next) {
                    u = Point::origin();
                }
            }
            velocities[i].push(u.clone());
            choices.push(StepChoice::moving(u));
        }
        replay.step(&choices).ok()?;
    }
    let run = replay.finish();
    let (obstacle, separation) = run.closest()?;
    let collided = run.collides(clearance) == Some(true);
    let behaviour = PlanarBehaviour {
        obstacles: starts
            .into_iter()
            .zip(velocities)
            .zip(hides)
            .map(|((start, v), hide)| ObstacleBehaviour {
                hide,
                ..ObstacleBehaviour::moving(start, v)
            })
            .collect(),
    };
    Some(ClosestRun {
        seed,
        obstacle,
        separation,
        behaviour,
        collided,
    })
}

/// A velocity within the obstacle's bound, exactly: a random rational heading (or its fixed
/// direction) times W·u, u at 1 half the time, else uniform in [0, 1].
fn random_velocity(rng: &mut ChaCha8Rng, o: &crate::core::planar::PlanarObstacle) -> Point {
    let u: f64 = if rng.random_bool(0.5) {
        1.0
    } else {
        rng.random_range(0.0..1.0)
    };
    let speed = &o.max_speed * &exact_decimal(u);
    match &o.direction {
        Some(d) => d.unit() * &speed,
        None => {
            // A heading 2h, the half-angle h uniform in (−π/2, π/2) (all but ±0.06°).
            let h: f64 = rng.random_range(-1.5703..1.5703);
            let unit = RationalDirection::from_half_angle_tangent(&exact_decimal(h.tan()));
            unit.unit() * &speed
        }
    }
}

fn between(rng: &mut ChaCha8Rng, lo: &Exact, hi: &Exact) -> Exact {
    let f: f64 = rng.random_range(0.0..=1.0);
    lo + &(&(hi - lo) * &exact_decimal(f))
}
