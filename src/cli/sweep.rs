//! `safereach sweep` and `safereach report`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};

use safereach::analysis::Verdict;
use safereach::analysis::report;
use safereach::analysis::sweep::{self, CellResult, Grid, Shard};
use safereach::core::output::write_atomic;

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
}

/// Arguments of `safereach report`.
#[derive(clap::Args)]
pub struct ReportArgs {
    /// Grid files (default: every `problems/*grid*.toml`).
    grids: Vec<PathBuf>,
    /// Merge sweep results (and shards) from these directories instead of sweeping.
    #[arg(long = "from", value_name = "DIR")]
    from: Vec<PathBuf>,
    /// Output directory.
    #[arg(long, default_value = "reports")]
    out: PathBuf,
}

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

fn run_grid(grid: &Grid, shard: Shard, runs: usize, seed: u64) -> Result<Vec<CellResult>> {
    let owned = (0..grid.len()).filter(|&c| shard.owns(c)).count();
    let bar = progress(owned);
    let results = grid
        .run(shard, runs, seed, || bar.inc(1))
        .context("sweep failed")?;
    bar.finish_and_clear();
    Ok(results)
}

fn counts(results: &[CellResult]) -> String {
    let n = |v: Verdict| results.iter().filter(|r| r.verdict == v).count();
    format!(
        "{} certified, {} refuted, {} inconclusive",
        n(Verdict::Certified),
        n(Verdict::Refuted),
        n(Verdict::Inconclusive)
    )
}

fn keys(grid: &Grid) -> Vec<String> {
    grid.axes.iter().map(|(k, _)| k.clone()).collect()
}

fn write(path: &Path, text: &str) -> Result<()> {
    write_atomic(path, text.as_bytes()).with_context(|| format!("writing {}", path.display()))
}

/// Runs `safereach sweep`.
pub fn run(args: SweepArgs) -> Result<ExitCode> {
    let grid = Grid::load(&args.grid)?;
    let shard = match &args.shard {
        Some(s) => Shard::parse(s).map_err(anyhow::Error::msg)?,
        None => Shard::ALL,
    };
    let runs = args.runs.unwrap_or(grid.runs);
    let seed = args.seed.unwrap_or(grid.seed);
    let start = Instant::now();
    let results = run_grid(&grid, shard, runs, seed)?;
    let elapsed = start.elapsed();
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let stem = if shard == Shard::ALL {
        grid.name.clone()
    } else {
        format!("{}.shard-{}-of-{}", grid.name, shard.index, shard.count)
    };
    let jsonl = args.out.join(format!("{stem}.jsonl"));
    let csv = args.out.join(format!("{stem}.csv"));
    write(&jsonl, &sweep::to_jsonl(&results))?;
    write(&csv, &sweep::to_csv(&results, &keys(&grid)))?;
    outln!(
        "{}: {} of {} cells in {:.2} s ({:.0} cells/s): {}; wrote {} and {}",
        grid.name,
        results.len(),
        grid.len(),
        elapsed.as_secs_f64(),
        results.len() as f64 / elapsed.as_secs_f64().max(1e-9),
        counts(&results),
        jsonl.display(),
        csv.display()
    );
    Ok(ExitCode::SUCCESS)
}

/// Results for a grid merged from the `--from` directories (whole sweeps or shards).
fn merged(grid: &Grid, dirs: &[PathBuf]) -> Result<Vec<CellResult>> {
    let keys = keys(grid);
    let mut parts = Vec::new();
    for dir in dirs {
        let entries =
            std::fs::read_dir(dir).with_context(|| format!("reading {}", dir.display()))?;
        let mut files: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                let name = p
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default();
                name == format!("{}.jsonl", grid.name)
                    || (name.starts_with(&format!("{}.shard-", grid.name))
                        && name.ends_with(".jsonl"))
            })
            .collect();
        files.sort();
        for f in files {
            let text =
                std::fs::read_to_string(&f).with_context(|| format!("reading {}", f.display()))?;
            parts.push(
                sweep::from_jsonl(&text, &keys, &f.display().to_string())
                    .map_err(anyhow::Error::msg)?,
            );
        }
    }
    if parts.is_empty() {
        bail!("no results for grid {} in {:?}", grid.name, dirs);
    }
    sweep::merge(grid, parts).map_err(|e| anyhow::anyhow!("grid {}: {e}", grid.name))
}

/// Speeds at which the report draws ρ*(W): 0 to a little past the grid's fastest, by 0.01.
fn curve_speeds(grid: &Grid) -> Vec<f64> {
    let top = grid
        .axes
        .iter()
        .filter(|(k, _)| k == "environment.obstacle_speed")
        .flat_map(|(_, v)| {
            v.iter()
                .filter_map(|x| x.as_float().or_else(|| x.as_integer().map(|i| i as f64)))
        })
        .fold(0.0, f64::max);
    if top <= 0.0 {
        return Vec::new();
    }
    let steps = ((top + 0.05) / 0.01).round() as usize;
    (0..=steps)
        .map(|i| (i as f64 * 0.01 * 100.0).round() / 100.0)
        .collect()
}

/// Runs `safereach report`.
pub fn report_cmd(args: ReportArgs) -> Result<ExitCode> {
    let grids = if args.grids.is_empty() {
        let mut found: Vec<PathBuf> = std::fs::read_dir("problems")
            .context("reading problems/ (run from the repository root, or name the grid files)")?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                let n = p
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default();
                n.contains("grid") && n.ends_with(".toml")
            })
            .collect();
        found.sort();
        found
    } else {
        args.grids.clone()
    };
    if grids.is_empty() {
        bail!("no grid files found");
    }
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    for path in grids {
        let grid = Grid::load(&path)?;
        let results = if args.from.is_empty() {
            run_grid(&grid, Shard::ALL, grid.runs, grid.seed)?
        } else {
            merged(&grid, &args.from)?
        };
        let curve =
            report::radius_curve(&grid, &curve_speeds(&grid)).map_err(anyhow::Error::msg)?;
        let rep = report::grid_report(&grid, &results, &curve);
        let md = args.out.join(format!("{}.md", grid.name));
        write(&md, &rep.markdown)?;
        for (name, svg) in &rep.figures {
            write(&args.out.join(name), svg)?;
        }
        write(
            &args.out.join(format!("{}.jsonl", grid.name)),
            &sweep::to_jsonl(&results),
        )?;
        write(
            &args.out.join(format!("{}.csv", grid.name)),
            &sweep::to_csv(&results, &keys(&grid)),
        )?;
        outln!(
            "{}: {} cells ({}); wrote {}",
            grid.name,
            results.len(),
            counts(&results),
            md.display()
        );
    }
    Ok(ExitCode::SUCCESS)
}
