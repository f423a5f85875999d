//! Sensing noise (DESIGN.md §1.2; docs/semantics.md §12): every observed gap within ±σ_g
//! of the true one, every measured speed within ±σ_w, the errors chosen adversarially per
//! observation. Held against independent answers:
//! - the closed form: gap noise adds σ_g to the brake-on-entry radius (rule `area`,
//!   latency 0, a cruising robot);
//! - an exhaustive search through the step function, independent of the analyser's
//!   reductions: every obstacle speed of a finite set in every period, and in every period
//!   both aims of the environment's error (let the robot react if some error does, keep it
//!   quiet if some error does: the only thing an error can change is whether the guard
//!   fires). Its minimum is never below s*, and a collision in it means `refuted`;
//! - noise never helps: s* never rises with σ, and σ = 0 is today's answer exactly;
//! - every certificate of a noisy problem passes `check` (its witness replays with the
//!   errors its schedule asks for).

use std::collections::HashSet;

use safereach::analysis::{Analysis, Verdict, analyse, radius};
use safereach::core::model::{DangerRule, Problem, Sensing};
use safereach::core::num::Exact;
use safereach::core::semantics::{Mode, World};
use safereach::proof::certificate::{Certificate, check};

use crate::common::spec::Spec;

fn noisy(mut p: Problem, gap: f64, speed: f64) -> Problem {
    p.sensing = Some(Sensing {
        gap_noise: Some(gap),
        speed_noise: Some(speed),
        first_detection_gap: None,
    });
    p.validate("test").expect("a valid problem");
    p
}

#[test]
fn gap_noise_adds_itself_to_the_brake_on_entry_radius() {
    // (v, b, W, dt, clearance, σ_g)
    for (v, b, w, dt, c, sg) in [
        (0.2, 0.05, 0.15, 0.1, 0.0, 0.02),
        (0.5, 0.5, 0.1, 0.05, 0.05, 0.1),
        (1.0, 2.0, 0.3, 0.1, 0.1, 0.005),
    ] {
        let mut p = Spec {
            v_max: v,
            a: 0.5,
            b,
            dt,
            latency: 0,
            clearance: c,
            v_a: w,
            rho: 1.0,
            rule: DangerRule::Area,
            buffer: 0.0,
            wab: false,
            w,
            g0: 10.0,
            ..Spec::seed()
        }
        .build();
        p.robot.initial_speed = Some(v);
        let p = noisy(p, sg, 0.0);
        let closed = v * v / (2.0 * b) + w * v / b + (v + w) * dt + c + sg;
        let found = radius::safe_radius(&p).unwrap().value.expect("a radius");
        assert!(
            (found - closed).abs() <= 2e-6,
            "v={v} b={b} W={w} dt={dt} c={c} σ_g={sg}: radius {found}, closed form {closed}"
        );
    }
}

/// The least separation over every behaviour of the finite model: obstacle speeds from
/// `speeds`, and in every period the environment's error aimed at letting the robot react
/// or at keeping it quiet. Returns (least separation at rest, some behaviour collides).
pub(crate) fn exhaustive(p: &Problem, speeds: &[Exact]) -> (Option<Exact>, bool) {
    let params = p.params::<Exact>();
    let mut least: Option<Exact> = None;
    let mut collides = false;
    let mut seen = HashSet::new();
    let mut start = World::new(params.clone());
    if params.d_det.is_some() {
        start.hide_until(usize::MAX);
    }
    let mut stack = vec![start];
    let horizon = safereach::core::simulate::horizon(&p.params::<f64>()) + 5;
    while let Some(world) = stack.pop() {
        if world.stopped() || world.k() > horizon {
            continue;
        }
        // Occlusion: a hidden obstacle may be first seen now if its true observed gap is
        // ≥ d_det, and may stay hidden only while that still holds.
        if let Some(d_det) = &params.d_det
            && world.observation().is_none()
        {
            let mut shown = world.clone();
            shown.hide_until(world.k());
            if let Some(obs) = shown.observation() {
                if obs.gap >= *d_det {
                    let key = format!("{shown:?}");
                    if seen.insert(key) {
                        stack.push(shown);
                    }
                } else {
                    continue; // hidden too long: no first sighting at ≥ d_det is left
                }
            }
        }
        let moving = matches!(world.robot().mode, Mode::Accelerate | Mode::Drive);
        for w in speeds {
            for react in [false, true] {
                if react && !moving {
                    continue; // the aim matters only while a guard can fire
                }
                let mut next = world.clone();
                let rec = next.step_with(w.clone(), react);
                if rec.collision {
                    collides = true;
                    continue;
                }
                if let Some(g) = rec.rest_gap {
                    least = Some(match least.take() {
                        Some(l) if l <= g => l,
                        _ => g,
                    });
                    continue;
                }
                let key = format!("{:?}", next);
                if seen.insert(key) {
                    stack.push(next);
                }
            }
        }
    }
    (least, collides)
}

fn s_star(a: &Analysis) -> Option<f64> {
    if a.never_stops {
        Some(f64::NEG_INFINITY)
    } else {
        a.min_separation
    }
}

/// Small problems close to the robot (short runs), noisy in both gap and speed.
pub(crate) fn small_noisy() -> Vec<Problem> {
    let rules = [DangerRule::Paper, DangerRule::Kinematic, DangerRule::Area];
    let sensings = [(0.03, 0.0, None), (0.05, 0.06, None)];
    small_sensing(&rules, &[0, 1], &[0.45, 0.8], &sensings)
        .into_iter()
        .inspect(|p| p.validate("test").expect("a valid problem"))
        .collect()
}

/// Small problems close to the robot (short runs) for every rule, latency and radius
/// given, W below and above V_a with the wrong-assumption guard off and on, each with every
/// `(σ_g, σ_w, d_det)` given (not validated).
pub(crate) fn small_sensing(
    rules: &[DangerRule],
    latencies: &[u32],
    rhos: &[f64],
    sensings: &[(f64, f64, Option<f64>)],
) -> Vec<Problem> {
    let mut out = Vec::new();
    for &rule in rules {
        for &latency in latencies {
            for (w, wab) in [(0.1, false), (0.25, true), (0.15, true)] {
                for &rho in rhos {
                    for &(sg, sw, d_det) in sensings {
                        let mut p = Spec {
                            rule,
                            latency,
                            w,
                            wab,
                            rho,
                            g0: 1.2,
                            ..Spec::small()
                        }
                        .build();
                        p.sensing = Some(Sensing {
                            gap_noise: Some(sg),
                            speed_noise: Some(sw),
                            first_detection_gap: d_det,
                        });
                        out.push(p);
                    }
                }
            }
        }
    }
    out
}

#[test]
fn an_exhaustive_search_over_errors_never_beats_the_analyser() {
    let mut verdicts = [0usize; 3];
    let mut refuted_by_search = 0;
    for p in small_noisy() {
        // Every certificate of a noisy problem checks: its witness replays.
        let (a, collides) = held_to_the_search(&p);
        refuted_by_search += usize::from(collides);
        verdicts[match a.verdict {
            Verdict::Certified => 0,
            Verdict::Refuted => 1,
            _ => 2,
        }] += 1;
    }
    assert!(
        verdicts[0] > 0 && verdicts[1] > 0,
        "both verdicts occur: {verdicts:?}"
    );
    // The search is not vacuous: it finds the collisions of refuted problems. (It cannot
    // reach s* itself, which sits on guard thresholds no finite set hits; the other side,
    // s* realised by a behaviour, is the witness replay that `check` holds above.)
    assert!(refuted_by_search > 0, "{verdicts:?}");
}

/// Occlusion: with the obstacle first seen at d_det inside the area (d_det below
/// ρ − (v+W)·dt), the brake-on-entry robot's s* is d_det − v²/(2b) − W·v/b − nothing lost to
/// the period (it is seen at d_det at an observation instant): certified exactly when
/// d_det > v²/(2b) + W·v/b + clearance.
#[test]
fn a_late_first_sighting_costs_the_closed_form() {
    for (v, b, w, dt, c) in [(0.2, 0.05, 0.15, 0.1, 0.0), (0.5, 0.5, 0.1, 0.05, 0.05)] {
        let stop = v * v / (2.0 * b) + w * v / b;
        let rho = stop + c + 1.0;
        for d_det in [stop + c - 0.1, stop + c + 0.05, stop + c + 0.5] {
            let mut p = Spec {
                v_max: v,
                a: 0.5,
                b,
                dt,
                latency: 0,
                clearance: c,
                v_a: w,
                rho,
                rule: DangerRule::Area,
                buffer: 0.0,
                wab: false,
                w,
                g0: 10.0,
                ..Spec::seed()
            }
            .build();
            p.robot.initial_speed = Some(v);
            p.sensing = Some(Sensing {
                gap_noise: None,
                speed_noise: None,
                first_detection_gap: Some(d_det),
            });
            let a = analyse(&p).unwrap();
            let s = a.min_separation.expect("a worst case");
            assert!(
                (s - (d_det - stop)).abs() <= 1e-9,
                "v={v} W={w} d_det={d_det}: s* {s}, closed form {}",
                d_det - stop
            );
            assert_eq!(
                a.verdict == Verdict::Certified,
                d_det > stop + c,
                "d_det={d_det}"
            );
            check(&Certificate::from_analysis(&a)).expect("checks");
        }
    }
}

/// Analyses a problem and holds it to the exhaustive search over speeds {0, W/2, W}, both
/// aims of every error and (with occlusion) every admissible hiding prefix: a collision in
/// the search means `refuted`, the search's least rest gap is never below s*, and the
/// certificate checks. Returns the analysis and whether the search collides.
fn held_to_the_search(p: &Problem) -> (Analysis, bool) {
    p.validate("test").expect("a valid problem");
    let a = analyse(p).expect("analyses");
    let w = p.params::<Exact>().W;
    let speeds = [Exact::ZERO, w.clone() / Exact::from(2), w];
    let (least, collides) = exhaustive(p, &speeds);
    let text = p.to_toml_string();
    if collides {
        assert_eq!(a.verdict, Verdict::Refuted, "{text}: the search collides");
    }
    if let (Some(l), Some(s)) = (&least, s_star(&a)) {
        let l = l.to_f64().value();
        assert!(l >= s - 1e-9, "{text}: search minimum {l} below s* {s}");
    }
    check(&Certificate::from_analysis(&a)).unwrap_or_else(|e| panic!("{text}: {e}"));
    (a, collides)
}

/// Occlusion with the wrong-assumption guard active: an obstacle that appears *inside* the
/// area before the robot brakes was not bound by V_a while hidden. Obstacles starting inside
/// ρ, a controller assuming static obstacles (V_a = 0 < W = 0.1): the exhaustive search over
/// every admissible hiding prefix collides only where the analyser refutes and never goes
/// below s*, the worst case is a piece first seen in the area somewhere (the visible pieces
/// alone would certify the first problem here, which collides), and every certificate
/// checks.
#[test]
fn an_obstacle_appearing_inside_the_area_is_searched_exhaustively() {
    let (mut twins, mut refuted) = (0, 0);
    for (latency, sigma) in [(0, 0.0), (1, 0.0), (0, 0.02)] {
        for (d_det, g0) in [(0.3, 0.6), (0.5, 0.6), (0.3, 0.9)] {
            let mut p = Spec {
                rule: DangerRule::Paper,
                latency,
                b: 1.0,
                v_a: 0.0,
                w: 0.1,
                wab: true,
                rho: 1.0,
                g0,
                ..Spec::small()
            }
            .build();
            p.sensing = Some(Sensing {
                gap_noise: Some(sigma),
                speed_noise: Some(sigma),
                first_detection_gap: Some(d_det),
            });
            let (a, collides) = held_to_the_search(&p);
            let piece = a.witness.as_ref().expect("a witness").piece;
            twins += usize::from(piece.detected && piece.entry.is_some());
            refuted += usize::from(collides);
        }
    }
    assert!(twins > 0, "no worst case is first seen inside the area");
    assert!(refuted > 0, "the search collides nowhere");
}

/// (Slow: every other problem of the noise test, with the guard active or not; CI runs it.)
#[test]
#[ignore = "exhaustive search over hiding prefixes, ~50 s; CI runs it"]
fn an_exhaustive_search_over_late_sightings_never_beats_the_analyser() {
    let mut verdicts = [0usize; 2];
    // Every other problem of the noise test: hiding multiplies the search's branches.
    for p in small_noisy().into_iter().step_by(2) {
        let mut p = p;
        if let Some(s) = p.sensing.as_mut() {
            s.first_detection_gap = Some(0.3);
        }
        let (a, _) = held_to_the_search(&p);
        verdicts[usize::from(a.verdict == Verdict::Certified)] += 1;
    }
    assert!(verdicts[0] > 0 && verdicts[1] > 0, "{verdicts:?}");
}

#[test]
fn noise_never_helps_and_zero_noise_is_todays_answer() {
    for p in small_noisy() {
        let exact = {
            let mut q = p.clone();
            q.sensing = None;
            q
        };
        let zero = noisy(exact.clone(), 0.0, 0.0);
        let (a0, az, an) = (
            analyse(&exact).unwrap(),
            analyse(&zero).unwrap(),
            analyse(&p).unwrap(),
        );
        assert_eq!(a0.lower_bound, az.lower_bound);
        assert_eq!(a0.min_separation, az.min_separation);
        assert_eq!(a0.verdict, az.verdict);
        let s = |a: &Analysis| s_star(a).unwrap_or(f64::INFINITY);
        assert!(
            s(&an) <= s(&a0) + 1e-9,
            "{}: s* {} with noise, {} without",
            p.to_toml_string(),
            s(&an),
            s(&a0)
        );
    }
}

/// Monte Carlo plays occlusion late on every other run: the obstacle is first seen at the
/// last observation that surely shows a true gap ≥ d_det. Each such run's first sighting is
/// admissible and the last chance; the runs reach closer than the visible ones, never below
/// s*, and a certified occluded problem never collides.
#[test]
fn monte_carlo_hides_the_obstacle_as_late_as_the_premise_allows() {
    use safereach::analysis::{monte_carlo, monte_carlo_run};
    use safereach::core::simulate::horizon;

    let seed_problem = |d_det: Option<f64>| {
        let mut p = Problem::load(&crate::common::paths::seed_file()).expect("the seed loads");
        p.sensing = d_det.map(|d| Sensing {
            gap_noise: None,
            speed_noise: None,
            first_detection_gap: Some(d),
        });
        p.validate("test").expect("a valid problem");
        p
    };
    let visible = monte_carlo(&seed_problem(None).params::<f64>(), 200, 0);
    for d_det in [0.8, 1.2] {
        let p = seed_problem(Some(d_det));
        let params = p.params::<f64>();
        let step = (params.v_max + params.W) * params.dt;
        for i in [1, 3, 5] {
            let run = monte_carlo_run(&params, 0, i, horizon(&params), false);
            let k = run
                .records
                .iter()
                .position(|r| r.observation.is_some())
                .expect("the obstacle is seen");
            let gap = run.records[k].observation.as_ref().unwrap().gap;
            assert!(
                gap >= d_det && gap - step < d_det,
                "run {i}: first seen at {gap}"
            );
        }
        let mc = monte_carlo(&params, 200, 0);
        let a = analyse(&p).unwrap();
        let s = a.min_separation.expect("a worst case");
        assert!(
            mc.min_separation >= s - 1e-9,
            "{} below s* {s}",
            mc.min_separation
        );
        assert!(mc.min_separation < visible.min_separation);
        if a.verdict == Verdict::Certified {
            assert_eq!(mc.collisions, 0);
        }
    }
}
