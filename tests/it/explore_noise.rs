//! The explorer with sensing noise, occlusion and a range of initial gaps (docs/semantics.md
//! §12; docs/crosschecks.md), held against independent answers:
//! - the analyser: the explorer's minimum is never below s*, a collision means `refuted`,
//!   and where the analyser refutes, a speed set holding the witness's speeds finds a
//!   collision (the witness's errors and hiding are among the explored choices);
//! - the test-level exhaustive search of `noise.rs` (the step function, both aims of every
//!   error, every admissible hiding prefix, states told apart by every field of the world):
//!   the same least gap at rest and the same collision verdict;
//! - σ = 0 and no d_det are today's explorations: the same states, transitions and minima;
//! - a range: the exploration over N starts is the union of N single-start explorations;
//! - counterexamples replay with their choices (start, errors, first sighting) and collide.

use safereach::analysis::{Analysis, Verdict, analyse};
use safereach::core::model::{DangerRule, Position, Problem, Sensing};
use safereach::core::num::{Exact, exact_float};
use safereach::core::simulate;
use safereach::crosscheck::explore::{
    self, Exploration, ExploreVerdict, FiniteModel, Options, SpeedSet,
};

use crate::common::cli::{safereach, stdout};
use crate::common::paths::problem_file;
use crate::common::spec::Spec;
use crate::common::tmp;
use crate::noise::{exhaustive, small_noisy, small_sensing};

fn explore_with(p: &Problem, speeds: &[Exact]) -> Exploration {
    let w = p.params::<Exact>().W;
    let set = SpeedSet::from_list(&w, speeds.to_vec(), "test").expect("a valid set");
    let e = explore::explore(p, set, &Options::default()).expect("explores");
    assert!(
        e.complete,
        "{}: small problems explore completely",
        p.to_toml_string()
    );
    e
}

/// {0, W/2, W}: the set of the test-level exhaustive search.
fn three(p: &Problem) -> Vec<Exact> {
    let w = p.params::<Exact>().W;
    vec![Exact::ZERO, w.clone() / Exact::from(2), w]
}

fn sensing(p: &mut Problem, sg: f64, sw: f64, d_det: Option<f64>) {
    p.sensing = Some(Sensing {
        gap_noise: Some(sg),
        speed_noise: Some(sw),
        first_detection_gap: d_det,
    });
}

fn s_star(a: &Analysis) -> Option<f64> {
    if a.never_stops {
        Some(f64::NEG_INFINITY)
    } else {
        a.min_separation
    }
}

/// A counterexample collides when replayed from its start with its errors and hiding.
fn assert_replays(p: &Problem, e: &Exploration) {
    let Some(c) = &e.counterexample else {
        return;
    };
    let params = p.params::<Exact>();
    let hidden_until = match (&params.d_det, c.first_seen) {
        (None, _) => 0,
        (Some(_), Some(k)) => k,
        (Some(_), None) => usize::MAX,
    };
    let run = simulate::run_choosing(
        params,
        c.start.clone(),
        |k| (c.speeds[k].clone(), c.reacts[k]),
        hidden_until,
        c.periods(),
        true,
    );
    assert!(
        run.outcome.collided && run.records.len() == c.periods(),
        "{}: the counterexample collides at its last period",
        p.to_toml_string()
    );
}

/// The explorer's laws against the analyser (where it analyses the problem).
fn agrees_with_the_analyser(p: &Problem, e: &Exploration) -> Option<Analysis> {
    let a = analyse(p).ok()?;
    let text = p.to_toml_string();
    if e.verdict == ExploreVerdict::Collision {
        assert_eq!(a.verdict, Verdict::Refuted, "{text}: the explorer collides");
    }
    if e.never_stops {
        assert!(a.never_stops, "{text}: a behaviour never brakes");
    }
    if let (Some(s), Some(m)) = (s_star(&a), e.min_separation_f64()) {
        assert!(m >= s - 1e-9, "{text}: explorer minimum {m} below s* {s}");
    }
    Some(a)
}

/// The explorer's answer is the exhaustive search's: the same collision verdict, and the
/// same least gap at rest where nothing collides (the search stops a behaviour at its
/// collision, the explorer follows it to its rest, so with a collision its minimum may
/// only be lower).
fn same_answer(e: &Exploration, least: Option<Exact>, collides: bool, text: &str) {
    assert_eq!(
        e.verdict == ExploreVerdict::Collision,
        collides,
        "{text}: collision"
    );
    if collides {
        if let (Some(m), Some(l)) = (&e.min_separation, &least) {
            assert!(m <= l, "{text}: least gap at rest");
        }
    } else {
        assert_eq!(e.min_separation, least, "{text}: least gap at rest");
    }
}

/// The noise test's problems against its exhaustive search (every `stride`-th problem).
fn noise_agrees_with_the_exhaustive_search(stride: usize) {
    let mut collisions = 0;
    for p in small_noisy().into_iter().step_by(stride) {
        let speeds = three(&p);
        let e = explore_with(&p, &speeds);
        let (least, collides) = exhaustive(&p, &speeds);
        same_answer(&e, least, collides, &p.to_toml_string());
        agrees_with_the_analyser(&p, &e).expect("analyses");
        assert_replays(&p, &e);
        collisions += usize::from(collides);
    }
    assert!(collisions > 0, "some problem collides");
}

/// Occlusion on the noise test's problems (every `stride`-th), d_det inside and outside
/// the area, also with the wrong-assumption guard active (where the analyser needs its
/// pieces of an obstacle first seen inside the area): the explorer is the exhaustive search,
/// and never goes below the analyser's s*.
fn occlusion_agrees_with_the_exhaustive_search(stride: usize) {
    let (mut guarded, mut collisions) = (0, 0);
    for (i, mut p) in small_noisy().into_iter().enumerate().step_by(stride) {
        let d_det = [0.3, 0.6][i / stride % 2];
        if let Some(s) = p.sensing.as_mut() {
            s.first_detection_gap = Some(d_det);
        }
        let speeds = three(&p);
        let e = explore_with(&p, &speeds);
        let (least, collides) = exhaustive(&p, &speeds);
        let text = p.to_toml_string();
        same_answer(&e, least, collides, &text);
        assert_replays(&p, &e);
        agrees_with_the_analyser(&p, &e).unwrap_or_else(|| panic!("{text}: analyses"));
        guarded += usize::from(p.params::<Exact>().wrong_assumption_active());
        collisions += usize::from(collides);
    }
    assert!(
        guarded > 0 && collisions > 0,
        "{guarded} with the guard active, {collisions} collide"
    );
}

#[test]
fn with_noise_the_explorer_is_the_exhaustive_search() {
    noise_agrees_with_the_exhaustive_search(5);
}

#[test]
fn with_occlusion_the_explorer_is_the_exhaustive_search() {
    occlusion_agrees_with_the_exhaustive_search(9);
}

/// Latency 2 (two pending observations in the key), noise and occlusion: the exhaustive
/// search's answer (slower).
#[test]
#[ignore]
fn at_latency_two_the_explorer_is_the_exhaustive_search() {
    let sensings = [(0.05, 0.06, None), (0.03, 0.0, Some(0.5))];
    let mut collisions = 0;
    for p in small_sensing(&[DangerRule::Kinematic], &[2], &[0.8], &sensings) {
        let speeds = three(&p);
        let e = explore_with(&p, &speeds);
        let (least, collides) = exhaustive(&p, &speeds);
        same_answer(&e, least, collides, &p.to_toml_string());
        assert_replays(&p, &e);
        collisions += usize::from(collides);
    }
    assert!(collisions > 0);
}

/// Every other problem of the noise test with noise, every third with occlusion (slower).
#[test]
#[ignore]
fn the_explorer_is_the_exhaustive_search_on_every_noise_problem() {
    noise_agrees_with_the_exhaustive_search(2);
    occlusion_agrees_with_the_exhaustive_search(3);
}

/// Small problems (L ∈ {0, 1}, rules `area` and `paper`, the guard on and off, noise and
/// occlusion): where the analyser refutes, the explorer with the witness's speeds (plus 0
/// tail W) collides: the witness's errors and hiding are choices it explores.
fn refutations_are_found(problems: impl Iterator<Item = Problem>) -> (usize, usize) {
    let (mut found, mut certified) = (0, 0);
    for p in problems {
        let a = analyse(&p).unwrap_or_else(|e| panic!("{}: {e}", p.to_toml_string()));
        if a.verdict == Verdict::Certified {
            let e = explore_with(&p, &three(&p));
            agrees_with_the_analyser(&p, &e);
            certified += 1;
            continue;
        }
        let Some(witness) = a.witness.as_ref().filter(|w| w.collides) else {
            continue;
        };
        let w = p.params::<Exact>().W;
        let mut list: Vec<Exact> = witness
            .obstacle_speeds
            .to_vec()
            .iter()
            .map(|&x| exact_float(x))
            .collect();
        // The witness holds W after its listed speeds.
        list.push(w.clone());
        let set = SpeedSet::from_list(&w, list, "witness").expect("within [0, W]");
        if set.len() > 4 {
            continue;
        }
        let e = explore_with(&p, set.speeds());
        agrees_with_the_analyser(&p, &e);
        assert_eq!(
            e.verdict,
            ExploreVerdict::Collision,
            "{}: the analyser's witness collides",
            p.to_toml_string()
        );
        assert_replays(&p, &e);
        found += 1;
    }
    (found, certified)
}

fn small_uncertain(latencies: &[u32], rhos: &[f64]) -> Vec<Problem> {
    let sensings = [
        (0.03, 0.0, None),
        (0.05, 0.06, None),
        (0.0, 0.0, Some(0.35)),
        (0.02, 0.0, Some(0.5)),
    ];
    small_sensing(
        &[DangerRule::Area, DangerRule::Paper],
        latencies,
        rhos,
        &sensings,
    )
}

#[test]
fn the_explorer_finds_the_analysers_refutations_with_noise_and_occlusion() {
    let (found, certified) =
        refutations_are_found(small_uncertain(&[0, 1], &[0.45, 0.8]).into_iter());
    assert!(
        found > 5 && certified > 5,
        "{found} found, {certified} certified"
    );
}

/// The same with latency 2 too and two more radii (slower).
#[test]
#[ignore]
fn the_explorer_finds_the_analysers_refutations_over_more_problems() {
    let (found, certified) =
        refutations_are_found(small_uncertain(&[0, 1, 2], &[0.3, 0.8]).into_iter());
    assert!(
        found > 20 && certified > 20,
        "{found} found, {certified} certified"
    );
}

/// σ = 0 written out and no d_det explore exactly as without a `[sensing]` table: the same
/// states, transitions, depth and minima (and the explorer's pinned state counts in
/// `explore.rs` hold unchanged).
#[test]
fn zero_noise_is_todays_exploration() {
    for rule in [DangerRule::Paper, DangerRule::Kinematic, DangerRule::Area] {
        for latency in [0, 1, 2] {
            for (w, wab) in [(0.1, true), (0.3, true), (0.3, false)] {
                let plain = Spec {
                    rule,
                    latency,
                    w,
                    wab,
                    rho: 0.6,
                    ..Spec::small()
                }
                .build();
                let mut zero = plain.clone();
                sensing(&mut zero, 0.0, 0.0, None);
                let (a, b) = (
                    explore_with(&plain, &three(&plain)),
                    explore_with(&zero, &three(&zero)),
                );
                assert_eq!(
                    (a.states, a.transitions, a.depth, a.never_stops, a.verdict),
                    (b.states, b.transitions, b.depth, b.never_stops, b.verdict),
                    "{}",
                    plain.to_toml_string()
                );
                assert_eq!(a.min_separation, b.min_separation);
            }
        }
    }
}

/// Noise never helps the robot in the explorer either: its minimum with σ is at most the
/// noise-free one (every noise-free behaviour is one of the noisy model's).
#[test]
fn noise_and_occlusion_never_raise_the_explorers_minimum() {
    for p in small_uncertain(&[0, 1], &[0.45]) {
        let mut plain = p.clone();
        plain.sensing = None;
        let (e, e0) = (
            explore_with(&p, &three(&p)),
            explore_with(&plain, &three(&p)),
        );
        let low = |e: &Exploration| e.min_separation_f64().unwrap_or(f64::INFINITY);
        if p.params::<Exact>().d_det.is_none() {
            assert!(low(&e) <= low(&e0), "{}", p.to_toml_string());
            assert!(e.states >= e0.states);
        }
        if e0.verdict == ExploreVerdict::Collision && p.params::<Exact>().d_det.is_none() {
            assert_eq!(e.verdict, ExploreVerdict::Collision);
        }
    }
}

fn ranged(lo: f64, hi: f64) -> Problem {
    let mut p = Spec {
        w: 0.1,
        rho: 0.45,
        ..Spec::small()
    }
    .build();
    p.environment.initial_gap = Position::Range(lo, hi);
    p
}

/// A range explored at N starts is the union of the N single-start explorations: the least
/// gap at rest over them, a collision iff one collides, and the counterexample starts at
/// one of them and replays.
#[test]
fn a_range_is_explored_at_its_starts() {
    for (lo, hi) in [(1.0, 1.2), (0.6, 1.5), (1.7, 1.75)] {
        let p = ranged(lo, hi);
        let set = SpeedSet::evenly_spaced(&p.params::<Exact>().W, 3).unwrap();
        for n in [2, 5] {
            let model = FiniteModel::new(&p, set.clone()).with_starts(n).unwrap();
            assert_eq!(model.starts().len(), n);
            let e = explore::explore_model(&model, &Options::default()).unwrap();
            assert!(e.complete);
            let points: Vec<Exploration> = model
                .starts()
                .iter()
                .map(|g| {
                    let mut q = p.clone();
                    q.environment.initial_gap = Position::At(g.to_f64().value());
                    assert_eq!(q.params::<Exact>().g0, *g, "decimal starts");
                    explore_with(&q, set.speeds())
                })
                .collect();
            let least = points.iter().filter_map(|x| x.min_separation.clone()).min();
            assert_eq!(e.min_separation, least, "[{lo}, {hi}] at {n} starts");
            assert_eq!(
                e.verdict == ExploreVerdict::Collision,
                points
                    .iter()
                    .any(|x| x.verdict == ExploreVerdict::Collision)
            );
            assert_eq!(e.never_stops, points.iter().any(|x| x.never_stops));
            if let Some(c) = &e.counterexample {
                assert!(model.starts().contains(&c.start));
                assert_replays(&p, &e);
            }
        }
        // The default is five starts, both ends included.
        let model = FiniteModel::new(&p, set.clone());
        assert_eq!(model.starts().len(), explore::DEFAULT_STARTS);
        assert_eq!(model.starts()[0], p.params::<Exact>().g0);
        assert_eq!(model.starts()[4], p.params::<Exact>().g0_max);
    }
    assert!(
        FiniteModel::new(
            &ranged(1.0, 1.2),
            SpeedSet::evenly_spaced(&Exact::ZERO, 2).unwrap()
        )
        .with_starts(1)
        .is_err()
    );
}

#[test]
fn cli_explores_noise_occlusion_and_ranges() {
    let dir = tmp();
    let out = safereach(dir.path())
        .arg("explore")
        .arg(problem_file("seed.toml"))
        .args(["--speeds", "3", "--json"])
        .args(["--set", "sensing.first_detection_gap=0.8"])
        .assert()
        .code(1);
    let v: serde_json::Value = serde_json::from_str(&stdout(out.get_output())).unwrap();
    assert_eq!(v["verdict"], "collision");
    assert!(v["path"]["first_seen_period"].as_u64().is_some(), "{v}");
    // The analyser's s* (−0.235 m, docs/semantics.md §12) is reached: W throughout.
    let m = v["min_separation"].as_f64().unwrap();
    assert!((m + 0.235).abs() < 1e-9, "{m}");
    let out = safereach(dir.path())
        .arg("explore")
        .arg(problem_file("seed.toml"))
        .args(["--speeds", "3"])
        .args([
            "--set",
            "sensing.gap_noise=0.002",
            "--set",
            "sensing.speed_noise=0.01",
        ])
        .assert()
        .code(0);
    assert!(stdout(out.get_output()).contains("observation errors keep the guard quiet"));
    let out = safereach(dir.path())
        .arg("explore")
        .arg(problem_file("weaker-brakes.toml"))
        .args(["--speeds", "2", "--starts", "3", "--json"])
        .assert()
        .code(0);
    let v: serde_json::Value = serde_json::from_str(&stdout(out.get_output())).unwrap();
    assert_eq!(v["starts_exact"], serde_json::json!(["8", "10", "12"]));
    safereach(dir.path())
        .arg("explore")
        .arg(problem_file("weaker-brakes.toml"))
        .args(["--starts", "1"])
        .assert()
        .code(2);
}
