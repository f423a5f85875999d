//! The analyser held against independent answers (DESIGN.md §5):
//!
//! - the closed form of brake-on-entry with no latency and a cruising robot;
//! - exact replay of every witness through the semantics (and the proved bound below every
//!   replayed behaviour);
//! - seeded Monte Carlo simulation, which never beats the worst case and never collides in a
//!   certified problem;
//! - monotonicity laws of the semantics: a faster obstacle, a smaller reaction area or more
//!   latency never make the worst case better.

use proptest::prelude::*;
use safereach::analysis::monte_carlo;
use safereach::analysis::{Analysis, PieceResult, Verdict, analyse, replay};
use safereach::core::model::{DangerRule, Params, Position, Problem};
use safereach::core::num::{Exact, exact_decimal, exact_float};
use safereach::proof::program::ProofKind;

use crate::common::paths::seed_file;
use crate::common::spec::{Spec, any_rule, any_spec, cents, config};

fn f(x: &Exact) -> f64 {
    x.to_f64().value()
}

/// s* as an extended real: −∞ for a robot that may never stop, +∞ when no behaviour moves the
/// robot towards the obstacle at all (every piece infeasible), else the analyser's s*.
/// `None` when the analyser realised no worst case although some piece has one.
fn worst(a: &Analysis) -> Option<f64> {
    if a.never_stops {
        return Some(f64::NEG_INFINITY);
    }
    if let Some(s) = a.min_separation {
        return Some(s);
    }
    let all_infeasible = a.outcomes.iter().all(|o| {
        matches!(
            o.result,
            PieceResult::Proved {
                kind: ProofKind::Infeasible,
                ..
            }
        )
    });
    all_infeasible.then_some(f64::INFINITY)
}

// ---------------------------------------------------------------------------------------------
// 1. Closed form: brake on entry, no latency, cruising robot
// ---------------------------------------------------------------------------------------------

/// Where the clearance lies in a closed-form case.
#[derive(Clone, Copy, Debug)]
enum ClearanceAt {
    /// At most ρ − (v+W)·dt: the gap is above it until the robot brakes.
    BeforeBraking,
    /// Above ρ − (v+W)·dt: the worst case reaches the clearance while the robot still drives.
    WhileDriving,
}

/// A brake-on-entry problem with latency 0 whose robot cruises long before the obstacle can
/// reach the reaction area, and ρ > (v+W)·dt (the obstacle cannot jump over the area), with
/// its closed-form s* = ρ − (v+W)·dt − v²/(2b) − W·v/b in exact rationals.
fn closed_form_case(at: ClearanceAt) -> impl Strategy<Value = (Spec, Exact)> {
    (
        (
            20u32..=200,    // v (cents)
            cents(50, 200), // a
            20u32..=300,    // b (cents)
            2u32..=20,      // dt (cents)
            1u32..=100,     // W (cents)
        ),
        (
            -150i64..=150,     // s* near this many cents
            0u32..=100,        // clearance, in percent of its range
            cents(0, 50),      // V_a
            any::<bool>(),     // wrong-assumption guard
            cents(2000, 4000), // initial gap beyond ρ
        ),
    )
        .prop_map(
            move |((vc, a, bc, dtc, wc), (target, pct, v_a, wab, extra))| {
                let [v, b, dt, w] = [vc, bc, dtc, wc].map(|c| f64::from(c) / 100.0);
                let stopping = v * v / (2.0 * b) + w * v / b;
                // ρ in cents: near the value that puts s* at `target` cents, and above (v+W)·dt,
                // which is (vc + wc)·dtc / 100 cents.
                let jump = u64::from((vc + wc) * dtc);
                let near = ((stopping + (v + w) * dt) * 100.0).round() as i64 + target;
                let rho_c = (near.max(0) as u64).max(jump / 100 + 1);
                // The gap at the end of the step before braking is above ρ − (v+W)·dt.
                let room = 100 * rho_c - jump; // ρ − (v+W)·dt, in units of 1e-4
                let clearance_c = match at {
                    ClearanceAt::BeforeBraking => room / 100 * u64::from(pct) / 100,
                    // Strictly above ρ − (v+W)·dt, at most 0.3 m above it.
                    ClearanceAt::WhileDriving => room / 100 + 1 + 29 * u64::from(pct) / 100,
                };
                let cm = |c: u64| c as f64 / 100.0;
                let rho = cm(rho_c);
                let spec = Spec {
                    name: "test",
                    v_max: v,
                    a,
                    b,
                    dt,
                    latency: 0,
                    clearance: cm(clearance_c),
                    v_a,
                    rho,
                    rule: DangerRule::Area,
                    buffer: 0.1,
                    wab,
                    w,
                    g0: ((rho + extra) * 100.0).round() / 100.0,
                };
                let [v, b, dt, w, rho] = [v, b, dt, w, rho].map(exact_decimal);
                let two = Exact::from(2);
                let s = rho
                    - (v.clone() + w.clone()) * dt
                    - v.clone() * v.clone() / (two * b.clone())
                    - w * v / b;
                (spec, s)
            },
        )
}

/// The closed-form checks of one case.
fn check_closed_form(spec: &Spec, exact: &Exact) -> Result<(), TestCaseError> {
    let a = analyse(&spec.problem()).expect("analysis");
    let closed = f(exact);
    // The closed form's premise, checked on the decomposition: the robot cruises before the
    // fastest obstacle can first be observed in the area.
    prop_assert!(a.decomposition.cruise_from <= a.decomposition.first_brake);
    let s = a.min_separation;
    prop_assert!(
        s.is_some(),
        "no s* (verdict {:?}) for {:?}; closed form {}",
        a.verdict,
        spec,
        closed
    );
    let s = s.unwrap();
    prop_assert!(
        (s - closed).abs() <= 1e-9,
        "s* = {s}, closed form {closed} (diff {:e}) for {spec:?}",
        s - closed
    );
    let lb = a.lower_bound.clone();
    prop_assert!(lb.is_some(), "no lower bound for {spec:?}");
    let lb = lb.unwrap();
    prop_assert!(
        lb <= *exact,
        "lower bound {} above s* {closed} for {spec:?}",
        f(&lb)
    );
    prop_assert!(
        f(&(exact.clone() - lb.clone())) <= 1e-7,
        "lower bound {} more than 1e-7 below s* {closed} for {spec:?}",
        f(&lb)
    );
    let clearance = exact_decimal(spec.clearance);
    if f(&(exact.clone() - clearance.clone())).abs() > 1e-6 {
        let expected = if *exact > clearance {
            Verdict::Certified
        } else {
            Verdict::Refuted
        };
        prop_assert_eq!(
            a.verdict,
            expected,
            "s* = {} against clearance {} for {:?}",
            closed,
            spec.clearance,
            spec
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(64))]

    #[test]
    fn brake_on_entry_matches_the_closed_form(
        (spec, exact) in closed_form_case(ClearanceAt::BeforeBraking)
    ) {
        check_closed_form(&spec, &exact)?;
    }

    /// The same closed form when the worst case reaches the clearance one step before the
    /// robot brakes (then s* < clearance: refuted). Regression: the replay used to stop at
    /// that first collision, leaving no s* and an `inconclusive` verdict.
    #[test]
    fn brake_on_entry_matches_the_closed_form_when_the_clearance_is_hit_while_driving(
        (spec, exact) in closed_form_case(ClearanceAt::WhileDriving)
    ) {
        check_closed_form(&spec, &exact)?;
    }
}

// ---------------------------------------------------------------------------------------------
// 2. Every witness replays exactly to s*
// ---------------------------------------------------------------------------------------------

/// Replays the witness of `a` (if any) and checks it against the analysis; checks the
/// verdict against the evidence.
fn check_witness_and_verdict(spec: &Spec, a: &Analysis) -> Result<(), TestCaseError> {
    let p = &a.problem;
    let params: Params<Exact> = p.params();
    let clearance = params.clearance.clone();
    if let Some(w) = &a.witness {
        let speeds = &w.obstacle_speeds.to_vec();
        for (k, &s) in speeds.iter().enumerate() {
            prop_assert!(
                s >= 0.0 && exact_float(s) <= params.W,
                "witness speed {s} in period {k} outside [0, W] for {spec:?}"
            );
        }
        let run = replay(&params, speeds);
        let rest = run.outcome.rest_gap.clone();
        prop_assert_eq!(
            w.collides,
            run.outcome.collided,
            "collision flag for {:?}",
            spec
        );
        prop_assert_eq!(
            w.separation.is_some(),
            rest.is_some(),
            "rest flag for {:?}",
            spec
        );
        if let (Some(stated), Some(r)) = (w.separation, &rest) {
            prop_assert!(
                (stated - f(r)).abs() <= 1e-9,
                "witness separation {stated} vs replay {} for {spec:?}",
                f(r)
            );
        }
        if a.never_stops {
            prop_assert!(
                run.outcome.collided,
                "never_stops witness does not collide: {spec:?}"
            );
            prop_assert!(
                rest.is_none(),
                "never_stops witness comes to rest: {spec:?}"
            );
            prop_assert!(
                run.outcome.brake.is_none(),
                "never_stops witness brakes: {spec:?}"
            );
            prop_assert!(a.min_separation.is_none());
        }
        if let Some(s) = a.min_separation {
            prop_assert!(
                rest.is_some(),
                "witness of s* = {s} never rests for {spec:?}"
            );
            let r = rest.clone().unwrap();
            let rf = f(&r);
            prop_assert!(
                (rf - s).abs() <= 1e-6 && rf >= s - 1e-6,
                "replayed rest gap {rf} vs s* {s} for {spec:?}"
            );
            // The replayed behaviour is a real one: no proved lower bound may exceed it.
            if let Some(lb) = &a.lower_bound {
                prop_assert!(
                    *lb <= r,
                    "lower bound {} above a replayed rest gap {rf} for {spec:?}",
                    f(lb)
                );
            }
        }
        if a.verdict == Verdict::Certified {
            prop_assert!(
                !run.outcome.collided,
                "certified, yet the witness collides: {spec:?}"
            );
        }
    }
    match a.verdict {
        Verdict::Certified => {
            let lb = a.lower_bound.clone();
            prop_assert!(
                lb.as_ref().is_some_and(|lb| *lb > clearance),
                "certified without a bound above the clearance: {spec:?}"
            );
            if let Some(s) = a.min_separation {
                prop_assert!(
                    s > spec.clearance - 1e-9,
                    "certified with s* = {s} below the clearance: {spec:?}"
                );
            }
        }
        Verdict::Refuted => {
            let w = a.witness.as_ref();
            prop_assert!(w.is_some(), "refuted without a witness: {spec:?}");
            let w = w.unwrap();
            let run = replay(&params, &w.obstacle_speeds.to_vec());
            prop_assert!(
                run.outcome.collided,
                "refuting witness does not collide: {spec:?}"
            );
            prop_assert!(
                a.lower_bound.as_ref().is_none_or(|lb| *lb <= clearance),
                "refuted with a bound above the clearance: {spec:?}"
            );
        }
        Verdict::Inconclusive => {}
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(160))]

    #[test]
    fn witnesses_replay_to_the_worst_case(spec in any_spec()) {
        let a = analyse(&spec.problem()).expect("analysis");
        check_witness_and_verdict(&spec, &a)?;
    }
}

/// Hand-picked cases the random ones may miss: a robot still accelerating when it brakes,
/// one that stops mid-step, a static obstacle, an obstacle faster than assumed.
#[test]
fn witnesses_replay_on_hand_picked_cases() {
    let seed = Spec::seed();
    let cases = [
        seed,
        Spec { g0: 0.6, ..seed },
        Spec {
            g0: 1.0,
            latency: 0,
            ..seed
        },
        Spec {
            g0: 2.0,
            latency: 3,
            ..seed
        },
        Spec {
            g0: 0.5,
            rule: DangerRule::Area,
            ..seed
        },
        Spec { w: 0.0, ..seed },
        Spec { w: 0.25, ..seed },
        Spec {
            w: 0.25,
            wab: false,
            ..seed
        },
        Spec { w: 0.6, ..seed },
        Spec {
            rule: DangerRule::Kinematic,
            ..seed
        },
        Spec {
            rule: DangerRule::Area,
            latency: 0,
            ..seed
        },
        Spec {
            rule: DangerRule::Area,
            rho: 0.05,
            ..seed
        },
        Spec {
            b: 3.0,
            dt: 0.2,
            ..seed
        },
        Spec {
            clearance: 0.3,
            ..seed
        },
        Spec {
            w: 0.0,
            clearance: 1.5,
            ..seed
        },
    ];
    for spec in cases {
        let a = analyse(&spec.problem()).expect("analysis");
        check_witness_and_verdict(&spec, &a).unwrap_or_else(|e| panic!("{e}"));
    }
}

/// `inconclusive` only at the boundary (DESIGN.md §1): away from it, the analyser realises
/// a worst case, and the verdict is `certified` or `refuted`.
fn check_decisive(spec: &Spec, a: &Analysis) -> Result<(), TestCaseError> {
    let realised = worst(a);
    prop_assert!(
        realised.is_some(),
        "no worst case realised (verdict {:?}, lower bound {:?}) for {:?}",
        a.verdict,
        a.lower_bound.as_ref().map(f),
        spec
    );
    // s* is the least piece optimum, which the lower bound proves up to the solver's gap.
    if let (Some(s), Some(lb)) = (a.min_separation, &a.lower_bound) {
        prop_assert!(
            (s - f(lb)).abs() <= 1e-6,
            "s* = {} is not the proved worst case {} for {:?}",
            s,
            f(lb),
            spec
        );
    }
    if a.verdict == Verdict::Inconclusive {
        let near = |x: f64| (x - spec.clearance).abs() <= 1e-6;
        let lb = a.lower_bound.as_ref().map(f);
        prop_assert!(
            lb.is_some_and(near) || a.min_separation.is_some_and(near),
            "inconclusive away from the boundary: lower bound {:?}, s* {:?}, clearance {} for {:?}",
            lb,
            a.min_separation,
            spec.clearance,
            spec
        );
    }
    Ok(())
}

/// A robot that reaches the clearance (or passes the obstacle) before its guard fires — a
/// positive clearance, or observations older than the last step — still collides: the
/// verdict is `refuted`, and s* is the gap where it comes to rest. (Regression: the replay
/// used to stop at the first collision, so no worst case was realised.)
#[test]
fn collisions_before_braking_are_refuted() {
    let seed = Spec::seed();
    let cases = [
        // A static obstacle: the robot drives into the clearance (1.5 m) before its reaction
        // area (1.4 m) sees the obstacle.
        Spec {
            w: 0.0,
            clearance: 1.5,
            ..seed
        },
        Spec {
            w: 0.0,
            clearance: 1.5,
            rule: DangerRule::Area,
            latency: 0,
            ..seed
        },
        // Latency 1, up to 0.19 m closed per step, danger at 0.367 m: the robot can pass the
        // obstacle before it brakes.
        Spec {
            b: 3.0,
            dt: 0.2,
            ..seed
        },
        Spec {
            b: 3.0,
            dt: 0.2,
            clearance: 0.05,
            ..seed
        },
    ];
    for spec in cases {
        let a = analyse(&spec.problem()).expect("analysis");
        check_witness_and_verdict(&spec, &a).unwrap_or_else(|e| panic!("{e}"));
        check_decisive(&spec, &a).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(a.verdict, Verdict::Refuted, "{spec:?}");
        // The robot's behaviour does not depend on the clearance, so neither does s*.
        let free = analyse(
            &Spec {
                clearance: 0.0,
                ..spec
            }
            .problem(),
        )
        .expect("analysis");
        if let (Some(s), Some(s0)) = (a.min_separation, worst(&free)) {
            assert!(
                (s - s0).abs() <= 1e-9,
                "s* {s} with the clearance, {s0} without: {spec:?}"
            );
        }
    }
}

proptest! {
    #![proptest_config(config(160))]

    #[test]
    fn verdicts_are_decisive_away_from_the_boundary(spec in any_spec()) {
        let a = analyse(&spec.problem()).expect("analysis");
        check_decisive(&spec, &a)?;
    }
}

/// Exact ties between a guard threshold and a gap the obstacle reaches by standing still
/// (g0 − P_k = ρ, common with decimal inputs): closing the strict row would admit a
/// behaviour that does not exist (the robot brakes a step earlier), so the proved bound would
/// fall a whole step short of s* and the verdict be `inconclusive` far from the boundary.
/// Each case is decided by one behaviour, replayed here: the obstacle at full speed W
/// throughout (for W = 0, the only behaviour there is).
#[test]
fn exact_ties_with_a_guard_are_decided() {
    let tie = Spec {
        name: "test",
        v_max: 0.66,
        a: 0.22,
        b: 0.2,
        dt: 0.1,
        latency: 0,
        clearance: 0.15,
        v_a: 0.0,
        rho: 1.27,
        rule: DangerRule::Area,
        buffer: 0.0,
        wab: false,
        w: 0.0,
        g0: 2.26, // g0 − P_30 = ρ
    };
    let cases = [
        // Static obstacle: rests at 0.181 > 0.15; bound 0.115.
        tie,
        // W = 0.01: rests at 0.118 > 0.10 at worst; bound 0.081.
        Spec {
            w: 0.01,
            clearance: 0.1,
            ..tie
        },
        // A static obstacle, paper rule, latency 3, first seen exactly at ρ.
        Spec {
            name: "test",
            v_max: 0.52,
            a: 1.07,
            b: 0.2,
            dt: 0.07,
            latency: 3,
            clearance: 0.5,
            v_a: 0.19,
            rho: 0.72,
            rule: DangerRule::Paper,
            buffer: 0.26,
            wab: false,
            w: 0.0,
            g0: 0.72,
        },
        // g0 = ρ, latency 0: the robot brakes at rest at t = 0 and never moves.
        Spec {
            g0: 1.27,
            w: 0.15,
            clearance: 1.26,
            ..tie
        },
    ];
    let mut failures = Vec::new();
    for spec in cases {
        let p = spec.problem();
        let a = analyse(&p).expect("analysis");
        let params: Params<Exact> = p.params();
        let run = replay(&params, &vec![spec.w; 2000]);
        let rest = run.outcome.rest_gap.as_ref().map(f);
        let lb = a.lower_bound.as_ref().map(f);
        let tight = match (rest, lb) {
            (Some(r), Some(lb)) => (r - lb).abs() <= 1e-6,
            // Never moves: nothing to be tight against.
            (None, Some(_)) => run
                .records
                .iter()
                .all(|r| r.motion.moving_for == Exact::ZERO),
            _ => false,
        };
        if a.verdict != Verdict::Certified || !tight {
            failures.push(format!(
                "{spec:?}: verdict {:?}, lower bound {lb:?}, s* {:?}, full-speed behaviour rests at {rest:?}",
                a.verdict, a.min_separation
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

// ---------------------------------------------------------------------------------------------
// 3. Simulation never contradicts the analyser
// ---------------------------------------------------------------------------------------------

fn seed_problem() -> Problem {
    Problem::load(&seed_file()).expect("problems/seed.toml loads")
}

#[test]
fn seed_file_is_certified() {
    let p = seed_problem();
    let a = analyse(&p).expect("analysis");
    assert_eq!(a.verdict, Verdict::Certified, "s* = {:?}", a.min_separation);
}

#[test]
fn random_runs_never_beat_the_worst_case() {
    let seed = Spec::seed();
    let certified = [
        seed,
        Spec {
            latency: 3,
            rho: 2.0,
            ..seed
        },
        Spec {
            rule: DangerRule::Kinematic,
            latency: 0,
            ..seed
        },
        Spec {
            rule: DangerRule::Kinematic,
            latency: 2,
            buffer: 0.5,
            ..seed
        },
        Spec {
            rule: DangerRule::Area,
            latency: 0,
            rho: 1.2,
            ..seed
        },
        Spec {
            rule: DangerRule::Area,
            latency: 2,
            rho: 1.5,
            w: 0.3,
            ..seed
        },
        Spec { w: 0.0, ..seed },
        // The robot still accelerates when it brakes.
        Spec { g0: 0.9, ..seed },
        Spec {
            g0: 0.5,
            rule: DangerRule::Area,
            ..seed
        },
        Spec {
            clearance: 0.1,
            rho: 2.0,
            ..seed
        },
    ];
    let mut problems: Vec<Problem> = vec![seed_problem()];
    problems.extend(certified.iter().map(Spec::problem));
    for (i, p) in problems.iter().enumerate() {
        let a = analyse(p).expect("analysis");
        assert_eq!(
            a.verdict,
            Verdict::Certified,
            "problem {i} {p:?}: s* {:?}",
            a.min_separation
        );
        let lb = f(a.lower_bound.as_ref().expect("certified has a bound"));
        let s = worst(&a).expect("a certified problem has a realised worst case");
        let params: Params<f64> = p.params();
        let mut runs = 0;
        for chunk in 0..4u64 {
            let mc = monte_carlo(&params, 2500, 1000 * chunk + i as u64);
            runs += mc.runs;
            assert_eq!(mc.collisions, 0, "problem {i} {p:?}: {mc:?}");
            assert!(
                mc.min_separation >= lb - 1e-9,
                "problem {i}: simulation reached {} below the lower bound {lb}",
                mc.min_separation
            );
            // Sharpness: random runs cannot beat the worst case.
            assert!(
                mc.min_separation >= s - 1e-9,
                "problem {i}: simulation reached {} below s* {s}",
                mc.min_separation
            );
        }
        assert_eq!(runs, 10_000);
    }
}

#[test]
fn refuted_problems_have_colliding_witnesses() {
    let seed = Spec::seed();
    let refuted = [
        Spec {
            w: 0.6,
            wab: false,
            ..seed
        },
        Spec { w: 0.6, ..seed },
        Spec { rho: 0.3, ..seed },
        Spec {
            rule: DangerRule::Area,
            rho: 0.5,
            latency: 3,
            ..seed
        },
        Spec {
            rule: DangerRule::Kinematic,
            w: 0.8,
            buffer: 0.0,
            ..seed
        },
    ];
    for spec in refuted {
        let p = spec.problem();
        let a = analyse(&p).expect("analysis");
        assert_eq!(
            a.verdict,
            Verdict::Refuted,
            "{spec:?}: s* {:?}",
            a.min_separation
        );
        let w = a.witness.as_ref().expect("refuted has a witness");
        let run = replay(&p.params(), &w.obstacle_speeds.to_vec());
        assert!(run.outcome.collided, "{spec:?}");
        // The same behaviour in floats collides as well (the simulator agrees).
        let fast = safereach::core::simulate::run(
            p.params::<f64>(),
            |k| w.obstacle_speeds.get(k).unwrap_or(spec.w),
            w.obstacle_speeds.len(),
            true,
        );
        assert!(fast.outcome.collided, "{spec:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// 4. Monotonicity laws
// ---------------------------------------------------------------------------------------------

/// The analysis of a problem with clearance 0 (s* does not depend on the clearance: the
/// robot's behaviour does not), and its s*.
fn s_star(spec: &Spec) -> Result<(Analysis, f64), TestCaseError> {
    let a = analyse(
        &Spec {
            clearance: 0.0,
            ..*spec
        }
        .problem(),
    )
    .expect("analysis");
    let s = worst(&a);
    prop_assert!(s.is_some(), "no worst case realised for {:?}", spec);
    Ok((a, s.unwrap()))
}

/// Replays the witness of `from` (if it rests) under the parameters of `to`, returning the
/// exact rest gap when the robot comes to rest there.
fn cross_replay(from: &Analysis, to: &Analysis) -> Option<Exact> {
    let w = from.witness.as_ref()?;
    let params: Params<Exact> = to.problem.params();
    // The witness lists speeds up to its own rest; the replay holds W_to after them, which
    // only matters when `to` stops later.
    replay(&params, &w.obstacle_speeds.to_vec())
        .outcome
        .rest_gap
        .filter(|_| w.separation.is_some())
}

proptest! {
    #![proptest_config(config(48))]

    /// Every behaviour with speeds ≤ W is one with speeds ≤ W' ≥ W: s* can only fall.
    #[test]
    fn faster_obstacles_never_help(spec in any_spec(), extra in cents(1, 50)) {
        let faster = Spec { w: ((spec.w + extra) * 100.0).round() / 100.0, ..spec };
        let (a1, s1) = s_star(&spec)?;
        let (a2, s2) = s_star(&faster)?;
        prop_assert!(s2 <= s1 + 1e-9, "s*(W={}) = {s1} < s*(W={}) = {s2} for {spec:?}", spec.w, faster.w);
        // The slower obstacle's worst case is open to the faster one: the same speeds give
        // the same run, and no proved bound may lie above it.
        let w1 = a1.witness.as_ref();
        if let (Some(w1), Some(r)) = (w1, cross_replay(&a1, &a2)) {
            prop_assert!(w1.separation.is_some_and(|s| (s - f(&r)).abs() <= 1e-9));
            prop_assert!(s2 <= f(&r) + 1e-9, "s*(W={}) = {s2} above a behaviour resting at {} for {spec:?}", faster.w, f(&r));
            prop_assert!(a2.lower_bound.as_ref().is_none_or(|lb| *lb <= r), "lower bound above a behaviour for {faster:?}");
        }
    }

    /// A larger reaction area only makes the robot brake earlier.
    #[test]
    fn larger_reaction_areas_never_hurt(spec in any_spec(), extra in cents(1, 100), rule in any_rule()) {
        let spec = Spec { rule, ..spec };
        let larger = Spec { rho: ((spec.rho + extra) * 100.0).round() / 100.0, ..spec };
        let (a1, s1) = s_star(&spec)?;
        let (a2, s2) = s_star(&larger)?;
        prop_assert!(s2 >= s1 - 1e-9, "s*(rho={}) = {s1} > s*(rho={}) = {s2} for {spec:?}", spec.rho, larger.rho);
        // The larger area's worst case, in the smaller area: the robot brakes no earlier,
        // so it rests no further from the obstacle.
        if let (Some(r2), Some(r1)) = (cross_replay(&a2, &a2), cross_replay(&a2, &a1)) {
            prop_assert!(r1 <= r2, "same behaviour rests at {} with rho={} but {} with rho={} for {spec:?}", f(&r1), spec.rho, f(&r2), larger.rho);
            prop_assert!(a1.lower_bound.as_ref().is_none_or(|lb| *lb <= r1), "lower bound above a behaviour for {spec:?}");
        }
    }

    /// Older observations never make the worst case better.
    #[test]
    fn more_latency_never_helps(spec in any_spec()) {
        let later = Spec { latency: spec.latency + 1, ..spec };
        let (_, s1) = s_star(&spec)?;
        let (_, s2) = s_star(&later)?;
        prop_assert!(s2 <= s1 + 1e-9, "s*(L={}) = {s1} < s*(L={}) = {s2} for {spec:?}", spec.latency, later.latency);
    }
}

/// The first counterexample the monotonicity law in W found (the witness of the slower
/// obstacle replays below the faster one's s*): the analyser used to fall back to a
/// shallower piece when the deepest piece's witness collided before braking.
#[test]
fn a_faster_obstacle_is_never_safer_regression() {
    let slow = Spec {
        name: "test",
        v_max: 0.87,
        a: 0.94,
        b: 2.77,
        dt: 0.16,
        latency: 2,
        clearance: 0.0,
        v_a: 0.0,
        rho: 0.66,
        rule: DangerRule::Area,
        buffer: 0.0,
        wab: false,
        w: 0.37,
        g0: 1.51,
    };
    let fast = Spec { w: 0.51, ..slow };
    let (a1, s1) = s_star(&slow).unwrap();
    let (a2, s2) = s_star(&fast).unwrap();
    assert!(s2 <= s1 + 1e-9, "s*(W=0.37) = {s1}, s*(W=0.51) = {s2}");
    let r = cross_replay(&a1, &a2).expect("the slow witness rests");
    assert!(
        s2 <= f(&r) + 1e-9,
        "s*(W=0.51) = {s2}, a behaviour rests at {}",
        f(&r)
    );
    let lb = a2.lower_bound.expect("bound");
    assert!(
        (s2 - f(&lb)).abs() <= 1e-6,
        "s* {s2} vs lower bound {}",
        f(&lb)
    );
}

/// The fast exact replay (machine-word rationals with big-integer fallback) that witnesses
/// and `check` use equals the all-big-rational replay, number for number, on the witnesses
/// of problems across every rule, latency and both sides of the safe radius.
#[test]
fn fast_replay_equals_big_rational_replay() {
    use safereach::core::simulate::{Aim, replay, replay_exact, replay_recorded, trace};
    let mut compared = 0;
    for rule in [DangerRule::Paper, DangerRule::Kinematic, DangerRule::Area] {
        for latency in 0..3 {
            for (w, rho) in [(0.15, 1.4), (0.3, 0.9), (0.25, 1.6), (0.6, 0.5)] {
                let mut p = Problem::load(&seed_file()).expect("seed loads");
                p.controller.danger_rule = rule;
                p.robot.latency = latency;
                p.environment.obstacle_speed = w;
                p.controller.reaction_radius = rho;
                p.environment.initial_gap = Position::At(3.0);
                let a = analyse(&p).expect("analyses");
                let Some(wit) = a.witness else { continue };
                let params = p.params::<safereach::core::num::Exact>();
                let n = wit.obstacle_speeds.len();
                let big = replay_exact(&params, &wit.obstacle_speeds.to_vec(), n, false);
                let fast = replay_recorded(
                    &params,
                    &wit.obstacle_speeds.to_vec(),
                    Aim::default(),
                    n,
                    false,
                );
                assert_eq!(fast.periods(), big.records.len());
                assert_eq!(fast.collided(), big.outcome.collided);
                assert_eq!(fast.rest_gap(), big.outcome.rest_gap);
                // The leaping replay is the same run: the same summary.
                let leaping = replay(&params, &wit.obstacle_speeds.to_vec(), n, false);
                assert_eq!(leaping.run, fast.run);
                for (f, b) in fast.records().iter().zip(&big.records) {
                    assert_eq!(f.end_gap.to_exact(), b.end_gap);
                    assert_eq!(f.motion.end.position.to_exact(), b.motion.end.position);
                    assert_eq!(f.brake, b.brake);
                }
                let (rows_fast, rows_big) = (fast.trace(), trace(&params, &big));
                assert_eq!(rows_fast.len(), rows_big.len());
                for (x, y) in rows_fast.iter().zip(&rows_big) {
                    assert!((x.gap - y.gap).abs() <= 1e-12 && (x.t - y.t).abs() <= 1e-12);
                }
                compared += 1;
            }
        }
    }
    assert!(compared >= 30, "only {compared} witnesses compared");
}
