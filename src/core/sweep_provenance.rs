//! What a sweep's output ran: the tool and its version, the grid's axes and the base problem
//! (with a digest of each), the shard, the Monte Carlo runs and seed. Every sweep output
//! starts with this record, so results are never merged with, or reported for, a grid or a
//! base problem they were not computed from.
//!
//! The digests are SHA-256 of the canonical JSON of the axes (keys and values, in order) and
//! of the base problem as read (every key, defaults filled in; a planar problem's table as
//! its file states it), not of the files' bytes: a
//! comment edited in a grid file leaves its results valid; any changed value does not. The
//! axes and the problem are stored beside their digests so a refusal can say what changed.

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::core::grid::{BaseKind, Grid};
use crate::core::model::{Problem, ProblemError};
use crate::core::planar::PlanarProblem;
use crate::core::scene::Scene;
use crate::core::shard::Shard;

/// The tool that writes sweep outputs.
pub const TOOL: &str = "safereach";

/// This build's version (`Cargo.toml`'s): outputs of another version are not merged.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// Most differences a refusal lists before "and N more".
const MAX_LISTED: usize = 4;

/// The provenance record of a sweep output.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct SweepProvenance {
    /// Always [`TOOL`].
    pub tool: String,
    /// The version that wrote it.
    pub version: String,
    /// The grid's name (its file stem).
    pub grid: String,
    /// SHA-256 (hex) of the canonical JSON of `axes`.
    pub grid_digest: String,
    /// The grid's axes: dotted key → its values, in the grid's order.
    pub axes: serde_json::Map<String, serde_json::Value>,
    /// SHA-256 (hex) of the canonical JSON of `base_problem`.
    pub base_digest: String,
    /// The base problem (or scene) as read, every key present.
    pub base_problem: serde_json::Value,
    /// Number of cells of the whole grid.
    pub cells: usize,
    /// The shard this output holds (null: every cell).
    pub shard: Option<Shard>,
    /// Monte Carlo runs per cell.
    pub runs: usize,
    /// Seed of the first Monte Carlo run.
    pub seed: u64,
}

fn sha256_hex(text: &str) -> String {
    Sha256::digest(text.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

impl SweepProvenance {
    /// The record of a run of `grid`'s `shard` (or every cell, for [`Shard::ALL`]).
    pub fn of(grid: &Grid, shard: Shard, runs: usize, seed: u64) -> Result<Self, ProblemError> {
        let axes: serde_json::Map<String, serde_json::Value> = grid
            .axes
            .iter()
            .map(|(k, values)| {
                let json = serde_json::to_value(values).unwrap_or(serde_json::Value::Null);
                (k.clone(), json)
            })
            .collect();
        let origin = grid.base_path.display().to_string();
        let base_problem = match grid.kind {
            BaseKind::Scene => {
                serde_json::to_value(Scene::from_toml_str(&grid.base_text, &origin)?)
            }
            BaseKind::Problem => {
                serde_json::to_value(Problem::from_toml_str(&grid.base_text, &origin)?)
            }
            // A planar problem as its file states it (validated by the reader first): its
            // table, so comments and layout do not count, every stated value does.
            BaseKind::Planar => {
                PlanarProblem::from_toml_str(&grid.base_text, &origin)?;
                let table: toml::Table =
                    grid.base_text
                        .parse()
                        .map_err(|e: toml::de::Error| ProblemError::Invalid {
                            origin: origin.clone(),
                            key: String::new(),
                            value: String::new(),
                            reason: e.to_string(),
                            location: None,
                        })?;
                serde_json::to_value(table)
            }
        }
        .expect("problems serialise");
        Ok(SweepProvenance {
            tool: TOOL.into(),
            version: VERSION.into(),
            grid: grid.name.clone(),
            grid_digest: sha256_hex(&serde_json::Value::Object(axes.clone()).to_string()),
            axes,
            base_digest: sha256_hex(&base_problem.to_string()),
            base_problem,
            cells: grid.len(),
            shard: (shard != Shard::ALL).then_some(shard),
            runs,
            seed,
        })
    }

    /// The shard this output holds ([`Shard::ALL`] for a whole sweep).
    pub fn shard_or_all(&self) -> Shard {
        self.shard.unwrap_or(Shard::ALL)
    }

    /// How this record differs from `expected` in what decides the results (tool, version,
    /// grid, axes, base problem), in the user's words; empty when it does not. Shard, runs
    /// and seed are the merge's to compare.
    pub fn stale_against(&self, expected: &SweepProvenance) -> Vec<String> {
        let mut out = Vec::new();
        if self.tool != expected.tool || self.version != expected.version {
            out.push(format!(
                "written by {} {}, not {} {} (re-run it with this version)",
                self.tool, self.version, expected.tool, expected.version
            ));
        }
        if self.grid != expected.grid {
            out.push(format!("ran grid {:?}, not {:?}", self.grid, expected.grid));
        }
        if self.grid_digest != expected.grid_digest {
            let mut axes = axis_differences(&self.axes, &expected.axes);
            if axes.is_empty() {
                axes.push(
                    "its grid digest does not match its own axes (was the file edited?)".into(),
                );
            }
            out.extend(axes);
        }
        if self.base_digest != expected.base_digest {
            let mut leaves = Vec::new();
            leaf_differences("", &self.base_problem, &expected.base_problem, &mut leaves);
            if leaves.is_empty() {
                out.push(
                    "its base-problem digest does not match its own base problem (was the file \
                     edited?)"
                        .into(),
                );
            } else {
                let more = leaves.len().saturating_sub(MAX_LISTED);
                leaves.truncate(MAX_LISTED);
                let mut said = format!("the base problem has changed since: {}", leaves.join(", "));
                if more > 0 {
                    said.push_str(&format!(", and {more} more"));
                }
                out.push(said);
            }
        }
        out
    }
}

/// `axis K was [..], is now [..]`, `axis K is new`, `axis K is gone`.
fn axis_differences(
    found: &serde_json::Map<String, serde_json::Value>,
    expected: &serde_json::Map<String, serde_json::Value>,
) -> Vec<String> {
    let mut out = Vec::new();
    for (k, v) in found {
        match expected.get(k) {
            Some(now) if now == v => {}
            Some(now) => out.push(format!("axis {k} was {v}, is now {now}")),
            None => out.push(format!("axis {k} ({v}) is no longer in the grid")),
        }
    }
    for (k, v) in expected {
        if !found.contains_key(k) {
            out.push(format!("axis {k} ({v}) was not in the grid"));
        }
    }
    if out.is_empty() && found.keys().ne(expected.keys()) {
        out.push("the grid's axes are in another order (cells are numbered differently)".into());
    }
    out
}

/// `robot.braking was 0.05, is now 0.02`, for every leaf where two JSON values differ.
fn leaf_differences(
    path: &str,
    found: &serde_json::Value,
    expected: &serde_json::Value,
    out: &mut Vec<String>,
) {
    use serde_json::Value::Object;
    let join = |k: &str| {
        if path.is_empty() {
            k.to_string()
        } else {
            format!("{path}.{k}")
        }
    };
    match (found, expected) {
        (Object(a), Object(b)) => {
            for (k, v) in a {
                match b.get(k) {
                    Some(w) => leaf_differences(&join(k), v, w, out),
                    None => out.push(format!("{} was {v}, is now absent", join(k))),
                }
            }
            for (k, w) in b {
                if !a.contains_key(k) {
                    out.push(format!("{} was absent, is now {w}", join(k)));
                }
            }
        }
        (a, b) if a != b => out.push(format!("{path} was {a}, is now {b}")),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn a_changed_leaf_is_named_with_both_values() {
        let mut out = Vec::new();
        leaf_differences(
            "",
            &json!({"robot": {"braking": 0.05, "max_speed": 0.2}}),
            &json!({"robot": {"braking": 0.02, "max_speed": 0.2}}),
            &mut out,
        );
        assert_eq!(out, ["robot.braking was 0.05, is now 0.02"]);
    }

    #[test]
    fn axes_that_changed_appeared_or_left_are_named() {
        let found = json!({"a": [1, 2], "b": [3]});
        let expected = json!({"a": [1, 3], "c": [4]});
        let (serde_json::Value::Object(f), serde_json::Value::Object(e)) = (found, expected) else {
            unreachable!()
        };
        assert_eq!(
            axis_differences(&f, &e),
            [
                "axis a was [1,2], is now [1,3]",
                "axis b ([3]) is no longer in the grid",
                "axis c ([4]) was not in the grid"
            ]
        );
    }
}
