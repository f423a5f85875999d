//! Benchmark: certify the seed problem in the library, and the analyser against the
//! brake-on-entry closed form on the same problems. Run with `cargo bench --bench certify`.
//!
//! Plain wall-clock medians over many repetitions (no timing assertions anywhere: speed is
//! measured here, never in tests).

use std::hint::black_box;
use std::path::Path;
use std::time::{Duration, Instant};

use safereach::analysis::lp::{self, LpOutcome};
use safereach::analysis::{Options, WitnessPolicy, analyse, analyse_with};
use safereach::core::model::{DangerRule, Problem, Sensing};
use safereach::core::num::Exact;
use safereach::core::parameter::ParamAffine;
use safereach::proof::certificate::{Certificate, check};
use safereach::proof::program::{Program, Row, Var};
use safereach::proof::schedule::Decomposition;

/// Median time per call of `f`, over `rounds` rounds of `per_round` calls.
fn median(rounds: usize, per_round: usize, mut f: impl FnMut()) -> Duration {
    let mut times: Vec<Duration> = (0..rounds)
        .map(|_| {
            let start = Instant::now();
            for _ in 0..per_round {
                f();
            }
            start.elapsed() / per_round as u32
        })
        .collect();
    times.sort();
    times[rounds / 2]
}

/// A feasible random linear program with `n` variables in [0, 10] and `m` rows through a
/// point of the box (small integer coefficients, some rows with slack), and an objective.
fn random_program(n: usize, m: usize, seed: &mut u64) -> Program {
    let mut next = |k: i64| -> i64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*seed >> 33) % k as u64) as i64
    };
    let point: Vec<i64> = (0..n).map(|_| next(11)).collect();
    let rows = (0..m)
        .map(|_| {
            let a: Vec<i64> = (0..n).map(|_| next(9) - 4).collect();
            let b = a.iter().zip(&point).map(|(a, x)| a * x).sum::<i64>() + next(4);
            Row {
                label: String::new(),
                a: a.into_iter().map(Exact::from).collect(),
                b: ParamAffine::constant(Exact::from(b)),
                strict: false,
            }
        })
        .collect();
    let vars = (0..n)
        .map(|j| Var {
            name: format!("x{j}"),
            lower: ParamAffine::constant(Exact::ZERO),
            upper: ParamAffine::constant(Exact::from(10)),
        })
        .collect();
    let objective = (0..n).map(|_| Exact::from(next(11) - 5)).collect();
    Program::linear(
        vars,
        rows,
        Some(objective),
        ParamAffine::constant(Exact::ZERO),
    )
}

/// The dense simplex against Clarabel on the same programs: the seed's pieces, then random
/// programs of growing size (where the simplex's dense tableau stops paying).
fn lp_solvers(seed: &Problem) {
    let dec = Decomposition::new(seed);
    let programs: Vec<Program> = dec.pieces.iter().map(|p| dec.program(p)).collect();
    let t_simplex = median(31, 200, || {
        for p in &programs {
            black_box(lp::solve(black_box(p), 0.0));
        }
    });
    let t_clarabel = median(31, 200, || {
        for p in &programs {
            black_box(lp::solve_by_clarabel(black_box(p), 0.0));
        }
    });
    println!(
        "seed's {} programs: simplex {:>8.2} µs, Clarabel {:>8.2} µs ({:.0}x)",
        programs.len(),
        t_simplex.as_secs_f64() * 1e6,
        t_clarabel.as_secs_f64() * 1e6,
        t_clarabel.as_secs_f64() / t_simplex.as_secs_f64()
    );
    let mut state = 0x5eed;
    for n in [2, 4, 8, 16, 32, 48, 64] {
        let programs: Vec<Program> = (0..20)
            .map(|_| random_program(n, 3 * n, &mut state))
            .collect();
        let dense = median(5, 5, || {
            for p in &programs {
                black_box(lp::solve(black_box(p), 0.0));
            }
        });
        let interior = median(5, 5, || {
            for p in &programs {
                black_box(lp::solve_by_clarabel(black_box(p), 0.0));
            }
        });
        let by_simplex = programs
            .iter()
            .filter(|p| {
                matches!(lp::solve(p, 0.0), LpOutcome::Optimal { .. })
                    && lp::solve(p, 0.0) != lp::solve_by_clarabel(p, 0.0)
            })
            .count();
        println!(
            "random LPs, {n} variables, {} rows: lp::solve {:>9.2} µs, Clarabel {:>9.2} µs per program ({:.1}x; {by_simplex}/20 answered by the simplex)",
            3 * n,
            dense.as_secs_f64() * 1e6 / 20.0,
            interior.as_secs_f64() * 1e6 / 20.0,
            interior.as_secs_f64() / dense.as_secs_f64()
        );
    }
}

fn closed_form(p: &Problem) -> f64 {
    let v = p.robot.max_speed;
    let b = p.robot.braking;
    let w = p.environment.obstacle_speed;
    p.controller.reaction_radius - (v + w) * p.robot.control_period - v * v / (2.0 * b) - w * v / b
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let seed = Problem::load(&root.join("problems/seed.toml")).expect("seed problem loads");

    lp_solvers(&seed);
    let analysis = analyse(&seed).expect("seed analyses");
    let cert = Certificate::from_analysis(&analysis);
    check(&cert).expect("seed certificate verifies");
    println!(
        "seed: verdict {}, s* = {:?}, {} pieces, {} linear programs per certificate",
        analysis.verdict.as_str(),
        analysis.min_separation,
        analysis.outcomes.len(),
        analysis.programs_solved
    );
    let t_analyse = median(31, 20, || {
        black_box(analyse(black_box(&seed)).expect("analyses"));
    });
    let proof_only = Options {
        witness: WitnessPolicy::ToRefute,
    };
    let t_proof = median(31, 20, || {
        black_box(analyse_with(black_box(&seed), proof_only).expect("analyses"));
    });
    let t_check = median(31, 20, || {
        black_box(check(black_box(&cert)).expect("verifies"));
    });
    let t_full = median(31, 20, || {
        let a = analyse(black_box(&seed)).expect("analyses");
        let c = Certificate::from_analysis(&a);
        black_box(check(&c).expect("verifies"));
    });
    println!(
        "seed: proof only (pieces, LPs, exact bounds)  {:>8.1} µs",
        t_proof.as_secs_f64() * 1e6
    );
    println!(
        "seed: analyse (proof + exact witness replay)  {:>8.1} µs",
        t_analyse.as_secs_f64() * 1e6
    );
    println!(
        "seed: check (exact, no solver)              {:>10.1} µs",
        t_check.as_secs_f64() * 1e6
    );
    println!(
        "seed: certify = analyse + certificate + check {:>8.1} µs",
        t_full.as_secs_f64() * 1e6
    );

    // Sensing noise and occlusion (issue 10): the seed with 2 mm / 0.01 m/s of noise, and
    // with an obstacle first seen at 1.2 m too, against itself without, in the same run;
    // then the same with W = 0.25 m/s > V_a, where the wrong-assumption guard is active and
    // occlusion adds the pieces of an obstacle first seen inside the area. Pieces, programs
    // and time.
    let certify = |p: &Problem| {
        let a = analyse(p).expect("analyses");
        let c = Certificate::from_analysis(&a);
        black_box(check(&c).expect("verifies"));
        a
    };
    let sensed = |p: &Problem, d_det: Option<f64>| {
        let mut q = p.clone();
        q.sensing = Some(Sensing {
            gap_noise: Some(0.002),
            speed_noise: Some(0.01),
            first_detection_gap: d_det,
        });
        q
    };
    let mut guarded = seed.clone();
    guarded.environment.obstacle_speed = 0.25;
    for (base, label) in [(&seed, "seed"), (&guarded, "seed, W 0.25 (guard active)")] {
        let t_plain = median(31, 20, || {
            certify(black_box(base));
        });
        let plain = certify(base);
        for (d_det, what) in [(None, "noise"), (Some(1.2), "noise + occlusion 1.2 m")] {
            let p = sensed(base, d_det);
            let a = certify(&p);
            let t = median(31, 20, || {
                certify(black_box(&p));
            });
            println!(
                "{what}: {label} {} pieces / {} LPs {:.1} µs; with sigma_g 2 mm, sigma_w 0.01 m/s{} {} pieces / {} LPs {:.1} µs ({:.2}x), s* {:?} -> {:?}",
                plain.outcomes.len(),
                plain.programs_solved,
                t_plain.as_secs_f64() * 1e6,
                d_det.map_or(String::new(), |d| format!(", d_det {d} m")),
                a.outcomes.len(),
                a.programs_solved,
                t.as_secs_f64() * 1e6,
                t.as_secs_f64() / t_plain.as_secs_f64(),
                plain.min_separation,
                a.min_separation,
            );
        }
    }

    // Brake-on-entry, latency 0: the analyser against the closed form on the same cases.
    let mut cases = Vec::new();
    for (i, w) in [0.05, 0.1, 0.15, 0.2, 0.3].iter().enumerate() {
        for rho in [1.0, 1.2, 1.4, 1.6] {
            let mut p = seed.clone();
            p.name = format!("entry-{i}");
            p.controller.danger_rule = DangerRule::Area;
            p.robot.latency = 0;
            p.environment.obstacle_speed = *w;
            p.controller.reaction_radius = rho;
            cases.push(p);
        }
    }
    let mut worst_gap: f64 = 0.0;
    for p in &cases {
        let a = analyse(p).expect("analyses");
        if let Some(s) = a.min_separation {
            worst_gap = worst_gap.max((s - closed_form(p)).abs());
        }
    }
    let t_cases = median(11, 3, || {
        for p in &cases {
            black_box(analyse(black_box(p)).expect("analyses"));
        }
    }) / cases.len() as u32;
    let t_formula = median(11, 10_000, || {
        for p in &cases {
            black_box(closed_form(black_box(p)));
        }
    }) / cases.len() as u32;
    println!(
        "brake-on-entry ({} cases): analyser {:.1} µs/case, closed form {:.4} µs/case, ratio {:.0}x; max |s* - closed form| = {:.1e} m",
        cases.len(),
        t_cases.as_secs_f64() * 1e6,
        t_formula.as_secs_f64() * 1e6,
        t_cases.as_secs_f64() / t_formula.as_secs_f64(),
        worst_gap
    );

    // What grows with the horizon (issue 12): the seed from 100 m at control periods from
    // 1 s to 0.5 ms, 5·10² to 10⁶ witness periods. The replay leaps over the cruise and the
    // braking; what still walks periods is the drive profile up to top speed (v_max/(a·dt)
    // periods, stepped and stored by the decomposition that analyse and check each build).
    for dt in [1.0, 0.1, 0.01, 0.001, 0.0005] {
        let mut p = seed.clone();
        p.environment.initial_gap = safereach::core::model::Position::At(100.0);
        p.robot.control_period = dt;
        let a = analyse(&p).expect("analyses");
        let periods = a.witness.as_ref().map_or(0, |w| w.obstacle_speeds.len());
        let t = median(11, 3, || {
            certify(black_box(&p));
        });
        let t_check = median(11, 3, || {
            black_box(check(black_box(&Certificate::from_analysis(&a))).expect("verifies"));
        });
        println!(
            "seed from 100 m at dt = {dt} s ({periods} periods): certify {:>8.1} µs, check {:>8.1} µs",
            t.as_secs_f64() * 1e6,
            t_check.as_secs_f64() * 1e6
        );
    }

    // What grows with the latency (issue 12): the seed at dt = 0.01 s with L from 0 to 200
    // periods (up to 2 s of lag), its buffer grown by what robot and obstacle close during
    // the lag so that every case certifies (a case that refutes stops at its first colliding
    // piece and says nothing about cost). Both sides of the wrong-assumption guard: W below
    // V_a (no in-area pieces) and above it (ρ = 4 m).
    for (w, rho) in [(0.15, 3.0), (0.3, 4.0)] {
        for l in [0u32, 1, 10, 50, 100, 200] {
            let mut p = seed.clone();
            p.robot.control_period = 0.01;
            p.robot.acceleration = 0.05;
            p.robot.latency = l;
            p.environment.obstacle_speed = w;
            p.controller.reaction_radius = rho;
            p.controller.buffer = 0.11 + (0.2 + w) * 0.01 * f64::from(l);
            let a = analyse(&p).expect("analyses");
            let t = median(11, 3, || {
                certify(black_box(&p));
            });
            let cert = Certificate::from_analysis(&a);
            let t_check = median(11, 3, || {
                black_box(check(black_box(&cert)).expect("verifies"));
            });
            println!(
                "latency {l:>3} (W = {w}, dt = 0.01 s): {} with {} pieces, {} programs; certify {:>8.1} µs, check {:>8.1} µs",
                a.verdict.as_str(),
                a.outcomes.len(),
                a.programs_solved,
                t.as_secs_f64() * 1e6,
                t_check.as_secs_f64() * 1e6
            );
        }
    }
}
