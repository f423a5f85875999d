//! Benchmark: a 10,000-cell sweep (formal verdicts only) on the machine's cores, against
//! evaluating the brake-on-entry closed form for the same cells. Run with
//! `cargo bench --bench sweep`.

use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

use safereach::analysis::Verdict;
use safereach::analysis::sweep::{Grid, Shard, SweepBudget};

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::copy(
        root.join("problems/seed.toml"),
        dir.path().join("seed.toml"),
    )
    .expect("copies seed");
    let speeds: Vec<String> = (0..100)
        .map(|i| format!("{}", 0.005 + 0.003 * f64::from(i)))
        .collect();
    let radii: Vec<String> = (0..100)
        .map(|i| format!("{}", 0.5 + 0.015 * f64::from(i)))
        .collect();
    let grid_text = format!(
        "base = \"seed.toml\"\n[axes]\n\"environment.obstacle_speed\" = [{}]\n\"controller.reaction_radius\" = [{}]\n",
        speeds.join(", "),
        radii.join(", ")
    );
    let path = dir.path().join("bench-grid.toml");
    std::fs::write(&path, grid_text).expect("writes grid");
    let grid = Grid::load(&path).expect("grid loads");
    assert_eq!(grid.len(), 10_000);

    let start = Instant::now();
    let results = grid
        .run(Shard::ALL, 0, 0, &SweepBudget::default(), || {})
        .expect("sweeps");
    let sweep = start.elapsed();
    let n = |v: Verdict| results.iter().filter(|r| r.verdict == v).count();

    // The same cells by the closed form (brake on entry, latency folded in as (L+1) periods).
    let problems: Vec<_> = (0..grid.len())
        .map(|c| grid.problem(c).expect("cell problem"))
        .collect();
    let start = Instant::now();
    let mut certified_by_formula = 0;
    for _ in 0..100 {
        certified_by_formula = 0;
        for p in &problems {
            let (v, b, w, dt) = (
                p.robot.max_speed,
                p.robot.braking,
                p.environment.obstacle_speed,
                p.robot.control_period,
            );
            let s = p.controller.reaction_radius
                - f64::from(p.robot.latency + 1) * (v + w) * dt
                - v * v / (2.0 * b)
                - w * v / b;
            if black_box(s) > p.robot.clearance {
                certified_by_formula += 1;
            }
        }
    }
    let formula = start.elapsed() / 100;
    println!(
        "sweep: {} cells in {:.2} s on {} threads = {:.0} cells/s ({} certified, {} refuted, {} inconclusive; {} programs solved)",
        results.len(),
        sweep.as_secs_f64(),
        rayon::current_num_threads(),
        results.len() as f64 / sweep.as_secs_f64(),
        n(Verdict::Certified),
        n(Verdict::Refuted),
        n(Verdict::Inconclusive),
        results.iter().map(|r| r.programs).sum::<usize>()
    );
    println!(
        "closed form, same cells: {:.3} ms ({} certified by the formula); ratio sweep/formula = {:.0}x",
        formula.as_secs_f64() * 1e3,
        certified_by_formula,
        sweep.as_secs_f64() / formula.as_secs_f64()
    );
}
