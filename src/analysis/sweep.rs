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
use crate::analysis::sweep_file::SweepFile;
pub use crate::analysis::sweep_planar::PlanarClosest;
use crate::analysis::{self, Options, SpeedPattern, Verdict, WitnessPolicy};
use crate::core::budget::{Budget, Meter, OverBudget, Work, grouped};
pub use crate::core::grid::{CellInput, Grid, GridError};
use crate::core::model::ProblemError;
use crate::core::num::f64_at_most;
use crate::core::scene::Scene;
pub use crate::core::shard::Shard;
use crate::core::simulate;
use crate::core::sweep_provenance::SweepProvenance;

/// The result of one cell.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
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
    /// s* ≤ this: a replayed behaviour's separation (planar cells with a witness; absent
    /// elsewhere).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub upper_bound: Option<f64>,
    /// A planar cell's worst case: the obstacle its witness brings closest, when, and why
    /// the robot braked (absent elsewhere).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub closest: Option<PlanarClosest>,
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
        let exact = scene.params::<crate::core::rational::Rational>();
        crate::analysis::scene_monte_carlo(&exact, runs, seed, &[SpeedPattern::Uniform])
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
        upper_bound: None,
        closest: None,
    })
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
                // A random planar run ends at rest, or after this many periods.
                CellInput::Planar(_) => crate::analysis::planar::MAX_RUN_STEPS,
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
            CellInput::Planar(p) => {
                let sets: Vec<String> = values.iter().map(|(k, v)| format!("{k}={v}")).collect();
                let origin = self.base_path.display().to_string();
                return crate::analysis::sweep_planar::planar_cell(
                    cell,
                    axes_map(&values),
                    (&self.base_text, &origin),
                    &sets,
                    &p,
                    (runs, seed),
                );
            }
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
        let exact = || problem.params::<crate::core::rational::Rational>();
        let mc = (runs > 0).then(|| crate::analysis::monte_carlo(&exact(), runs, seed));
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
            upper_bound: None,
            closest: None,
        })
    }

    /// Runs the cells of a shard in parallel, as [`Grid::run`], and returns them with the
    /// provenance record of the run (what its output file starts with).
    pub fn sweep(
        &self,
        shard: Shard,
        runs: usize,
        seed: u64,
        budget: &SweepBudget,
        tick: impl Fn() + Sync,
    ) -> Result<SweepFile, SweepError> {
        let provenance = SweepProvenance::of(self, shard, runs, seed)?;
        let cells = self.run(shard, runs, seed, budget, tick)?;
        Ok(SweepFile { provenance, cells })
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
                CellInput::Planar(_) => crate::analysis::planar::MAX_RUN_STEPS,
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
