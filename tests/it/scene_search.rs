//! The exact run search (`proof::scene_search`) on the shipped problems and scenes: the
//! single-obstacle analyser's answers exactly, and the lane-change scenes as README states
//! them. (Random scenes against the schedule analyser and the explorer are in
//! `scene_explore::run_search`.)

use safereach::analysis::{Verdict, analyse};
use safereach::core::model::Problem;
use safereach::core::scene::Scene;
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
