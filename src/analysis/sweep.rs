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

use std::path::{Path, PathBuf};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::analysis::scene_answer::SceneAnswer;
use crate::analysis::scene_worst::SceneWorstCase;
use crate::analysis::{self, Options, SpeedPattern, Verdict, WitnessPolicy};
use crate::core::model::{Problem, ProblemError};
use crate::core::num::f64_at_most;
use crate::core::scene::Scene;

/// Grid-file errors (all name the file).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum GridError {
    /// The grid file could not be read.
    #[error("{path}: cannot read the file")]
    Read {
        /// The file.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// The grid file is not valid.
    #[error("{path}: {reason}")]
    Invalid {
        /// The file.
        path: String,
        /// Why.
        reason: String,
    },
    /// The base problem, or a cell of it, is not valid.
    #[error(transparent)]
    Problem(#[from] ProblemError),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct GridFile {
    base: String,
    #[serde(default)]
    runs: usize,
    #[serde(default)]
    seed: u64,
    axes: toml::Table,
}

/// A loaded grid.
#[derive(Clone, Debug)]
pub struct Grid {
    /// Where the grid file is.
    pub path: PathBuf,
    /// Grid name (the file stem).
    pub name: String,
    /// The base problem's path.
    pub base_path: PathBuf,
    /// The base problem's text.
    pub base_text: String,
    /// Axes: dotted key and values, in file order.
    pub axes: Vec<(String, Vec<toml::Value>)>,
    /// Monte Carlo runs per cell (0: none).
    pub runs: usize,
    /// Seed of the first Monte Carlo run.
    pub seed: u64,
    /// The base is a scene file (else a single-obstacle problem file).
    pub scene: bool,
}

/// What one cell analyses.
#[derive(Clone, Debug)]
pub enum CellInput {
    /// A single-obstacle problem.
    Problem(Problem),
    /// A scene.
    Scene(Scene),
}

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
}

impl Grid {
    /// Loads a grid file and its base problem (validated).
    pub fn load(path: &Path) -> Result<Grid, GridError> {
        let shown = path.display().to_string();
        let text = crate::core::text_file::read_text(path).map_err(|source| GridError::Read {
            path: shown.clone(),
            source,
        })?;
        Self::from_toml_str(&text, path)
    }

    /// Reads a grid from its TOML `text`, as if it were the file at `path`: `path` names the
    /// grid in errors and gives its name, and the base problem is read from disk relative to
    /// `path`'s directory. [`Grid::load`] is this after reading the file.
    pub fn from_toml_str(text: &str, path: &Path) -> Result<Grid, GridError> {
        let shown = path.display().to_string();
        let file: GridFile = toml::from_str(text).map_err(|e| GridError::Invalid {
            path: shown.clone(),
            reason: e.to_string(),
        })?;
        let base_path = path.parent().unwrap_or(Path::new(".")).join(&file.base);
        let base_text =
            crate::core::text_file::read_text(&base_path).map_err(|source| GridError::Read {
                path: format!("{shown}: base = {:?} ({})", file.base, base_path.display()),
                source,
            })?;
        let origin = base_path.display().to_string();
        let scene = match Problem::from_toml_str(&base_text, &origin) {
            Ok(_) => false,
            Err(e) => {
                // Not a problem file: a scene, or the problem reader's error stands.
                Scene::from_toml_str(&base_text, &origin).map_err(|_| e)?;
                true
            }
        };
        let mut axes = Vec::new();
        for (key, value) in file.axes {
            if key.trim() != key || key.is_empty() {
                // Overrides trim their key: " robot.braking" would be a second axis of
                // robot.braking, silently doubling the cells.
                return Err(GridError::Invalid {
                    path: shown,
                    reason: format!(
                        "axes.{key:?}: a key may not be empty or start or end with a space"
                    ),
                });
            }
            let toml::Value::Array(values) = value else {
                return Err(GridError::Invalid {
                    path: shown,
                    reason: format!("axes.{key:?} must be an array of values"),
                });
            };
            if values.is_empty() {
                return Err(GridError::Invalid {
                    path: shown,
                    reason: format!("axes.{key:?} is empty"),
                });
            }
            axes.push((key, values));
        }
        if axes.is_empty() {
            return Err(GridError::Invalid {
                path: shown,
                reason: "[axes] names no key".into(),
            });
        }
        if axes
            .iter()
            .try_fold(1usize, |n, (_, v)| n.checked_mul(v.len()))
            .is_none()
        {
            return Err(GridError::Invalid {
                path: shown,
                reason: "the axes make more cells than can be counted".into(),
            });
        }
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "grid".into());
        let grid = Grid {
            path: path.to_path_buf(),
            name,
            base_path,
            base_text,
            axes,
            runs: file.runs,
            seed: file.seed,
            scene,
        };
        // Every value must make a valid problem: check each axis value once, up front. The
        // error names the grid file and the axis (the value reaches the problem as an
        // override, whose own name would mislead).
        for (key, values) in &grid.axes {
            for v in values {
                if let Err(e) = grid.input_with(&[(key.clone(), v.clone())]) {
                    let set = format!("--set {key}={v}");
                    let reason = e.to_string();
                    let reason = match reason.strip_prefix(&format!("{set}: ")) {
                        Some(rest) => format!("axes.{key:?}, value {v}: {rest}"),
                        None => reason,
                    };
                    return Err(GridError::Invalid {
                        path: grid.path.display().to_string(),
                        reason,
                    });
                }
            }
        }
        Ok(grid)
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.axes.iter().map(|(_, v)| v.len()).product()
    }

    /// Whether the grid has no cells (never, for a loaded grid).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The axis values of a cell.
    pub fn cell_values(&self, cell: usize) -> Vec<(String, toml::Value)> {
        let mut rest = cell;
        let mut out = vec![(String::new(), toml::Value::Boolean(false)); self.axes.len()];
        for (i, (key, values)) in self.axes.iter().enumerate().rev() {
            out[i] = (key.clone(), values[rest % values.len()].clone());
            rest /= values.len();
        }
        out
    }

    fn input_with(&self, values: &[(String, toml::Value)]) -> Result<CellInput, ProblemError> {
        let sets: Vec<String> = values.iter().map(|(k, v)| format!("{k}={v}")).collect();
        let origin = self.base_path.display().to_string();
        if self.scene {
            Scene::from_toml_str_with_overrides(&self.base_text, &origin, &sets)
                .map(CellInput::Scene)
        } else {
            // A range of initial gaps is answered by the scene engines (see
            // `AnalysisError::GapRange`).
            Problem::from_toml_str_with_overrides(&self.base_text, &origin, &sets).map(|p| {
                if p.environment.initial_gap.is_range() {
                    CellInput::Scene(Scene::from_problem(&p))
                } else {
                    CellInput::Problem(p)
                }
            })
        }
    }

    /// The problem of a cell (an error for a scene grid: see [`Grid::input`]).
    pub fn problem(&self, cell: usize) -> Result<Problem, ProblemError> {
        match self.input(cell)? {
            CellInput::Problem(p) => Ok(p),
            CellInput::Scene(s) => s.as_problem().ok_or_else(|| ProblemError::Invalid {
                origin: self.base_path.display().to_string(),
                key: "environment".into(),
                value: String::new(),
                reason: "the base is a scene, not a single-obstacle problem".into(),
                location: None,
            }),
        }
    }

    /// What a cell analyses.
    pub fn input(&self, cell: usize) -> Result<CellInput, ProblemError> {
        self.input_with(&self.cell_values(cell))
    }

    /// Analyses one cell (and simulates it, with `runs` > 0).
    pub fn run_cell(&self, cell: usize, runs: usize, seed: u64) -> Result<CellResult, SweepError> {
        let values = self.cell_values(cell);
        let problem = match self.input_with(&values)? {
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
    /// Results are in cell order.
    pub fn run(
        &self,
        shard: Shard,
        runs: usize,
        seed: u64,
        tick: impl Fn() + Sync,
    ) -> Result<Vec<CellResult>, SweepError> {
        let cells: Vec<usize> = (0..self.len()).filter(|&c| shard.owns(c)).collect();
        cells
            .par_iter()
            .map(|&c| {
                let r = self.run_cell(c, runs, seed);
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
