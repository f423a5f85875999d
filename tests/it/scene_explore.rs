//! The scene explorer (`safereach::crosscheck::explore::scene`) held against what is known
//! independently (docs/crosschecks.md, "Scenes"):
//!
//! - the scene analyser, on small scenes without lane changes: explorer collision ⇒
//!   `refuted`; every explored separation ≥ the analyser's exact lower bound and its s*
//!   (− 1e-9), per obstacle and overall; with speed sets that contain the analyser's witness
//!   speeds, the explorer's least separation equals s*;
//! - the single-obstacle explorer, on one-obstacle scenes: the same verdict, least
//!   separation (exactly), never-stopping behaviours and shortest counterexample length;
//! - a search without any state abstraction (every field of the world, in big rationals), on
//!   scenes with lane changes, goals and sensing ranges: the same answers;
//! - hand-derived answers for lane changes: a free lane saves the robot, an occupied one is
//!   refused and braking alone collides, the other side is taken;
//! - replays from scratch of every path it reports, and the CLI.

use std::collections::{HashMap, VecDeque};

use rand::{Rng, SeedableRng};
use safereach::analysis::Verdict;
use safereach::analysis::scene::{SceneAnalysis, analyse_scene};
use safereach::core::model::DangerRule;
use safereach::core::num::{Exact, exact_decimal, exact_float};
use safereach::core::scene::safety::Side;
use safereach::core::scene::{
    LaneChange, Obstacle, Position, Scene, SceneParams, SceneWorld, simulate,
};
use safereach::core::semantics::{BrakeReason, Mode};
use safereach::crosscheck::explore::scene::{
    SceneExploration, SceneModel, ScenePath, SceneSpeeds, explore_scene, explore_scene_model,
};
use safereach::crosscheck::explore::{self, ExploreVerdict, Options, SpeedSet};
use serde_json::Value;

use crate::common::cli::{safereach, stdout};
use crate::common::paths::{problem_file, seed_file};
use crate::common::spec::Spec;
use crate::common::tmp;

// ---------------------------------------------------------------------------------------------
// Scenes
// ---------------------------------------------------------------------------------------------

fn obstacle(name: &str, lane: i32, x: f64, w: f64, is_static: bool) -> Obstacle {
    Obstacle {
        name: name.into(),
        lane,
        position: Position::At(x),
        max_speed: w,
        is_static,
    }
}

/// A coarse robot: v_max reached in one 0.5 s period, two periods to stop, so that
/// obstacles a few metres ahead are passed or braked for within a dozen periods.
fn coarse(latency: u32, rule: DangerRule, wab: bool) -> Spec {
    Spec {
        name: "scene-explore",
        v_max: 0.5,
        a: 0.5,
        b: 0.5,
        dt: 0.5,
        latency,
        clearance: 0.0,
        v_a: 0.2,
        rho: 1.2,
        rule,
        buffer: 0.1,
        wab,
        w: 0.1,
        g0: 2.0,
    }
}

/// The scene of `spec`'s robot and controller with `obstacles` (lanes: those used, with 0).
fn scene_of(spec: &Spec, obstacles: Vec<Obstacle>) -> Scene {
    let mut scene = Scene::from_problem(&spec.problem());
    let mut lanes: Vec<i32> = obstacles.iter().map(|o| o.lane).chain([0]).collect();
    lanes.sort();
    lanes.dedup();
    scene.lanes = lanes;
    scene.obstacles = obstacles;
    scene
}

fn valid(scene: Scene) -> Scene {
    scene.validate("test").expect("test scenes are valid");
    scene
}

const RULES: [DangerRule; 3] = [DangerRule::Paper, DangerRule::Kinematic, DangerRule::Area];

/// Small scenes without lane changes, drawn from a fixed seed: two or three obstacles in
/// lane 0 (moving or static), sometimes a goal, sometimes a moving obstacle in lane 1.
fn small_scenes(n: usize, seed: u64) -> Vec<Scene> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let spec = Spec {
                clearance: [0.0, 0.05][rng.random_range(0..2)],
                rho: [0.8, 1.2, 2.0][rng.random_range(0..3)],
                ..coarse(
                    rng.random_range(0..=2),
                    RULES[rng.random_range(0..3)],
                    rng.random(),
                )
            };
            let count = rng.random_range(2..=3);
            let mut obstacles: Vec<Obstacle> = (0..count)
                .map(|i| {
                    let x = f64::from(rng.random_range(12..=60u32)) / 20.0;
                    let is_static = rng.random_range(0..3) == 0;
                    let w = if is_static {
                        0.0
                    } else {
                        [0.0, 0.1, 0.2, 0.3][rng.random_range(0..4)]
                    };
                    obstacle(&format!("o{i}"), 0, x, w, is_static)
                })
                .collect();
            if rng.random_range(0..3) == 0 {
                obstacles.push(obstacle("beside", 1, 1.0, 0.3, false));
            }
            let mut scene = scene_of(&spec, obstacles);
            if rng.random_range(0..3) == 0 {
                scene.goal = Some(f64::from(rng.random_range(4..=16u32)) / 4.0);
            }
            valid(scene)
        })
        .collect()
}

/// Small scenes with everything the simulator runs: obstacles in lanes −1..1 (at most two
/// moving), lane changes on most of the time, sometimes a goal or a sensing range.
fn lane_scenes(n: usize, seed: u64) -> Vec<Scene> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let spec = Spec {
                clearance: [0.0, 0.05][rng.random_range(0..2)],
                rho: [0.8, 1.2][rng.random_range(0..2)],
                ..coarse(
                    rng.random_range(0..=2),
                    RULES[rng.random_range(0..3)],
                    rng.random(),
                )
            };
            let count = rng.random_range(1..=3);
            let obstacles: Vec<Obstacle> = (0..count)
                .map(|i| {
                    let lane = [0, 0, 1, -1][rng.random_range(0..4)];
                    let x = f64::from(rng.random_range(20..=60u32)) / 20.0;
                    let is_static = i == 2 || rng.random_range(0..3) == 0;
                    let w = if is_static {
                        0.0
                    } else {
                        [0.1, 0.3][rng.random_range(0..2)]
                    };
                    obstacle(&format!("o{i}"), lane, x, w, is_static)
                })
                .collect();
            let mut scene = scene_of(&spec, obstacles);
            scene.lanes = vec![-1, 0, 1];
            if rng.random_range(0..3) > 0 {
                scene.lane_change = Some(LaneChange {
                    periods: rng.random_range(1..=3),
                    rear_gap: 0.3,
                });
            }
            if rng.random_range(0..3) == 0 {
                scene.goal = Some(f64::from(rng.random_range(4..=12u32)) / 4.0);
            }
            if rng.random_range(0..4) == 0 {
                scene.sensing_range = Some(spec.rho + 0.25);
            }
            valid(scene)
        })
        .collect()
}

fn exact_params(scene: &Scene) -> SceneParams<Exact> {
    scene.params()
}

fn explore_with(scene: &Scene, speeds: SceneSpeeds, max_states: usize) -> SceneExploration {
    explore_scene(
        scene,
        speeds,
        &Options {
            max_states,
            ..Options::default()
        },
    )
    .expect("exploration succeeds")
}

fn to_f64(x: &Exact) -> f64 {
    x.to_f64().value()
}

// ---------------------------------------------------------------------------------------------
// Replays: every reported path, from scratch
// ---------------------------------------------------------------------------------------------

/// A path replayed from scratch through the simulator's exact replay.
fn replay_path(scene: &Scene, path: &ScenePath, stop: bool) -> simulate::SceneReplay {
    simulate::replay_exact_speeds(
        &exact_params(scene),
        &path.speeds,
        &path.starts,
        path.periods(),
        stop,
    )
}

/// Every path the explorer reports replays to what it claims: the counterexample collides
/// in its last period (and not before), each obstacle's closest path has its least
/// separation.
fn check_paths(scene: &Scene, e: &SceneExploration) {
    if let Some(c) = &e.counterexample {
        let r = replay_path(scene, c, true);
        assert!(r.collided(), "{}: the counterexample collides", scene.name);
        assert_eq!(r.periods(), c.periods(), "collides in its last period");
        assert_eq!(
            r.run.records.iter().filter(|rec| rec.collision()).count(),
            1
        );
    }
    for (i, o) in e.obstacles.iter().enumerate() {
        if o.unbounded {
            continue;
        }
        let Some(path) = &o.closest else {
            assert!(o.min_separation.is_none());
            continue;
        };
        let r = replay_path(scene, path, false);
        assert_eq!(
            r.separations()[i],
            o.min_separation,
            "obstacle {i}: the closest path replays to the least separation"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Agreement with the scene analyser
// ---------------------------------------------------------------------------------------------

/// The agreement laws between the analyser and an exploration of the same scene (complete
/// or not: whatever was explored is a real behaviour).
fn check_agreement(scene: &Scene, a: &SceneAnalysis, e: &SceneExploration) {
    let name = scene.to_toml_string();
    if e.verdict == ExploreVerdict::Collision {
        assert_eq!(
            a.verdict,
            Verdict::Refuted,
            "{name}: the explorer found a collision, the analyser must refute"
        );
    }
    assert!(
        e.verdict != ExploreVerdict::Safe || e.complete,
        "safe only when complete"
    );
    let lb = |x: &Option<Exact>| x.as_ref().map(to_f64);
    for oa in &a.obstacles {
        let o = &e.obstacles[oa.obstacle];
        if o.unbounded {
            assert!(
                a.never_stops && oa.lower_bound.is_none(),
                "{name}: obstacle {} is passed unbraked; the analyser must have no bound",
                oa.obstacle
            );
            continue;
        }
        let Some(m) = o.min_separation_f64() else {
            continue;
        };
        if let Some(l) = lb(&oa.lower_bound) {
            assert!(
                m >= l - 1e-9,
                "{name}: obstacle {}: {m} < bound {l}",
                oa.obstacle
            );
        }
        if let Some(s) = oa.min_separation {
            assert!(
                m >= s - 1e-9,
                "{name}: obstacle {}: {m} < s* {s}",
                oa.obstacle
            );
        }
    }
    for (i, o) in scene.obstacles.iter().enumerate() {
        if o.lane != 0 {
            assert!(
                e.obstacles[i].min_separation.is_none() && !e.obstacles[i].collides,
                "{name}: the robot never enters lane {}",
                o.lane
            );
        }
    }
    if e.never_stops() {
        assert!(a.never_stops && a.lower_bound.is_none(), "{name}");
    } else if let Some(m) = e.min_separation_f64() {
        if let Some(l) = lb(&a.lower_bound) {
            assert!(m >= l - 1e-9, "{name}: explorer {m} below the bound {l}");
        }
        if let Some(s) = a.min_separation {
            assert!(m >= s - 1e-9, "{name}: explorer {m} below s* {s}");
        }
    }
}

/// The speed sets of the agreement runs: {0, W_i}, plus V_a where W_i exceeds it (the
/// wrong-assumption guard's edge).
fn extremes_and_v_a(scene: &Scene) -> SceneSpeeds {
    let p = exact_params(scene);
    SceneSpeeds::with_levels(&p, std::slice::from_ref(&p.robot.V_a), "test")
        .unwrap_or_else(|_| SceneSpeeds::extremes(&p))
}

/// 80 small scenes without lane changes: the laws hold on every one, at least 50 are
/// explored completely, and both verdicts occur.
#[test]
fn explorer_agrees_with_the_scene_analyser_on_small_scenes() {
    let (mut complete, mut collisions, mut safe, mut witnesses) = (0, 0, 0, 0);
    for scene in small_scenes(80, 7) {
        let a = analyse_scene(&scene).expect("analysed");
        let e = explore_with(&scene, extremes_and_v_a(&scene), 5_000);
        check_agreement(&scene, &a, &e);
        check_paths(&scene, &e);
        complete += usize::from(e.complete);
        collisions += usize::from(e.verdict == ExploreVerdict::Collision);
        safe += usize::from(e.verdict == ExploreVerdict::Safe);
        witnesses += usize::from(witness_run(&scene, &a).is_some());
    }
    assert!(complete >= 50, "only {complete} scenes explored completely");
    assert!(
        collisions >= 15 && safe >= 15,
        "{collisions} collisions, {safe} safe"
    );
    assert!(
        witnesses >= 25,
        "only {witnesses} witness speed sets explored"
    );
}

/// The analyser's witness explored: with each obstacle's set made of {0, W_i} and the
/// witness's own speeds, the witness is one of the explored behaviours, so the explorer's
/// least separation lies between s* and the witness's replayed separation — equal to s*
/// (1e-9) where the witness attains it. None when the witness does not attain s* or the
/// sets are too large to explore quickly.
fn witness_run(scene: &Scene, a: &SceneAnalysis) -> Option<()> {
    let w = a.witness.as_ref()?;
    let s = a.min_separation?;
    let sep = w.separation?;
    if (sep - s).abs() > 1e-9 {
        return None;
    }
    let p = exact_params(scene);
    let sets: Vec<Vec<Exact>> = p
        .obstacles
        .iter()
        .enumerate()
        .map(|(i, o)| {
            let mut list = vec![Exact::ZERO, o.max_speed.clone()];
            list.extend(w.obstacle_speeds[i].to_vec().into_iter().map(exact_float));
            list
        })
        .collect();
    let speeds = SceneSpeeds::from_sets(&p, sets).ok()?;
    let joint: usize = (0..p.obstacles.len())
        .filter(|&i| p.obstacles[i].lane == 0)
        .map(|i| speeds.of(i).len())
        .product();
    if joint > 27 {
        return None;
    }
    let e = explore_with(scene, speeds, 20_000);
    if !e.complete {
        return None;
    }
    check_agreement(scene, a, &e);
    let name = scene.to_toml_string();
    let mine = e.obstacles[w.obstacle].min_separation_f64().unwrap();
    assert!(
        mine <= sep + 1e-12,
        "{name}: the witness ({sep}) is explored, min {mine}"
    );
    let m = e.min_separation_f64().unwrap();
    assert!((m - s).abs() <= 1e-9, "{name}: explorer {m} vs s* {s}");
    Some(())
}

// ---------------------------------------------------------------------------------------------
// One obstacle: the single-obstacle explorer
// ---------------------------------------------------------------------------------------------

/// A one-obstacle scene explores exactly as the single-obstacle explorer explores its
/// problem: the same verdict and completeness, the same never-stopping behaviours, the same
/// least separation (exact rationals, equal), the same shortest counterexample length.
#[test]
fn a_one_obstacle_scene_explores_as_the_single_obstacle_explorer() {
    let mut cases = 0;
    for rule in RULES {
        for latency in 0..=3 {
            for (w, rho) in [(0.05, 0.6), (0.1, 1.4), (0.3, 0.3), (0.3, 1.4), (0.0, 0.5)] {
                let spec = Spec {
                    rule,
                    latency,
                    w,
                    rho,
                    ..Spec::small()
                };
                let p = spec.problem();
                let wb = p.params::<Exact>().W;
                let set = SpeedSet::evenly_spaced(&wb, 3).unwrap();
                let single = explore::explore(&p, set.clone(), &Options::default()).unwrap();
                let scene = Scene::from_problem(&p);
                let speeds =
                    SceneSpeeds::from_sets(&exact_params(&scene), vec![set.speeds().to_vec()])
                        .unwrap();
                let e = explore_with(&scene, speeds, 1_000_000);
                let tag = format!("{spec:?}");
                assert_eq!(e.verdict, single.verdict, "{tag}");
                assert_eq!(e.complete, single.complete, "{tag}");
                assert_eq!(e.never_stops(), single.never_stops, "{tag}");
                if !single.never_stops {
                    assert_eq!(
                        e.obstacles[0].min_separation, single.min_separation,
                        "{tag}"
                    );
                }
                assert_eq!(
                    e.counterexample.as_ref().map(ScenePath::periods),
                    single.counterexample.as_ref().map(|c| c.periods()),
                    "{tag}"
                );
                check_paths(&scene, &e);
                cases += 1;
            }
        }
    }
    assert_eq!(cases, 60);
}

// ---------------------------------------------------------------------------------------------
// The state keys are exact: a search without them agrees
// ---------------------------------------------------------------------------------------------

/// Every field of a scene world (its parameters are constant): step index, robot position,
/// speed and mode, lane and lane change, and per obstacle its gap, its whole remembered
/// history and its occupancy side.
type FullKey = (
    usize,
    Exact,
    Exact,
    Mode,
    i32,
    Option<(i32, usize)>,
    Vec<(Exact, Vec<Exact>, Vec<Exact>, Option<bool>)>,
);

fn full_key(w: &SceneWorld<Exact>) -> FullKey {
    let lateral = w.lateral();
    let robot = w.robot();
    (
        w.k(),
        robot.position.clone(),
        robot.speed.clone(),
        robot.mode,
        lateral.lane,
        lateral.change.map(|c| (c.from, c.step)),
        (0..w.params().obstacles.len())
            .map(|i| {
                let (gaps, speeds) = w.history(i);
                (
                    w.gap(i).clone(),
                    gaps.iter().cloned().collect(),
                    speeds.iter().cloned().collect(),
                    w.side(i).map(|s| s == Side::Ahead),
                )
            })
            .collect(),
    )
}

/// What the unabstracted search finds.
#[derive(Debug, PartialEq)]
struct Found {
    shortest_collision: Option<usize>,
    min: Vec<Option<Exact>>,
    unbounded: Vec<bool>,
}

/// The obstacles whose separation falls for ever from `w` (the explorer's never-braking
/// rule, written out again): no goal, driving, no change under way, every obstacle of the
/// lane observed at a gap ≤ 0; those of them entered ahead.
fn driving_through(w: &SceneWorld<Exact>) -> Vec<usize> {
    let p = w.params();
    let lateral = w.lateral();
    if p.goal.is_some()
        || !matches!(w.robot().mode, Mode::Accelerate | Mode::Drive)
        || lateral.change.is_some()
    {
        return Vec::new();
    }
    let lane: Vec<usize> = (0..p.obstacles.len())
        .filter(|&i| p.obstacles[i].lane == lateral.lane)
        .collect();
    if !lane
        .iter()
        .all(|&i| w.seen(i).is_some_and(|o| o.gap <= Exact::ZERO))
    {
        return Vec::new();
    }
    lane.into_iter()
        .filter(|&i| w.side(i).unwrap_or_else(|| Side::of(w.gap(i))) == Side::Ahead)
        .collect()
}

/// Breadth-first search over complete world states in big rationals, with every joint
/// speed choice from `sets` (each obstacle all of its set) and both ends of every range.
fn unabstracted(scene: &Scene, sets: &SceneSpeeds) -> (Found, usize) {
    let p = exact_params(scene);
    let n = p.obstacles.len();
    let mut joint: Vec<Vec<Exact>> = vec![Vec::new()];
    for i in 0..n {
        joint = joint
            .into_iter()
            .flat_map(|prefix| {
                sets.of(i).speeds().iter().map(move |s| {
                    let mut v = prefix.clone();
                    v.push(s.clone());
                    v
                })
            })
            .collect();
    }
    let mut starts: Vec<Vec<Exact>> = vec![Vec::new()];
    for o in &p.obstacles {
        let mut ends = vec![o.start_min.clone(), o.start_max.clone()];
        ends.dedup();
        starts = starts
            .into_iter()
            .flat_map(|prefix| {
                ends.iter().map(move |x| {
                    let mut v = prefix.clone();
                    v.push(x.clone());
                    v
                })
            })
            .collect();
    }
    let mut found = Found {
        shortest_collision: None,
        min: vec![None; n],
        unbounded: vec![false; n],
    };
    let mut seen: HashMap<FullKey, ()> = HashMap::new();
    let mut queue: VecDeque<SceneWorld<Exact>> = starts
        .into_iter()
        .map(|s| SceneWorld::new(p.clone(), s))
        .collect();
    while let Some(world) = queue.pop_front() {
        for speeds in &joint {
            let mut next = world.clone();
            let rec = next.step(speeds);
            if rec.collision() && found.shortest_collision.is_none() {
                found.shortest_collision = Some(rec.k + 1);
            }
            for (i, step) in rec.obstacles.iter().enumerate() {
                if let Some(s) = &step.safety
                    && found.min[i].as_ref().is_none_or(|m| s.sep < *m)
                {
                    found.min[i] = Some(s.sep.clone());
                }
            }
            let through = driving_through(&next);
            for &i in &through {
                found.unbounded[i] = true;
            }
            let ended = next.stopped() || next.settled() || !through.is_empty();
            if !ended && seen.insert(full_key(&next), ()).is_none() {
                queue.push_back(next);
            }
        }
    }
    let states = seen.len();
    (found, states)
}

/// On scenes with lane changes, goals, sensing ranges and obstacles in every lane, the
/// explorer (exact keys that leave things out) and a search over complete world states
/// find the same shortest collision, the same least separation per obstacle, the same
/// obstacles passed unbraked; the keys merge states (fewer are stored).
#[test]
fn the_state_keys_are_exact_against_an_unabstracted_search() {
    let (mut merged, mut changes, mut collisions) = (0, 0, 0);
    for scene in lane_scenes(40, 11) {
        let speeds = SceneSpeeds::extremes(&exact_params(&scene));
        let e = explore_with(&scene, speeds.clone(), 200_000);
        assert!(e.complete, "{}", scene.to_toml_string());
        check_paths(&scene, &e);
        let (full, states) = unabstracted(&scene, &speeds);
        let mine = Found {
            shortest_collision: e.counterexample.as_ref().map(ScenePath::periods),
            min: e
                .obstacles
                .iter()
                .map(|o| o.min_separation.clone())
                .collect(),
            unbounded: e.obstacles.iter().map(|o| o.unbounded).collect(),
        };
        // Past a never-braking state the full search stops too, so the minima agree
        // for unbounded obstacles as well.
        assert_eq!(mine, full, "{}", scene.to_toml_string());
        merged += usize::from(e.states < states);
        changes += usize::from(
            e.obstacles
                .iter()
                .filter_map(|o| o.closest.as_ref())
                .any(|c| !c.replay.run.outcome.lane_changes.is_empty()),
        );
        collisions += usize::from(e.verdict == ExploreVerdict::Collision);
    }
    assert!(
        merged >= 20,
        "the keys merged states in only {merged} scenes"
    );
    assert!(changes >= 5, "lane changes on only {changes} closest paths");
    assert!((5..=35).contains(&collisions), "{collisions} collisions");
}

// ---------------------------------------------------------------------------------------------
// Lane changes, by hand
// ---------------------------------------------------------------------------------------------

/// The hand-derived lane-change scene: an oncoming obstacle in lane 0 at 4 m, faster
/// (W = 0.6) than the controller assumes (V_a = 0.2, wrong-assumption guard off). Kinematic
/// rule, no latency; v_max = 0.5 reached at t = 1 s (x = 0.25 m), b = 0.25, dt = 0.25.
///
/// - d_coll(v_max) = 0.25/0.5 + 0.2·0.5/0.25 + 0.1 = 1.0 m; the robot cruises before the
///   gap can reach it (at most 0.85 m of the 4 m close in the first second).
/// - Gaps then are 3.75 − 0.15·j − 0.125·m (j periods at W, m cruising periods): multiples
///   of 0.025. Danger fires at the first gap ≤ 1.0, which is > 1.0 − 0.275 (one period at
///   most closes 0.125 + 0.15): at least 0.75, reached (j = 5, m = 18) after 1.025.
/// - A lane change (P = 2 periods) needs the gap above d_lc = (0.5 + 0.2)·0.5 + 0.1 = 0.45:
///   always. During it the gap falls at most 2·0.275 = 0.55, so sep ≥ 0.75 − 0.55 = 0.2 > 0,
///   attained with W throughout the change.
/// - Braking instead (no free lane): the robot needs 2 s and 0.5 m to stop, the obstacle
///   closes 1.2 m more: rest gap 0.75 − 1.7 = −0.95, a collision.
fn oncoming(lanes: Vec<i32>, parked: Option<i32>, lane_change: bool) -> Scene {
    let spec = Spec {
        name: "lane-change",
        v_max: 0.5,
        a: 0.5,
        b: 0.25,
        dt: 0.25,
        latency: 0,
        clearance: 0.0,
        v_a: 0.2,
        rho: 2.0,
        rule: DangerRule::Kinematic,
        buffer: 0.1,
        wab: false,
        w: 0.6,
        g0: 4.0,
    };
    let mut obstacles = vec![obstacle("oncoming", 0, 4.0, 0.6, false)];
    // The robot meets danger between x = 1.25 (obstacle at W throughout) and x = 3.0 (at
    // rest throughout); a box at 2.5 is then observed within [−0.5, 1.25] ⊂ [−rear_gap, ρ]:
    // its lane is never free.
    obstacles.extend(parked.map(|lane| obstacle("parked", lane, 2.5, 0.0, true)));
    let mut scene = scene_of(&spec, obstacles);
    scene.lanes = lanes;
    if lane_change {
        scene.lane_change = Some(LaneChange {
            periods: 2,
            rear_gap: 0.5,
        });
    }
    valid(scene)
}

fn explore_default(scene: &Scene) -> SceneExploration {
    explore_with(scene, SceneSpeeds::extremes(&exact_params(scene)), 100_000)
}

/// With lane 1 free, every behaviour changes lanes at the danger step: no collision, and
/// the least separation from the oncoming obstacle is 0.2 m exactly, at the change's end.
#[test]
fn a_free_lane_saves_the_robot() {
    let scene = oncoming(vec![0, 1], None, true);
    let e = explore_default(&scene);
    check_paths(&scene, &e);
    assert_eq!(e.verdict, ExploreVerdict::Safe);
    assert_eq!(e.obstacles[0].min_separation, Some(exact_decimal(0.2)));
    let closest = e.closest().expect("a closest approach");
    let outcome = &closest.replay.run.outcome;
    assert_eq!(outcome.brake, None, "the robot never brakes");
    assert_eq!(outcome.lane_changes.len(), 1);
    let change = outcome.lane_changes[0];
    assert_eq!((change.from, change.to), (0, 1));
    // It ends with the change: the separation is the gap 2 periods after it began.
    assert_eq!(closest.periods(), change.step + 2);
    let w = exact_decimal(0.6);
    assert!(closest.speeds[0][change.step..].iter().all(|s| *s == w));
}

/// With a box in lane 1 beside the robot whenever danger fires, the lane is never free: the
/// robot brakes, and the obstacle at W hits it (least separation −0.95 m exactly); the
/// answers are those of the same scene with lane changes off, number for number. With lane
/// −1 there too, the robot goes there instead and is safe again (0.2 m).
#[test]
fn an_occupied_lane_is_refused_and_braking_collides() {
    let refused = oncoming(vec![0, 1], Some(1), true);
    let e = explore_default(&refused);
    check_paths(&refused, &e);
    assert_eq!(e.verdict, ExploreVerdict::Collision);
    assert_eq!(e.obstacles[0].min_separation, Some(exact_decimal(-0.95)));
    assert_eq!(
        e.obstacles[1].min_separation, None,
        "lane 1 is never entered"
    );
    for path in [e.counterexample.as_ref(), e.closest()] {
        let outcome = &path.unwrap().replay.run.outcome;
        assert!(outcome.lane_changes.is_empty());
        assert_eq!(
            outcome.brake.map(|b| b.1),
            Some(BrakeReason::CollisionDanger)
        );
    }
    let braking = explore_default(&oncoming(vec![0, 1], Some(1), false));
    assert_eq!(braking.verdict, ExploreVerdict::Collision);
    assert_eq!(
        braking.obstacles[0].min_separation,
        e.obstacles[0].min_separation
    );
    assert_eq!(
        braking.counterexample.as_ref().map(ScenePath::periods),
        e.counterexample.as_ref().map(ScenePath::periods)
    );

    let other_side = oncoming(vec![-1, 0, 1], Some(1), true);
    let e = explore_default(&other_side);
    check_paths(&other_side, &e);
    assert_eq!(e.verdict, ExploreVerdict::Safe);
    assert_eq!(e.obstacles[0].min_separation, Some(exact_decimal(0.2)));
    let changes = &e.closest().unwrap().replay.run.outcome.lane_changes;
    assert_eq!((changes[0].from, changes[0].to), (0, -1));
}

// ---------------------------------------------------------------------------------------------
// Ranges, budgets, the horizon
// ---------------------------------------------------------------------------------------------

/// A start range is explored at both ends: per obstacle, the least separation is the lesser
/// of the two scenes with the obstacle at either end, exactly.
#[test]
fn a_start_range_is_explored_at_both_ends() {
    for scene in small_scenes(12, 3) {
        let mut ranged = scene.clone();
        let x = scene.obstacles[0].position.min();
        ranged.obstacles[0].position = Position::Range(x, x + 0.35);
        let mut far = scene.clone();
        far.obstacles[0].position = Position::At(x + 0.35);
        let speeds = SceneSpeeds::extremes(&exact_params(&scene));
        let both = explore_with(&valid(ranged), speeds.clone(), 100_000);
        let near = explore_with(&scene, speeds.clone(), 100_000);
        let far = explore_with(&valid(far), speeds, 100_000);
        for i in 0..scene.obstacles.len() {
            let least = [&near, &far]
                .iter()
                .filter_map(|e| e.obstacles[i].min_separation.clone())
                .min();
            assert_eq!(both.obstacles[i].min_separation, least);
            assert_eq!(
                both.obstacles[i].unbounded,
                near.obstacles[i].unbounded || far.obstacles[i].unbounded
            );
        }
        assert_eq!(
            both.verdict == ExploreVerdict::Collision,
            near.verdict == ExploreVerdict::Collision || far.verdict == ExploreVerdict::Collision
        );
        assert_eq!(both.starts[0].len(), 2);
    }
}

/// A state budget or a horizon that cuts the search never gives `safe`: the answer is
/// `inconclusive` (or a collision found before the cut, which replays).
#[test]
fn a_budget_or_a_horizon_never_gives_a_false_safe() {
    let scene = oncoming(vec![0, 1], None, true);
    let e = explore_with(&scene, SceneSpeeds::extremes(&exact_params(&scene)), 50);
    assert!(e.budget_exhausted && !e.complete);
    assert_eq!(e.verdict, ExploreVerdict::Inconclusive);
    assert_eq!(e.states, 50);

    let model = SceneModel::new(
        exact_params(&scene),
        SceneSpeeds::extremes(&exact_params(&scene)),
    )
    .unwrap()
    .with_horizon(10);
    let e = explore_scene_model(&model, &Options::default()).unwrap();
    assert!(e.horizon_reached && !e.budget_exhausted && !e.complete);
    assert_eq!(e.verdict, ExploreVerdict::Inconclusive);

    // A collision found before the budget runs out is still a collision.
    let refused = oncoming(vec![0, 1], Some(1), true);
    let full = explore_default(&refused);
    let cut = explore_with(
        &refused,
        SceneSpeeds::extremes(&exact_params(&refused)),
        full.states - 1,
    );
    assert!(cut.budget_exhausted);
    if cut.counterexample.is_some() {
        assert_eq!(cut.verdict, ExploreVerdict::Collision);
        check_paths(&refused, &cut);
    } else {
        assert_eq!(cut.verdict, ExploreVerdict::Inconclusive);
    }
    let zero = explore_scene(
        &refused,
        SceneSpeeds::extremes(&exact_params(&refused)),
        &Options {
            max_states: 0,
            ..Options::default()
        },
    );
    assert!(zero.is_err());
}

/// The search is deterministic: the same scene gives the same states, verdict and paths.
#[test]
fn the_scene_search_is_deterministic() {
    let scene = &small_scenes(5, 7)[4];
    let a = explore_default(scene);
    let b = explore_default(scene);
    assert_eq!(
        (a.states, a.transitions, a.depth),
        (b.states, b.transitions, b.depth)
    );
    assert_eq!(
        a.counterexample.as_ref().map(|c| c.speeds.clone()),
        b.counterexample.as_ref().map(|c| c.speeds.clone())
    );
}

// ---------------------------------------------------------------------------------------------
// The CLI
// ---------------------------------------------------------------------------------------------

/// An exact number as the CLI shows it: a decimal, or a fraction `n/d`.
fn parse_exact(text: &str) -> Exact {
    match text.split_once('/') {
        Some((n, d)) => {
            Exact::from(n.parse::<i64>().unwrap()) / Exact::from(d.parse::<i64>().unwrap())
        }
        None => exact_decimal(text.parse().unwrap()),
    }
}

/// `safereach explore SCENE`: a scene file is explored as a scene (a problem file as
/// before): the verdict as exit status, per-obstacle separations, the counterexample's
/// speeds per obstacle, a scene trace with `--trace`; the JSON's path replays to a collision.
#[test]
fn cli_explores_scene_files() {
    let dir = tmp();
    let path = dir.path().join("refused.toml");
    std::fs::write(&path, oncoming(vec![0, 1], Some(1), true).to_toml_string()).unwrap();
    let out = safereach(dir.path())
        .arg("explore")
        .arg(&path)
        .args(["--trace", "cx.csv"])
        .assert()
        .code(1)
        .get_output()
        .clone();
    let text = stdout(&out);
    assert!(text.starts_with("lane-change: collision\n"), "{text}");
    assert!(text.contains("\"oncoming\" (lane 0): -0.95"), "{text}");
    assert!(text.contains("\"parked\" (lane 1): never met"), "{text}");
    assert!(text.contains("oncoming: "), "{text}");
    let csv = std::fs::read_to_string(dir.path().join("cx.csv")).unwrap();
    assert!(csv.lines().next().unwrap().contains("robot_lane"), "{csv}");

    let out = safereach(dir.path())
        .arg("explore")
        .arg(&path)
        .arg("--json")
        .assert()
        .code(1)
        .get_output()
        .clone();
    let v: Value = serde_json::from_str(&stdout(&out)).unwrap();
    assert_eq!(v["verdict"], "collision");
    assert_eq!(v["obstacles"][0]["min_separation_exact"], "-0.95");
    assert_eq!(v["obstacles"][1]["min_separation"], Value::Null);
    // The exact speeds, read back from their text: they replay to the collision.
    let exact: Vec<Vec<Exact>> = v["path"]["obstacle_speeds_exact"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            s.as_array()
                .unwrap()
                .iter()
                .map(|x| parse_exact(x.as_str().unwrap()))
                .collect()
        })
        .collect();
    let scene = Scene::load(&path).unwrap();
    let p = exact_params(&scene);
    let periods = v["path"]["periods"].as_u64().unwrap() as usize;
    let r = simulate::replay_exact_speeds(&p, &exact, &p.nearest_starts(), periods, true);
    assert!(r.collided() && r.periods() == periods);

    let safe = dir.path().join("free.toml");
    std::fs::write(&safe, oncoming(vec![0, 1], None, true).to_toml_string()).unwrap();
    let out = safereach(dir.path())
        .arg("explore")
        .arg(&safe)
        .assert()
        .code(0)
        .get_output()
        .clone();
    let text = stdout(&out);
    assert!(text.contains("\"oncoming\" (lane 0): 0.2 m"), "{text}");
    assert!(text.contains("{0, 0.6}"), "{text}");
}

/// A large scene reaches the state budget: exit 3 and a message saying so; bad speed sets
/// and broken scene files exit 2 naming what is wrong; problem files keep today's output.
#[test]
fn cli_scene_budget_and_bad_input() {
    let dir = tmp();
    let scene = problem_file("scene-oncoming.toml");
    let out = safereach(dir.path())
        .arg("explore")
        .arg(&scene)
        .args(["--max-states", "500"])
        .assert()
        .code(3)
        .get_output()
        .clone();
    assert!(
        stdout(&out).contains("inconclusive: state budget reached (500 states)"),
        "{}",
        stdout(&out)
    );
    let err = |args: &[&str]| {
        let out = safereach(dir.path())
            .arg("explore")
            .arg(&scene)
            .args(args)
            .assert()
            .code(2)
            .get_output()
            .clone();
        String::from_utf8_lossy(&out.stderr).to_string()
    };
    assert!(err(&["--speeds", "0.5"]).contains("largest obstacle bound"));
    // --grid runs the scene's UPPAAL network (tests/it/scene_uppaal.rs), which has no trace.
    assert!(err(&["--grid", "--trace", "t.csv"]).contains("--trace"));
    assert!(err(&["--set", "obstacle.0.lane=7"]).contains("obstacle[0]"));
    // A problem file: the single-obstacle explorer, as before (default --speeds 5).
    let out = safereach(dir.path())
        .arg("explore")
        .arg(seed_file())
        .args(["--max-states", "100"])
        .assert()
        .code(3)
        .get_output()
        .clone();
    let text = stdout(&out);
    assert!(
        text.contains("inconclusive: state budget reached (100 states)"),
        "{text}"
    );
    assert!(
        text.contains("(5 actions per state, fixed order)"),
        "{text}"
    );
}

// ---------------------------------------------------------------------------------------------
// The exact run search (proof::scene_search) against the explorer and the schedule analyser
// ---------------------------------------------------------------------------------------------

mod run_search {
    use safereach::core::rational::Rational;
    use safereach::proof::scene_search::search_scene;
    use safereach::proof::search_certificate::certify_by_search;
    use safereach::proof::search_check::check_search;

    use super::*;

    /// s* of the search as an exact number (None: −∞ or nothing measured).
    fn star(scene: &Scene) -> (Option<Exact>, bool) {
        let s = search_scene(scene).expect("the search finishes");
        (s.min_separation().map(Rational::to_exact), s.unbounded())
    }

    /// Two exact methods with nothing in common but the step function: on scenes both
    /// decide, the search's s* is the schedule analyser's (to its LP's precision) and so is
    /// the verdict, and every search certificate checks.
    #[test]
    fn the_search_equals_the_schedule_analyser_on_small_scenes() {
        let scenes = small_scenes(60, 0x5ea7c4);
        for (n, scene) in scenes.iter().enumerate() {
            let a = analyse_scene(scene).expect("analysed");
            let cert = certify_by_search(scene).expect("searched");
            check_search(&cert).unwrap_or_else(|e| panic!("scene {n}: {e}"));
            let (s, unbounded) = star(scene);
            if a.never_stops {
                // The analyser reports −∞ once an obstacle passes unbraked; the search
                // measures that pass exactly: a collision either way.
                assert!(
                    unbounded
                        || s.as_ref()
                            .is_some_and(|s| to_f64(s) <= scene.robot.clearance),
                    "scene {n}: analyser never stops, search {s:?}"
                );
                assert_eq!(cert.verdict, Verdict::Refuted, "scene {n}");
                continue;
            }
            assert!(
                !unbounded,
                "scene {n}: search unbounded, analyser {:?}",
                a.min_separation
            );
            match (&s, a.min_separation) {
                (Some(s), Some(m)) => assert!(
                    (to_f64(s) - m).abs() <= 1e-6,
                    "scene {n}: search {} analyser {m}",
                    to_f64(s)
                ),
                (None, None) => {}
                other => panic!("scene {n}: {other:?}"),
            }
            if a.verdict != Verdict::Inconclusive && cert.verdict != Verdict::Inconclusive {
                assert_eq!(a.verdict, cert.verdict, "scene {n}");
            }
        }
    }

    /// On scenes with lane changes (and everything else the simulator runs) the explorer's
    /// exact least separation over its finite speeds is never below the search's s*, a
    /// collision it finds is never certified, and every search certificate checks (its
    /// witness replays to s*).
    #[test]
    fn the_search_is_never_above_the_explorer_on_lane_change_scenes() {
        let scenes = lane_scenes(60, 0x1a4e5);
        let mut changes = 0;
        for (n, scene) in scenes.iter().enumerate() {
            let cert = certify_by_search(scene).expect("searched");
            check_search(&cert).unwrap_or_else(|e| panic!("scene {n}: {e}"));
            changes += cert.witness.as_ref().map_or(0, |w| w.lane_changes.len());
            let (s, unbounded) = star(scene);
            let e = explore_with(scene, SceneSpeeds::extremes(&exact_params(scene)), 200_000);
            if !e.complete {
                continue;
            }
            let collides = e.verdict == ExploreVerdict::Collision;
            if collides {
                assert_ne!(cert.verdict, Verdict::Certified, "scene {n}");
            }
            if unbounded {
                continue;
            }
            match (e.min_separation(), &s) {
                (Some(m), Some(s)) => assert!(m >= *s, "scene {n}: explorer {m} < search {s}"),
                (Some(m), None) => {
                    panic!("scene {n}: the explorer measures {m}, the search nothing")
                }
                (None, _) => assert!(!e.never_stops(), "scene {n}"),
            }
        }
        assert!(
            changes > 5,
            "the scenes exercise lane changes ({changes} in witnesses)"
        );
    }

    /// Random behaviours replayed exactly never separate less than s*, and never collide
    /// where the search certifies.
    #[test]
    fn random_behaviours_never_beat_the_search() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for (n, scene) in lane_scenes(25, 0xbe4a).iter().enumerate() {
            let cert = certify_by_search(scene).expect("searched");
            let (s, unbounded) = star(scene);
            let p = exact_params(scene);
            let horizon = simulate::horizon(&scene.params::<f64>());
            for _ in 0..20 {
                let speeds: Vec<Vec<Exact>> = p
                    .obstacles
                    .iter()
                    .map(|o| {
                        (0..horizon)
                            .map(|_| {
                                o.max_speed.clone() * Exact::from(rng.random_range(0..=4u8))
                                    / Exact::from(4u8)
                            })
                            .collect()
                    })
                    .collect();
                let starts: Vec<Exact> = p.obstacles.iter().map(|o| o.start_min.clone()).collect();
                let r = simulate::replay_exact_speeds(&p, &speeds, &starts, horizon, false);
                if cert.verdict == Verdict::Certified {
                    assert!(!r.collided(), "scene {n}: a certified scene collides");
                }
                if unbounded {
                    continue;
                }
                let least = r.separations().into_iter().flatten().min();
                if let (Some(l), Some(s)) = (least, &s) {
                    assert!(l >= *s, "scene {n}: a behaviour separates {l} < s* {s}");
                }
            }
        }
    }

    /// Editing the scene inside a certificate (an obstacle's position or lane, the lane
    /// change's length or rear gap) and recomputing the digest is caught by the search.
    /// (An edit whose scene has the same answer is no forgery: 5 periods instead of 10
    /// give seed-lanes the same runs, s* and witness, and `check` accepts it, rightly.)
    #[test]
    fn edited_scenes_are_rejected_even_with_a_fresh_digest() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/seed-lanes.toml");
        let scene = Scene::load_with_overrides(&path, &[]).expect("loads");
        let cert = certify_by_search(&scene).expect("searched");
        check_search(&cert).expect("the original checks");
        type Edit = Box<dyn Fn(&mut Scene)>;
        let edits: Vec<(&str, Edit)> = vec![
            (
                "position",
                Box::new(|s: &mut Scene| s.obstacles[1].position = Position::At(7.5)),
            ),
            ("lane", Box::new(|s: &mut Scene| s.obstacles[1].lane = -1)),
            (
                "periods",
                Box::new(|s: &mut Scene| s.lane_change.as_mut().unwrap().periods = 30),
            ),
            (
                "rear gap",
                Box::new(|s: &mut Scene| s.lane_change.as_mut().unwrap().rear_gap = 3.0),
            ),
            (
                "speed",
                Box::new(|s: &mut Scene| s.obstacles[0].max_speed = 0.3),
            ),
        ];
        for (what, edit) in edits {
            let mut forged = cert.clone();
            edit(&mut forged.scene);
            forged.digest = forged.compute_digest();
            let e = check_search(&forged).expect_err(what);
            assert!(
                e.0.contains("differ") || e.0.contains("verdict") || e.0.contains("witness"),
                "{what}: {e}"
            );
        }
    }
}
