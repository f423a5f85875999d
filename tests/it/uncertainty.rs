//! Weaker brakes, a robot already moving and a range of initial gaps (DESIGN.md §1.2,
//! docs/semantics.md §12), held against independent answers:
//! - the closed form of the brake-on-entry radius (KeYmaera X, IJRR 2017) with the plant's
//!   braking b_min: ρ* = v²/(2b_min) + W·v/b_min + (v+W)·dt + clearance, for a cruising
//!   robot (initial_speed = max_speed, also with a short initial gap);
//! - the explorer (every behaviour of a finite speed set through the step function):
//!   explorer collision ⇒ refuted, explorer minimum ≥ s*, on problems with b_min < b and
//!   robots starting at several speeds;
//! - the defaults (b_min = b given explicitly, initial_speed = 0) give today's analysis
//!   exactly; a weaker brake never raises s*;
//! - a range of initial gaps: its s* is the least over its points (each analysed alone by
//!   the schedule analyser), and the static obstacle's safe radius no longer depends on how
//!   the start lines up with the control period once the range spans one period's travel.

use safereach::analysis::scene_answer::SceneAnswer;
use safereach::analysis::scene_radius::scene_radius;
use safereach::analysis::{Verdict, analyse, radius};
use safereach::core::model::{DangerRule, Position, Problem};
use safereach::core::num::Exact;
use safereach::core::scene::Scene;
use safereach::crosscheck::explore::{self, ExploreVerdict, Options, SpeedSet};

use crate::common::paths::seed_file;
use crate::common::spec::Spec;

/// A brake-on-entry problem (rule `area`, latency 0, no wrong-assumption guard) with the
/// plant braking at `b_min` and the robot cruising from t = 0.
fn cruising(v: f64, b: f64, b_min: f64, w: f64, dt: f64, clearance: f64, g0: f64) -> Problem {
    let mut p = Spec {
        v_max: v,
        a: 0.5,
        b,
        dt,
        latency: 0,
        clearance,
        v_a: w,
        rho: 1.0,
        rule: DangerRule::Area,
        buffer: 0.0,
        wab: false,
        w,
        g0,
        ..Spec::seed()
    }
    .build();
    p.robot.braking_min = Some(b_min);
    p.robot.initial_speed = Some(v);
    p.validate("test").expect("a valid problem");
    p
}

#[test]
fn weaker_brakes_give_the_closed_form_radius() {
    // (v, b, b_min, W, dt, clearance, initial gap)
    let cases = [
        (0.2, 0.05, 0.04, 0.15, 0.1, 0.0, 10.0),
        (0.2, 0.05, 0.05, 0.15, 0.1, 0.0, 10.0),
        (0.5, 0.5, 0.25, 0.1, 0.05, 0.05, 8.0),
        (1.0, 2.0, 0.8, 0.3, 0.1, 0.1, 12.0),
        (0.3, 0.4, 0.1, 0.02, 0.2, 0.0, 9.0),
        // A short initial gap: the cruising robot needs no run-up, so the form still holds.
        (0.2, 0.05, 0.04, 0.15, 0.1, 0.0, 2.5),
    ];
    // (W = 0 is left out: a static obstacle cannot choose its alignment with the control
    // period, so a point start may do better than the form; see the range tests below.)
    for (v, b, b_min, w, dt, c, g0) in cases {
        let p = cruising(v, b, b_min, w, dt, c, g0);
        let closed = v * v / (2.0 * b_min) + w * v / b_min + (v + w) * dt + c;
        let found = radius::safe_radius(&p)
            .expect("the radius search runs")
            .value
            .expect("a radius exists below the initial gap");
        assert!(
            (found - closed).abs() <= 2e-6,
            "v={v} b={b} b_min={b_min} W={w} dt={dt} c={c} g0={g0}: radius {found}, closed form {closed}"
        );
    }
}

/// The analysis of `p` as the numbers that make its answer.
fn answer(p: &Problem) -> (Verdict, Option<Exact>, Option<f64>, bool, usize) {
    let a = analyse(p).expect("analyses");
    (
        a.verdict,
        a.lower_bound,
        a.min_separation,
        a.never_stops,
        a.decomposition.pieces.len(),
    )
}

fn small_problems() -> impl Iterator<Item = Problem> {
    let rules = [DangerRule::Paper, DangerRule::Kinematic, DangerRule::Area];
    rules.into_iter().flat_map(|rule| {
        [0u32, 1, 2].into_iter().flat_map(move |latency| {
            [0.05, 0.25].into_iter().flat_map(move |w| {
                [0.4, 0.9].into_iter().map(move |rho| {
                    Spec {
                        rule,
                        latency,
                        w,
                        rho,
                        ..Spec::small()
                    }
                    .build()
                })
            })
        })
    })
}

#[test]
fn defaults_given_explicitly_change_nothing() {
    for p in small_problems().chain([Spec::seed().build()]) {
        let mut explicit = p.clone();
        explicit.robot.braking_min = Some(p.robot.braking);
        explicit.robot.initial_speed = Some(0.0);
        assert_eq!(answer(&p), answer(&explicit), "{}", p.to_toml_string());
    }
}

#[test]
fn a_weaker_brake_never_raises_s_star() {
    for p in small_problems() {
        let mut weak = p.clone();
        weak.robot.braking_min = Some(p.robot.braking * 0.6);
        let (strong, weaker) = (analyse(&p).unwrap(), analyse(&weak).unwrap());
        let s = |a: &safereach::analysis::Analysis| {
            if a.never_stops {
                f64::NEG_INFINITY
            } else {
                a.min_separation.unwrap_or(f64::INFINITY)
            }
        };
        assert!(
            s(&weaker) <= s(&strong) + 1e-9,
            "{}: s* {} with b_min < b, {} with b",
            p.to_toml_string(),
            s(&weaker),
            s(&strong)
        );
        if strong.verdict == Verdict::Refuted {
            assert_eq!(weaker.verdict, Verdict::Refuted);
        }
    }
}

#[test]
fn the_explorer_agrees_with_weaker_brakes_and_a_moving_start() {
    let mut verdicts = [0usize; 2];
    for p in small_problems() {
        for v0 in [0.0, 0.5 * p.robot.max_speed, p.robot.max_speed] {
            let mut q = p.clone();
            q.robot.braking_min = Some(p.robot.braking * 0.7);
            q.robot.initial_speed = Some(v0);
            let a = analyse(&q).expect("analyses");
            let w = q.params::<Exact>().W;
            let set = SpeedSet::evenly_spaced(&w, 3).expect("a valid count");
            let e = explore::explore(&q, set, &Options::default()).expect("explores");
            assert!(e.complete, "{}", q.to_toml_string());
            if e.verdict == ExploreVerdict::Collision {
                assert_eq!(
                    a.verdict,
                    Verdict::Refuted,
                    "{}: the explorer collides",
                    q.to_toml_string()
                );
            }
            if e.never_stops {
                assert!(a.never_stops, "{}", q.to_toml_string());
            }
            if let (Some(s), Some(m)) = (a.min_separation, e.min_separation_f64())
                && !a.never_stops
            {
                assert!(
                    m >= s - 1e-9,
                    "{}: explorer minimum {m} below s* {s}",
                    q.to_toml_string()
                );
            }
            verdicts[usize::from(a.verdict == Verdict::Certified)] += 1;
        }
    }
    assert!(
        verdicts[0] > 0 && verdicts[1] > 0,
        "both verdicts occur: {verdicts:?}"
    );
}

/// The shipped seed robot (problems/seed.toml: cruising at 0.2 m/s, dt = 0.1 s) facing a
/// static obstacle whose start is anywhere in `[lo, hi]`.
fn static_seed(lo: f64, hi: f64) -> Problem {
    let mut p = Problem::load(&seed_file()).expect("the seed loads");
    p.environment.obstacle_speed = 0.0;
    p.environment.initial_gap = if lo == hi {
        Position::At(lo)
    } else {
        Position::Range(lo, hi)
    };
    p
}

#[test]
fn a_range_of_gaps_answers_for_its_worst_point() {
    for (lo, hi) in [(10.0, 10.02), (9.5, 9.9), (3.0, 3.05)] {
        let ranged = SceneAnswer::of(&Scene::from_problem(&static_seed(lo, hi)))
            .expect("analyses")
            .min_separation()
            .expect("a worst case");
        let points: Vec<f64> = (0..=40)
            .map(|i| lo + (hi - lo) * f64::from(i) / 40.0)
            .map(|g| {
                analyse(&static_seed(g, g))
                    .unwrap()
                    .min_separation
                    .expect("a worst case")
            })
            .collect();
        let least = points.iter().copied().fold(f64::INFINITY, f64::min);
        // Every point is covered; the least over a grid of spacing h is within h of the
        // range's (a static gap at rest moves one for one with the start between two
        // alignments).
        assert!(ranged <= least + 1e-9, "[{lo}, {hi}]: {ranged} > {least}");
        let h = (hi - lo) / 40.0;
        assert!(
            ranged >= least - h - 1e-9,
            "[{lo}, {hi}]: {ranged} < {least} − {h}"
        );
    }
    // The library's single-start analyser refuses a range rather than guess.
    assert!(analyse(&static_seed(10.0, 10.02)).is_err());
}

#[test]
fn the_static_radius_stops_depending_on_alignment() {
    // The seed robot cruises at 0.2 m/s with dt = 0.1: one period's travel is 0.02 m.
    let point_radius = |g: f64| {
        radius::safe_radius(&static_seed(g, g))
            .unwrap()
            .value
            .expect("a radius")
    };
    let points: Vec<f64> = (0..8)
        .map(|i| point_radius(10.0 + 0.0025 * f64::from(i)))
        .collect();
    let (lo, hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    assert!(
        hi - lo > 1e-3,
        "point radii depend on alignment: {points:?}"
    );
    for offset in [10.0, 10.0075, 10.013] {
        let r = scene_radius(&Scene::from_problem(&static_seed(offset, offset + 0.02)))
            .expect("searches")
            .value
            .expect("a radius");
        assert!(
            (r - hi).abs() <= 3e-6,
            "range from {offset}: radius {r}, worst point radius {hi}"
        );
    }
}
