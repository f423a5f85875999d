//! A sweep as a Slurm array job: one task per shard (each runs `safereach sweep --shard
//! auto`, which reads its shard from the array variables) and a merge job that runs only
//! after every task has succeeded (`--dependency=afterok`, `--kill-on-invalid-dep=yes`: a
//! failed shard cancels the merge, and `squeue`/`scontrol` say why) and writes the whole
//! sweep's output, byte for byte what an unsharded sweep writes.
//!
//! The scripts name the `safereach` executable, the grid and the output directory by absolute
//! path: on a cluster they must be where the compute nodes see them (a shared filesystem).
//! They are written under `<out>/slurm/` with the tasks' logs, so a run can be re-submitted
//! or read later; `--dry-run` prints them instead.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::analysis::sweep_file::file_stem;
use crate::core::shard::Shard;

/// A sweep to run as a Slurm array job.
#[derive(Clone, Debug, PartialEq)]
pub struct SlurmSweep {
    /// The `safereach` executable (absolute).
    pub executable: PathBuf,
    /// The grid file (absolute).
    pub grid: PathBuf,
    /// The grid's name (its file stem; names the jobs and files).
    pub grid_name: String,
    /// The output directory (absolute).
    pub out: PathBuf,
    /// Number of shards (array tasks).
    pub shards: usize,
    /// Flags every shard's `sweep` gets besides the shard (`--runs`, `--seed`, budgets).
    pub sweep_flags: Vec<String>,
    /// Extra `#SBATCH` options for both jobs (`--partition=debug`, `--time=10`, …).
    pub sbatch_args: Vec<String>,
}

/// The jobs a submission created.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Submitted {
    /// The array job's id (every shard).
    pub array_job: String,
    /// The merge job's id.
    pub merge_job: String,
}

/// Why a Slurm sweep cannot be written or submitted.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SlurmError {
    /// A setting cannot go into a job script.
    #[error("{0}")]
    Invalid(String),
    /// `sbatch` could not be run, or refused a job.
    #[error("{0}")]
    Sbatch(String),
    /// A script could not be written.
    #[error("{path}: cannot write the job script")]
    Write {
        /// The script.
        path: String,
        /// Why.
        source: std::io::Error,
    },
}

/// `text` as one word for a POSIX shell: as it is when it holds only characters no shell
/// treats specially, else in single quotes (each `'` as `'\''`).
pub fn shell_quoted(text: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c);
    if !text.is_empty() && text.chars().all(plain) {
        text.to_string()
    } else {
        format!("'{}'", text.replace('\'', r"'\''"))
    }
}

impl SlurmSweep {
    /// Checks what the scripts cannot hold: no shards, or paths and options that Slurm's
    /// `#SBATCH` lines cannot carry (white space, quotes, line breaks).
    pub fn validate(&self) -> Result<(), SlurmError> {
        if self.shards == 0 {
            return Err(SlurmError::Invalid(
                "--shards: need at least 1 shard".into(),
            ));
        }
        let logs = self.logs_dir();
        let shown = logs.display().to_string();
        if shown.contains(|c: char| c.is_whitespace() || c == '"' || c == '\'' || c == '%') {
            return Err(SlurmError::Invalid(format!(
                "--out {}: the job logs' directory ({shown}) goes into #SBATCH --output, which \
                 cannot hold white space, quotes or %; choose a directory without them",
                self.out.display()
            )));
        }
        for arg in &self.sbatch_args {
            if !arg.starts_with('-') || arg.contains(['\n', '\r']) {
                return Err(SlurmError::Invalid(format!(
                    "--sbatch-arg {arg:?}: expected one sbatch option such as \
                     --partition=debug (starting with -, on one line)"
                )));
            }
        }
        Ok(())
    }

    /// Where the scripts and the jobs' logs go: `<out>/slurm`.
    pub fn logs_dir(&self) -> PathBuf {
        self.out.join("slurm")
    }

    /// The array job's script path.
    pub fn array_script_path(&self) -> PathBuf {
        self.logs_dir().join(format!("{}.array.sh", self.grid_name))
    }

    /// The merge job's script path.
    pub fn merge_script_path(&self) -> PathBuf {
        self.logs_dir().join(format!("{}.merge.sh", self.grid_name))
    }

    fn header(&self, job_name: &str, output: &str) -> String {
        let mut s = String::from("#!/bin/bash\n");
        s.push_str(&format!("#SBATCH --job-name={job_name}\n"));
        s.push_str(&format!(
            "#SBATCH --output={}/{output}\n",
            self.logs_dir().display()
        ));
        s.push_str("#SBATCH --ntasks=1\n");
        for arg in &self.sbatch_args {
            s.push_str(&format!("#SBATCH {arg}\n"));
        }
        s
    }

    /// The array job: task `i` of `0..shards` runs shard `i/shards`.
    pub fn array_script(&self) -> String {
        let mut s = self.header(&format!("safereach-{}", self.grid_name), "%x-%A_%a.out");
        s.push_str(&format!("#SBATCH --array=0-{}\n", self.shards - 1));
        s.push_str(&format!(
            "# Written by `safereach sweep --slurm`: one task per shard of grid {} ({} shards).\n\
             # Each task reads its shard from SLURM_ARRAY_TASK_ID (`--shard auto`) and writes\n\
             # {}/{}.shard-<i>-of-{}.jsonl and .csv.\n",
            self.grid_name,
            self.shards,
            self.out.display(),
            self.grid_name,
            self.shards
        ));
        s.push_str("set -euo pipefail\n");
        // Slurm gives a task one CPU unless asked for more; the sweep's threads follow.
        s.push_str("export RAYON_NUM_THREADS=\"${SLURM_CPUS_PER_TASK:-1}\"\n");
        let mut cmd = vec![
            shell_quoted(&self.executable.display().to_string()),
            "sweep".into(),
            shell_quoted(&self.grid.display().to_string()),
            "--out".into(),
            shell_quoted(&self.out.display().to_string()),
            "--shard".into(),
            "auto".into(),
            "--shards".into(),
            self.shards.to_string(),
        ];
        cmd.extend(self.sweep_flags.iter().map(|f| shell_quoted(f)));
        s.push_str(&format!("exec {}\n", cmd.join(" ")));
        s
    }

    /// The merge job: the shards' outputs into the whole sweep's (refusing a missing,
    /// duplicated or stale shard).
    pub fn merge_script(&self) -> String {
        let mut s = self.header(&format!("safereach-{}-merge", self.grid_name), "%x-%j.out");
        s.push_str(&format!(
            "# Written by `safereach sweep --slurm`: runs after every task of the array job has\n\
             # succeeded (submitted with --dependency=afterok:<array job> --kill-on-invalid-dep=yes)\n\
             # and writes {}/{}.jsonl and .csv.\n",
            self.out.display(),
            file_stem(&self.grid_name, Shard::ALL)
        ));
        s.push_str("set -euo pipefail\n");
        let cmd = [
            shell_quoted(&self.executable.display().to_string()),
            "merge".into(),
            shell_quoted(&self.grid.display().to_string()),
            "--from".into(),
            shell_quoted(&self.out.display().to_string()),
            "--out".into(),
            shell_quoted(&self.out.display().to_string()),
        ];
        s.push_str(&format!("exec {}\n", cmd.join(" ")));
        s
    }

    /// The `sbatch` command lines that submit the two scripts (`<array job>` stands for the
    /// first one's id), as `--dry-run` shows them.
    pub fn submit_commands(&self) -> [String; 2] {
        [
            format!(
                "sbatch --parsable {}",
                shell_quoted(&self.array_script_path().display().to_string())
            ),
            format!(
                "sbatch --parsable --dependency=afterok:<array job> --kill-on-invalid-dep=yes {}",
                shell_quoted(&self.merge_script_path().display().to_string())
            ),
        ]
    }

    /// Writes both scripts under [`SlurmSweep::logs_dir`] (creating it: Slurm does not create
    /// the directory of `--output`).
    pub fn write_scripts(&self) -> Result<(), SlurmError> {
        self.validate()?;
        let write = |path: &Path, text: &str| -> Result<(), SlurmError> {
            let err = |source| SlurmError::Write {
                path: path.display().to_string(),
                source,
            };
            std::fs::create_dir_all(self.logs_dir()).map_err(err)?;
            crate::core::output::write_atomic(path, text.as_bytes()).map_err(err)
        };
        write(&self.array_script_path(), &self.array_script())?;
        write(&self.merge_script_path(), &self.merge_script())
    }

    /// Writes the scripts and submits them with `sbatch` (the first `sbatch` on `PATH`): the
    /// array job, then the merge job depending on it. When the merge job cannot be
    /// submitted, the array job is cancelled (`scancel`) so nothing runs unmerged.
    pub fn submit(&self) -> Result<Submitted, SlurmError> {
        self.write_scripts()?;
        let array_job = sbatch(&[], &self.array_script_path())?;
        let dependency = format!("--dependency=afterok:{array_job}");
        match sbatch(
            &[&dependency, "--kill-on-invalid-dep=yes"],
            &self.merge_script_path(),
        ) {
            Ok(merge_job) => Ok(Submitted {
                array_job,
                merge_job,
            }),
            Err(e) => {
                let cancelled = Command::new("scancel")
                    .arg(&array_job)
                    .status()
                    .is_ok_and(|s| s.success());
                Err(SlurmError::Sbatch(format!(
                    "{e}; the array job {array_job} {}",
                    if cancelled {
                        "was cancelled"
                    } else {
                        "could not be cancelled: cancel it with scancel"
                    }
                )))
            }
        }
    }
}

/// Runs `sbatch --parsable [flags] script`; returns the job id.
fn sbatch(flags: &[&str], script: &Path) -> Result<String, SlurmError> {
    let output = Command::new("sbatch")
        .arg("--parsable")
        .args(flags)
        .arg(script)
        .output()
        .map_err(|e| {
            SlurmError::Sbatch(format!(
                "cannot run sbatch ({e}): is Slurm's client installed and on PATH?"
            ))
        })?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    if !output.status.success() {
        return Err(SlurmError::Sbatch(format!(
            "sbatch refused {}: {}",
            script.display(),
            String::from_utf8_lossy(&output.stderr).trim()
        )));
    }
    // `--parsable` prints `<id>` or `<id>;<cluster>`.
    let id = stdout.trim().split(';').next().unwrap_or("").to_string();
    if id.is_empty() || !id.chars().all(|c| c.is_ascii_digit()) {
        return Err(SlurmError::Sbatch(format!(
            "sbatch accepted {} but printed no job id: {:?}",
            script.display(),
            stdout.trim()
        )));
    }
    Ok(id)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn job() -> SlurmSweep {
        SlurmSweep {
            executable: "/opt/safe reach/bin/safereach".into(),
            grid: "/data/it's/seed-grid.toml".into(),
            grid_name: "seed-grid".into(),
            out: "/scratch/res".into(),
            shards: 4,
            sweep_flags: vec!["--runs".into(), "100".into()],
            sbatch_args: vec!["--partition=debug".into()],
        }
    }

    #[test]
    fn the_array_runs_every_shard_with_paths_quoted() {
        let s = job().array_script();
        assert!(s.contains("#SBATCH --array=0-3\n"));
        assert!(s.contains("#SBATCH --partition=debug\n"));
        assert!(s.contains("#SBATCH --output=/scratch/res/slurm/%x-%A_%a.out\n"));
        assert!(s.contains(
            "exec '/opt/safe reach/bin/safereach' sweep '/data/it'\\''s/seed-grid.toml' --out \
             /scratch/res --shard auto --shards 4 --runs 100\n"
        ));
    }

    #[test]
    fn the_merge_reads_and_writes_the_output_directory() {
        let s = job().merge_script();
        assert!(s.contains(
            "merge '/data/it'\\''s/seed-grid.toml' --from /scratch/res --out /scratch/res"
        ));
        assert!(!s.contains("--array"));
    }

    #[test]
    fn what_an_sbatch_line_cannot_hold_is_refused() {
        let mut j = job();
        j.out = "/scratch/my results".into();
        assert!(
            j.validate()
                .unwrap_err()
                .to_string()
                .contains("white space")
        );
        let mut j = job();
        j.sbatch_args = vec!["partition=debug".into()];
        assert!(
            j.validate()
                .unwrap_err()
                .to_string()
                .contains("--sbatch-arg")
        );
        let mut j = job();
        j.shards = 0;
        assert!(j.validate().is_err());
    }
}
