//! `safereach sweep GRID --out DIR --slurm --shards N`: writes the array and merge job
//! scripts under DIR/slurm/ and submits them with `sbatch` (or, with `--dry-run`, prints
//! them), then says how to follow the jobs.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};

use safereach::analysis::sweep::Grid;
use safereach::analysis::sweep_file::results_in;
use safereach::cluster::slurm::SlurmSweep;

use super::exit::Exit;
use super::output::{Output, create_dir};

/// What `sweep --slurm` was given.
pub struct SlurmArgs {
    /// The grid file as given.
    pub grid: PathBuf,
    /// The output directory as given.
    pub out: PathBuf,
    /// Number of shards.
    pub shards: usize,
    /// Flags each shard's sweep repeats.
    pub sweep_flags: Vec<String>,
    /// Extra #SBATCH options.
    pub sbatch_args: Vec<String>,
    /// Print, do not submit.
    pub dry_run: bool,
}

/// Writes and submits (or prints) the jobs of a Slurm sweep.
pub fn submit(args: &SlurmArgs, grid: &Grid, out: &mut Output) -> Result<Exit> {
    let executable = std::env::current_exe()
        .and_then(|p| p.canonicalize())
        .context("cannot find the safereach executable's path for the job scripts")?;
    let grid_path = args
        .grid
        .canonicalize()
        .with_context(|| format!("{}: cannot resolve the grid's path", args.grid.display()))?;
    if !args.dry_run {
        create_dir(&args.out)?;
    }
    let out_dir = std::path::absolute(&args.out)
        .and_then(|p| {
            if args.dry_run {
                Ok(p)
            } else {
                p.canonicalize()
            }
        })
        .with_context(|| format!("--out {}: cannot resolve the path", args.out.display()))?;
    if out_dir.is_dir() {
        let earlier = results_in(&out_dir, &grid.name)
            .with_context(|| format!("--out {}: cannot read the directory", args.out.display()))?;
        if let Some(first) = earlier.first() {
            bail!(
                "--out {}: already holds results of grid {} ({}{}); the merge would mix them \
                 with this run's: choose another directory or remove them",
                args.out.display(),
                grid.name,
                first.display(),
                if earlier.len() > 1 { ", …" } else { "" }
            );
        }
    }
    let job = SlurmSweep {
        executable,
        grid: grid_path,
        grid_name: grid.name.clone(),
        out: out_dir,
        shards: args.shards,
        sweep_flags: args.sweep_flags.clone(),
        sbatch_args: args.sbatch_args.clone(),
    };
    job.validate()?;
    if args.dry_run {
        let [array, merge] = job.submit_commands();
        writeln!(
            out,
            "# {} (dry run: nothing written or submitted)\n{}",
            job.array_script_path().display(),
            job.array_script()
        )?;
        writeln!(
            out,
            "# {}\n{}",
            job.merge_script_path().display(),
            job.merge_script()
        )?;
        writeln!(out, "# submitted with:\n{array}\n{merge}")?;
        return Ok(Exit::Pass);
    }
    let ids = job.submit()?;
    writeln!(
        out,
        "{}: submitted array job {} ({} shards of {} cells) and merge job {} (runs when every \
         shard has succeeded; cancelled if one fails)\n  scripts and logs: {}\n  follow: squeue \
         -j {},{}   (then: scontrol show job {})\n  result: {} when job {} has completed; then \
         safereach report {} --from {}",
        grid.name,
        ids.array_job,
        job.shards,
        grid.len(),
        ids.merge_job,
        job.logs_dir().display(),
        ids.array_job,
        ids.merge_job,
        ids.merge_job,
        job.out.join(format!("{}.jsonl", grid.name)).display(),
        ids.merge_job,
        args.grid.display(),
        args.out.display()
    )?;
    Ok(Exit::Pass)
}
