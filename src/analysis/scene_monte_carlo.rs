//! Monte Carlo over scenes: random obstacle behaviours (per obstacle, a speed pattern and,
//! for a range, a start), run through the scene semantics. Like the single-obstacle
//! [`monte_carlo`](super::monte_carlo), a cross-check beside the proofs: a certified scene
//! must never collide here.
//!
//! Reproducible: run i draws obstacle j's speeds from a ChaCha8 stream seeded with
//! `seed + i` on stream j, and the starts and patterns from stream `u64::MAX` of the same
//! seed. So obstacle 0 under [`SpeedPattern::Uniform`] gets exactly the speeds
//! [`random_speeds`](super::random_speeds) gives the single-obstacle run i.
//!
//! With `[sensing]` the environment also plays the observations as the single-obstacle
//! Monte Carlo does ([`LateObserver`]): every error makes the obstacle look farther and
//! slower (or already passed, where the noise allows), and with occlusion the odd runs
//! keep every obstacle hidden as late as the premise allows.
//!
//! As the single-obstacle Monte Carlo, runs step the semantics in the number type of the
//! parameters given: exact ones (what `simulate` uses) decide every guard as a replay does,
//! each drawn speed and start read as the decimal its float prints as.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::core::num::Scalar;
use crate::core::scene::SceneParams;
use crate::core::scene::simulate::{SceneRun, horizon, run_observing};
use crate::core::semantics::Observation;

/// How an obstacle picks its speed each period in a random run (W = its bound W_i).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum SpeedPattern {
    /// Uniform in (0, W] each period, independently (the single-obstacle Monte Carlo's).
    Uniform,
    /// One speed, uniform in [0, W], for the whole run.
    Constant,
    /// A random walk: a uniform start in [0, W], then each period a step uniform in
    /// [−W/4, W/4], kept inside [0, W].
    RandomWalk,
    /// Bang-bang: 0 or W, starting at either, switching with probability 1/8 each period.
    BangBang,
}

impl SpeedPattern {
    /// Every pattern.
    pub const ALL: [SpeedPattern; 4] = [
        SpeedPattern::Uniform,
        SpeedPattern::Constant,
        SpeedPattern::RandomWalk,
        SpeedPattern::BangBang,
    ];
}

/// One obstacle's speed source in a random run.
#[derive(Clone, Debug)]
struct Source {
    pattern: SpeedPattern,
    bound: f64,
    rng: ChaCha8Rng,
    /// The speed of the last period drawn (None before the first).
    last: Option<f64>,
}

impl Source {
    fn next(&mut self) -> f64 {
        let w = self.bound;
        let speed = match (self.pattern, self.last) {
            (SpeedPattern::Uniform, _) => w * (1.0 - self.rng.random::<f64>()),
            (SpeedPattern::Constant | SpeedPattern::RandomWalk, None) => {
                w * self.rng.random::<f64>()
            }
            (SpeedPattern::Constant, Some(s)) => s,
            (SpeedPattern::RandomWalk, Some(s)) => {
                let step = w / 4.0 * (2.0 * self.rng.random::<f64>() - 1.0);
                (s + step).clamp(0.0, w)
            }
            (SpeedPattern::BangBang, None) => {
                if self.rng.random::<bool>() {
                    w
                } else {
                    0.0
                }
            }
            (SpeedPattern::BangBang, Some(s)) => {
                if self.rng.random_ratio(1, 8) {
                    w - s
                } else {
                    s
                }
            }
        };
        self.last = Some(speed);
        speed
    }
}

/// The random behaviour of one Monte Carlo run: each obstacle's start and speed pattern,
/// and its speeds drawn as the run asks for them.
#[derive(Clone, Debug)]
pub struct RandomBehaviour {
    /// Each obstacle's start: its number, or uniform in its range.
    pub starts: Vec<f64>,
    /// Each obstacle's speed pattern.
    pub patterns: Vec<SpeedPattern>,
    sources: Vec<Source>,
}

impl RandomBehaviour {
    /// The behaviour of run `run` of a Monte Carlo with `seed`, each obstacle's pattern drawn
    /// uniformly from `patterns`.
    ///
    /// # Panics
    /// If `patterns` is empty.
    pub fn new(
        params: &SceneParams<f64>,
        seed: u64,
        run: usize,
        patterns: &[SpeedPattern],
    ) -> RandomBehaviour {
        assert!(!patterns.is_empty(), "at least one speed pattern");
        let run_seed = seed.wrapping_add(run as u64);
        let mut choices = ChaCha8Rng::seed_from_u64(run_seed);
        choices.set_stream(u64::MAX);
        let mut starts = Vec::new();
        let mut chosen = Vec::new();
        let mut sources = Vec::new();
        for (j, o) in params.obstacles.iter().enumerate() {
            let span = o.start_max - o.start_min;
            let start = if span > 0.0 {
                (o.start_min + span * choices.random::<f64>()).min(o.start_max)
            } else {
                o.start_min
            };
            let pattern = patterns[choices.random_range(0..patterns.len())];
            let mut rng = ChaCha8Rng::seed_from_u64(run_seed);
            rng.set_stream(j as u64);
            starts.push(start);
            chosen.push(pattern);
            sources.push(Source {
                pattern,
                bound: o.max_speed,
                rng,
                last: None,
            });
        }
        RandomBehaviour {
            starts,
            patterns: chosen,
            sources,
        }
    }

    /// Obstacle `i`'s speed in its next period (a run asks for periods in order).
    pub fn next_speed(&mut self, i: usize) -> f64 {
        self.sources[i].next()
    }
}

/// The observations of a random run with `[sensing]`: what keeps the robot from reacting
/// for as long as the premises allow.
///
/// - **Errors**: each observation's gap is shown σ_g farther, or σ_g nearer where that
///   shows it already passed (≤ 0); its speed σ_w slower (not the speed read before any
///   period has ended, the initial 0). With one obstacle this keeps the guard quiet exactly
///   when some error can (as `World::seen` does), so a one-obstacle scene runs as the
///   single-obstacle Monte Carlo.
/// - **Occlusion** (`hide_late`): an obstacle stays hidden while its next observation is
///   sure to show a true gap ≥ d_det (a gap falls by at most (v_max + W_i)·dt per period),
///   and is shown from the last observation that surely does — a pedestrian stepping out
///   as late as the premise allows (`simulate::run_hiding_late`).
#[derive(Clone, Debug)]
pub struct LateObserver<N> {
    sigma_g: N,
    sigma_w: N,
    /// Per obstacle: the least true gap it may still be hidden at (None: shown).
    hide_above: Vec<Option<N>>,
    latency: usize,
}

impl<N: Scalar> LateObserver<N> {
    /// The observer of a run; `hide_late`: hide every obstacle as late as allowed (only
    /// with occlusion).
    pub fn new(params: &SceneParams<N>, hide_late: bool) -> LateObserver<N> {
        let p = &params.robot;
        let hide_above = params
            .obstacles
            .iter()
            .map(|o| match (&p.d_det, hide_late) {
                (Some(d), true) => {
                    Some(d.clone() + (p.v_max.clone() + o.max_speed.clone()) * p.dt.clone())
                }
                _ => None,
            })
            .collect();
        LateObserver {
            sigma_g: p.sigma_g.clone(),
            sigma_w: p.sigma_w.clone(),
            hide_above,
            latency: p.L,
        }
    }

    /// What the robot is shown of obstacle i at step k's start, whose true observation is
    /// `truth` (None: hidden).
    pub fn show(&mut self, i: usize, k: usize, truth: Observation<N>) -> Option<Observation<N>> {
        if let Some(above) = &self.hide_above[i] {
            if truth.gap >= *above {
                return None;
            }
            self.hide_above[i] = None;
        }
        let gap = if truth.gap.clone() - self.sigma_g.clone() <= N::zero() {
            truth.gap - self.sigma_g.clone()
        } else {
            truth.gap + self.sigma_g.clone()
        };
        let speed = if k > self.latency {
            truth.speed - self.sigma_w.clone()
        } else {
            truth.speed
        };
        Some(Observation { gap, speed })
    }
}

/// Monte Carlo run `run` of a scene: [`RandomBehaviour::new`]'s speeds and starts, and with
/// `[sensing]` the [`LateObserver`]'s observations (hiding late in the odd runs), until the
/// robot rests, collides (if `stop_at_collision`), nothing can happen any more, or
/// `max_steps` periods. `simulate --trace` replays the closest run so.
pub fn scene_monte_carlo_run<N: Scalar>(
    params: &SceneParams<N>,
    seed: u64,
    run: usize,
    patterns: &[SpeedPattern],
    max_steps: usize,
    stop_at_collision: bool,
) -> SceneRun<N> {
    let mut behaviour = RandomBehaviour::new(&params.map(Scalar::as_f64), seed, run, patterns);
    let starts = behaviour.starts.iter().map(|&x| N::decimal(x)).collect();
    let hide_late = params.robot.d_det.is_some() && run % 2 == 1;
    let mut observer = LateObserver::new(params, hide_late);
    run_observing(
        params.clone(),
        |j, _| N::decimal(behaviour.next_speed(j)),
        |i, k, truth| observer.show(i, k, truth),
        starts,
        max_steps,
        stop_at_collision,
    )
}

/// One obstacle's share of a Monte Carlo summary.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct ObstacleMonteCarlo {
    /// Its name.
    pub name: String,
    /// Runs in which the robot collided with it.
    pub collisions: usize,
    /// Its least separation seen, over all runs (m); None: the robot never moved in its lane.
    pub min_separation: Option<f64>,
}

/// Monte Carlo summary of a scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct SceneMonteCarlo {
    /// Runs simulated.
    pub runs: usize,
    /// Runs that collided (with any obstacle).
    pub collisions: usize,
    /// The least separation seen, over all runs and obstacles (m); None: the robot never
    /// moved in any obstacle's lane.
    pub min_separation: Option<f64>,
    /// The obstacle of that least separation.
    pub closest_obstacle: Option<String>,
    /// The run of that least separation.
    pub closest_run: usize,
    /// Seed of the first run; run i uses seed + i.
    pub seed: u64,
    /// Per obstacle, in the scene's order.
    pub obstacles: Vec<ObstacleMonteCarlo>,
}

/// Simulates `runs` random behaviours of the scene (each obstacle's pattern drawn from
/// `patterns`), each until the robot rests, collides, or nothing can happen any more.
pub fn scene_monte_carlo<N: Scalar>(
    params: &SceneParams<N>,
    runs: usize,
    seed: u64,
    patterns: &[SpeedPattern],
) -> SceneMonteCarlo {
    let max = horizon(&params.map(Scalar::as_f64));
    let mut least: Option<N> = None;
    let mut summary = SceneMonteCarlo {
        runs,
        collisions: 0,
        min_separation: None,
        closest_obstacle: None,
        closest_run: 0,
        seed,
        obstacles: params
            .obstacles
            .iter()
            .map(|o| ObstacleMonteCarlo {
                name: o.name.clone(),
                collisions: 0,
                min_separation: None,
            })
            .collect(),
    };
    for i in 0..runs {
        let outcome = scene_monte_carlo_run(params, seed, i, patterns, max, true).outcome;
        summary.collisions += usize::from(outcome.collided);
        for (total, o) in summary.obstacles.iter_mut().zip(&outcome.obstacles) {
            total.collisions += usize::from(o.collided);
            if let Some(s) = &o.sep {
                let s = s.as_f64();
                total.min_separation = Some(total.min_separation.map_or(s, |m| m.min(s)));
            }
        }
        if let Some((j, s)) = outcome.min_separation()
            && least.as_ref().is_none_or(|m| s < *m)
        {
            summary.min_separation = Some(s.as_f64());
            least = Some(s);
            summary.closest_obstacle = Some(params.obstacles[j].name.clone());
            summary.closest_run = i;
        }
    }
    summary
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::monte_carlo;
    use crate::core::model::Problem;
    use crate::core::rational::Rational;
    use crate::core::scene::{Obstacle, Position, Scene};

    fn seed_problem(w: f64) -> Problem {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/seed.toml");
        let mut p = Problem::load(std::path::Path::new(path)).expect("the shipped seed reads");
        p.environment.obstacle_speed = w;
        p
    }

    /// A one-obstacle scene under the uniform pattern is today's Monte Carlo, run for run:
    /// the same collisions, least separation and closest run — with noise and occlusion
    /// too (the same errors' effect, the same late sightings).
    #[test]
    fn uniform_one_obstacle_scene_is_the_single_obstacle_monte_carlo() {
        let sensings = [
            None,
            Some((0.02, 0.05, None)),
            Some((0.0, 0.0, Some(0.5))),
            Some((0.03, 0.02, Some(1.1))),
        ];
        for (w, sensing) in [0.15, 0.3, 0.6]
            .into_iter()
            .flat_map(|w| sensings.map(|s| (w, s)))
        {
            let mut problem = seed_problem(w);
            problem.sensing = sensing.map(|(g, s, d)| crate::core::model::Sensing {
                gap_noise: Some(g),
                speed_noise: Some(s),
                first_detection_gap: d,
            });
            let old = monte_carlo(&problem.params::<Rational>(), 200, 7);
            let scene = Scene::from_problem(&problem);
            let new = scene_monte_carlo(
                &scene.params::<Rational>(),
                200,
                7,
                &[SpeedPattern::Uniform],
            );
            assert_eq!(old.collisions, new.collisions, "W = {w}, {sensing:?}");
            assert_eq!(
                Some(old.min_separation),
                new.min_separation,
                "W = {w}, {sensing:?}"
            );
            assert_eq!(old.closest_run, new.closest_run, "W = {w}, {sensing:?}");
            assert_eq!(new.closest_obstacle.as_deref(), Some("obstacle-0"));
            assert_eq!(new.obstacles[0].collisions, new.collisions);
            if sensing.is_none() {
                assert_eq!(
                    new.collisions > 0,
                    w > 0.5,
                    "only the fastest obstacle hits"
                );
            }
        }
    }

    /// An obstacle in a lane the robot never enters changes nothing for the others and is
    /// never measured.
    #[test]
    fn an_obstacle_out_of_the_robots_lanes_changes_nothing() {
        let problem = seed_problem(0.3);
        let alone = Scene::from_problem(&problem);
        let mut crowded = alone.clone();
        crowded.lanes = vec![0, 1];
        crowded.obstacles.push(Obstacle {
            name: "beside".into(),
            lane: 1,
            position: Position::Range(1.0, 3.0),
            max_speed: 0.4,
            is_static: false,
        });
        let patterns = &SpeedPattern::ALL;
        let a = scene_monte_carlo(&alone.params::<Rational>(), 100, 3, patterns);
        let b = scene_monte_carlo(&crowded.params::<Rational>(), 100, 3, patterns);
        assert_eq!(a.collisions, b.collisions);
        assert_eq!(a.min_separation, b.min_separation);
        assert_eq!(a.obstacles[0], b.obstacles[0]);
        assert_eq!(b.obstacles[1].min_separation, None);
    }

    /// Every pattern keeps speeds in [0, W] and has its shape; starts fall in their ranges.
    #[test]
    fn patterns_have_their_shapes_and_bounds() {
        let mut scene = Scene::from_problem(&seed_problem(0.3));
        scene.obstacles[0].position = Position::Range(8.0, 12.0);
        let params: SceneParams<f64> = scene.params();
        for pattern in SpeedPattern::ALL {
            for run in 0..50 {
                let mut b = RandomBehaviour::new(&params, 11, run, &[pattern]);
                assert!((8.0..=12.0).contains(&b.starts[0]));
                let speeds: Vec<f64> = (0..200).map(|_| b.next_speed(0)).collect();
                assert!(
                    speeds.iter().all(|s| (0.0..=0.3).contains(s)),
                    "{pattern:?}"
                );
                let shaped = match pattern {
                    SpeedPattern::Uniform => speeds.iter().all(|&s| s > 0.0),
                    SpeedPattern::Constant => speeds.iter().all(|&s| s == speeds[0]),
                    SpeedPattern::RandomWalk => speeds
                        .windows(2)
                        .all(|w| (w[1] - w[0]).abs() <= 0.075 + 1e-15),
                    SpeedPattern::BangBang => speeds.iter().all(|&s| s == 0.0 || s == 0.3),
                };
                assert!(shaped, "{pattern:?}, run {run}");
            }
        }
    }

    /// The closest run, run again from its seed, gives the least separation reported.
    #[test]
    fn the_closest_run_replays_to_the_reported_separation() {
        let mut scene = Scene::from_problem(&seed_problem(0.25));
        scene.lanes = vec![0, 1];
        scene.obstacles.push(Obstacle {
            name: "second".into(),
            lane: 0,
            position: Position::Range(6.0, 14.0),
            max_speed: 0.25,
            is_static: false,
        });
        let params: SceneParams<f64> = scene.params();
        let mc = scene_monte_carlo(&params, 100, 5, &SpeedPattern::ALL);
        let again = scene_monte_carlo_run(
            &params,
            5,
            mc.closest_run,
            &SpeedPattern::ALL,
            horizon(&params),
            true,
        );
        let (j, sep) = again.outcome.min_separation().expect("moved");
        assert_eq!(Some(sep), mc.min_separation);
        assert_eq!(
            Some(&params.obstacles[j].name),
            mc.closest_obstacle.as_ref()
        );
    }
}
