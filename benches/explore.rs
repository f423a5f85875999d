//! Explorer throughput and memory (a plain `main`, no timing assertions anywhere).
//!
//! `cargo bench --bench explore` prints, for each problem: states, transitions, wall time,
//! states and transitions per second, and the process's peak resident memory (VmHWM from
//! /proc/self/status) with the growth per stored state. The large case is the seed problem
//! with the obstacle speeds {0, 0.0371, 0.15} m/s: two incommensurate speeds make the gaps
//! a fine lattice, over 10⁶ distinct states.

use std::time::Instant;

use safereach::core::model::Problem;
use safereach::core::num::Exact;
use safereach::crosscheck::explore::{self, Options, SpeedSet};
use safereach::crosscheck::uppaal;

/// A field of /proc/self/status in kB (0 where the file does not exist).
fn status_kb(field: &str) -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with(field))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|v| v.parse().ok())
        })
        .unwrap_or(0)
}

fn seed(sets: &[&str]) -> Problem {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/seed.toml");
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    Problem::load_with_overrides(&path, &sets).expect("the seed problem loads")
}

fn bench(label: &str, problem: &Problem, speeds: &str) {
    let w = problem.params::<Exact>().W;
    let set = SpeedSet::parse(speeds, &w).expect("valid speeds");
    let rss_before = status_kb("VmRSS:");
    let hwm_before = status_kb("VmHWM:");
    let start = Instant::now();
    let e = explore::explore(
        problem,
        set,
        &Options {
            max_states: 10_000_000,
            // The bench measures bytes per state itself: no memory cap on the states.
            max_memory: u64::MAX,
        },
    )
    .expect("exploration succeeds");
    let secs = start.elapsed().as_secs_f64();
    let hwm = status_kb("VmHWM:");
    println!(
        "{label:<44} {:>9} states {:>10} transitions {:>8.2} s {:>9.0} states/s {:>9.0} transitions/s  \
         peak RSS {:>7.1} MB ({})  verdict {} min {:.6} m",
        e.states,
        e.transitions,
        secs,
        e.states as f64 / secs,
        e.transitions as f64 / secs,
        hwm as f64 / 1024.0,
        if hwm > hwm_before {
            format!(
                "{:.0} B/state",
                (hwm - rss_before) as f64 * 1024.0 / e.states as f64
            )
        } else {
            "below an earlier peak".to_string()
        },
        e.verdict.as_str(),
        e.min_separation_f64().unwrap_or(f64::NAN),
    );
}

fn bench_grid(label: &str, problem: &Problem, speeds: &str) {
    let w = problem.params::<Exact>().W;
    let set = SpeedSet::parse(speeds, &w).expect("valid speeds");
    let model = uppaal::export(problem, &set).expect("exports");
    let start = Instant::now();
    let g = uppaal::explore_grid(
        &model,
        &Options {
            max_states: 10_000_000,
            // The bench measures bytes per state itself: no memory cap on the states.
            max_memory: u64::MAX,
        },
    )
    .expect("the network runs");
    let secs = start.elapsed().as_secs_f64();
    println!(
        "{label:<44} {:>9} network states {:>8.2} s {:>9.0} states/s  verdict {}",
        g.states,
        secs,
        g.states as f64 / secs,
        g.verdict.as_str()
    );
}

fn main() {
    // `cargo bench` passes `--bench`; nothing else is accepted.
    println!("explorer (exact rationals, World::step), release build, one thread");
    bench(
        "fast-obstacle (collision), --speeds 5",
        &seed(&["environment.obstacle_speed=0.6"]),
        "5",
    );
    bench("seed, --speeds 5", &seed(&[]), "5");
    bench("seed, --speeds 17", &seed(&[]), "17");
    bench_grid(
        "UPPAAL network interpreter, seed --speeds 3",
        &seed(&[]),
        "3",
    );
    bench(
        "seed, --speeds 0,0.0371,0.15 (>= 10^6 states)",
        &seed(&[]),
        "0,0.0371,0.15",
    );
}
