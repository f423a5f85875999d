//! Shards of a sweep: which cells one of several machines analyses, given as `i/n` or read
//! from the batch scheduler that started the process.
//!
//! Shard `i/n` takes cells `i, i+n, i+2n, …`, so the shards of a huge sweep get similar mixes
//! of cheap and expensive cells. Nothing here distributes work: a scheduler (a Slurm array job,
//! a Kubernetes Indexed Job) starts one process per shard, and each reads its own index from
//! the environment the scheduler gives it ([`Shard::from_scheduler`]).

use serde::{Deserialize, Serialize};

/// A shard of a sweep: cells `index, index + count, …`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct Shard {
    /// This shard's number, from 0.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

/// Where a shard read from the environment came from (said in the run's summary).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ShardSource {
    /// A Slurm array task: its job id and task id.
    Slurm {
        /// `SLURM_ARRAY_JOB_ID` (empty when unset).
        job: String,
        /// `SLURM_ARRAY_TASK_ID`.
        task: i64,
    },
    /// A Kubernetes Indexed Job's pod: `JOB_COMPLETION_INDEX`.
    Kubernetes {
        /// The completion index.
        index: usize,
    },
}

impl Shard {
    /// The whole sweep.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parses `i/n` (0 ≤ i < n).
    pub fn parse(s: &str) -> Result<Shard, String> {
        let (i, n) = s
            .split_once('/')
            .ok_or_else(|| format!("shard {s:?}: expected i/n (e.g. 0/4) or auto"))?;
        let index: usize = i
            .trim()
            .parse()
            .map_err(|_| format!("shard {s:?}: {i:?} is not a number"))?;
        let count: usize = n
            .trim()
            .parse()
            .map_err(|_| format!("shard {s:?}: {n:?} is not a number"))?;
        if count == 0 || index >= count {
            return Err(format!("shard {s:?}: need 0 <= i < n"));
        }
        Ok(Shard { index, count })
    }

    /// Whether this shard owns a cell.
    pub fn owns(&self, cell: usize) -> bool {
        cell % self.count == self.index
    }

    /// How many of `len` cells this shard owns.
    pub fn share(&self, len: usize) -> usize {
        len.saturating_sub(self.index).div_ceil(self.count)
    }

    /// `i/n`.
    pub fn label(&self) -> String {
        format!("{}/{}", self.index, self.count)
    }

    /// The shard of this process as its batch scheduler started it: a Slurm array task
    /// (`SLURM_ARRAY_TASK_ID`, `_COUNT`, `_MIN`, `_STEP`, `_MAX`), else a Kubernetes Indexed
    /// Job's pod (`JOB_COMPLETION_INDEX`, with the count from `shards`). `var` reads one
    /// environment variable (`std::env::var(..).ok()` in the command; a map in tests).
    ///
    /// Array task ids map to shards in order: task `MIN + k·STEP` is shard `k` of `COUNT`. A
    /// stepped array (`--array=1-9:4`) therefore maps; a sparse one (`--array=0,3,7`) has no
    /// step that reaches every task and is refused, as is an array whose `COUNT` differs from
    /// `shards` when both are given.
    pub fn from_scheduler(
        var: impl Fn(&str) -> Option<String>,
        shards: Option<usize>,
    ) -> Result<(Shard, ShardSource), String> {
        if let Some(task) = var("SLURM_ARRAY_TASK_ID") {
            return slurm_shard(&var, &task, shards);
        }
        if let Some(index) = var("JOB_COMPLETION_INDEX") {
            let index: usize = index.trim().parse().map_err(|_| {
                format!("--shard auto: JOB_COMPLETION_INDEX={index:?} is not a whole number")
            })?;
            let count = shards.ok_or(
                "--shard auto under a Kubernetes Indexed Job needs --shards N (the Job's \
                 completions)",
            )?;
            if count == 0 || index >= count {
                return Err(format!(
                    "--shard auto: JOB_COMPLETION_INDEX={index} is not below --shards {count}"
                ));
            }
            return Ok((Shard { index, count }, ShardSource::Kubernetes { index }));
        }
        Err(
            "--shard auto: neither SLURM_ARRAY_TASK_ID (a Slurm array job) nor \
             JOB_COMPLETION_INDEX (a Kubernetes Indexed Job) is set; give the shard as \
             --shard i/n"
                .into(),
        )
    }
}

/// The shard of a Slurm array task (see [`Shard::from_scheduler`]).
fn slurm_shard(
    var: &impl Fn(&str) -> Option<String>,
    task: &str,
    shards: Option<usize>,
) -> Result<(Shard, ShardSource), String> {
    let number = |name: &str| -> Result<i64, String> {
        let text = var(name).ok_or_else(|| {
            format!("--shard auto: SLURM_ARRAY_TASK_ID is set but {name} is not (Slurm sets both)")
        })?;
        text.trim()
            .parse()
            .map_err(|_| format!("--shard auto: {name}={text:?} is not a whole number"))
    };
    let id = task
        .trim()
        .parse::<i64>()
        .map_err(|_| format!("--shard auto: SLURM_ARRAY_TASK_ID={task:?} is not a whole number"))?;
    let count = number("SLURM_ARRAY_TASK_COUNT")?;
    let min = number("SLURM_ARRAY_TASK_MIN")?;
    let max = number("SLURM_ARRAY_TASK_MAX")?;
    let step = match var("SLURM_ARRAY_TASK_STEP") {
        Some(_) => number("SLURM_ARRAY_TASK_STEP")?,
        None => 1,
    };
    let array =
        format!("the array's tasks run from {min} to {max} in steps of {step}, {count} of them");
    if count < 1 || step < 1 || min > max || id < min || id > max {
        return Err(format!(
            "--shard auto: task {id} does not fit its array ({array})"
        ));
    }
    if (max - min) / step + 1 != count || (max - min) % step != 0 {
        return Err(format!(
            "--shard auto: a sparse array ({array}) cannot be mapped to shards 0..{count}; \
             submit it as --array=0-{}",
            count - 1
        ));
    }
    if (id - min) % step != 0 {
        return Err(format!(
            "--shard auto: task {id} is not on the array's step ({array})"
        ));
    }
    let count = usize::try_from(count).map_err(|_| format!("--shard auto: {array}"))?;
    if let Some(n) = shards
        && n != count
    {
        return Err(format!(
            "--shard auto: --shards {n} but the Slurm array has {count} tasks ({array})"
        ));
    }
    let index = usize::try_from((id - min) / step).map_err(|_| format!("--shard auto: {array}"))?;
    let job = var("SLURM_ARRAY_JOB_ID").unwrap_or_default();
    Ok((Shard { index, count }, ShardSource::Slurm { job, task: id }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn env(pairs: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> + use<> {
        let map: HashMap<String, String> = pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        move |k| map.get(k).cloned()
    }

    fn slurm(
        id: i64,
        count: i64,
        min: i64,
        max: i64,
        step: i64,
    ) -> impl Fn(&str) -> Option<String> {
        let (id, count, min, max, step) = (
            id.to_string(),
            count.to_string(),
            min.to_string(),
            max.to_string(),
            step.to_string(),
        );
        env(&[
            ("SLURM_ARRAY_JOB_ID", "41"),
            ("SLURM_ARRAY_TASK_ID", &id),
            ("SLURM_ARRAY_TASK_COUNT", &count),
            ("SLURM_ARRAY_TASK_MIN", &min),
            ("SLURM_ARRAY_TASK_MAX", &max),
            ("SLURM_ARRAY_TASK_STEP", &step),
        ])
    }

    #[test]
    fn every_task_of_a_stepped_array_is_a_different_shard() {
        // --array=1-9:4 → tasks 1, 5, 9 (what Slurm 22.05 sets, recorded on this machine).
        let shards: Vec<Shard> = [1, 5, 9]
            .iter()
            .map(|&id| {
                Shard::from_scheduler(slurm(id, 3, 1, 9, 4), None)
                    .unwrap()
                    .0
            })
            .collect();
        assert_eq!(
            shards,
            (0..3)
                .map(|index| Shard { index, count: 3 })
                .collect::<Vec<_>>()
        );
        let (_, source) = Shard::from_scheduler(slurm(5, 3, 1, 9, 4), Some(3)).unwrap();
        assert_eq!(
            source,
            ShardSource::Slurm {
                job: "41".into(),
                task: 5
            }
        );
    }

    #[test]
    fn a_sparse_array_is_refused_with_the_array_named() {
        // --array=0,3,7: Slurm reports COUNT=3, MIN=0, MAX=7, STEP=1.
        let e = Shard::from_scheduler(slurm(3, 3, 0, 7, 1), None).unwrap_err();
        assert!(
            e.contains("sparse array") && e.contains("--array=0-2"),
            "{e}"
        );
    }

    #[test]
    fn a_count_that_disagrees_with_shards_is_refused() {
        let e = Shard::from_scheduler(slurm(2, 4, 0, 3, 1), Some(8)).unwrap_err();
        assert!(e.contains("--shards 8") && e.contains("4 tasks"), "{e}");
    }

    #[test]
    fn kubernetes_needs_the_count_and_an_index_below_it() {
        let k = env(&[("JOB_COMPLETION_INDEX", "2")]);
        assert_eq!(
            Shard::from_scheduler(&k, Some(5)).unwrap().0,
            Shard { index: 2, count: 5 }
        );
        assert!(
            Shard::from_scheduler(&k, None)
                .unwrap_err()
                .contains("--shards N")
        );
        assert!(
            Shard::from_scheduler(&k, Some(2))
                .unwrap_err()
                .contains("not below")
        );
    }

    #[test]
    fn no_scheduler_is_a_clear_error() {
        let e = Shard::from_scheduler(env(&[]), Some(4)).unwrap_err();
        assert!(e.contains("SLURM_ARRAY_TASK_ID") && e.contains("JOB_COMPLETION_INDEX"));
    }

    #[test]
    fn shares_partition_the_cells() {
        for len in 0..20 {
            for count in 1..6 {
                let shares: usize = (0..count)
                    .map(|index| Shard { index, count }.share(len))
                    .sum();
                assert_eq!(shares, len);
                for index in 0..count {
                    let s = Shard { index, count };
                    assert_eq!((0..len).filter(|&c| s.owns(c)).count(), s.share(len));
                }
            }
        }
    }
}
