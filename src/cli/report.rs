//! `safereach report`: regenerates the Markdown + SVG reports of grids, sweeping them or
//! merging the results (and shards) that `sweep` wrote. `reports/` in the repository is what
//! this writes, byte for byte.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

use safereach::analysis::report;
use safereach::analysis::sweep::{self, CellResult, Grid, Shard, SweepBudget};
use safereach::core::text_file;

use super::exit::Exit;
use super::output::{Output, create_dir, write_file};
use super::sweep::{counts, keys, run_grid};

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

/// Runs `safereach report`: exit 0 when every grid's report is written.
pub fn run(args: ReportArgs, out: &mut Output) -> Result<Exit> {
    let grids = if args.grids.is_empty() {
        shipped_grids()?
    } else {
        args.grids.clone()
    };
    if grids.is_empty() {
        bail!("no grid files found");
    }
    create_dir(&args.out)?;
    for path in grids {
        let grid = Grid::load(&path)?;
        let results = if args.from.is_empty() {
            run_grid(
                &grid,
                Shard::ALL,
                grid.runs,
                grid.seed,
                &SweepBudget::default(),
            )?
        } else {
            merged(&grid, &args.from)?
        };
        let md = write_report(&grid, &results, &args.out)?;
        writeln!(
            out,
            "{}: {} cells ({}); wrote {}",
            grid.name,
            results.len(),
            counts(&results),
            md.display()
        )?;
    }
    Ok(Exit::Pass)
}

/// Every `problems/*grid*.toml`, sorted.
fn shipped_grids() -> Result<Vec<PathBuf>> {
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
    Ok(found)
}

/// Writes the grid's report (Markdown, figures, JSON Lines, CSV) into `dir`; returns the
/// Markdown file's path.
fn write_report(grid: &Grid, results: &[CellResult], dir: &Path) -> Result<PathBuf> {
    let curve = report::radius_curve(grid).map_err(anyhow::Error::msg)?;
    let map = report::certified_map(grid).map_err(anyhow::Error::msg)?;
    let rep = report::grid_report(grid, results, &curve, map.as_ref());
    let md = dir.join(format!("{}.md", grid.name));
    write_file(&md, rep.markdown.as_bytes())?;
    for (name, svg) in &rep.figures {
        write_file(&dir.join(name), svg.as_bytes())?;
    }
    write_file(
        &dir.join(format!("{}.jsonl", grid.name)),
        sweep::to_jsonl(results).as_bytes(),
    )?;
    write_file(
        &dir.join(format!("{}.csv", grid.name)),
        sweep::to_csv(results, &keys(grid)).as_bytes(),
    )?;
    Ok(md)
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
            let text = text_file::read_text(&f, text_file::MAX_CERTIFICATE_BYTES)
                .with_context(|| format!("reading {}", f.display()))?;
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
