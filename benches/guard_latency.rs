//! Benchmark: a long observation latency with the wrong-assumption guard active (issue 37,
//! item 5). Run with `cargo bench --bench guard_latency`.
//!
//! The robot: v_max 1 m/s, a 0.05 m/s², b 3 m/s², dt 0.01 s, V_a = 0 with the guard on,
//! W 0.2 m/s, ρ 5 m, buffer 0, from 10 m, at latencies 50 to 400 periods. Every early
//! piece's box end is the fastest approach's gap at its anchor; stepped once per piece it
//! cost O(latency · steps) per piece (34 s at latency 200), in closed form
//! (`proof::approach_closed_form`) neither the time nor the pieces grow with the latency.
//! Each latency is reported as a ratio to the same robot at latency 0, measured in the same
//! run (wall-clock medians; no timing assertions anywhere: speed is measured here, never in
//! tests).

#[path = "support/median.rs"]
mod support_median;

use std::hint::black_box;
use std::time::Duration;

use support_median::median;

use safereach::analysis::{Analysis, analyse};
use safereach::core::model::{Position, Problem};
use safereach::proof::certificate::{Certificate, check};

/// The robot at latency `l`.
fn problem(l: u32) -> Problem {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut p = Problem::load(&root.join("problems/seed.toml")).expect("seed problem loads");
    p.name = format!("guard-latency-{l}");
    p.robot.max_speed = 1.0;
    p.robot.acceleration = 0.05;
    p.robot.braking = 3.0;
    p.robot.control_period = 0.01;
    p.robot.latency = l;
    p.controller.assumed_obstacle_speed = 0.0;
    p.controller.wrong_assumption_brake = true;
    p.controller.reaction_radius = 5.0;
    p.controller.buffer = 0.0;
    p.environment.obstacle_speed = 0.2;
    p.environment.initial_gap = Position::At(10.0);
    p
}

/// Certify (analyse, write the certificate, check it) and check alone: the analysis and the
/// median times of both.
fn measure(l: u32) -> (Analysis, Duration, Duration) {
    let p = problem(l);
    let a = analyse(&p).expect("analyses");
    let cert = Certificate::from_analysis(&a);
    let t_certify = median(5, || {
        let a = analyse(black_box(&p)).expect("analyses");
        black_box(check(&Certificate::from_analysis(&a)).expect("verifies"));
    });
    let t_check = median(5, || {
        black_box(check(black_box(&cert)).expect("verifies"));
    });
    (a, t_certify, t_check)
}

fn main() {
    let mut baseline = None;
    for l in [0, 50, 100, 200, 400] {
        let (a, t, t_check) = measure(l);
        let (base, base_check) = *baseline.get_or_insert((t, t_check));
        println!(
            "guard active, V_a = 0, latency {l:>3}: {} with {} pieces, {} programs; certify {:>7.1} ms ({:.2}x latency 0), check {:>7.1} ms ({:.2}x)",
            a.verdict.as_str(),
            a.outcomes.len(),
            a.programs_solved,
            t.as_secs_f64() * 1e3,
            t.as_secs_f64() / base.as_secs_f64(),
            t_check.as_secs_f64() * 1e3,
            t_check.as_secs_f64() / base_check.as_secs_f64(),
        );
    }
}
