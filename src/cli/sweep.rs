//! `safereach sweep`: analyses every cell of a grid of problems in parallel and writes the
//! results as JSON Lines and CSV — whole, or one shard of several machines' share (given,
//! read from the scheduler's environment, or submitted to Slurm by `sweep_slurm`).
//!
//! The helpers here (running a grid with a progress bar, counting verdicts) are shared with
//! `report`, which sweeps too when it is not given results to merge.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};

use safereach::analysis::Verdict;
use safereach::analysis::sweep::{CellResult, Grid, Shard, SweepBudget};
use safereach::analysis::sweep_file::{SweepFile, file_stem};
use safereach::core::budget::{Budget, Work};
use safereach::core::shard::ShardSource;

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
    /// Run one n-th of the cells: `i/n` takes cells i, i+n, i+2n, ...; `auto` reads the shard
    /// from a Slurm array task (SLURM_ARRAY_TASK_*) or a Kubernetes Indexed Job
    /// (JOB_COMPLETION_INDEX, with --shards N).
    #[arg(long, value_name = "I/N|auto")]
    shard: Option<String>,
    /// Number of shards: with `--shard auto` (required for Kubernetes, checked against the
    /// Slurm array), or with `--slurm`.
    #[arg(long, value_name = "N")]
    shards: Option<usize>,
    /// Submit the sweep to Slurm as an array job of --shards tasks plus a merge job that
    /// runs when every task has succeeded (scripts and logs in OUT/slurm/).
    #[arg(long, requires = "shards", conflicts_with = "shard")]
    slurm: bool,
    /// With --slurm: one more #SBATCH option for both jobs (repeatable), e.g.
    /// --sbatch-arg=--partition=debug.
    #[arg(
        long = "sbatch-arg",
        value_name = "ARG",
        allow_hyphen_values = true,
        requires = "slurm"
    )]
    sbatch_args: Vec<String>,
    /// With --slurm: print the job scripts and sbatch commands; write and submit nothing.
    #[arg(long, requires = "slurm")]
    dry_run: bool,
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

/// Runs `safereach sweep`: exit 0 when the results are written (or the jobs submitted).
pub fn run(args: SweepArgs, out: &mut Output) -> Result<Exit> {
    let grid = Grid::load(&args.grid)?;
    let runs = args.runs.unwrap_or(grid.runs);
    let seed = args.seed.unwrap_or(grid.seed);
    if args.slurm {
        return super::sweep_slurm::submit(&args_for_slurm(&args, runs, seed), &grid, out);
    }
    let shard = match args.shard.as_deref() {
        Some("auto") => {
            let (shard, source) = Shard::from_scheduler(|k| std::env::var(k).ok(), args.shards)
                .map_err(anyhow::Error::msg)?;
            writeln!(
                out,
                "{}: shard {} ({})",
                grid.name,
                shard.label(),
                said(&source)
            )?;
            shard
        }
        Some(s) => {
            let shard = Shard::parse(s).map_err(anyhow::Error::msg)?;
            if let Some(n) = args.shards.filter(|&n| n != shard.count) {
                anyhow::bail!(
                    "--shard {s} is one of {} shards, not of --shards {n}",
                    shard.count
                );
            }
            shard
        }
        None if args.shards.is_some() => {
            anyhow::bail!("--shards N needs --shard auto or --slurm")
        }
        None => Shard::ALL,
    };
    let start = Instant::now();
    let budget = SweepBudget {
        cells: Budget::new(Work::Cells, args.max_cells),
        periods: Budget::new(Work::SimulatedPeriods, args.max_periods),
    };
    let result = run_grid(&grid, shard, runs, seed, &budget)?;
    let elapsed = start.elapsed();
    let (jsonl, csv) = write_sweep(&result, &args.out)?;
    writeln!(
        out,
        "{}: {} of {} cells in {:.2} s ({:.0} cells/s): {}; wrote {} and {}",
        grid.name,
        result.cells.len(),
        grid.len(),
        elapsed.as_secs_f64(),
        result.cells.len() as f64 / elapsed.as_secs_f64().max(1e-9),
        counts(&result.cells),
        jsonl.display(),
        csv.display()
    )?;
    Ok(Exit::Pass)
}

/// The flags a Slurm shard task repeats, with the run's effective runs and seed.
fn args_for_slurm(args: &SweepArgs, runs: usize, seed: u64) -> super::sweep_slurm::SlurmArgs {
    let mut flags = vec![
        "--runs".to_string(),
        runs.to_string(),
        "--seed".to_string(),
        seed.to_string(),
    ];
    if let Some(n) = args.max_cells {
        flags.extend(["--max-cells".to_string(), n.to_string()]);
    }
    if let Some(n) = args.max_periods {
        flags.extend(["--max-periods".to_string(), n.to_string()]);
    }
    super::sweep_slurm::SlurmArgs {
        grid: args.grid.clone(),
        out: args.out.clone(),
        shards: args.shards.unwrap_or(1),
        sweep_flags: flags,
        sbatch_args: args.sbatch_args.clone(),
        dry_run: args.dry_run,
    }
}

/// `Slurm array job 41, task 5` / `Kubernetes Indexed Job, completion index 2`.
fn said(source: &ShardSource) -> String {
    match source {
        ShardSource::Slurm { job, task } if job.is_empty() => format!("Slurm array task {task}"),
        ShardSource::Slurm { job, task } => format!("Slurm array job {job}, task {task}"),
        ShardSource::Kubernetes { index } => {
            format!("Kubernetes Indexed Job, completion index {index}")
        }
    }
}

/// Writes a sweep output (JSON Lines and CSV) into `dir`; returns both paths.
pub fn write_sweep(result: &SweepFile, dir: &Path) -> Result<(PathBuf, PathBuf)> {
    create_dir(dir)?;
    let stem = file_stem(&result.provenance.grid, result.provenance.shard_or_all());
    let jsonl = dir.join(format!("{stem}.jsonl"));
    let csv = dir.join(format!("{stem}.csv"));
    write_file(&jsonl, result.to_jsonl().as_bytes())?;
    write_file(&csv, result.to_csv().as_bytes())?;
    Ok((jsonl, csv))
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
) -> Result<SweepFile> {
    let owned = shard.share(grid.len());
    let bar = progress(owned);
    let results = grid
        .sweep(shard, runs, seed, budget, || bar.inc(1))
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
