//! `safereach report`: regenerates the Markdown + SVG reports of grids, sweeping them or
//! merging the results (and shards) that `sweep` wrote. `reports/` in the repository is what
//! this writes, byte for byte.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

use safereach::analysis::report;
use safereach::analysis::sweep::{Grid, Shard, SweepBudget};
use safereach::analysis::sweep_file::SweepFile;

use super::exit::Exit;
use super::merge::merged_results;
use super::output::{Output, create_dir, write_file};
use super::sweep::{counts, run_grid, write_sweep};

/// Arguments of `safereach report`.
#[derive(clap::Args)]
pub struct ReportArgs {
    /// Grid files (default: every `problems/*grid*.toml`).
    grids: Vec<PathBuf>,
    /// Report sweep results (whole, or shards merged) from these directories or files
    /// instead of sweeping; repeatable, or several after one --from. Results of another
    /// grid, base problem or version are refused.
    #[arg(long = "from", value_name = "DIR|FILE", num_args = 1..)]
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
            merged_results(&grid, &args.from)?
        };
        let md = write_report(&grid, &results, &args.out)?;
        writeln!(
            out,
            "{}: {} cells ({}); wrote {}",
            grid.name,
            results.cells.len(),
            counts(&results.cells),
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
fn write_report(grid: &Grid, sweep: &SweepFile, dir: &Path) -> Result<PathBuf> {
    let results = &sweep.cells;
    let curve = report::radius_curve(grid).map_err(anyhow::Error::msg)?;
    let map = report::certified_map(grid).map_err(anyhow::Error::msg)?;
    let views = report::planar_views(grid, results).map_err(anyhow::Error::msg)?;
    let rep = report::grid_report(grid, results, &curve, map.as_ref(), &views);
    let md = dir.join(format!("{}.md", grid.name));
    write_file(&md, rep.markdown.as_bytes())?;
    for (name, svg) in &rep.figures {
        write_file(&dir.join(name), svg.as_bytes())?;
    }
    write_sweep(sweep, dir)?;
    Ok(md)
}
