//! Region certificates and maps, held against the point analyser: every point `certify`
//! refutes lies outside every certified leaf, points inside certified leaves certify with s*
//! at least the leaf's bound, the certified boundary of the seed plane follows the `radius`
//! curve, `check` verifies maps and rejects tampered ones, and the command line answers as
//! documented.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use safereach::analysis::radius;
use safereach::analysis::region_search::{RegionOptions, map_region};
use safereach::analysis::{Verdict, analyse};
use safereach::core::model::Problem;
use safereach::core::param_box::{Axis, ParamBox};
use safereach::core::parameter::Parameter;
use safereach::proof::region_check::check_map;
use safereach::proof::region_map::{LeafVerdict, RegionMap};

use crate::common::cli::{safereach, seed_box_region, stdout};
use crate::common::forgery::{halve_largest_multiplier, map_rejected, with_first_axis_to};
use crate::common::map_points::{leaves_holding, random_point};
use crate::common::paths::{load_problem, seed_file};
use crate::common::tmp;

fn axis(key: &str, lo: f64, hi: f64) -> Axis {
    Axis::new(Parameter::from_key(key).expect("a rangeable key"), lo, hi)
}

fn map(problem: &Problem, axes: Vec<Axis>, depth: u32) -> RegionMap {
    let whole = ParamBox::new(axes).expect("a valid box");
    let options = RegionOptions {
        depth,
        min_width: 0.0,
        ..RegionOptions::default()
    };
    let m = map_region(problem, &whole, &options, &|_| {}).expect("mappable");
    check_map(&m).expect("the map checks");
    m
}

/// The leaf holding the point (on a shared face, the first found).
fn leaf_at<'m>(m: &'m RegionMap, values: &[f64]) -> &'m safereach::proof::region_map::Leaf {
    leaves_holding(m, values)
        .next()
        .expect("the leaves cover the box")
}

/// Random points of the box analysed one by one: a refuted point is in no certified leaf
/// (checked over every leaf holding it, faces included), a point of a certified leaf
/// certifies with s* no lower than the leaf's bound.
fn points_agree(problem: &Problem, m: &RegionMap, points: usize, seed: u64) -> (usize, usize) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut certified, mut refuted) = (0, 0);
    for _ in 0..points {
        let values = random_point(m, || rng.random::<f64>(), 4);
        let mut p = problem.clone();
        for (a, v) in m.ranges.iter().zip(&values) {
            a.parameter.set_in(&mut p, *v);
        }
        let answer = analyse(&p).expect("analysable");
        for leaf in leaves_holding(m, &values) {
            if leaf.verdict != LeafVerdict::Certified {
                continue;
            }
            assert_eq!(
                answer.verdict,
                Verdict::Certified,
                "{values:?} lies in certified leaf {:?} but is {:?}",
                leaf.path,
                answer.verdict
            );
            let s = answer.min_separation.expect("certified points have s*");
            let bound = leaf.lower_bound.expect("certified leaves state a bound");
            assert!(
                s >= bound - 1e-9,
                "{values:?}: s* {s} below the leaf's bound {bound}"
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
fn the_seed_plane_agrees_with_certify_at_random_points() {
    let seed = load_problem("seed.toml", &[]);
    let m = map(
        &seed,
        vec![
            axis("environment.obstacle_speed", 0.10, 0.30),
            axis("controller.reaction_radius", 1.0, 1.6),
        ],
        10,
    );
    assert!(
        m.coverage.certified > 0.3 && m.coverage.refuted > 0.3,
        "{:?}",
        m.coverage
    );
    let (c, r) = points_agree(&seed, &m, 600, 1);
    assert!(
        c > 100 && r > 100,
        "both verdicts sampled: {c} certified, {r} refuted"
    );
}

/// The seed problem at `w` (obstacle speed) and `rho` (reaction radius).
fn seed_at(seed: &Problem, w: f64, rho: f64) -> Problem {
    let mut p = seed.clone();
    Parameter::ObstacleSpeed.set_in(&mut p, w);
    Parameter::ReactionRadius.set_in(&mut p, rho);
    p
}

#[test]
fn the_seed_plane_at_the_default_budget_leaves_at_most_two_percent_undecided() {
    let seed = load_problem("seed.toml", &[]);
    let whole = ParamBox::new(vec![
        axis("environment.obstacle_speed", 0.10, 0.30),
        axis("controller.reaction_radius", 1.0, 1.6),
    ])
    .expect("a valid box");
    let m = map_region(&seed, &whole, &RegionOptions::default(), &|_| {}).expect("mappable");
    // Every certified leaf's proofs and every refuted leaf's behaviour, exactly, no solver.
    let report = check_map(&m).expect("the map checks");
    assert!(
        report.coverage.undecided <= 0.02,
        "undecided {:.2}% at the default budget",
        100.0 * report.coverage.undecided
    );
    let (w_key, rho_key) = ("environment.obstacle_speed", "controller.reaction_radius");
    // The safe radius at a speed, by the point search (an oracle independent of the map).
    let mut radii = std::collections::BTreeMap::new();
    let mut star = |w: f64| -> f64 {
        *radii.entry(w.to_bits()).or_insert_with(|| {
            let p = load_problem("seed.toml", &[&format!("{w_key}={w}")]);
            let b = radius::safe_radius(&p).expect("search");
            b.value.unwrap_or(f64::INFINITY)
        })
    };
    for leaf in &m.leaves {
        let ([w0, w1], [r0, r1]) = (leaf.bounds[w_key], leaf.bounds[rho_key]);
        match leaf.verdict {
            LeafVerdict::Certified => {
                let centre = seed_at(&seed, (w0 + w1) / 2.0, (r0 + r1) / 2.0);
                assert_eq!(
                    analyse(&centre).expect("analysable").verdict,
                    Verdict::Certified
                );
            }
            LeafVerdict::Refuted => {
                let r = leaf
                    .refutation
                    .as_ref()
                    .expect("a refuted leaf names its point");
                let at = seed_at(&seed, r.point[w_key], r.point[rho_key]);
                assert_eq!(
                    analyse(&at).expect("analysable").verdict,
                    Verdict::Refuted,
                    "leaf {}",
                    leaf.path
                );
            }
            // Undecided only where the boundary ρ*(W), increasing in W, crosses the leaf.
            LeafVerdict::Undecided => assert!(
                star(w0) <= r1 && r0 <= star(w1),
                "leaf {} ({w0}..{w1} x {r0}..{r1}) is off the boundary",
                leaf.path
            ),
        }
    }
}

#[test]
fn other_rules_planes_and_noise_agree_with_certify() {
    // V_a = 0.17 is no cut point, so leaves straddle W = V_a (the wrong-assumption guard
    // active in part of a leaf); the kinematic rule over (V_a, buffer); the area rule over
    // (W, initial gap); noise over (σ_g, ρ); a clearance over (clearance, W); d_det.
    let cases: Vec<(Problem, Vec<Axis>)> = vec![
        (
            load_problem("seed.toml", &["controller.assumed_obstacle_speed=0.17"]),
            vec![
                axis("environment.obstacle_speed", 0.12, 0.25),
                axis("controller.reaction_radius", 1.0, 1.6),
            ],
        ),
        (
            load_problem("kinematic-rule.toml", &[]),
            vec![
                axis("controller.assumed_obstacle_speed", 0.1, 0.3),
                axis("controller.buffer", 0.0, 0.4),
            ],
        ),
        (
            load_problem("area-rule.toml", &[]),
            vec![
                axis("environment.obstacle_speed", 0.05, 0.3),
                axis("environment.initial_gap", 3.0, 12.0),
            ],
        ),
        (
            load_problem("seed.toml", &["robot.latency=2"]),
            vec![
                axis("sensing.gap_noise", 0.0, 0.1),
                axis("controller.reaction_radius", 1.0, 1.8),
            ],
        ),
        (
            load_problem("seed.toml", &["sensing.speed_noise=0.02"]),
            vec![
                axis("robot.clearance", 0.0, 0.4),
                axis("environment.obstacle_speed", 0.1, 0.25),
            ],
        ), // Occlusion: the first sighting's gap d_det over (W, d_det) where the guard cannot
        // fire (W ≤ V_a), and without the guard over (d_det, ρ).
        (
            load_problem("seed.toml", &[]),
            vec![
                axis("environment.obstacle_speed", 0.1, 0.19),
                axis("sensing.first_detection_gap", 0.3, 1.4),
            ],
        ),
        (
            load_problem("seed.toml", &["controller.wrong_assumption_brake=false"]),
            vec![
                axis("sensing.first_detection_gap", 0.2, 1.5),
                axis("controller.reaction_radius", 1.0, 1.8),
            ],
        ),
    ];
    for (i, (problem, axes)) in cases.into_iter().enumerate() {
        let m = map(&problem, axes, 8);
        let (c, r) = points_agree(&problem, &m, 150, 10 + i as u64);
        eprintln!(
            "case {i}: {:?}, points {c} certified, {r} refuted",
            m.coverage
        );
        assert!(m.coverage.certified > 0.05, "case {i}: {:?}", m.coverage);
    }
}

#[test]
fn the_certified_boundary_follows_the_radius_curve() {
    let seed = load_problem("seed.toml", &[]);
    let depth = 12;
    let m = map(
        &seed,
        vec![
            axis("environment.obstacle_speed", 0.10, 0.30),
            axis("controller.reaction_radius", 1.0, 1.6),
        ],
        depth,
    );
    // A leaf at the depth limit is at most (2/3)^(depth/2) of each range (cuts fall in the
    // middle third): the certified region may stop short of ρ* by a few of them.
    let leaf = 0.6 * (2.0f64 / 3.0).powi(depth as i32 / 2);
    for w in [0.12, 0.15, 0.175, 0.2, 0.23] {
        let p = load_problem("seed.toml", &[&format!("environment.obstacle_speed={w}")]);
        let star = radius::safe_radius(&p).expect("search").value;
        let lowest = m
            .leaves
            .iter()
            .filter(|l| l.verdict == LeafVerdict::Certified)
            .filter(|l| {
                let [lo, hi] = l.bounds["environment.obstacle_speed"];
                lo <= w && w <= hi
            })
            .map(|l| l.bounds["controller.reaction_radius"][0])
            .fold(f64::INFINITY, f64::min);
        match star {
            Some(star) if star <= 1.6 => {
                assert!(
                    lowest >= star - 1e-9,
                    "W {w}: certified at {lowest} below ρ* {star}"
                );
                assert!(
                    lowest <= star.max(1.0) + 3.0 * leaf,
                    "W {w}: certified only from {lowest}, ρ* is {star}"
                );
            }
            _ => assert!(
                lowest.is_infinite(),
                "W {w}: no radius, yet certified from {lowest}"
            ),
        }
        // Well above ρ*, the top of the plane is certified.
        if star.is_some_and(|s| s < 1.6 - 3.0 * leaf) {
            assert_eq!(
                leaf_at(&m, &[w, 1.6]).verdict,
                LeafVerdict::Certified,
                "W {w}"
            );
        }
    }
}

#[test]
fn tampered_maps_are_rejected() {
    let seed = load_problem("seed.toml", &[]);
    let m = map(
        &seed,
        vec![
            axis("environment.obstacle_speed", 0.10, 0.22),
            axis("controller.reaction_radius", 1.2, 1.6),
        ],
        6,
    );
    let rejects = map_rejected;
    let certified = m
        .leaves
        .iter()
        .position(|l| l.verdict == LeafVerdict::Certified && !l.proofs.is_empty())
        .expect("a certified leaf");
    // An edit without a new digest is named as such.
    let mut x = m.clone();
    x.leaves[certified].lower_bound = Some(5.0);
    let e = check_map(&x).expect_err("unsigned edit");
    assert!(e.0.contains("digest"), "{}", e.0);
    // A wider box (the leaves' boxes follow the new whole box).
    rejects(with_first_axis_to(&m, 0.5), "a wider box");
    // A dropped piece.
    let mut x = m.clone();
    x.leaves[certified].proofs.pop();
    rejects(x, "a dropped piece");
    // An edited multiplier (the largest one, halved).
    let mut x = m.clone();
    halve_largest_multiplier(&mut x.leaves[certified]);
    rejects(x, "an edited multiplier");
    // A leaf's box that is not its path's, a leaf left out, a verdict flipped.
    let mut x = m.clone();
    x.leaves[certified]
        .bounds
        .get_mut("controller.reaction_radius")
        .unwrap()[0] -= 0.01;
    rejects(x, "a moved face");
    let mut x = m.clone();
    x.leaves.remove(certified);
    rejects(x, "a leaf left out");
    if let Some(r) = m
        .leaves
        .iter()
        .position(|l| l.verdict == LeafVerdict::Refuted)
    {
        let mut x = m.clone();
        x.leaves[r].verdict = LeafVerdict::Certified;
        rejects(x, "a refuted leaf called certified");
        let mut x = m.clone();
        let point = &mut x.leaves[r].refutation.as_mut().unwrap().point;
        *point.get_mut("environment.obstacle_speed").unwrap() = 0.01;
        rejects(x, "a refuted point moved outside its leaf");
    }
    let mut x = m.clone();
    x.coverage.certified += 0.1;
    rejects(x, "coverage overstated");
}

#[test]
fn the_command_line_certifies_a_box_maps_and_checks() {
    let dir = tmp();
    let out = seed_box_region(dir.path(), &[]);
    assert!(
        stdout(&out).contains("certified for every point of the box"),
        "{}",
        stdout(&out)
    );
    let out = safereach(dir.path())
        .args(["region"])
        .arg(seed_file())
        .args([
            "--range",
            "environment.obstacle_speed=0.10..0.30",
            "--range",
            "controller.reaction_radius=1.0..1.6",
            "--depth",
            "8",
            "--out",
            "map.json",
            "--svg",
            "map.svg",
        ])
        .assert()
        .code(1)
        .get_output()
        .clone();
    assert!(stdout(&out).contains("refuted"), "{}", stdout(&out));
    let svg = std::fs::read_to_string(dir.path().join("map.svg")).expect("svg written");
    for needed in [
        "environment.obstacle_speed",
        "(m/s)",
        "(m)",
        "certified",
        "undecided",
        "v_max",
    ] {
        assert!(svg.contains(needed), "the plot lacks {needed}");
    }
    roxmltree::Document::parse(&svg).expect("well-formed SVG");
    let out = safereach(dir.path())
        .args(["check", "map.json"])
        .assert()
        .code(0)
        .get_output()
        .clone();
    assert!(stdout(&out).contains("valid"), "{}", stdout(&out));
    // A valid map with refuted leaves is not the whole box certified.
    safereach(dir.path())
        .args(["check", "map.json", "--require", "certified"])
        .assert()
        .code(1);
    safereach(dir.path())
        .args(["check", "map.json", "--require", "refuted"])
        .assert()
        .code(0);
    // An edited map is invalid (exit 1).
    let text = std::fs::read_to_string(dir.path().join("map.json")).unwrap();
    let edited = text.replacen("\"certified\"", "\"refuted\"", 1);
    std::fs::write(dir.path().join("edited.json"), edited).unwrap();
    safereach(dir.path())
        .args(["check", "edited.json"])
        .assert()
        .code(1);
}

#[test]
fn ranges_the_programs_cannot_take_are_refused_with_the_reason() {
    let dir = tmp();
    crate::common::cli::bad_input_exits_2(
        dir.path(),
        "region",
        &seed_file(),
        &[
            (
                vec!["--range", "robot.max_speed=0.1..0.3"],
                "decide the schedule itself",
            ),
            (
                vec!["--range", "controller.reaction_radius=1.6..1.0"],
                "reversed",
            ),
            (
                vec!["--range", "controller.reaction_radius=1.0..x"],
                "not a finite number",
            ),
            (vec!["--range", "controller.reaction_radius"], "KEY=LO..HI"),
            (
                vec![
                    "--range",
                    "controller.reaction_radius=1.0..1.2",
                    "--range",
                    "controller.reaction_radius=1.2..1.4",
                ],
                "twice",
            ),
            (
                vec!["--range", "controller.reaction_radius=-1..1"],
                "controller.reaction_radius",
            ),
            (
                vec![
                    "--range",
                    "sensing.first_detection_gap=0.5..1",
                    "--range",
                    "environment.obstacle_speed=0.1..0.3",
                ],
                "wrong-assumption guard",
            ),
            (
                vec!["--range", "sensing.first_detection_gap=0..1"],
                "sensing.first_detection_gap",
            ),
        ],
    );
    crate::common::cli::bad_input_exits_2(
        dir.path(),
        "region",
        &crate::common::paths::problem_file("seed-lanes.toml"),
        &[(
            vec!["--range", "controller.reaction_radius=1..1.2"],
            "scenes",
        )],
    );
}

#[test]
fn a_map_is_the_same_map_on_every_run() {
    // Threads share the corners' analyses: who analyses a corner first must not show in the
    // map (its count of programs solved, hence its digest).
    let seed = load_problem("seed.toml", &[]);
    let axes = vec![
        axis("environment.obstacle_speed", 0.10, 0.30),
        axis("controller.reaction_radius", 1.0, 1.6),
    ];
    let first = map(&seed, axes.clone(), 12);
    for _ in 0..4 {
        let again = map(&seed, axes.clone(), 12);
        assert_eq!(again.programs_solved, first.programs_solved);
        assert_eq!(again.digest, first.digest);
    }
}
