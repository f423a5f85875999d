//! Parameter sweeps: a grid of problems, analysed in parallel, in a stable order.
//!
//! A grid file names a base problem (a path relative to the grid file) and axes over any
//! dotted keys of it:
//!
//! ```toml
//! base = "seed.toml"
//! runs = 100                      # optional: Monte Carlo runs per cell (the paper's measure)
//! seed = 0                        # optional: seed of the first run
//! [axes]
//! "environment.obstacle_speed" = [0.15, 0.2, 0.25, 0.3]
//! "controller.reaction_radius" = [1.0, 1.2, 1.4, 1.6]
//! ```
//!
//! Cells are the cartesian product, the *last* axis varying fastest, numbered from 0. Each
//! cell is the base problem with the axis values applied as `--set` overrides (the same
//! validation), analysed with [`WitnessPolicy::ToRefute`] (certified cells need no replay;
//! refuted ones always carry an exactly replayed collision). Results come back in cell
//! order whatever the parallel schedule, so output files are reproducible byte for byte.
//! A shard `i/n` takes cells `i, i+n, i+2n, …`, so shards of a huge sweep have similar
//! mixes of cheap and expensive cells; merging shards sorts by cell number.
//!
//! The base may be a scene file: axes then take its keys too (`obstacle.0.max_speed`,
//! `robot.goal`, …), cells are analysed by the scene analyser, and Monte Carlo runs every
//! obstacle with uniform random speeds.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::analysis::scene_answer::SceneAnswer;
use crate::analysis::scene_worst::SceneWorstCase;
use crate::analysis::{self, Options, SpeedPattern, Verdict, WitnessPolicy};
use crate::core::budget::{Budget, Meter, OverBudget, Work, grouped};
pub use crate::core::grid::{CellInput, Grid, GridError};
use crate::core::model::ProblemError;
use crate::core::num::f64_at_most;
use crate::core::scene::Scene;
use crate::core::simulate;

/// The result of one cell.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CellResult {
    /// Cell number.
    pub cell: usize,
    /// The cell's axis values, keyed by dotted key, in axis order.
    pub axes: serde_json::Map<String, serde_json::Value>,
    /// The verdict.
    pub verdict: Verdict,
    /// s* (least piece optimum; null when the robot may never stop, or none was found).
    pub min_separation: Option<f64>,
    /// The robot may miss the obstacle and never brake (s* = −∞).
    pub never_stops: bool,
    /// Rigorous lower bound on s* (null: none proved).
    pub lower_bound: Option<f64>,
    /// Monte Carlo collisions (when runs were asked for).
    pub collisions: Option<usize>,
    /// Monte Carlo runs.
    pub runs: Option<usize>,
    /// Lowest gap seen by Monte Carlo while the robot moved.
    pub simulated_min_separation: Option<f64>,
    /// Pieces in the cell's decomposition.
    pub pieces: usize,
    /// Linear programs solved.
    pub programs: usize,
    /// A scene cell's worst case: which obstacle, its lane, why the robot braked (absent
    /// for single-obstacle cells, and when the scene analyser found none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub worst: Option<SceneWorstCase>,
}

/// The axis values of a cell as JSON, keyed by dotted key.
fn axes_map(values: &[(String, toml::Value)]) -> serde_json::Map<String, serde_json::Value> {
    values
        .iter()
        .map(|(k, v)| {
            (
                k.clone(),
                serde_json::to_value(v).unwrap_or(serde_json::Value::Null),
            )
        })
        .collect()
}

/// One cell of a scene grid.
fn scene_cell(
    cell: usize,
    values: &[(String, toml::Value)],
    scene: &Scene,
    runs: usize,
    seed: u64,
) -> Result<CellResult, SweepError> {
    let a = SceneAnswer::of(scene).map_err(|e| SweepError::Analysis {
        cell,
        reason: e.to_string(),
    })?;
    let mc = (runs > 0).then(|| {
        crate::analysis::scene_monte_carlo(&scene.params(), runs, seed, &[SpeedPattern::Uniform])
    });
    Ok(CellResult {
        cell,
        axes: axes_map(values),
        verdict: a.verdict(),
        min_separation: a.min_separation(),
        never_stops: a.never_stops(),
        lower_bound: a.lower_bound(),
        collisions: mc.as_ref().map(|m| m.collisions),
        runs: mc.as_ref().map(|m| m.runs),
        simulated_min_separation: mc.as_ref().and_then(|m| m.min_separation),
        pieces: a.cases(),
        programs: a.programs(),
        worst: a.worst_case(),
    })
}

/// A shard of a sweep: cells `index, index + count, …`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// This shard's number, from 0.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl Shard {
    /// The whole sweep.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parses `i/n` (0 ≤ i < n).
    pub fn parse(s: &str) -> Result<Shard, String> {
        let (i, n) = s
            .split_once('/')
            .ok_or_else(|| format!("shard {s:?}: expected i/n, e.g. 0/4"))?;
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
}

/// The budgets of a sweep: how many cells (of its shard), and how many control periods its
/// Monte Carlo runs may simulate in all (runs × each cell's horizon).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SweepBudget {
    /// Cells of the shard.
    pub cells: Budget,
    /// Simulated control periods, all cells together.
    pub periods: Budget,
}

impl Default for SweepBudget {
    fn default() -> Self {
        SweepBudget {
            cells: Budget::default_for(Work::Cells),
            periods: Budget::default_for(Work::SimulatedPeriods),
        }
    }
}

impl Grid {
    /// Analyses one cell (and simulates it, with `runs` > 0, charging its runs to `meter`
    /// first).
    pub fn run_cell(
        &self,
        cell: usize,
        runs: usize,
        seed: u64,
        meter: &Meter,
    ) -> Result<CellResult, SweepError> {
        let values = self.cell_values(cell);
        let input = self.input_with(&values)?;
        if runs > 0 {
            let horizon = match &input {
                CellInput::Problem(p) => simulate::horizon(&p.params::<f64>()),
                CellInput::Scene(s) => crate::core::scene::simulate::horizon(&s.params::<f64>()),
            };
            let work = (runs as u64).saturating_mul(horizon as u64);
            meter.charge(
                || format!("the Monte Carlo runs up to cell {cell} ({runs} runs per cell)"),
                work,
            )?;
        }
        let problem = match input {
            CellInput::Problem(p) => p,
            CellInput::Scene(s) => return scene_cell(cell, &values, &s, runs, seed),
        };
        let a = analysis::analyse_with(
            &problem,
            Options {
                witness: WitnessPolicy::ToRefute,
            },
        )
        .map_err(|e| SweepError::Analysis {
            cell,
            reason: e.to_string(),
        })?;
        let axes = axes_map(&values);
        let mc =
            (runs > 0).then(|| crate::analysis::monte_carlo(&problem.params::<f64>(), runs, seed));
        Ok(CellResult {
            cell,
            axes,
            verdict: a.verdict,
            min_separation: a.min_separation,
            never_stops: a.never_stops,
            lower_bound: a.lower_bound.as_ref().map(f64_at_most),
            collisions: mc.as_ref().map(|m| m.collisions),
            runs: mc.as_ref().map(|m| m.runs),
            simulated_min_separation: mc.as_ref().map(|m| m.min_separation),
            pieces: a.outcomes.len(),
            programs: a.programs_solved,
            worst: None,
        })
    }

    /// Runs the cells of a shard in parallel; `tick` is called once per finished cell.
    /// Results are in cell order. Work past `budget` is refused: too many cells before any
    /// is run, Monte Carlo runs up front when the base problem's horizon already exceeds
    /// it, and else when the running count (each cell's own horizon) reaches it.
    pub fn run(
        &self,
        shard: Shard,
        runs: usize,
        seed: u64,
        budget: &SweepBudget,
        tick: impl Fn() + Sync,
    ) -> Result<Vec<CellResult>, SweepError> {
        let share = shard.share(self.len());
        let name = if shard == Shard::ALL {
            self.path.display().to_string()
        } else {
            format!(
                "{}, shard {}/{},",
                self.path.display(),
                shard.index,
                shard.count
            )
        };
        budget.cells.allow(name.clone(), Some(share as u64))?;
        if runs > 0 {
            let base = match self.input_with(&[])? {
                CellInput::Problem(p) => simulate::horizon(&p.params::<f64>()),
                CellInput::Scene(s) => crate::core::scene::simulate::horizon(&s.params::<f64>()),
            };
            let needed = (share as u64)
                .checked_mul(runs as u64)
                .and_then(|n| n.checked_mul(base as u64));
            budget.periods.allow(
                format!(
                    "{name}: {} cells of {runs} Monte Carlo runs, each of up to {} control \
                     periods (the base problem's horizon),",
                    grouped(share as u64),
                    grouped(base as u64)
                ),
                needed,
            )?;
        }
        let meter = Meter::new(budget.periods);
        let cells: Vec<usize> = (0..self.len()).filter(|&c| shard.owns(c)).collect();
        cells
            .par_iter()
            .map(|&c| {
                let r = self.run_cell(c, runs, seed, &meter);
                tick();
                r
            })
            .collect()
    }
}

/// Sweep failures.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SweepError {
    /// A cell's problem is invalid.
    #[error(transparent)]
    Problem(#[from] ProblemError),
    /// The sweep asks for more work than its budget.
    #[error(transparent)]
    OverBudget(#[from] OverBudget),
    /// A cell's analysis failed.
    #[error("cell {cell}: {reason}")]
    Analysis {
        /// The cell.
        cell: usize,
        /// Why.
        reason: String,
    },
}

/// Cell results as JSON Lines, one object per cell: its number, its axis values (as
/// top-level dotted keys), then the results.
pub fn to_jsonl(results: &[CellResult]) -> String {
    let mut out = String::new();
    for r in results {
        let mut obj = serde_json::Map::new();
        obj.insert("cell".into(), r.cell.into());
        for (k, v) in &r.axes {
            obj.insert(k.clone(), v.clone());
        }
        let rest = serde_json::to_value(r).expect("cell results serialise");
        if let serde_json::Value::Object(fields) = rest {
            for (k, v) in fields {
                if k != "cell" && k != "axes" {
                    obj.insert(k, v);
                }
            }
        }
        out.push_str(&serde_json::Value::Object(obj).to_string());
        out.push('\n');
    }
    out
}

/// Reads cell results from JSON Lines written by [`to_jsonl`], given the grid's axis keys.
pub fn from_jsonl(
    text: &str,
    axis_keys: &[String],
    origin: &str,
) -> Result<Vec<CellResult>, String> {
    let mut out = Vec::new();
    for (n, line) in text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
    {
        let mut obj: serde_json::Map<String, serde_json::Value> =
            serde_json::from_str(line).map_err(|e| format!("{origin}:{}: {e}", n + 1))?;
        let mut axes = serde_json::Map::new();
        for k in axis_keys {
            let v = obj
                .remove(k)
                .ok_or_else(|| format!("{origin}:{}: no value for axis {k:?}", n + 1))?;
            axes.insert(k.clone(), v);
        }
        obj.insert("axes".into(), serde_json::Value::Object(axes));
        let r: CellResult = serde_json::from_value(serde_json::Value::Object(obj))
            .map_err(|e| format!("{origin}:{}: {e}", n + 1))?;
        out.push(r);
    }
    Ok(out)
}

fn csv_field(v: &serde_json::Value) -> String {
    match v {
        serde_json::Value::Null => String::new(),
        serde_json::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// Cell results as CSV with a header: cell, the axes, then the results.
pub fn to_csv(results: &[CellResult], axis_keys: &[String]) -> String {
    let mut out = String::from("cell");
    for k in axis_keys {
        out.push(',');
        out.push_str(k);
    }
    out.push_str(",verdict,min_separation,never_stops,lower_bound,collisions,runs,simulated_min_separation,pieces,programs");
    // Scene cells add their worst case; single-obstacle CSV keeps its columns.
    let scene = results.iter().any(|r| r.worst.is_some());
    if scene {
        out.push_str(",worst_obstacle,worst_lane,worst_cause");
    }
    out.push('\n');
    for r in results {
        out.push_str(&r.cell.to_string());
        for k in axis_keys {
            out.push(',');
            out.push_str(&r.axes.get(k).map(csv_field).unwrap_or_default());
        }
        let opt = |x: Option<f64>| x.map(|v| v.to_string()).unwrap_or_default();
        out.push_str(&format!(
            ",{},{},{},{},{},{},{},{},{}",
            r.verdict.as_str(),
            opt(r.min_separation),
            r.never_stops,
            opt(r.lower_bound),
            r.collisions.map(|c| c.to_string()).unwrap_or_default(),
            r.runs.map(|c| c.to_string()).unwrap_or_default(),
            opt(r.simulated_min_separation),
            r.pieces,
            r.programs
        ));
        if scene {
            if let Some(w) = &r.worst {
                out.push_str(&format!(
                    ",{},{},{}",
                    csv_quoted(&w.name),
                    w.lane,
                    csv_quoted(&w.cause.tag())
                ));
            } else {
                out.push_str(",,,");
            }
        }
        out.push('\n');
    }
    out
}

/// A CSV field, quoted (quotes doubled) when it holds a comma, a quote or a line break.
fn csv_quoted(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Merges shard results: sorted by cell, every cell of the grid exactly once.
pub fn merge(grid: &Grid, parts: Vec<Vec<CellResult>>) -> Result<Vec<CellResult>, String> {
    let mut all: Vec<CellResult> = parts.into_iter().flatten().collect();
    all.sort_by_key(|r| r.cell);
    let n = grid.len();
    for (i, r) in all.iter().enumerate() {
        if r.cell != i {
            return Err(if r.cell < i {
                format!("cell {} appears twice", r.cell)
            } else {
                format!("cell {i} is missing (of {n})")
            });
        }
    }
    if all.len() != n {
        return Err(format!("{} of {n} cells present", all.len()));
    }
    Ok(all)
}
