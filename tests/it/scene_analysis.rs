//! The scene analyser against what is known independently: the single-obstacle analyser
//! (a scene that is one obstacle, or whose extra obstacles are out of reach), and the
//! closed form of a static obstacle alone.

use proptest::prelude::*;
use safereach::analysis::scene::analyse_scene;
use safereach::analysis::{Verdict, analyse};
use safereach::core::model::Problem;
use safereach::core::num::{Exact, Scalar};
use safereach::core::scene::{self, Obstacle, Position, Scene};
use safereach::core::semantics::{Mode, RobotState, robot_motion};
use safereach::proof::program::ProofKind;
use safereach::proof::scene_certificate::SceneCertificate;
use safereach::proof::scene_check::check_scene;

use crate::common::paths::load_problem;
use crate::common::spec::{any_spec, config};

fn obstacle(name: &str, lane: i32, x: f64, w: f64, is_static: bool) -> Obstacle {
    Obstacle {
        name: name.into(),
        lane,
        position: Position::At(x),
        max_speed: w,
        is_static,
    }
}

/// The single-obstacle answer: whether certified, exact lower bound and s*.
fn single(problem: &Problem) -> (bool, Option<Exact>, Option<f64>) {
    let a = analyse(problem).expect("analysed");
    (
        a.verdict == Verdict::Certified,
        a.lower_bound,
        a.min_separation,
    )
}

fn scene_answer(scene: &Scene) -> (bool, Option<Exact>, Option<f64>) {
    let a = analyse_scene(scene).expect("analysed");
    (
        a.verdict == Verdict::Certified,
        a.lower_bound,
        a.min_separation,
    )
}

/// Every shipped single-obstacle problem, read as a scene, gives its own answer exactly.
#[test]
fn shipped_problems_as_scenes_give_their_own_answers() {
    for name in [
        "seed",
        "fast-obstacle",
        "static-obstacle",
        "zero-latency",
        "area-rule",
        "kinematic-rule",
    ] {
        let problem = load_problem(&format!("{name}.toml"), &[]);
        let scene = Scene::from_problem(&problem);
        assert_eq!(scene_answer(&scene), single(&problem), "{name}");
    }
}

proptest! {
    #![proptest_config(config(24))]

    /// Obstacles in lanes the robot never enters (no lane changes) change nothing: the
    /// answer is exactly the single obstacle's.
    #[test]
    fn obstacles_in_other_lanes_are_out_of_reach(spec in any_spec(), x in 0.5f64..20.0, w in 0.0f64..1.0) {
        let problem = spec.problem();
        let mut scene = Scene::from_problem(&problem);
        scene.lanes = vec![-1, 0, 1];
        scene.obstacles.push(obstacle("left", -1, x, w, false));
        scene.obstacles.push(obstacle("right", 1, x * 0.5 + 0.2, 0.0, true));
        prop_assert_eq!(scene_answer(&scene), single(&problem));
    }
}

/// d_static(v): the danger distance with V_a = 0, written out from docs/semantics.md §11.
fn d_static(p: &safereach::core::model::Params<Exact>, v: &Exact) -> Option<Exact> {
    use safereach::core::model::DangerRule;
    match p.rule {
        DangerRule::Paper => Some(v.clone() * v.clone() / p.b.clone() + p.buffer.clone()),
        DangerRule::Kinematic => {
            Some(v.clone() * v.clone() / (Exact::from(2) * p.b.clone()) + p.buffer.clone())
        }
        DangerRule::Area => None,
    }
}

/// s* for a static obstacle alone at x0 (docs/semantics.md §11.8): the robot brakes at the
/// first step T ≥ L whose observed gap x0 − P_{T−L} is in (0, min(ρ, d_static(v_T))], and
/// stops v_T²/(2b) further on. None: the observed gap jumps to ≤ 0 first (a collision).
fn static_closed_form(p: &safereach::core::model::Params<Exact>, x0: &Exact) -> Option<Exact> {
    let mut profile = vec![RobotState {
        position: Exact::ZERO,
        speed: Exact::ZERO,
        mode: Mode::Accelerate,
    }];
    for k in 0.. {
        while profile.len() <= k {
            let last = profile.last().unwrap().clone();
            profile.push(robot_motion(p, &last).end);
        }
        if k < p.L {
            continue;
        }
        let seen = x0.clone() - profile[k - p.L].position.clone();
        if seen <= Exact::ZERO {
            return None;
        }
        let v = profile[k].speed.clone();
        let threshold = match d_static(p, &v) {
            Some(d) if d < p.rho => d,
            _ => p.rho.clone(),
        };
        if seen <= threshold {
            let stop = v.clone() * v / (Exact::from(2) * p.b.clone());
            return Some(x0.clone() - profile[k].position.clone() - stop);
        }
    }
    unreachable!()
}

proptest! {
    #![proptest_config(config(32))]

    /// A static obstacle alone: s* is the robot's stopping distance short of it, in closed
    /// form (with a collision where the observed gap skips the danger zone).
    #[test]
    fn static_obstacle_alone_is_the_stopping_distance(spec in any_spec(), x in 0.3f64..6.0) {
        let problem = spec.problem();
        let mut scene = Scene::from_problem(&problem);
        scene.obstacles = vec![obstacle("wall", 0, x, 0.0, true)];
        let a = analyse_scene(&scene).expect("analysed");
        let p = scene.obstacle_params::<Exact>(0);
        match static_closed_form(&p, &<Exact as Scalar>::decimal(x)) {
            Some(s) => {
                // The bound is proved by float multipliers, exactly: at most a hair below.
                let bound = a.lower_bound.clone().expect("a bound");
                prop_assert!(bound <= s, "{bound} above the closed form {s}");
                prop_assert!((bound - s.clone()).to_f64().value() > -1e-9);
                if let Some(sep) = a.min_separation {
                    prop_assert!((sep - s.to_f64().value()).abs() < 1e-9, "{sep} vs {s}");
                }
            }
            _ => prop_assert!(a.never_stops && a.lower_bound.is_none()),
        }
    }
}

/// Small random scenes: a random robot and controller, two or three obstacles in the
/// robot's lane (moving or static, different bounds and starts), sometimes a destination,
/// sometimes an obstacle in the next lane.
fn any_scene() -> impl Strategy<Value = Scene> {
    let one = (0.4f64..6.0, 0u32..=60, any::<bool>());
    (
        any_spec(),
        proptest::collection::vec(one, 2..=3),
        proptest::option::of(1.0f64..12.0),
        any::<bool>(),
    )
        .prop_map(|(spec, obstacles, goal, beside)| {
            let mut scene = Scene::from_problem(&spec.problem());
            let round = |x: f64| (x * 100.0).round() / 100.0;
            scene.obstacles = obstacles
                .into_iter()
                .enumerate()
                .map(|(i, (x, w, is_static))| {
                    let w = if is_static { 0.0 } else { f64::from(w) / 100.0 };
                    obstacle(&format!("o{i}"), 0, round(x + 0.2 * i as f64), w, is_static)
                })
                .collect();
            scene.goal = goal.map(round);
            if beside {
                scene.lanes = vec![0, 1];
                scene.obstacles.push(obstacle("beside", 1, 1.0, 0.3, false));
            }
            scene
        })
}

proptest! {
    #![proptest_config(config(24))]

    /// Every scene certificate checks exactly with the analyser's verdict and bound; its
    /// witness replays to s* (collides when refuted); tampering with an obstacle, its lane,
    /// or a bystander proof is rejected.
    #[test]
    fn scene_certificates_check_and_witnesses_replay(scene in any_scene()) {
        let a = analyse_scene(&scene).expect("analysed");
        let cert = SceneCertificate::from_analysis(&a);
        let report = check_scene(&cert).expect("the certificate checks");
        prop_assert_eq!(report.verdict, a.verdict);
        prop_assert_eq!(report.lower_bound.clone(), a.lower_bound.clone());
        if let Some(w) = &a.witness {
            if let (Some(s), Some(r)) = (a.min_separation, w.separation) {
                prop_assert!((s - r).abs() <= 1e-6, "s* {s} vs replay {r}");
            }
            prop_assert_eq!(w.collides, a.verdict == Verdict::Refuted);
        }
        if a.verdict == Verdict::Refuted {
            prop_assert!(a.witness.as_ref().is_some_and(|w| w.collides));
        }
        let reseal = |mut c: SceneCertificate| {
            c.digest = c.compute_digest();
            c
        };
        // Any edit without a new digest: rejected as an edit.
        let mut faster = cert.clone();
        faster.scene.obstacles[0].max_speed += 0.01;
        prop_assert!(check_scene(&faster).is_err());
        // Resealed edits the proofs cannot stand behind.
        let mut moved = cert.clone();
        moved.scene.lanes = vec![0, 1];
        moved.scene.obstacles[1].lane = 1;
        prop_assert!(check_scene(&reseal(moved)).is_err());
        if let Some(o) = cert.obstacles.iter().position(|o| !o.bystanders.is_empty()) {
            let mut dropped = cert.clone();
            dropped.obstacles[o].bystanders.pop();
            prop_assert!(check_scene(&reseal(dropped)).is_err());
        }
        // Claiming a feasible firing piece empty (to drop the bystander steps it makes
        // possible) needs a proof that verifies: a fake one is rejected.
        for (o, proofs) in cert.obstacles.iter().enumerate() {
            if let Some(p) = proofs.own.iter().position(|p| p.kind == Some(ProofKind::Bound)) {
                let mut fake = cert.clone();
                fake.obstacles[o].own[p].kind = Some(ProofKind::Infeasible);
                prop_assert!(check_scene(&reseal(fake)).is_err());
            }
        }
    }

    /// Random behaviours never collide in a certified scene, and never come closer than the
    /// certified bound to an obstacle of the robot's lane.
    #[test]
    fn random_behaviours_respect_the_bound(scene in any_scene(), seed in any::<u64>()) {
        use rand::{Rng, SeedableRng};
        let a = analyse_scene(&scene).expect("analysed");
        prop_assume!(a.verdict == Verdict::Certified);
        let bound = a.lower_bound.clone().expect("certified has a bound").to_f64().value();
        let params = scene.params::<f64>();
        let exact = scene.params::<Exact>();
        let steps = scene::simulate::horizon(&params);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        for _ in 0..40 {
            let speeds: Vec<Vec<f64>> = params
                .obstacles
                .iter()
                .map(|o| {
                    let style = rng.random_range(0..3);
                    let constant = rng.random::<f64>() * o.max_speed;
                    (0..steps)
                        .map(|_| match style {
                            0 => constant,
                            1 => rng.random::<f64>() * o.max_speed,
                            _ => if rng.random::<bool>() { o.max_speed } else { 0.0 },
                        })
                        .collect()
                })
                .collect();
            let starts: Vec<Exact> = exact.obstacles.iter().map(|o| o.start_min.clone()).collect();
            let replay = scene::simulate::replay(&exact, &speeds, &starts, steps, true);
            prop_assert!(!replay.collided(), "a certified scene collides");
            for (i, sep) in replay.separations().iter().enumerate() {
                if let Some(sep) = sep && scene.obstacles[i].lane == 0 {
                    prop_assert!(sep.to_f64().value() >= bound - 1e-9);
                }
            }
        }
    }
}

/// A merged piece stands exactly for its shifts (docs/reductions.md, Lemma 11′): its optimum
/// is the least optimum of the single pieces at its brake step and every later one up to
/// the obstacle's z, solved one by one (infeasible ones skipped), for every merged piece —
/// own (cut at T_max) and bystander — of scenes with two and three obstacles in the lane, a
/// destination and a latency of 2.
#[test]
fn a_merged_piece_is_the_union_of_its_shifts() {
    use safereach::analysis::lp::{LpOutcome, solve};
    use safereach::proof::scene_schedule::SceneDecomposition;

    fn optimum(
        d: &safereach::proof::schedule::Decomposition,
        p: &safereach::proof::schedule::Piece,
    ) -> Option<f64> {
        match solve(&d.program(p), 0.0) {
            LpOutcome::Optimal { value, .. } => Some(value),
            LpOutcome::Infeasible { .. } => None,
            LpOutcome::Failed { status } => panic!("solver failed: {status}"),
        }
    }
    let scenes = [
        shipped_scene("scene-oncoming", &[]),
        shipped_scene("scene-oncoming", &["robot.latency=2", "robot.goal=9.0"]),
        shipped_scene(
            "scene-oncoming",
            &["obstacle.1.position=11.0", "obstacle.2.position=11.5"],
        ),
    ];
    let mut checked = 0;
    for s in &scenes {
        let dec = SceneDecomposition::new(s).expect("decided");
        for (a, o) in dec.obstacles.iter().enumerate() {
            let d = &o.decomposition;
            let z = o
                .quiet_until
                .expect("every obstacle here fires standing still");
            let pieces: Vec<_> = d
                .pieces
                .iter()
                .copied()
                .chain(dec.bystanders_needed(a, |_| true))
                .filter(|p| p.merged && p.has_objective())
                .collect();
            for merged in pieces {
                let whole = optimum(d, &merged);
                let single = (merged.brake..=z)
                    .filter_map(|t| merged.shifted_to(t))
                    .filter_map(|p| optimum(d, &p))
                    .fold(None, |m: Option<f64>, v| Some(m.map_or(v, |m| m.min(v))));
                match (whole, single) {
                    (Some(w), Some(least)) => assert!(
                        (w - least).abs() <= 1e-6,
                        "{}: {} optimum {w}, its shifts' least {least}",
                        s.name,
                        merged.describe()
                    ),
                    (w, s) => assert_eq!(w.is_some(), s.is_some(), "{}", merged.describe()),
                }
                checked += 1;
            }
        }
    }
    assert!(checked >= 6, "merged pieces checked: {checked}");
}

/// A shipped scene with `--set` overrides.
fn shipped_scene(name: &str, sets: &[&str]) -> Scene {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    Scene::load_with_overrides(
        &crate::common::paths::problem_file(&format!("{name}.toml")),
        &sets,
    )
    .expect("the scene loads")
}
