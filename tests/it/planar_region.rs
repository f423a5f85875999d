//! Region maps of planar problems (docs/reductions.md Lemma P7), held against independent
//! answers: the seed embedded in the plane maps leaf for leaf as the line's exact engine
//! maps problems/seed.toml; points inside certified planar leaves certify on the line
//! (the seed) and in the plane (the crossing car, whose certificates are not the leaf's);
//! refuted leaves name points that collide on the line; `check` rejects maps whose
//! certificates are moved, swapped or re-labelled; keys the lemma does not cover exit 2.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use safereach::analysis::planar::{PlanarVerdict, certify_text};
use safereach::analysis::region_search::{RegionOptions, map_planar_region, map_region};
use safereach::analysis::{Verdict, analyse};
use safereach::core::param_box::{Axis, ParamBox};
use safereach::core::parameter::Parameter;
use safereach::core::planar::PlanarProblem;
use safereach::proof::region_check::check_map;
use safereach::proof::region_map::{LeafVerdict, RegionMap};

use crate::common::cli::{bad_input_exits_2, safereach, stdout};
use crate::common::forgery::map_rejected;
use crate::common::map_points::{leaves_holding, random_point};
use crate::common::paths::{load_problem, root};
use crate::common::tmp;

fn planar_text(name: &str) -> String {
    std::fs::read_to_string(root().join("problems/planar").join(name)).expect("shipped")
}

fn options(depth: u32) -> RegionOptions {
    RegionOptions {
        depth,
        ..RegionOptions::default()
    }
}

fn planar_map(name: &str, axes: Vec<Axis>, depth: u32) -> (String, RegionMap) {
    let text = planar_text(name);
    let problem = PlanarProblem::from_toml_str(&text, name).expect("shipped problems read");
    let whole = ParamBox::new(axes).expect("a valid box");
    let m = map_planar_region(&text, &[], &problem, &whole, &options(depth), &|_| {})
        .expect("mappable");
    check_map(&m).expect("the planar map checks");
    (text, m)
}

fn radius(lo: f64, hi: f64) -> Axis {
    Axis::new(Parameter::ReactionRadius, lo, hi)
}

fn obstacle_speed(i: usize, lo: f64, hi: f64) -> Axis {
    Axis {
        obstacle: Some(i),
        ..Axis::new(Parameter::ObstacleSpeed, lo, hi)
    }
}

/// The seed plane W ∈ [0.1, 0.3] × ρ ∈ [1.0, 1.6] in the plane, to depth 4.
fn seed_plane() -> RegionMap {
    planar_map(
        "seed-in-plane.toml",
        vec![radius(1.0, 1.6), obstacle_speed(0, 0.1, 0.3)],
        4,
    )
    .1
}

#[test]
fn the_seed_in_the_plane_maps_as_the_line_does() {
    let planar = seed_plane();
    let seed = load_problem("seed.toml", &[]);
    let whole = ParamBox::new(vec![
        radius(1.0, 1.6),
        Axis::new(Parameter::ObstacleSpeed, 0.1, 0.3),
    ])
    .expect("a valid box");
    let line = map_region(&seed, &whole, &options(4), &|_| {}).expect("mappable");
    let leaves = |m: &RegionMap| -> Vec<(String, LeafVerdict)> {
        m.leaves
            .iter()
            .map(|l| (l.path.clone(), l.verdict))
            .collect()
    };
    assert_eq!(leaves(&planar), leaves(&line));
    assert!(planar.coverage.certified > 0.3 && planar.coverage.refuted > 0.1);
    // Certified leaves state no more than the line's exact s* at their weak corner (a
    // corner's bound-only run claims the clearance, every instant strictly above it).
    for l in planar
        .leaves
        .iter()
        .filter(|l| l.verdict == LeafVerdict::Certified)
    {
        let [lo, _] = l.bounds["controller.reaction_radius"];
        let [_, hi] = l.bounds["obstacle.0.max_speed"];
        let mut p = seed.clone();
        Parameter::ReactionRadius.set_in(&mut p, lo);
        Parameter::ObstacleSpeed.set_in(&mut p, hi);
        let s = analyse(&p)
            .expect("analysable")
            .min_separation
            .expect("certified");
        let bound = l.lower_bound.expect("a certified leaf states its bound");
        assert!(
            bound <= s + 1e-12 && bound >= seed.robot.clearance,
            "leaf {}: bound {bound}, the line's s* {s}",
            l.path
        );
    }
}

#[test]
fn certified_planar_leaves_hold_on_the_line_and_refuted_points_collide_there() {
    let planar = seed_plane();
    let seed = load_problem("seed.toml", &[]);
    let at = |values: &[f64]| {
        let mut p = seed.clone();
        Parameter::ReactionRadius.set_in(&mut p, values[0]);
        Parameter::ObstacleSpeed.set_in(&mut p, values[1]);
        analyse(&p).expect("analysable")
    };
    let mut rng = ChaCha8Rng::seed_from_u64(36);
    let mut inside = 0;
    for _ in 0..200 {
        let values = random_point(&planar, || rng.random::<f64>(), 3);
        let answer = at(&values);
        for l in leaves_holding(&planar, &values) {
            if l.verdict == LeafVerdict::Certified {
                inside += 1;
                assert_eq!(
                    answer.verdict,
                    Verdict::Certified,
                    "{values:?} in {}",
                    l.path
                );
                let s = answer.min_separation.expect("certified");
                assert!(s >= l.lower_bound.expect("stated") - 1e-12, "{values:?}");
            }
        }
    }
    assert!(inside > 40, "{inside} points fell in certified leaves");
    let mut refuted = 0;
    for l in planar
        .leaves
        .iter()
        .filter(|l| l.verdict == LeafVerdict::Refuted)
    {
        let cert = l
            .planar_certificate
            .as_ref()
            .expect("a refuted leaf's certificate");
        let value = |key: &str| -> f64 {
            let set = cert
                .overrides
                .iter()
                .find_map(|s| s.strip_prefix(&format!("{key}=")))
                .expect("the point sets every ranged key");
            set.parse().expect("a number")
        };
        let values = [
            value("controller.reaction_radius"),
            value("obstacle.0.max_speed"),
        ];
        assert_eq!(
            at(&values).verdict,
            Verdict::Refuted,
            "{values:?} of {}",
            l.path
        );
        refuted += 1;
    }
    assert!(refuted > 0);
}

#[test]
fn points_of_certified_crossing_car_leaves_certify_in_the_plane() {
    let (text, m) = planar_map(
        "crossing-car.toml",
        vec![radius(2.0, 6.0), obstacle_speed(0, 1.0, 4.0)],
        2,
    );
    let certified: Vec<_> = m
        .leaves
        .iter()
        .filter(|l| l.verdict == LeafVerdict::Certified)
        .collect();
    assert!(!certified.is_empty(), "{:?}", m.coverage);
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for l in certified {
        // Points other than the weak corner the leaf's certificate is for: Lemma P7 at work.
        let [rl, rh] = l.bounds["controller.reaction_radius"];
        let [wl, wh] = l.bounds["obstacle.0.max_speed"];
        for _ in 0..2 {
            let r = ((rl + rng.random::<f64>() * (rh - rl)) * 100.0).round() / 100.0;
            let w = ((wl + rng.random::<f64>() * (wh - wl)) * 100.0).round() / 100.0;
            let sets = [
                format!("controller.reaction_radius={r}"),
                format!("obstacle.0.max_speed={w}"),
            ];
            let (verdict, cert) = certify_text(&text, "crossing-car.toml", &sets).expect("answers");
            assert_eq!(
                verdict,
                PlanarVerdict::Certified,
                "ρ = {r}, W = {w} in {}",
                l.path
            );
            assert!(cert.lower_bound >= l.lower_bound.expect("stated") - 1e-9);
        }
    }
}

#[test]
fn check_rejects_planar_maps_with_moved_or_relabelled_certificates() {
    let m = seed_plane();
    let certified: Vec<usize> = (0..m.leaves.len())
        .filter(|&i| m.leaves[i].verdict == LeafVerdict::Certified)
        .collect();
    let refuted = (0..m.leaves.len())
        .find(|&i| m.leaves[i].verdict == LeafVerdict::Refuted)
        .expect("a refuted leaf");
    let undecided = (0..m.leaves.len())
        .find(|&i| m.leaves[i].verdict == LeafVerdict::Undecided)
        .expect("an undecided leaf");
    assert!(certified.len() >= 2);
    let (a, b) = (certified[0], certified[1]);

    let mut x = m.clone();
    x.leaves[a].planar_certificate = x.leaves[b].planar_certificate.clone();
    map_rejected(x, "a certified leaf with another leaf's certificate");

    let mut x = m.clone();
    x.leaves[undecided].verdict = LeafVerdict::Certified;
    x.leaves[undecided].lower_bound = x.leaves[a].lower_bound;
    x.leaves[undecided].planar_certificate = x.leaves[a].planar_certificate.clone();
    map_rejected(
        x,
        "an undecided leaf certified by a neighbour's certificate",
    );

    let mut x = m.clone();
    x.leaves[refuted].verdict = LeafVerdict::Certified;
    x.leaves[refuted].lower_bound = Some(0.5);
    map_rejected(x, "a refuted leaf relabelled certified");

    let mut x = m.clone();
    x.leaves[a].lower_bound = x.leaves[a].lower_bound.map(|l| l + 0.01);
    map_rejected(x, "a certified leaf stating more than its certificate");

    let mut x = m.clone();
    x.leaves[a].planar_certificate = None;
    map_rejected(x, "a certified leaf without a certificate");

    let mut x = m.clone();
    let source = x.planar.as_mut().expect("a planar map");
    source.overrides.push("controller.buffer=0".into());
    map_rejected(x, "a map whose base overrides are not its certificates'");

    let mut x = m.clone();
    x.planar.as_mut().expect("planar").clearance = -1.0;
    map_rejected(x, "a map stating another clearance than its problem's");

    let mut x = m.clone();
    x.problem = Some(load_problem("seed.toml", &[]));
    map_rejected(x, "a map of both a line problem and a planar one");
}

#[test]
fn region_on_a_planar_file_writes_a_map_check_verifies_and_refuses_other_keys() {
    let dir = tmp();
    let planar = root().join("problems/planar/seed-in-plane.toml");
    let out = safereach(dir.path())
        .arg("region")
        .arg(&planar)
        .args([
            "--range",
            "controller.reaction_radius=1.3..1.6",
            "--range",
            "obstacle.0.max_speed=0.1..0.2",
            "--depth",
            "2",
            "--out",
            "map.json",
            "--svg",
            "map.svg",
        ])
        .assert()
        .code(0)
        .get_output()
        .clone();
    let text = stdout(&out);
    assert!(
        text.contains("certified for every point of the box"),
        "{text}"
    );
    let svg = std::fs::read_to_string(dir.path().join("map.svg")).expect("written");
    assert!(
        svg.contains("controller.reaction_radius") || svg.contains('ρ'),
        "{svg}"
    );
    let check = safereach(dir.path())
        .args(["check", "map.json", "--require", "certified"])
        .assert()
        .code(0)
        .get_output()
        .clone();
    assert!(stdout(&check).contains("valid"), "{}", stdout(&check));
    bad_input_exits_2(
        dir.path(),
        "region",
        &planar,
        &[
            (
                vec!["--range", "environment.obstacle_speed=0.1..0.2"],
                "obstacle.<i>.max_speed",
            ),
            (vec!["--range", "sensing.gap_noise=0..0.1"], "Lemma P7"),
            (vec!["--range", "obstacle.3.max_speed=0.1..0.2"], "obstacle"),
            (
                vec!["--range", "controller.reaction_radius=-1..1"],
                "controller.reaction_radius",
            ),
        ],
    );
}
