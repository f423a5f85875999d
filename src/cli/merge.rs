//! `safereach merge GRID --from DIR|FILE... --out DIR`: the shards of a sweep (from
//! directories or named files) into the whole sweep's output, byte for byte what the
//! unsharded sweep writes — refusing shards of another grid, base problem or version, and
//! missing or duplicated cells (exit 2, naming the file and what differs). `report --from`
//! reads its results the same way.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};

use safereach::analysis::sweep::Grid;
use safereach::analysis::sweep_file::{self, SweepFile, results_in};
use safereach::core::text_file;

use super::exit::Exit;
use super::output::Output;
use super::sweep::{counts, write_sweep};

/// Arguments of `safereach merge`.
#[derive(clap::Args)]
pub struct MergeArgs {
    /// Grid file (TOML) the shards ran.
    grid: PathBuf,
    /// Directories holding the grid's shard outputs (`<grid>.shard-i-of-n.jsonl`), or such
    /// files themselves; repeatable, or several after one --from.
    #[arg(long = "from", value_name = "DIR|FILE", num_args = 1.., required = true)]
    from: Vec<PathBuf>,
    /// Output directory for `<grid>.jsonl` and `<grid>.csv`.
    #[arg(long)]
    out: PathBuf,
}

/// Runs `safereach merge`: exit 0 when the whole sweep is written.
pub fn run(args: MergeArgs, out: &mut Output) -> Result<Exit> {
    let grid = Grid::load(&args.grid)?;
    let merged = merged_results(&grid, &args.from)?;
    let (jsonl, csv) = write_sweep(&merged, &args.out)?;
    writeln!(
        out,
        "{}: merged {} cells ({}); wrote {} and {}",
        grid.name,
        merged.cells.len(),
        counts(&merged.cells),
        jsonl.display(),
        csv.display()
    )?;
    Ok(Exit::Pass)
}

/// The grid's whole sweep from the outputs in `from` (directories: their whole-sweep output
/// if present, else their shards; files: read as named), checked against the grid as it is
/// now.
pub fn merged_results(grid: &Grid, from: &[PathBuf]) -> Result<SweepFile> {
    let mut files = Vec::new();
    for place in from {
        if place.is_dir() {
            let found = results_in(place, &grid.name).with_context(|| {
                format!("--from {}: cannot read the directory", place.display())
            })?;
            if found.is_empty() {
                bail!(
                    "--from {}: no results of grid {} ({}.jsonl or {}.shard-*.jsonl)",
                    place.display(),
                    grid.name,
                    grid.name,
                    grid.name
                );
            }
            files.extend(found);
        } else if place.exists() {
            files.push(place.clone());
        } else {
            bail!("--from {}: no such file or directory", place.display());
        }
    }
    // The same file reached twice (a directory and a file in it) is read once.
    let mut seen = std::collections::HashSet::new();
    files.retain(|f| seen.insert(f.canonicalize().unwrap_or_else(|_| f.clone())));
    let mut parts = Vec::new();
    for f in files {
        let shown = f.display().to_string();
        let text = text_file::read_text(&f, text_file::MAX_CERTIFICATE_BYTES)
            .with_context(|| format!("{shown}: cannot read the file"))?;
        parts.push((
            shown.clone(),
            SweepFile::from_jsonl(&text, &shown).map_err(anyhow::Error::msg)?,
        ));
    }
    sweep_file::merge(grid, parts).map_err(anyhow::Error::msg)
}
