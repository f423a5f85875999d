//! `safereach sweep`: analyses every cell of a grid of problems in parallel and writes the
//! results as JSON Lines and CSV — whole, or one shard of several machines' share.
//!
//! The helpers here (running a grid with a progress bar, counting verdicts) are shared with
//! `report`, which sweeps too when it is not given results to merge.

use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};

use safereach::analysis::Verdict;
use safereach::analysis::sweep::{self, CellResult, Grid, Shard, SweepBudget};
use safereach::core::budget::{Budget, Work};

use super::exit::Exit;
use super::output::{Output, create_dir, write_file};

/// Arguments of `safereach sweep`.
#[derive(clap::Args)]
pub struct SweepArgs {
    /// Grid file (TOML): a base problem and axes over its keys.
    grid: PathBuf,
    /// Monte Carlo runs per cell (default: the grid's `runs`, else 0).
    #[arg(long)]
    runs: Option<usize>,
    /// Seed of the first Monte Carlo run (default: the grid's `seed`, else 0).
    #[arg(long)]
    seed: Option<u64>,
    /// Run one n-th of the cells: `i/n` takes cells i, i+n, i+2n, ...
    #[arg(long, value_name = "I/N")]
    shard: Option<String>,
    /// Output directory (JSON Lines and CSV, written atomically).
    #[arg(long)]
    out: PathBuf,
    /// Budget: the most cells this run (its shard) analyses (default 1,000,000).
    #[arg(long, value_name = "N")]
    max_cells: Option<u64>,
    /// Budget: the most control periods the Monte Carlo runs simulate in all, counted as
    /// runs times each cell's horizon (default 2,000,000,000).
    #[arg(long, value_name = "N")]
    max_periods: Option<u64>,
}

/// Runs `safereach sweep`: exit 0 when the results are written.
pub fn run(args: SweepArgs, out: &mut Output) -> Result<Exit> {
    let grid = Grid::load(&args.grid)?;
    let shard = match &args.shard {
        Some(s) => Shard::parse(s).map_err(anyhow::Error::msg)?,
        None => Shard::ALL,
    };
    let runs = args.runs.unwrap_or(grid.runs);
    let seed = args.seed.unwrap_or(grid.seed);
    let start = Instant::now();
    let budget = SweepBudget {
        cells: Budget::new(Work::Cells, args.max_cells),
        periods: Budget::new(Work::SimulatedPeriods, args.max_periods),
    };
    let results = run_grid(&grid, shard, runs, seed, &budget)?;
    let elapsed = start.elapsed();
    create_dir(&args.out)?;
    let stem = if shard == Shard::ALL {
        grid.name.clone()
    } else {
        format!("{}.shard-{}-of-{}", grid.name, shard.index, shard.count)
    };
    let jsonl = args.out.join(format!("{stem}.jsonl"));
    let csv = args.out.join(format!("{stem}.csv"));
    write_file(&jsonl, sweep::to_jsonl(&results).as_bytes())?;
    write_file(&csv, sweep::to_csv(&results, &keys(&grid)).as_bytes())?;
    writeln!(
        out,
        "{}: {} of {} cells in {:.2} s ({:.0} cells/s): {}; wrote {} and {}",
        grid.name,
        results.len(),
        grid.len(),
        elapsed.as_secs_f64(),
        results.len() as f64 / elapsed.as_secs_f64().max(1e-9),
        counts(&results),
        jsonl.display(),
        csv.display()
    )?;
    Ok(Exit::Pass)
}

/// A progress bar over `len` cells (drawn on stderr, and only on a terminal).
fn progress(len: usize) -> ProgressBar {
    let bar = ProgressBar::new(len as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{elapsed_precise} [{bar:40}] {pos}/{len} cells ({per_sec}, eta {eta})",
        )
        .expect("static template")
        .progress_chars("=> "),
    );
    bar
}

/// Analyses the cells of `grid` that `shard` owns, showing progress.
pub fn run_grid(
    grid: &Grid,
    shard: Shard,
    runs: usize,
    seed: u64,
    budget: &SweepBudget,
) -> Result<Vec<CellResult>> {
    let owned = shard.share(grid.len());
    let bar = progress(owned);
    let results = grid
        .run(shard, runs, seed, budget, || bar.inc(1))
        .context("sweep failed")?;
    bar.finish_and_clear();
    Ok(results)
}

/// `N certified, N refuted, N inconclusive`.
pub fn counts(results: &[CellResult]) -> String {
    let n = |v: Verdict| results.iter().filter(|r| r.verdict == v).count();
    format!(
        "{} certified, {} refuted, {} inconclusive",
        n(Verdict::Certified),
        n(Verdict::Refuted),
        n(Verdict::Inconclusive)
    )
}

/// The grid's axis keys, in order (the CSV's leading columns).
pub fn keys(grid: &Grid) -> Vec<String> {
    grid.axes.iter().map(|(k, _)| k.clone()).collect()
}
