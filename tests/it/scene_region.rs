//! Region maps of scenes, held against the scene analyser at random points: a point the
//! scene analyser refutes lies in no certified leaf, and a point of a certified leaf
//! certifies with s* at least the leaf's bound — over planes of shared and per-obstacle
//! keys, with a destination and a static obstacle in the lane. A one-obstacle scene maps
//! exactly as its problem; `check` rejects tampered scene maps; the command line maps a
//! scene file and refuses keys a scene cannot range, naming the flag.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use safereach::analysis::Verdict;
use safereach::analysis::region::Hints;
use safereach::analysis::region_search::{RegionOptions, map_region, map_scene_region};
use safereach::analysis::scene::analyse_scene;
use safereach::analysis::scene_region::certify_scene_box;
use safereach::core::param_box::{Axis, ParamBox};
use safereach::core::parameter::Parameter;
use safereach::core::scene::Scene;
use safereach::proof::region_check::check_map;
use safereach::proof::region_map::{LeafVerdict, RegionMap};

use crate::common::cli::{bad_input_exits_2, safereach, stdout};
use crate::common::forgery::{halve_largest_multiplier, map_rejected, with_first_axis_to};
use crate::common::map_points::{leaves_holding, random_point};
use crate::common::paths::load_problem;
use crate::common::tmp;

/// Two oncoming obstacles in the robot's lane (the far one as fast as V_a) and a parked
/// one in the next lane.
const TWO: &str = r#"
name = "two-oncoming"
[robot]
max_speed = 0.2
acceleration = 0.1
braking = 0.05
control_period = 0.1
latency = 1
clearance = 0.0
[controller]
assumed_obstacle_speed = 0.2
reaction_radius = 1.4
danger_rule = "paper"
buffer = 0.1
wrong_assumption_brake = true
[scene]
lanes = [0, 1]
[[obstacle]]
name = "near"
lane = 0
position = 4.0
max_speed = 0.15
[[obstacle]]
name = "far"
lane = 0
position = 5.5
max_speed = 0.2
[[obstacle]]
name = "parked"
lane = 1
position = 3.0
max_speed = 0.0
static = true
"#;

fn scene(sets: &[&str]) -> Scene {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    Scene::from_toml_str_with_overrides(TWO, "two-oncoming", &sets).expect("a valid scene")
}

/// A shared key's axis.
fn shared(key: &str, lo: f64, hi: f64) -> Axis {
    Axis::new(Parameter::from_key(key).expect("a rangeable key"), lo, hi)
}

/// Obstacle `i`'s own axis: W_i (`speed`) or its start.
fn own(i: usize, speed: bool, lo: f64, hi: f64) -> Axis {
    let p = if speed {
        Parameter::ObstacleSpeed
    } else {
        Parameter::InitialGap
    };
    Axis {
        obstacle: Some(i),
        ..Axis::new(p, lo, hi)
    }
}

fn options(depth: u32) -> RegionOptions {
    RegionOptions {
        depth,
        ..RegionOptions::default()
    }
}

fn scene_map(s: &Scene, axes: Vec<Axis>, depth: u32) -> RegionMap {
    let whole = ParamBox::new(axes).expect("a valid box");
    let m = map_scene_region(s, &whole, &options(depth), &|_| {}).expect("mappable");
    check_map(&m).expect("the map checks");
    m
}

/// Random points of the map's box analysed one by one (see the module docs); returns how
/// many certified and how many were refuted. The first `as_boxes` points are also
/// certified as boxes of no width: a box's bound at a point is never above the point's s*,
/// and a refuted point's box is not certified.
fn points_agree(
    s: &Scene,
    m: &RegionMap,
    points: usize,
    as_boxes: usize,
    seed: u64,
) -> (usize, usize) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut certified, mut refuted) = (0, 0);
    for _ in 0..points {
        let values = random_point(m, || rng.random::<f64>(), 3);
        let mut at = s.clone();
        for (a, v) in m.ranges.iter().zip(&values) {
            a.set_in_scene(&mut at, *v).expect("a scene key");
        }
        let answer = analyse_scene(&at).expect("analysable");
        if certified + refuted < as_boxes {
            let point = ParamBox::new(
                m.ranges
                    .iter()
                    .zip(&values)
                    .map(|(a, v)| Axis {
                        lo: *v,
                        hi: *v,
                        ..*a
                    })
                    .collect(),
            )
            .expect("a point is a box");
            let cert = certify_scene_box(s, &point, &Hints::default(), &mut 0);
            match (&cert, answer.verdict, answer.min_separation) {
                (Ok(_), Verdict::Refuted, _) => {
                    panic!("{values:?}: refuted, yet its box certifies")
                }
                (Ok(c), _, Some(sep)) => assert!(
                    c.lower_bound.to_f64().value() <= sep + 1e-9,
                    "{values:?}: the box's bound {} is above s* = {sep}",
                    c.lower_bound
                ),
                _ => {}
            }
        }
        let holding = leaves_holding(m, &values);
        for leaf in holding.filter(|l| l.verdict == LeafVerdict::Certified) {
            assert_eq!(
                answer.verdict,
                Verdict::Certified,
                "{values:?} lies in certified leaf {:?} but is {:?}",
                leaf.path,
                answer.verdict
            );
            let lower = answer
                .lower_bound
                .as_ref()
                .expect("certified points are bounded");
            let bound = leaf.lower_bound.expect("certified leaves state a bound");
            assert!(
                lower.to_f64().value() >= bound - 1e-9,
                "{values:?}: lower bound {lower} below the leaf's bound {bound}"
            );
        }
        match answer.verdict {
            Verdict::Certified => certified += 1,
            Verdict::Refuted => refuted += 1,
            Verdict::Inconclusive => {}
        }
    }
    (certified, refuted)
}

#[test]
fn scene_planes_agree_with_the_scene_analyser_at_random_points() {
    let cases: Vec<(&str, Scene, Vec<Axis>)> = vec![
        (
            "the far obstacle's speed against ρ",
            scene(&[]),
            vec![
                own(1, true, 0.1, 0.3),
                shared("controller.reaction_radius", 1.0, 1.6),
            ],
        ),
        (
            "the near obstacle's start against the far one's speed",
            scene(&[]),
            vec![own(0, false, 3.0, 5.0), own(1, true, 0.1, 0.3)],
        ),
        (
            "a destination: V_a against the near obstacle's speed",
            scene(&["robot.goal=3.0"]),
            vec![
                shared("controller.assumed_obstacle_speed", 0.1, 0.3),
                own(0, true, 0.1, 0.3),
            ],
        ),
        (
            "a static obstacle in the lane, the others far: its start against ρ",
            scene(&[
                "obstacle.2.lane=0",
                "obstacle.2.position=2.0",
                "obstacle.0.position=9.0",
                "obstacle.1.position=10.0",
            ]),
            vec![
                own(2, false, 1.5, 3.5),
                shared("controller.reaction_radius", 0.2, 1.0),
            ],
        ),
        (
            "a static obstacle in the lane cutting short a mover's pieces: its start against \
             the mover's speed",
            scene(&["obstacle.2.lane=0", "obstacle.2.position=3.0"]),
            vec![own(2, false, 2.0, 4.5), own(0, true, 0.1, 0.4)],
        ),
    ];
    for (k, (what, s, axes)) in cases.into_iter().enumerate() {
        let m = scene_map(&s, axes, 7);
        let (c, r) = points_agree(&s, &m, 120, 40, k as u64);
        eprintln!(
            "{what}: {:?}; points: {c} certified, {r} refuted",
            m.coverage
        );
        assert!(
            m.coverage.certified > 0.05,
            "{what}: some of the plane is certified: {:?}",
            m.coverage
        );
        assert!(
            c > 10 && r > 10,
            "{what}: both verdicts sampled: {c} certified, {r} refuted"
        );
    }
}

#[test]
fn a_one_obstacle_scene_maps_as_its_problem() {
    let seed = load_problem("seed.toml", &[]);
    let as_scene = Scene::from_problem(&seed);
    let problem_box = ParamBox::new(vec![
        shared("environment.obstacle_speed", 0.10, 0.30),
        shared("controller.reaction_radius", 1.0, 1.6),
    ])
    .expect("valid");
    let scene_box = ParamBox::new(vec![
        own(0, true, 0.10, 0.30),
        shared("controller.reaction_radius", 1.0, 1.6),
    ])
    .expect("valid");
    let p = map_region(&seed, &problem_box, &options(8), &|_| {}).expect("mappable");
    let s = map_scene_region(&as_scene, &scene_box, &options(8), &|_| {}).expect("mappable");
    check_map(&s).expect("the scene map checks");
    assert_eq!(p.leaves.len(), s.leaves.len());
    for (a, b) in p.leaves.iter().zip(&s.leaves) {
        assert_eq!(
            (&a.path, a.verdict, a.lower_bound),
            (&b.path, b.verdict, b.lower_bound)
        );
        let pieces = |l: &safereach::proof::region_map::Leaf| {
            l.proofs.iter().map(|x| x.piece).collect::<Vec<_>>()
        };
        assert_eq!(pieces(a), pieces(b), "leaf {}", a.path);
    }
    assert!(p.coverage.certified > 0.3 && p.coverage.refuted > 0.3);
}

#[test]
fn tampered_scene_maps_are_rejected() {
    let s = scene(&[]);
    let m = scene_map(
        &s,
        vec![
            own(1, true, 0.1, 0.3),
            shared("controller.reaction_radius", 1.0, 1.6),
        ],
        6,
    );
    let rejects = map_rejected;
    let certified = m
        .leaves
        .iter()
        .position(|l| l.verdict == LeafVerdict::Certified)
        .expect("a certified leaf");
    rejects(with_first_axis_to(&m, 0.5), "a wider box");
    // The box put on another obstacle.
    let mut x = m.clone();
    x.ranges[0].obstacle = Some(0);
    rejects(
        with_first_axis_to(&x, x.ranges[0].hi),
        "the box on another obstacle",
    );
    // A dropped piece, and one obstacle's proofs passed off as another's.
    let mut x = m.clone();
    x.leaves[certified].proofs.pop();
    rejects(x, "a dropped piece");
    let mut x = m.clone();
    for p in &mut x.leaves[certified].proofs {
        p.obstacle = Some(1 - p.obstacle.expect("scene proofs name their obstacle"));
    }
    rejects(x, "proofs of the other obstacle");
    // An edited multiplier (the largest one of the longest proof, halved).
    let mut x = m.clone();
    halve_largest_multiplier(&mut x.leaves[certified]);
    rejects(x, "an edited multiplier");
    // A scene with another obstacle, or a lane change switched on.
    let mut x = m.clone();
    x.scene.as_mut().unwrap().obstacles[0].max_speed = 0.3;
    rejects(x, "a faster unranged obstacle");
    let mut x = m.clone();
    x.scene.as_mut().unwrap().obstacles[2].lane = 0;
    rejects(x, "the parked obstacle moved into the lane");
    // Refutations: moved out of the leaf, or slowed down so they no longer collide.
    let r = m
        .leaves
        .iter()
        .position(|l| l.verdict == LeafVerdict::Refuted)
        .expect("a refuted leaf");
    let mut x = m.clone();
    x.leaves[r].verdict = LeafVerdict::Certified;
    rejects(x, "a refuted leaf called certified");
    let mut x = m.clone();
    let point = &mut x.leaves[r].scene_refutation.as_mut().unwrap().point;
    *point.get_mut("obstacle.1.max_speed").unwrap() = 0.01;
    rejects(x, "a refuted point moved outside its leaf");
    let mut x = m.clone();
    for speeds in &mut x.leaves[r]
        .scene_refutation
        .as_mut()
        .unwrap()
        .obstacle_speeds
    {
        speeds.iter_mut().for_each(|v| *v = 0.0);
    }
    rejects(x, "a refutation that stands still");
}

#[test]
fn the_command_line_maps_a_scene_and_refuses_what_scenes_cannot_range() {
    let dir = tmp();
    let file = dir.path().join("two.toml");
    std::fs::write(&file, TWO).unwrap();
    let out = safereach(dir.path())
        .arg("region")
        .arg(&file)
        .args([
            "--range",
            "obstacle.1.max_speed=0.1..0.18",
            "--range",
            "controller.reaction_radius=1.3..1.6",
            "--out",
            "map.json",
            "--svg",
            "map.svg",
        ])
        .assert()
        .code(0)
        .get_output()
        .clone();
    assert!(
        stdout(&out).contains("certified for every point of the box"),
        "{}",
        stdout(&out)
    );
    let svg = std::fs::read_to_string(dir.path().join("map.svg")).expect("svg written");
    for needed in [
        "obstacle.1.max_speed",
        "W_1",
        "scene two-oncoming",
        "0 (near) at x = 4 m",
    ] {
        assert!(svg.contains(needed), "the plot lacks {needed}");
    }
    safereach(dir.path())
        .args(["check", "map.json", "--require", "certified"])
        .assert()
        .code(0);
    bad_input_exits_2(
        dir.path(),
        "region",
        &file,
        &[
            (
                vec!["--range", "obstacle.5.max_speed=0.1..0.2"],
                "obstacle.5.max_speed: the scene has 3 obstacles",
            ),
            (vec!["--range", "obstacle.2.position=2..4"], "is in lane 1"),
            (
                vec!["--range", "obstacle.0.lane=0..1"],
                "max_speed and position",
            ),
            (
                vec!["--range", "environment.obstacle_speed=0.1..0.2"],
                "each have their own",
            ),
            (
                vec![
                    "--range",
                    "obstacle.0.max_speed=0.1..0.2",
                    "--set",
                    "controller.lane_change=true",
                    "--set",
                    "controller.lane_change_periods=5",
                    "--set",
                    "controller.lane_change_rear_gap=0.5",
                ],
                "lane changes",
            ),
            (
                vec!["--range", "obstacle.0.position=0..4"],
                "invalid at a corner",
            ),
        ],
    );
}
