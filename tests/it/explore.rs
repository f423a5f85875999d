//! The exhaustive explorer (`safereach::crosscheck::explore`) held against the analyser and against an
//! unabstracted search (DESIGN.md §5: "an exhaustive explorer over a finite speed set can
//! only find behaviours the analyser already covers").
//!
//! - Agreement over a grid of small problems (every danger rule, latencies 0–3, W below and
//!   above V_a, the wrong-assumption guard on and off, reaction radii on both sides of the
//!   safe radius): explorer collision ⇒ analyser `refuted`, and the counterexample replays as
//!   a collision; explorer minimum ≥ analyser s* − 1e-9.
//! - Equal minima where the finite set contains the worst case: static obstacles, obstacles
//!   already inside the reaction area at t = 0 (the worst case is W throughout), and speed
//!   sets made of the analyser's witness speeds.
//! - The state abstraction is exact: an explorer without it (every field of the world, the
//!   robot's position and the step index included) finds the same verdict, minimum
//!   separation and shortest counterexample length.
//! - Exact state counts for a few small problems; determinism; shortest counterexamples;
//!   the state budget; the CLI.

use std::collections::{HashMap, VecDeque};

use safereach::analysis::{Analysis, Verdict, analyse};
use safereach::core::model::{DangerRule, Params, Problem};
use safereach::core::num::{Exact, exact_decimal, exact_float};
use safereach::core::semantics::{Mode, World};
use safereach::core::simulate;
use safereach::crosscheck::explore::{
    self, Exploration, ExploreError, ExploreVerdict, FiniteModel, Options, SpeedSet, Status,
};
use serde_json::Value;

use crate::common::cli::{bad_input_exits_2, safereach, stdout};
use crate::common::paths::{problem_file, seed_file};
use crate::common::spec::Spec;
use crate::common::tmp;

// ---------------------------------------------------------------------------------------------
// Problems
// ---------------------------------------------------------------------------------------------

const RULES: [DangerRule; 3] = [DangerRule::Paper, DangerRule::Kinematic, DangerRule::Area];

fn w_of(p: &Problem) -> Exact {
    p.params::<Exact>().W
}

fn speeds(p: &Problem, n: usize) -> SpeedSet {
    SpeedSet::evenly_spaced(&w_of(p), n).expect("a valid count")
}

fn run(p: &Problem, set: SpeedSet) -> Exploration {
    explore::explore(p, set, &Options::default()).expect("exploration succeeds")
}

/// The analyser's s*, −∞ when some behaviour never brakes.
fn s_star(a: &Analysis) -> Option<f64> {
    if a.never_stops {
        Some(f64::NEG_INFINITY)
    } else {
        a.min_separation
    }
}

/// The explorer's minimum, −∞ when some behaviour never brakes.
fn e_min(e: &Exploration) -> Option<f64> {
    e.min_separation_f64()
}

/// The agreement laws every problem must satisfy. Returns the analysis.
fn check_agreement(spec: &Spec, set: SpeedSet) -> (Analysis, Exploration) {
    let p = spec.problem();
    let a = analyse(&p).expect("analysis succeeds");
    let e = run(&p, set);
    assert!(
        e.complete,
        "{spec:?}: small problems are explored completely"
    );
    if e.verdict == ExploreVerdict::Collision {
        assert_eq!(
            a.verdict,
            Verdict::Refuted,
            "{spec:?}: the explorer found a collision, the analyser must refute"
        );
        let c = e.counterexample.as_ref().expect("a collision has a path");
        let params: Params<Exact> = p.params();
        let replay = simulate::run(params, |k| c.speeds[k].clone(), c.speeds.len(), true);
        assert!(
            replay.outcome.collided,
            "{spec:?}: the counterexample must replay as a collision"
        );
        assert_eq!(
            replay.records.len(),
            c.periods(),
            "{spec:?}: collides at its last period"
        );
        assert!(c.run.outcome.collided && c.trace.len() > c.periods());
    } else {
        assert!(e.counterexample.is_none());
    }
    if e.never_stops {
        assert!(
            a.never_stops,
            "{spec:?}: a behaviour of the finite set never brakes, so the analyser's s* is -inf"
        );
    }
    match (s_star(&a), e_min(&e)) {
        (Some(s), Some(m)) => assert!(
            m >= s - 1e-9,
            "{spec:?}: explorer minimum {m} below the analyser's s* {s}"
        ),
        (None, Some(m)) => panic!("{spec:?}: the analyser has no s* but the explorer has {m}"),
        (_, None) => {}
    }
    (a, e)
}

// ---------------------------------------------------------------------------------------------
// Agreement with the analyser
// ---------------------------------------------------------------------------------------------

/// Every rule, latency 0–3, W below and above V_a, the guard on and off, three radii: the
/// laws hold everywhere, and the grid really straddles the safe radius (both verdicts occur
/// for every rule and latency).
#[test]
fn explorer_agrees_with_the_analyser_over_a_grid_of_problems() {
    let mut seen: HashMap<(String, u32), (bool, bool)> = HashMap::new();
    let mut collisions = 0;
    let mut safe = 0;
    for rule in RULES {
        for latency in 0..=3 {
            for w in [0.1, 0.3] {
                for wab in [true, false] {
                    for rho in [0.3, 0.6, 1.4] {
                        let spec = Spec {
                            rule,
                            latency,
                            w,
                            wab,
                            rho,
                            // A buffer that covers the latency, so that a large enough
                            // radius is safe when W <= V_a.
                            buffer: [0.15, 0.3, 0.45, 0.6][latency as usize],
                            ..Spec::small()
                        };
                        let p = spec.problem();
                        // {0, W/2, W} plus V_a when W exceeds it (the wrong-assumption edge).
                        let mut list: Vec<Exact> = speeds(&p, 3).speeds().to_vec();
                        if w > spec.v_a {
                            list.push(exact_decimal(spec.v_a));
                        }
                        let set = SpeedSet::from_list(&w_of(&p), list, "test").unwrap();
                        let (a, e) = check_agreement(&spec, set);
                        match e.verdict {
                            ExploreVerdict::Collision => collisions += 1,
                            ExploreVerdict::Safe => safe += 1,
                            ExploreVerdict::Inconclusive => unreachable!(),
                        }
                        let entry = seen.entry((rule.to_string(), latency)).or_default();
                        entry.0 |= a.verdict == Verdict::Certified;
                        entry.1 |= a.verdict == Verdict::Refuted;
                    }
                }
            }
        }
    }
    assert!(
        collisions > 20 && safe > 20,
        "{collisions} collisions, {safe} safe"
    );
    for ((rule, latency), (certified, refuted)) in seen {
        assert!(
            certified && refuted,
            "rule {rule}, latency {latency}: the radii must straddle the safe radius"
        );
    }
}

/// More speeds can only find closer approaches: the minimum over {0, W/4, …, W} is at most
/// the minimum over {0, W/2, W} (a subset), and both stay above s*.
#[test]
fn finer_speed_sets_approach_the_analysers_worst_case_from_above() {
    for rule in RULES {
        for latency in [0, 2] {
            let spec = Spec {
                rule,
                latency,
                w: 0.15,
                ..Spec::small()
            };
            let (a, coarse) = check_agreement(&spec, speeds(&spec.problem(), 3));
            let (_, fine) = check_agreement(&spec, speeds(&spec.problem(), 5));
            let (c, m) = (e_min(&coarse).unwrap(), e_min(&fine).unwrap());
            assert!(m <= c, "{spec:?}: a superset of speeds found {m} > {c}");
            assert!(fine.states >= coarse.states);
            if let Some(s) = s_star(&a) {
                assert!(m >= s - 1e-9);
            }
        }
    }
}

/// A static obstacle (W = 0): the finite set {0} is every behaviour, so the two minima are
/// equal and so are the verdicts.
#[test]
fn static_obstacle_minima_are_equal() {
    let mut cases = 0;
    for rule in RULES {
        for latency in 0..=3 {
            for rho in [0.2, 0.5, 1.4] {
                for clearance in [0.0, 0.05] {
                    let spec = Spec {
                        rule,
                        latency,
                        rho,
                        clearance,
                        w: 0.0,
                        ..Spec::small()
                    };
                    let p = spec.problem();
                    let (a, e) = check_agreement(&spec, speeds(&p, 2));
                    assert_eq!(e.speeds.len(), 1, "W = 0: the set is {{0}}");
                    let (s, m) = (s_star(&a).unwrap(), e_min(&e).unwrap());
                    assert!(
                        (s - m).abs() <= 1e-9 || (s.is_infinite() && m.is_infinite()),
                        "{spec:?}: analyser {s} vs explorer {m}"
                    );
                    assert_eq!(
                        a.verdict == Verdict::Refuted,
                        e.verdict == ExploreVerdict::Collision,
                        "{spec:?}"
                    );
                    cases += 1;
                }
            }
        }
    }
    assert_eq!(cases, 72);
}

/// An obstacle already inside the reaction area at t = 0 makes the robot brake at its first
/// observation whatever the obstacle does, so the worst case is W throughout: {0, W} holds
/// it and the minima are equal (and the closest approach is W in every period).
#[test]
fn obstacle_inside_the_area_from_the_start_minima_are_equal() {
    let mut cases = 0;
    for rule in RULES {
        for latency in 1..=3 {
            for w in [0.1, 0.3] {
                let spec = Spec {
                    rule,
                    latency,
                    w,
                    g0: 0.6,
                    rho: 1.0,
                    buffer: 0.6,
                    ..Spec::small()
                };
                let p = spec.problem();
                let (a, e) = check_agreement(&spec, speeds(&p, 2));
                let (s, m) = (s_star(&a).unwrap(), e_min(&e).unwrap());
                assert!(
                    (s - m).abs() <= 1e-9,
                    "{spec:?}: analyser {s} vs explorer {m}"
                );
                let closest = e.closest.as_ref().expect("a closest approach");
                assert!(
                    closest.speeds.iter().all(|x| *x == w_of(&p)),
                    "{spec:?}: the worst case is W throughout"
                );
                cases += 1;
            }
        }
    }
    assert_eq!(cases, 18);
}

/// The analyser's witness, explored: with the witness's own distinct speeds (plus 0 and W)
/// as the finite set, the witness is one of the explored behaviours, so the explorer's
/// minimum lies between s* and the witness's replayed separation. Where the witness attains
/// s* (its separation within 1e-9 of it: the optimum is not on a strict guard boundary) the
/// explorer's minimum equals s* to 1e-9.
#[test]
fn witness_speed_sets_give_the_analysers_minimum() {
    let mut equal = 0;
    for rule in RULES {
        for latency in 0..=3 {
            for w in [0.05, 0.1, 0.3] {
                for rho in [0.3, 0.6, 1.4] {
                    for g0 in [0.5, 0.8] {
                        let spec = Spec {
                            rule,
                            latency,
                            w,
                            rho,
                            g0,
                            ..Spec::small()
                        };
                        let p = spec.problem();
                        let a = analyse(&p).unwrap();
                        let (Some(witness), Some(s)) = (a.witness.as_ref(), a.min_separation)
                        else {
                            continue;
                        };
                        let Some(sep) = witness.separation else {
                            continue;
                        };
                        if (sep - s).abs() > 1e-9 {
                            continue;
                        }
                        let mut list: Vec<Exact> = witness
                            .obstacle_speeds
                            .to_vec()
                            .iter()
                            .map(|&x| exact_float(x))
                            .collect();
                        list.extend([Exact::ZERO, w_of(&p)]);
                        let set = SpeedSet::from_list(&w_of(&p), list, "witness").unwrap();
                        if set.len() > 6 {
                            continue;
                        }
                        let (_, e) = check_agreement(&spec, set);
                        let m = e_min(&e).unwrap();
                        assert!(
                            m <= sep + 1e-12,
                            "{spec:?}: the witness ({sep}) is explored, min {m}"
                        );
                        assert!((m - s).abs() <= 1e-9, "{spec:?}: explorer {m} vs s* {s}");
                        equal += 1;
                    }
                }
            }
        }
    }
    assert!(
        equal >= 40,
        "only {equal} problems whose witness attains s*"
    );
}

/// Regression: an analyser under development certified these problems (s* = 0.6 m and
/// 0.46 m) while the explorer found collisions: an obstacle moving at exactly V_a inside the
/// reaction area never trips the wrong-assumption guard, then speeds up to W once the robot
/// is committed. Both engines must now refute.
#[test]
fn regression_obstacle_at_exactly_v_a_then_w_collides() {
    for latency in [1, 2] {
        let spec = Spec {
            latency,
            w: 0.3,
            rho: 1.4,
            ..Spec::small()
        };
        let p = spec.problem();
        let set = SpeedSet::parse("0,0.15,0.2,0.3", &w_of(&p)).unwrap();
        let (a, e) = check_agreement(&spec, set);
        assert_eq!(e.verdict, ExploreVerdict::Collision, "{spec:?}");
        assert_eq!(a.verdict, Verdict::Refuted, "{spec:?}");
        let c = e.counterexample.unwrap();
        assert!(
            c.speeds.contains(&exact_decimal(0.2)),
            "{spec:?}: the path uses V_a"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// The abstraction is exact: an unabstracted search agrees
// ---------------------------------------------------------------------------------------------

/// Everything a [`World`] holds (its parameters are constant): step index, robot position,
/// speed and mode, gap, and the last L+1 gaps and obstacle speeds — read from the records.
type FullKey = (usize, Exact, Exact, Mode, Exact, Vec<Exact>, Vec<Exact>);

struct Full {
    never_stops: bool,
    min_rest: Option<Exact>,
    shortest_collision: Option<usize>,
    states: usize,
}

/// A world and the history it was reached by (gap, speed per period).
type Visit = (World<Exact>, Vec<(Exact, Exact)>);

/// Breadth-first search over complete world states, with no abstraction at all. A path
/// ends when the robot rests, or when it accelerates or drives while observing a gap ≤ 0
/// (every later observation is ≤ 0 too: it never brakes).
fn unabstracted(p: &Problem, set: &SpeedSet) -> Full {
    let params: Params<Exact> = p.params();
    let l = params.L;
    let mut seen: HashMap<FullKey, ()> = HashMap::new();
    let mut queue: VecDeque<Visit> = VecDeque::from([(World::new(params.clone()), Vec::new())]);
    let mut out = Full {
        never_stops: false,
        min_rest: None,
        shortest_collision: None,
        states: 1,
    };
    while let Some((world, history)) = queue.pop_front() {
        for w in set.speeds() {
            let mut next = world.clone();
            let rec = next.step(w.clone());
            if rec.collision && out.shortest_collision.is_none() {
                out.shortest_collision = Some(rec.k + 1);
            }
            if let Some(g) = rec.rest_gap.clone()
                && out.min_rest.as_ref().is_none_or(|m| g < *m)
            {
                out.min_rest = Some(g);
            }
            let mut h = history.clone();
            h.push((rec.gap.clone(), w.clone()));
            if h.len() > l + 1 {
                h.remove(0);
            }
            let robot = next.robot().clone();
            let key: FullKey = (
                next.k(),
                robot.position.clone(),
                robot.speed.clone(),
                robot.mode,
                next.gap().clone(),
                h.iter().map(|x| x.0.clone()).collect(),
                h.iter().map(|x| x.1.clone()).collect(),
            );
            if seen.insert(key, ()).is_some() {
                continue;
            }
            out.states += 1;
            if next.stopped() {
                continue;
            }
            let blind = matches!(robot.mode, Mode::Accelerate | Mode::Drive)
                && next.observation().is_some_and(|o| o.gap <= Exact::ZERO);
            if blind {
                out.never_stops = true;
                continue;
            }
            queue.push_back((next, h));
        }
    }
    out
}

#[test]
fn the_state_abstraction_is_exact_against_an_unabstracted_search() {
    let mut merged = 0;
    let mut never = 0;
    let mut checked = 0;
    for rule in RULES {
        for latency in 0..=3 {
            for (w, wab, rho) in [
                (0.1, true, 0.4),
                (0.3, true, 1.0),
                (0.3, false, 0.4),
                // The obstacle can cross the whole area between two observations.
                (0.3, true, 0.1),
            ] {
                let spec = Spec {
                    rule,
                    latency,
                    w,
                    wab,
                    rho,
                    g0: 1.2,
                    ..Spec::small()
                };
                let p = spec.problem();
                let set = speeds(&p, 2);
                let e = run(&p, set.clone());
                let full = unabstracted(&p, &set);
                assert_eq!(
                    e.verdict == ExploreVerdict::Collision,
                    full.shortest_collision.is_some(),
                    "{spec:?}: verdict"
                );
                assert_eq!(
                    e.counterexample.as_ref().map(|c| c.periods()),
                    full.shortest_collision,
                    "{spec:?}: shortest counterexample length"
                );
                assert_eq!(e.never_stops, full.never_stops, "{spec:?}: never stops");
                assert_eq!(
                    e.min_separation, full.min_rest,
                    "{spec:?}: minimum separation"
                );
                assert!(e.states <= full.states);
                merged += usize::from(e.states < full.states);
                never += usize::from(e.never_stops);
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 48);
    assert!(
        merged >= 40,
        "the abstraction should merge states ({merged} of 48)"
    );
    assert!(never >= 6, "robots that never brake: {never}");
}

// ---------------------------------------------------------------------------------------------
// The explored space, pinned
// ---------------------------------------------------------------------------------------------

/// Exact state and transition counts (and the answers): a change in the explored space must
/// show here.
#[test]
fn state_counts_are_pinned() {
    struct Pin {
        spec: Spec,
        speeds: usize,
        verdict: ExploreVerdict,
        states: usize,
        transitions: usize,
        depth: usize,
        min_separation: &'static str,
        counterexample: Option<usize>,
    }
    let pins = [
        Pin {
            spec: Spec::small(),
            speeds: 3,
            verdict: ExploreVerdict::Safe,
            states: 223,
            transitions: 666,
            depth: 23,
            min_separation: "0.1",
            counterexample: None,
        },
        Pin {
            spec: Spec {
                rule: DangerRule::Area,
                latency: 0,
                ..Spec::small()
            },
            speeds: 3,
            verdict: ExploreVerdict::Safe,
            states: 158,
            transitions: 471,
            depth: 17,
            min_separation: "0.67",
            counterexample: None,
        },
        Pin {
            spec: Spec {
                rule: DangerRule::Kinematic,
                latency: 3,
                w: 0.3,
                ..Spec::small()
            },
            speeds: 2,
            verdict: ExploreVerdict::Collision,
            states: 722,
            transitions: 1442,
            depth: 27,
            min_separation: "-0.58",
            counterexample: Some(18),
        },
        Pin {
            spec: Spec {
                w: 0.0,
                ..Spec::small()
            },
            speeds: 2,
            verdict: ExploreVerdict::Safe,
            states: 27,
            transitions: 26,
            depth: 26,
            min_separation: "0.28",
            counterexample: None,
        },
        Pin {
            spec: Spec {
                latency: 2,
                w: 0.3,
                rho: 0.6,
                ..Spec::small()
            },
            speeds: 4,
            verdict: ExploreVerdict::Collision,
            states: 240,
            transitions: 956,
            depth: 19,
            min_separation: "-0.28",
            counterexample: Some(16),
        },
    ];
    for pin in pins {
        let p = pin.spec.problem();
        let e = run(&p, speeds(&p, pin.speeds));
        let got = (
            e.verdict,
            e.states,
            e.transitions,
            e.depth,
            e.min_separation.as_ref().map(explore::show_exact),
            e.counterexample.as_ref().map(|c| c.periods()),
        );
        let want = (
            pin.verdict,
            pin.states,
            pin.transitions,
            pin.depth,
            Some(pin.min_separation.to_string()),
            pin.counterexample,
        );
        assert_eq!(got, want, "{:?} with {} speeds", pin.spec, pin.speeds);
    }
}

#[test]
fn the_search_is_deterministic() {
    let spec = Spec {
        w: 0.3,
        latency: 2,
        ..Spec::small()
    };
    let p = spec.problem();
    let a = run(&p, speeds(&p, 4));
    let b = run(&p, speeds(&p, 4));
    assert_eq!(
        (a.states, a.transitions, a.depth),
        (b.states, b.transitions, b.depth)
    );
    assert_eq!(a.min_separation, b.min_separation);
    let (ca, cb) = (a.counterexample.unwrap(), b.counterexample.unwrap());
    assert_eq!(ca.speeds, cb.speeds);
    assert_eq!(ca.trace, cb.trace);
}

/// The counterexample is a shortest one: no sequence of fewer periods collides (checked by
/// enumerating every speed sequence of each shorter length).
#[test]
fn the_counterexample_is_a_shortest_path() {
    for rule in RULES {
        let spec = Spec {
            rule,
            w: 0.4,
            rho: 0.3,
            g0: 1.0,
            ..Spec::small()
        };
        let p = spec.problem();
        let set = speeds(&p, 2);
        let e = run(&p, set.clone());
        let c = e.counterexample.expect("this problem collides");
        let n = c.periods();
        assert!((3..=14).contains(&n), "{spec:?}: {n} periods");
        let params: Params<Exact> = p.params();
        for len in 1..n {
            for bits in 0u32..(1 << len) {
                let seq: Vec<Exact> = (0..len)
                    .map(|i| set.speeds()[((bits >> i) & 1) as usize].clone())
                    .collect();
                let r = simulate::run(params.clone(), |k| seq[k].clone(), len, true);
                assert!(
                    !r.outcome.collided,
                    "{spec:?}: {seq:?} collides in {len} < {n} periods"
                );
            }
        }
    }
}

#[test]
fn the_state_budget_ends_inconclusive() {
    let spec = Spec {
        w: 0.1,
        ..Spec::small()
    };
    let p = spec.problem();
    let full = run(&p, speeds(&p, 3));
    assert_eq!(full.verdict, ExploreVerdict::Safe);
    let e = explore::explore(
        &p,
        speeds(&p, 3),
        &Options {
            max_states: 50,
            ..Options::default()
        },
    )
    .unwrap();
    assert_eq!(e.verdict, ExploreVerdict::Inconclusive);
    assert!(!e.complete);
    assert_eq!(e.states, 50);
    assert!(matches!(
        explore::explore(
            &p,
            speeds(&p, 3),
            &Options {
                max_states: 0,
                ..Options::default()
            }
        ),
        Err(ExploreError::Options(_))
    ));
    // A collision found before the budget is still a collision.
    let bad = Spec {
        w: 0.4,
        rho: 0.3,
        g0: 1.0,
        ..Spec::small()
    };
    let p = bad.problem();
    let total = run(&p, speeds(&p, 2)).states;
    let e = explore::explore(
        &p,
        speeds(&p, 2),
        &Options {
            max_states: total - 1,
            ..Options::default()
        },
    )
    .unwrap();
    assert_eq!(e.verdict, ExploreVerdict::Collision);
    assert!(!e.complete && e.counterexample.is_some());
}

#[test]
fn a_long_latency_does_not_shrink_the_state_limit() {
    // Latency 999: each state used to copy its 999 pending observations into itself and its
    // key (60 KB a state, 1.9 GB at 29,644 states), and the memory budget cut the search to
    // what fitted. States now share their histories, so 64 MiB holds 20,000 of them.
    let p = Problem::from_toml_str_with_overrides(
        &std::fs::read_to_string(seed_file()).unwrap(),
        "seed.toml",
        &["robot.latency=999".to_string()],
    )
    .unwrap();
    let options = Options {
        max_states: 20_000,
        max_memory: 64 << 20,
    };
    let e = explore::explore(&p, speeds(&p, 5), &options).expect("explores");
    assert_eq!(e.state_limit, 20_000);
    assert_eq!(e.states, 20_000);
    // The robot sees nothing for 99.9 s: the shortest collision, replayed, collides.
    assert_eq!(e.verdict, ExploreVerdict::Collision);
    let c = e.counterexample.expect("a counterexample");
    assert!(c.run.records.last().is_some_and(|r| r.collision));
}

#[test]
fn terminal_states_have_no_actions() {
    let p = Spec::small().problem();
    let model = FiniteModel::new(&p, speeds(&p, 3));
    let init = model.init_states();
    assert_eq!(init.len(), 1);
    assert_eq!(model.status(&init[0]), Status::Running);
    // One choice per speed: without noise or occlusion the environment chooses nothing else.
    let speeds_of = |s| model.actions(s).iter().map(|c| c.speed).collect::<Vec<_>>();
    assert_eq!(speeds_of(&init[0]), [0, 1, 2]);
    // Drive the robot until it stops, with the obstacle at W.
    let mut s = init[0].clone();
    while model.status(&s) == Status::Running {
        let at_w = *model.actions(&s).last().unwrap();
        assert_eq!(at_w.speed, 2);
        s = model.next_state(&s, at_w).unwrap().next;
    }
    assert_eq!(model.status(&s), Status::Stopped);
    assert!(model.actions(&s).is_empty());
}

// ---------------------------------------------------------------------------------------------
// Speed sets
// ---------------------------------------------------------------------------------------------

#[test]
fn speed_sets_parse_counts_lists_and_fractions() {
    let w = exact_decimal(0.15);
    let five = SpeedSet::parse("5", &w).unwrap();
    assert_eq!(five.to_string(), "{0, 0.0375, 0.075, 0.1125, 0.15}");
    let list = SpeedSet::parse("0.15, 0, 0.05,0.05", &w).unwrap();
    assert_eq!(
        list.speeds(),
        &[Exact::ZERO, exact_decimal(0.05), exact_decimal(0.15)]
    );
    let frac = SpeedSet::parse("1/30,0.1", &w).unwrap();
    assert_eq!(frac.to_string(), "{1/30, 0.1}");
    assert_eq!(SpeedSet::parse("0.0", &w).unwrap().len(), 1);
    for bad in ["0", "1", "", "0.2", "-0.1", "x", "1/0", "0.1,,abc", "1001"] {
        let e = SpeedSet::parse(bad, &w).expect_err(bad);
        assert!(e.to_string().starts_with(&format!("--speeds {bad}")), "{e}");
    }
    // W = 0: every count gives {0}.
    assert_eq!(SpeedSet::parse("5", &Exact::ZERO).unwrap().len(), 1);
}

// ---------------------------------------------------------------------------------------------
// The command
// ---------------------------------------------------------------------------------------------

fn json(out: &std::process::Output) -> Value {
    let text = stdout(out);
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("not JSON ({e}):\n{text}"))
}

#[test]
fn cli_safe_problem_exits_0_with_the_documented_json() {
    let dir = tmp();
    let out = safereach(dir.path())
        .arg("explore")
        .arg(problem_file("seed.toml"))
        .args(["--speeds", "3", "--json"])
        .assert()
        .code(0)
        .get_output()
        .clone();
    let v = json(&out);
    assert_eq!(v["verdict"], "safe");
    assert!(v["states"].as_u64().unwrap() > 1000);
    assert!(v["path"].is_null());
    let m = v["min_separation"].as_f64().unwrap();
    let p = Problem::load(&problem_file("seed.toml")).unwrap();
    let s = analyse(&p).unwrap().min_separation.unwrap();
    assert!(m >= s - 1e-9 && m < s + 0.01, "{m} vs s* {s}");
    assert_eq!(v["speeds_exact"], serde_json::json!(["0", "0.075", "0.15"]));
    assert!(v["closest"]["steps"].as_array().unwrap().len() > 10);
}

#[test]
fn cli_collision_exits_1_and_writes_the_counterexample_trace() {
    let dir = tmp();
    let out = safereach(dir.path())
        .arg("explore")
        .arg(problem_file("fast-obstacle.toml"))
        .args(["--speeds", "0,0.6", "--json", "--trace", "cx.csv"])
        .assert()
        .code(1)
        .get_output()
        .clone();
    let v = json(&out);
    assert_eq!(v["verdict"], "collision");
    let path = &v["path"];
    let periods = path["periods"].as_u64().unwrap() as usize;
    assert_eq!(path["obstacle_speeds"].as_array().unwrap().len(), periods);
    assert_eq!(path["collides"], true);
    let steps = path["steps"].as_array().unwrap();
    let last = steps.last().unwrap();
    assert!(last["gap"].as_f64().unwrap() <= 0.0, "{last}");
    let csv = std::fs::read_to_string(dir.path().join("cx.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t,robot_x,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_v"
    );
    assert_eq!(lines.count(), steps.len());
    // The path's speeds replay as a collision through the exact replay of witnesses.
    let p = Problem::load(&problem_file("fast-obstacle.toml")).unwrap();
    let speeds: Vec<f64> = path["obstacle_speeds"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    let r = simulate::replay_exact(&p.params(), &speeds, speeds.len(), true);
    assert!(r.outcome.collided && r.records.len() == periods);
}

#[test]
fn cli_budget_exits_3_with_a_clear_message() {
    let dir = tmp();
    let out = safereach(dir.path())
        .arg("explore")
        .arg(problem_file("seed.toml"))
        .args(["--max-states", "100"])
        .assert()
        .code(3)
        .get_output()
        .clone();
    let text = stdout(&out);
    assert!(
        text.contains("inconclusive: state budget reached (100 states)"),
        "{text}"
    );
}

#[test]
fn cli_bad_input_exits_2() {
    let dir = tmp();
    let cases = [
        (vec!["--speeds", "0.5"], "outside [0, W]"),
        (vec!["--speeds", "1"], "at least 2"),
        (vec!["--speeds", "abc"], "not a number"),
        (vec!["--max-states", "0"], "at least 1"),
        (vec!["--set", "robot.braking=-1"], "robot.braking"),
    ];
    bad_input_exits_2(dir.path(), "explore", &seed_file(), &cases);
    safereach(dir.path())
        .args(["explore", "no-such-problem.toml"])
        .assert()
        .code(2);
}

#[test]
fn cli_set_changes_the_problem_explored() {
    let dir = tmp();
    safereach(dir.path())
        .arg("explore")
        .arg(problem_file("seed.toml"))
        .args(["--speeds", "2", "--set", "environment.obstacle_speed=0.6"])
        .assert()
        .code(1);
}
