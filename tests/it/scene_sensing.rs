//! Scenes with `[sensing]` (docs/semantics.md §12 for every obstacle of a scene): the run
//! search takes observation noise and occlusion, and is held to independent answers:
//! - the single-obstacle schedule analyser (its own reductions, LP proofs, held in turn to
//!   exhaustive searches over errors and hiding prefixes in `noise`): on a single-obstacle
//!   problem read as a scene, the search gives its verdict and s*;
//! - noise never helps: s* never rises with σ, and an empty `[sensing]` is today's answer;
//! - every search certificate checks, its witness replaying with the errors and the first
//!   sightings it states, and a witness edited to break a premise is rejected;
//! - the scene explorer with noise and occlusion as finite choices: explorer collision ⇒
//!   refuted, every explored separation ≥ s*, every path it reports keeps the premises;
//! - scene Monte Carlo with errors and late sightings: no collision and nothing below s*
//!   where the search certifies, collisions where only occlusion refutes.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use safereach::analysis::{
    SpeedPattern, Verdict, analyse, scene_monte_carlo, scene_monte_carlo_run,
};
use safereach::core::model::{DangerRule, Problem, Sensing};
use safereach::core::num::{Exact, Scalar};
use safereach::core::rational::Rational;
use safereach::core::scene::{Obstacle, Position, Scene, simulate};
use safereach::crosscheck::explore::scene::{SceneExploration, SceneSpeeds, explore_scene};
use safereach::crosscheck::explore::{ExploreVerdict, Options};
use safereach::proof::search_certificate::{SearchCertificate, certify_by_search};
use safereach::proof::search_check::check_search;
use safereach::proof::search_observations::premises_hold;

use crate::noise::small_sensing;

fn certify(scene: &Scene) -> SearchCertificate {
    let cert = certify_by_search(scene).expect("searched");
    check_search(&cert).unwrap_or_else(|e| panic!("{}: {e}", scene.to_toml_string()));
    cert
}

/// s* with −∞ for a robot that never stops.
fn star(cert: &SearchCertificate) -> Option<f64> {
    if cert.never_stops {
        Some(f64::NEG_INFINITY)
    } else {
        cert.min_separation
    }
}

/// Small single-obstacle problems with noise, occlusion (first sighting inside the area or
/// not) and both together, over every rule, latencies 0 and 1, W below and above V_a.
fn sensing_problems() -> Vec<Problem> {
    let rules = [DangerRule::Paper, DangerRule::Kinematic, DangerRule::Area];
    let sensings = [
        (0.03, 0.0, None),
        (0.05, 0.06, None),
        (0.0, 0.0, Some(0.5)),
        (0.02, 0.03, Some(0.9)),
    ];
    small_sensing(&rules, &[0, 1], &[0.45, 0.8], &sensings)
}

#[test]
fn the_search_gives_the_schedule_analysers_answers_under_noise_and_occlusion() {
    let (mut refuted, mut hidden, mut errors) = (0, 0, 0);
    for p in sensing_problems() {
        p.validate("test").expect("a valid problem");
        let text = p.to_toml_string();
        let a = analyse(&p).expect("analysed");
        let cert = certify(&Scene::from_problem(&p));
        assert_eq!(cert.verdict, a.verdict, "{text}");
        let analysed = if a.never_stops {
            Some(f64::NEG_INFINITY)
        } else {
            a.min_separation
        };
        match (star(&cert), analysed) {
            (Some(s), Some(m)) if s.is_infinite() || m.is_infinite() => {
                assert_eq!(s, m, "{text}")
            }
            (Some(s), Some(m)) => assert!((s - m).abs() < 1e-7, "{text}: search {s}, analyser {m}"),
            (s, m) => assert_eq!(s, m, "{text}"),
        }
        refuted += usize::from(cert.verdict == Verdict::Refuted);
        let w = cert.witness.as_ref().expect("a witness");
        hidden += usize::from(w.shown_from.iter().any(|s| s.is_none_or(|k| k > 1)));
        errors += usize::from(!w.observation_errors.is_empty());
    }
    // The family is not trivial: some problems collide, some witnesses hide an obstacle
    // past its first observation, some are shown off the truth.
    assert!(refuted > 0, "nothing refuted");
    assert!(hidden > 0, "no witness hides its obstacle");
    assert!(errors > 0, "no witness has an observation error");
}

/// Two obstacles in the robot's lane, one static and one moving, with lane changes off and
/// on: s* never rises with the noise bound or a later first sighting, and an empty
/// `[sensing]` table changes nothing.
#[test]
fn noise_and_occlusion_never_help_in_a_scene() {
    let base = r#"
name = "two"
[robot]
max_speed = 0.4
acceleration = 0.4
braking = 0.5
control_period = 0.2
latency = 1
clearance = 0.0
[controller]
assumed_obstacle_speed = 0.1
reaction_radius = 1.0
danger_rule = "paper"
buffer = 0.05
wrong_assumption_brake = true
lane_change = LC
lane_change_periods = 2
lane_change_rear_gap = 0.2
[scene]
lanes = [0, 1]
[[obstacle]]
name = "walker"
lane = 0
position = 2.4
max_speed = 0.15
[[obstacle]]
name = "parked"
lane = 1
position = 1.6
max_speed = 0.0
static = true
"#;
    for lc in ["false", "true"] {
        let text = base.replace("LC", lc);
        let read = |sensing: &str| {
            let scene = Scene::from_toml_str(&format!("{text}{sensing}"), "test")
                .unwrap_or_else(|e| panic!("{e}"));
            star(&certify(&scene)).expect("measured")
        };
        let exact = read("");
        assert_eq!(read("[sensing]\n"), exact, "lane_change = {lc}");
        let mut last = exact;
        for sg in [0.01, 0.03, 0.06] {
            let s = read(&format!(
                "[sensing]\ngap_noise = {sg}\nspeed_noise = {sg}\n"
            ));
            assert!(
                s <= last + 1e-12,
                "lane_change = {lc}: σ = {sg} gives {s} > {last}"
            );
            last = s;
        }
        let mut last = exact;
        for d in [1.4, 0.9, 0.5] {
            let s = read(&format!("[sensing]\nfirst_detection_gap = {d}\n"));
            assert!(
                s <= last + 1e-12,
                "lane_change = {lc}: d_det = {d} gives {s} > {last}"
            );
            last = s;
        }
    }
}

/// A search witness that hides an obstacle or shows it off the truth is held to the
/// premises: an error beyond σ, or a first sighting moved to a later step, is rejected.
#[test]
fn a_witness_that_breaks_a_sensing_premise_is_rejected() {
    let mut edited = 0;
    for p in sensing_problems() {
        let cert = certify(&Scene::from_problem(&p));
        let w = cert.witness.as_ref().expect("a witness");
        if let Some(e) = w.observation_errors.first() {
            let mut bad = cert.clone();
            let sigma = p.gap_noise();
            bad.witness.as_mut().unwrap().observation_errors[0].gap =
                format!("{}", (sigma * 1000.0).round() as i64 * 2) + "/1000";
            bad.digest = bad.compute_digest();
            assert!(
                check_search(&bad).is_err(),
                "error {:?} doubled past σ accepted",
                e
            );
            edited += 1;
        }
        if let Some(Some(k)) = w.shown_from.first() {
            let mut bad = cert.clone();
            bad.witness.as_mut().unwrap().shown_from[0] = Some(k + 40);
            bad.digest = bad.compute_digest();
            assert!(
                check_search(&bad).is_err(),
                "a first sighting 40 steps later accepted"
            );
            edited += 1;
        }
    }
    assert!(edited > 10, "only {edited} witnesses edited");
}

/// `[sensing]` in a scene file reads, writes back and is refused with the key and reason
/// when out of range.
#[test]
fn a_scene_reads_its_sensing_table() {
    let text = std::fs::read_to_string(crate::common::paths::problem_file("seed-lanes.toml"))
        .expect("the shipped scene");
    let with = format!("{text}\n[sensing]\ngap_noise = 0.02\nfirst_detection_gap = 0.8\n");
    let scene = Scene::from_toml_str(&with, "lanes.toml").expect("reads");
    assert_eq!(
        scene.sensing,
        Some(Sensing {
            gap_noise: Some(0.02),
            speed_noise: None,
            first_detection_gap: Some(0.8),
        })
    );
    let back = Scene::from_toml_str(&scene.to_toml_string(), "back").expect("reads back");
    assert_eq!(back, scene);
    let bad = format!("{text}\n[sensing]\ngap_noise = -0.02\n");
    let err = Scene::from_toml_str(&bad, "lanes.toml")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("lanes.toml") && err.contains("sensing.gap_noise"),
        "{err}"
    );
}

/// A range of initial gaps with `[sensing]` (refused before scenes took sensing): the
/// problem is read as its scene, and its s* is never above the schedule analyser's at any
/// start in the range; a one-point range is that start's answer exactly.
#[test]
fn a_range_of_initial_gaps_takes_sensing_settings() {
    for p in sensing_problems().into_iter().step_by(7) {
        let at = |g0: f64| {
            let mut q = p.clone();
            q.environment.initial_gap = safereach::core::model::Position::At(g0);
            analyse(&q).expect("analysed")
        };
        let mut ranged = p.clone();
        ranged.environment.initial_gap = safereach::core::model::Position::Range(1.1, 1.3);
        ranged
            .validate("test")
            .expect("a range with sensing is valid");
        let cert = certify(&Scene::from_problem(&ranged));
        let worst = star(&cert).expect("measured");
        for g0 in [1.1, 1.15, 1.2, 1.25, 1.3] {
            let a = at(g0);
            let s = if a.never_stops {
                f64::NEG_INFINITY
            } else {
                a.min_separation.expect("measured")
            };
            assert!(
                worst <= s + 1e-9,
                "{}: range {worst} above g0 = {g0}'s {s}",
                p.to_toml_string()
            );
        }
        ranged.environment.initial_gap = safereach::core::model::Position::Range(1.2, 1.2);
        let point = certify(&Scene::from_problem(&ranged));
        let s = star(&point).expect("measured");
        let a = at(1.2);
        let m = if a.never_stops {
            f64::NEG_INFINITY
        } else {
            a.min_separation.unwrap()
        };
        assert!(
            s == m || (s - m).abs() < 1e-7,
            "one-point range {s}, start {m}"
        );
    }
}

/// The shipped lane-change scene with a pedestrian-like first sighting inside ρ: decided
/// (a far hidden obstacle does not start a new lineage of runs at every read), certified,
/// and never above the exact answer.
#[test]
fn the_lane_change_scene_is_decided_with_occlusion_inside_the_area() {
    let file = crate::common::paths::problem_file("seed-lanes.toml");
    let exact = Scene::load(&file).expect("the shipped scene");
    let sets = ["sensing.first_detection_gap=0.8".to_string()];
    let occluded = Scene::load_with_overrides(&file, &sets).expect("reads");
    let (e, o) = (certify(&exact), certify(&occluded));
    assert_eq!(o.verdict, Verdict::Certified);
    assert!(star(&o).unwrap() <= star(&e).unwrap());
}

// ---------------------------------------------------------------------------------------------
// The scene explorer with noise and occlusion as finite choices
// ---------------------------------------------------------------------------------------------

/// A small scene of a coarse robot (v_max in one 0.5 s period) with a walker in its lane,
/// something parked or walking in the next lane, lane changes on or off and `[sensing]`.
fn sensing_scene(rng: &mut ChaCha8Rng) -> Scene {
    let lc = rng.random_range(0..2) == 1;
    let sensing = [
        "gap_noise = 0.05\n",
        "gap_noise = 0.03\nspeed_noise = 0.1\n",
        "first_detection_gap = 0.7\n",
        "first_detection_gap = 1.1\n",
        "gap_noise = 0.04\nfirst_detection_gap = 0.9\n",
    ][rng.random_range(0..5)];
    // No obstacle starts closer than d_det (validation refuses it: it could never be seen).
    let d_det = sensing
        .split("first_detection_gap = ")
        .nth(1)
        .map_or(0.0, |rest| rest.trim().parse::<f64>().expect("a number"));
    let walker = (f64::from(rng.random_range(24..=60u32)) / 20.0).max(d_det);
    let w = [0.0, 0.1, 0.2, 0.3][rng.random_range(0..4)];
    let other = (f64::from(rng.random_range(16..=50u32)) / 20.0).max(d_det);
    let (other_w, other_static) = if rng.random_range(0..2) == 0 {
        (0.0, true)
    } else {
        (0.2, false)
    };
    let text = format!(
        r#"name = "sensing-explore"
[robot]
max_speed = 0.5
acceleration = 0.5
braking = 0.5
control_period = 0.5
latency = {latency}
clearance = 0.0
[controller]
assumed_obstacle_speed = 0.2
reaction_radius = {rho}
danger_rule = "{rule}"
buffer = 0.1
wrong_assumption_brake = {wab}
lane_change = {lc}
lane_change_periods = 1
lane_change_rear_gap = 0.3
[scene]
lanes = [0, 1]
[[obstacle]]
name = "walker"
lane = 0
position = {walker}
max_speed = {w}
[[obstacle]]
name = "other"
lane = 1
position = {other}
max_speed = {other_w}
static = {other_static}
[sensing]
{sensing}"#,
        latency = rng.random_range(0..=1),
        rho = [1.2, 2.0][rng.random_range(0..2)],
        rule = ["paper", "kinematic", "area"][rng.random_range(0..3)],
        wab = rng.random_range(0..2) == 1,
    );
    Scene::from_toml_str(&text, "test").unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// Every path the explorer reports, replayed from scratch with the observations it states,
/// keeps the sensing premises and gives what the explorer says of it.
fn check_sensing_paths(scene: &Scene, e: &SceneExploration) -> (bool, bool) {
    let p = scene.params::<Exact>();
    let (mut hides, mut errs) = (false, false);
    let paths = e.counterexample.iter().map(|c| (c, None)).chain(
        e.obstacles.iter().enumerate().filter_map(|(i, o)| {
            (!o.unbounded).then_some(o.closest.as_ref().map(|c| (c, Some(i))))?
        }),
    );
    for (path, obstacle) in paths {
        let r = simulate::replay_observing(
            &p,
            &path.speeds,
            &path.plan,
            &path.starts,
            path.periods(),
            obstacle.is_none(),
        );
        premises_hold(&p, &path.plan, &r.run)
            .unwrap_or_else(|m| panic!("{}: {m}", scene.to_toml_string()));
        match obstacle {
            None => assert!(r.collided() && r.periods() == path.periods()),
            Some(i) => assert_eq!(r.separations()[i], e.obstacles[i].min_separation),
        }
        hides |= path.plan.hidden_until.iter().any(|&h| h > 1);
        errs |= !path.plan.errors.is_empty();
    }
    (hides, errs)
}

/// The scene explorer, with noise (errors −σ, 0, +σ) and occlusion (hidden or first shown
/// at every observation that may show it) as the environment's choices, against the run
/// search on 60 small scenes: explorer collision ⇒ refuted; every explored separation
/// ≥ s*; every reported path keeps the premises when replayed. The explorer's behaviours
/// are a finite subset of the semantics', so these laws fail only if the search misses a
/// behaviour (or the explorer invents one).
#[test]
fn the_scene_explorer_under_noise_and_occlusion_agrees_with_the_search() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut collisions, mut safe, mut tight, mut hides, mut errs) = (0, 0, 0, 0, 0);
    for _ in 0..60 {
        let scene = sensing_scene(&mut rng);
        let name = scene.to_toml_string();
        let cert = certify(&scene);
        let p = scene.params::<Exact>();
        let e = explore_scene(
            &scene,
            SceneSpeeds::extremes(&p),
            &Options {
                max_states: 20_000,
                ..Options::default()
            },
        )
        .expect("explored");
        if e.verdict == ExploreVerdict::Collision {
            assert_eq!(cert.verdict, Verdict::Refuted, "{name}");
            collisions += 1;
        }
        safe += usize::from(e.verdict == ExploreVerdict::Safe);
        if e.never_stops() {
            assert!(
                cert.never_stops,
                "{name}: the explorer drives through for ever"
            );
        } else if let (Some(m), Some(s)) = (e.min_separation_f64(), star(&cert)) {
            assert!(m >= s - 1e-9, "{name}: explorer {m} below s* {s}");
            tight += usize::from(e.complete && (m - s).abs() <= 1e-9);
        }
        let (h, r) = check_sensing_paths(&scene, &e);
        hides += usize::from(h);
        errs += usize::from(r);
    }
    // Not trivial: both verdicts, paths that hide or err, and explorations that reach s*.
    assert!(
        collisions >= 5 && safe >= 5,
        "{collisions} collisions, {safe} safe"
    );
    assert!(
        hides >= 5 && errs >= 5,
        "{hides} hiding paths, {errs} erring paths"
    );
    assert!(tight >= 10, "only {tight} explorations reach s*");
}

/// The shipped seed-lanes scene with an obstacle first seen as late as 0.8 m: the explorer
/// finds a closer approach than without occlusion (the parked obstacle shown only once the
/// robot has swerved towards it), and exactly the search's s*.
#[test]
fn occlusion_in_seed_lanes_is_explored_to_the_searchs_answer() {
    let text = std::fs::read_to_string(crate::common::paths::problem_file("seed-lanes.toml"))
        .expect("the shipped scene");
    let explore = |extra: &str| {
        let scene = Scene::from_toml_str(&format!("{text}{extra}"), "test").expect("reads");
        let p = scene.params::<Exact>();
        let e = explore_scene(&scene, SceneSpeeds::extremes(&p), &Options::default())
            .expect("explored");
        assert!(e.complete, "explored completely");
        (scene, e)
    };
    let (_, plain) = explore("");
    let (scene, hidden) = explore("\n[sensing]\nfirst_detection_gap = 0.8\n");
    let cert = certify(&scene);
    let m = hidden.min_separation_f64().expect("a separation");
    assert!(m < plain.min_separation_f64().unwrap() - 0.01);
    assert!(
        (m - star(&cert).unwrap()).abs() <= 1e-9,
        "explorer {m} vs search {:?}",
        star(&cert)
    );
    let (hides, _) = check_sensing_paths(&scene, &hidden);
    assert!(hides, "the closest approach hides an obstacle");
}

/// `safereach explore` on a scene file with `[sensing]`: a collision found by hiding an
/// obstacle exits 1 and states, in text and JSON, when each obstacle was first shown — the
/// library's path.
#[test]
fn cli_explores_a_scene_with_sensing() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (scene, plan) = (0..60)
        .find_map(|_| {
            let scene = sensing_scene(&mut rng);
            let p = scene.params::<Exact>();
            let e = explore_scene(&scene, SceneSpeeds::extremes(&p), &Options::default()).ok()?;
            let c = e.counterexample?;
            c.plan
                .hidden_until
                .iter()
                .any(|&h| h > 1)
                .then_some((scene, c.plan))
        })
        .expect("a collision that hides an obstacle");
    let dir = crate::common::tmp();
    let path = dir.path().join("hidden.toml");
    std::fs::write(&path, scene.to_toml_string()).unwrap();
    let run = |json: bool| {
        let mut cmd = crate::common::cli::safereach(dir.path());
        cmd.arg("explore").arg(&path);
        if json {
            cmd.arg("--json");
        }
        let out = cmd.assert().code(1).get_output().clone();
        crate::common::cli::stdout(&out)
    };
    let text = run(false);
    assert!(
        text.contains("observations (the environment's choices):"),
        "{text}"
    );
    assert!(text.contains("first shown at t = "), "{text}");
    let v: serde_json::Value = serde_json::from_str(&run(true)).unwrap();
    let shown: Vec<usize> =
        serde_json::from_value(v["path"]["first_shown_step"].clone()).expect("first_shown_step");
    assert_eq!(shown, plan.hidden_until);
}

// ---------------------------------------------------------------------------------------------
// Scene Monte Carlo with sensing
// ---------------------------------------------------------------------------------------------

/// The seed robot and walker (W = 0.15 m/s), starting 6 m away, and a box parked at 9 m.
fn walker_and_box() -> Scene {
    let seed = Problem::load(&crate::common::paths::seed_file()).expect("the shipped seed");
    let mut scene = Scene::from_problem(&seed);
    scene.name = "walker-and-box".into();
    scene.obstacles[0].position = Position::At(6.0);
    scene.obstacles.push(Obstacle {
        name: "box".into(),
        lane: 0,
        position: Position::At(9.0),
        max_speed: 0.0,
        is_static: true,
    });
    scene
}

/// A hidden walker inside a large reaction radius (ρ = 3 and 6 m, d_det = 1 m, gap noise):
/// the search's quiet-cell dominance (a first sighting that changes no command starts no
/// lineage of its own) keeps it to a fraction of a second where it once ran for minutes,
/// and its s* is the explorer's least separation exactly, both refuting.
#[test]
fn a_hidden_obstacle_inside_a_large_radius_is_searched_exactly() {
    for rho in [3.0, 6.0] {
        let mut scene = walker_and_box();
        scene.controller.reaction_radius = rho;
        scene.sensing = Some(Sensing {
            gap_noise: Some(0.01),
            speed_noise: None,
            first_detection_gap: Some(1.0),
        });
        scene.validate("test").expect("valid");
        let cert = certify(&scene);
        let p = scene.params::<Exact>();
        let e = explore_scene(&scene, SceneSpeeds::extremes(&p), &Options::default())
            .expect("explored");
        assert!(e.complete, "ρ = {rho}: explored completely");
        assert_eq!(cert.verdict, Verdict::Refuted, "ρ = {rho}");
        assert_eq!(e.verdict, ExploreVerdict::Collision, "ρ = {rho}");
        let (m, s) = (e.min_separation_f64().unwrap(), star(&cert).unwrap());
        assert!((m - s).abs() <= 1e-9, "ρ = {rho}: explorer {m}, search {s}");
    }
}

/// Random runs of a two-obstacle scene (a walker in front of a parked box) with `[sensing]`,
/// against the search: where the search certifies, no run collides and none comes closer
/// than s*; where only occlusion refutes it, more than a quarter of the runs collide, each
/// one that hides the walker late (the odd ones).
#[test]
fn scene_monte_carlo_plays_noise_and_occlusion_within_the_premises() {
    let base = walker_and_box();
    let runs = 200;
    let mc_of = |sensing: Option<(f64, f64, Option<f64>)>| {
        let mut scene = base.clone();
        scene.sensing = sensing.map(|(g, w, d)| Sensing {
            gap_noise: Some(g),
            speed_noise: Some(w),
            first_detection_gap: d,
        });
        scene.validate("test").expect("valid");
        let mc = scene_monte_carlo(&scene.params::<Rational>(), runs, 3, &SpeedPattern::ALL);
        (certify(&scene), scene, mc)
    };
    for sensing in [
        None,
        Some((0.01, 0.02, None)),
        Some((0.01, 0.02, Some(1.2))),
    ] {
        let (cert, _, mc) = mc_of(sensing);
        assert_eq!(cert.verdict, Verdict::Certified, "{sensing:?}");
        assert_eq!(mc.collisions, 0, "{sensing:?}");
        let (m, s) = (mc.min_separation.unwrap(), star(&cert).unwrap());
        assert!(m >= s - 1e-9, "{sensing:?}: Monte Carlo {m} below s* {s}");
    }
    let (cert, scene, mc) = mc_of(Some((0.0, 0.0, Some(0.5))));
    assert_eq!(cert.verdict, Verdict::Refuted);
    assert!(mc.collisions > runs / 4, "{} collisions", mc.collisions);
    let params = scene.params::<Rational>();
    let max = safereach::core::scene::simulate::horizon(&scene.params::<f64>());
    for i in 0..runs {
        let run = scene_monte_carlo_run(&params, 3, i, &SpeedPattern::ALL, max, true);
        assert!(
            !run.outcome.collided || i % 2 == 1,
            "run {i} shows the walker early"
        );
    }
    let closest = scene_monte_carlo_run(&params, 3, mc.closest_run, &SpeedPattern::ALL, max, true);
    assert_eq!(
        closest.outcome.min_separation().map(|(_, s)| s.as_f64()),
        mc.min_separation
    );
}

/// An obstacle that starts closer than d_det could never be first seen: the premise would
/// rule it out and every answer would hold vacuously (the search found no behaviour and
/// said s* = +∞). Refused, naming the obstacle's position, in scenes and problems, from the
/// file and from `--set`, exit 2.
#[test]
fn an_obstacle_starting_inside_d_det_is_refused() {
    let text = std::fs::read_to_string(crate::common::paths::problem_file("seed-lanes.toml"))
        .expect("the shipped scene");
    // parked-left starts at 6 m.
    let err = Scene::from_toml_str(
        &format!("{text}\n[sensing]\nfirst_detection_gap = 7\n"),
        "l.toml",
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("l.toml")
            && err.contains("(\"parked-left\").position = 6")
            && err.contains(">= sensing.first_detection_gap = 7 (m)"),
        "{err}"
    );
    assert!(
        Scene::from_toml_str(
            &format!("{text}\n[sensing]\nfirst_detection_gap = 6\n"),
            "l.toml"
        )
        .is_ok(),
        "a start at d_det itself can be seen at its first observation"
    );
    let dir = crate::common::tmp();
    let out = crate::common::cli::safereach(dir.path())
        .arg("certify")
        .arg(crate::common::paths::seed_file())
        .args([
            "--set",
            "environment.initial_gap=[0.5, 3]",
            "--set",
            "sensing.first_detection_gap=0.8",
        ])
        .assert()
        .code(2)
        .get_output()
        .clone();
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("environment.initial_gap = [0.5, 3]: its min must be >= sensing.first_detection_gap = 0.8 (m)"),
        "{err}"
    );
}

/// Lemma R7 (docs/reductions.md §7): jumping over the steps at which no guard can fire —
/// nothing within ρ + σ_g, or nothing within min(ρ, d_i) + σ_g of an obstacle that only
/// danger can make count — changes no obstacle's separation: the search that reads every
/// step agrees, on random small scenes with noise or occlusion (lane changes on or off) and
/// on the shipped lane-change scenes, with and without gap noise.
#[test]
fn jumping_over_quiet_steps_changes_no_answer() {
    use safereach::proof::scene_search::{SearchOptions, search_scene, search_scene_with};
    let step_by_step = SearchOptions {
        jump_quiet_steps: false,
        ..SearchOptions::default()
    };
    let mut scenes: Vec<Scene> = Vec::new();
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    for _ in 0..60 {
        scenes.push(sensing_scene(&mut rng));
    }
    for name in ["seed-lanes", "lane-change-saves", "lane-change-refused"] {
        let path = crate::common::paths::problem_file(&format!("{name}.toml"));
        let text = std::fs::read_to_string(path).expect("a shipped scene");
        for extra in ["", "\n[sensing]\ngap_noise = 0.03\n"] {
            let scene = Scene::from_toml_str(&format!("{text}{extra}"), name).expect("reads");
            scenes.push(scene);
        }
    }
    let mut jumped = 0;
    for scene in &scenes {
        let name = scene.to_toml_string();
        let fast = search_scene(scene).expect("searched");
        let slow = search_scene_with(scene, step_by_step).expect("searched step by step");
        assert_eq!(fast.obstacles, slow.obstacles, "{name}");
        assert_eq!(fast.min_separation(), slow.min_separation(), "{name}");
        jumped += usize::from(fast.stats.nodes < slow.stats.nodes);
    }
    assert!(
        jumped >= 40,
        "only {jumped} of {} searches jumped",
        scenes.len()
    );
}
