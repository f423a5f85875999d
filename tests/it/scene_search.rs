//! The exact run search (`proof::scene_search`) on the shipped problems and scenes: the
//! single-obstacle analyser's answers exactly, and the lane-change scenes as README states
//! them. (Random scenes against the schedule analyser and the explorer are in
//! `scene_explore::run_search`.)

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use safereach::analysis::{Verdict, analyse};
use safereach::core::model::Problem;
use safereach::core::scene::Scene;
use safereach::proof::scene_search::{SceneSearch, SearchOptions, search_scene, search_scene_with};
use safereach::proof::search_certificate::{SearchCertificate, certify_by_search};
use safereach::proof::search_check::check_search;

use crate::common::paths::{load_problem, problem_file};

fn scene(name: &str, sets: &[&str]) -> Scene {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    Scene::load_with_overrides(&problem_file(name), &sets).expect("scene loads")
}

fn certify(scene: &Scene) -> SearchCertificate {
    let cert = certify_by_search(scene).expect("searched");
    check_search(&cert).expect("the certificate checks");
    cert
}

/// Every shipped single-obstacle problem, as a scene, gets the schedule analyser's s* and
/// verdict from the search.
#[test]
fn the_search_gives_the_single_obstacle_answers() {
    for name in [
        "seed.toml",
        "fast-obstacle.toml",
        "static-obstacle.toml",
        "area-rule.toml",
        "kinematic-rule.toml",
        "zero-latency.toml",
    ] {
        let problem: Problem = load_problem(name, &[]);
        let a = analyse(&problem).expect("analysed");
        let cert = certify(&Scene::from_problem(&problem));
        assert_eq!(cert.verdict, a.verdict, "{name}");
        let (s, m) = (
            cert.min_separation.expect(name),
            a.min_separation.expect(name),
        );
        assert!((s - m).abs() < 1e-9, "{name}: search {s}, analyser {m}");
    }
}

/// The seed's picture: certified at 12/25 m, the worst case a parked car in lane 1 after
/// the robot swerved into that lane.
#[test]
fn the_seed_picture_is_certified_with_its_worst_case_after_a_lane_change() {
    let cert = certify(&scene("seed-lanes.toml", &[]));
    assert_eq!(cert.verdict, Verdict::Certified);
    assert_eq!(cert.min_separation_exact.as_deref(), Some("12/25"));
    let w = cert.witness.as_ref().expect("a witness");
    assert_eq!((w.obstacle, w.lane), (1, 1));
    assert_eq!(w.lane_changes.len(), 1);
    assert_eq!((w.lane_changes[0].from, w.lane_changes[0].to), (0, 1));
}

/// A lane change saves the robot where braking alone does not, and a lane occupied by a
/// row of parked cars takes that away again.
#[test]
fn a_lane_change_saves_the_robot_unless_the_other_lane_is_occupied() {
    let saves = certify(&scene("lane-change-saves.toml", &[]));
    assert_eq!(saves.verdict, Verdict::Certified);
    assert_eq!(saves.min_separation_exact.as_deref(), Some("4/5"));
    let braking = certify(&scene(
        "lane-change-saves.toml",
        &["controller.lane_change=false"],
    ));
    assert_eq!(braking.verdict, Verdict::Refuted);
    let refused = certify(&scene("lane-change-refused.toml", &[]));
    assert_eq!(refused.verdict, Verdict::Refuted);
    assert_eq!(refused.min_separation_exact, braking.min_separation_exact);
    let w = refused.witness.as_ref().expect("a witness");
    assert!(w.lane_changes.is_empty() && w.collides);
}

/// A position range holds every behaviour of each start in it: its s* is at most each
/// start's, and a range of one point is that position exactly.
#[test]
fn a_position_range_is_no_safer_than_any_start_in_it() {
    let range = certify(&scene(
        "seed-lanes.toml",
        &["obstacle.0.position=[9.5, 10.5]"],
    ));
    let at = |x: f64| {
        let set = format!("obstacle.0.position={x}");
        certify(&scene("seed-lanes.toml", &[set.as_str()]))
    };
    let worst = range.min_separation.expect("finite");
    for x in [9.5, 9.75, 10.0, 10.25, 10.5] {
        let s = at(x).min_separation.expect("finite");
        assert!(worst <= s, "range {worst} above the start {x}'s {s}");
    }
    let point = certify(&scene(
        "seed-lanes.toml",
        &["obstacle.0.position=[10.0, 10.0]"],
    ));
    assert_eq!(point.min_separation_exact, at(10.0).min_separation_exact);
    let start = &range.witness.as_ref().expect("a witness").starts[0];
    assert!(
        start.is_some(),
        "the witness says where the ranged obstacle started"
    );
}

/// Oncoming traffic for the robot that swerves: two or three obstacles coming down its lane
/// (sometimes one down a neighbouring lane), parked cars left and right, lane changes of
/// a few periods, and at random the guard, the rule, latency, gap noise, occlusion, a goal.
/// A coarse robot (0.25 s periods) keeps the search without shortcuts quick.
fn oncoming_traffic(rng: &mut ChaCha8Rng) -> Scene {
    let mut obstacles = String::new();
    let oncoming = rng.random_range(2..=3);
    for i in 0..oncoming {
        let lane = if i == 2 && rng.random_range(0..2) == 0 {
            1
        } else {
            0
        };
        obstacles += &format!(
            "[[obstacle]]\nname = \"o{i}\"\nlane = {lane}\nposition = {}\nmax_speed = {}\n",
            f64::from(rng.random_range(8..=24u32)) / 4.0 + 1.5 * f64::from(i),
            [0.05, 0.1, 0.2, 0.3][rng.random_range(0..4)],
        );
    }
    for (lane, name) in [(1, "right"), (-1, "left")] {
        if rng.random_range(0..4) > 0 {
            obstacles += &format!(
                "[[obstacle]]\nname = \"parked-{name}\"\nlane = {lane}\nposition = {}\nmax_speed = 0.0\nstatic = true\n",
                f64::from(rng.random_range(6..=28u32)) / 4.0,
            );
        }
    }
    let sensing = [
        "",
        "",
        "",
        "[sensing]\ngap_noise = 0.03\n",
        "[sensing]\nfirst_detection_gap = 0.9\n",
    ][rng.random_range(0..5)];
    let goal = match rng.random_range(0..4) {
        0 => format!("goal = {}\n", rng.random_range(6..=14)),
        _ => String::new(),
    };
    let text = format!(
        r#"name = "oncoming-traffic"
[robot]
max_speed = 0.4
acceleration = 0.4
braking = {braking}
control_period = 0.25
latency = {latency}
clearance = 0.0
{goal}[controller]
assumed_obstacle_speed = 0.2
reaction_radius = {rho}
danger_rule = "{rule}"
buffer = 0.1
wrong_assumption_brake = {wab}
lane_change = true
lane_change_periods = {periods}
lane_change_rear_gap = {rear}
[scene]
lanes = [-1, 0, 1]
{obstacles}{sensing}"#,
        braking = [0.2, 0.4][rng.random_range(0..2)],
        latency = rng.random_range(0..=2),
        rho = [1.5, 2.0, 2.5][rng.random_range(0..3)],
        rule = ["paper", "kinematic", "area"][rng.random_range(0..3)],
        wab = rng.random_range(0..2) == 1,
        periods = rng.random_range(2..=5),
        rear = [0.0, 0.3, 0.6][rng.random_range(0..3)],
    );
    Scene::from_toml_str(&text, "oncoming-traffic").unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The search without leaving out dominated step starts (Lemma R9).
fn unpruned(scene: &Scene) -> SceneSearch {
    let every_run = SearchOptions {
        prune_dominated: false,
        ..SearchOptions::default()
    };
    search_scene_with(scene, every_run).expect("searched without pruning")
}

/// Leaving out the runs whose every future is worth no less than a searched one's (Lemma
/// R9: they differ only in their past) changes no obstacle's separation, nor which
/// obstacle is the worst or how far, whichever runs it meets first (children searched
/// first first and last first): against the search without it, on the shipped
/// lane-change scenes (one and two oncoming obstacles in the seed's picture) and on
/// oncoming traffic with noise, occlusion, goals and neighbouring traffic.
#[test]
fn leaving_out_dominated_runs_changes_no_answer() {
    let mut scenes: Vec<Scene> = [
        "seed-lanes.toml",
        "lane-change-saves.toml",
        "lane-change-refused.toml",
    ]
    .iter()
    .map(|name| scene(name, &[]))
    .collect();
    scenes.push(scene(
        "seed-lanes.toml",
        &[
            "obstacle.1.max_speed=0.1",
            "obstacle.1.static=false",
            "obstacle.1.lane=0",
            "obstacle.1.position=11.5",
        ],
    ));
    let mut rng = ChaCha8Rng::seed_from_u64(0x0d0);
    for _ in 0..40 {
        scenes.push(oncoming_traffic(&mut rng));
    }
    let mut pruned = 0;
    for scene in &scenes {
        let name = scene.to_toml_string();
        let every = unpruned(scene);
        let reversed = SearchOptions {
            reverse_children: true,
            ..SearchOptions::default()
        };
        let fast = search_scene(scene).expect("searched");
        let other_order = search_scene_with(scene, reversed).expect("searched last first");
        assert_eq!(other_order.obstacles, every.obstacles, "{name}");
        assert_eq!(
            other_order.min_separation(),
            every.min_separation(),
            "{name}"
        );
        assert_eq!(fast.obstacles, every.obstacles, "{name}");
        assert_eq!(fast.min_separation(), every.min_separation(), "{name}");
        assert_eq!(fast.unbounded(), every.unbounded(), "{name}");
        assert_eq!(
            fast.worst.as_ref().map(|w| w.obstacle),
            every.worst.as_ref().map(|w| w.obstacle),
            "{name}"
        );
        assert_eq!(every.stats.pruned, 0);
        pruned += usize::from(fast.stats.pruned > 0);
    }
    assert!(
        pruned >= 12,
        "only {pruned} of {} searches pruned",
        scenes.len()
    );
}
