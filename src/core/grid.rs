//! A grid of problems: a base problem (line, scene or planar) and axes over its dotted keys, the cells
//! being their cartesian product. This module reads and validates grid files and builds
//! each cell's input; running the cells is the analyser's (`analysis::sweep`), so the grid
//! reader is part of the lean library (what a fuzz target or another front end links).
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
//! Cells are numbered from 0, the *last* axis varying fastest. Each cell is the base with the
//! axis values applied as `--set` overrides (the same validation).

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::core::model::{Problem, ProblemError};
use crate::core::parameter::Parameter;
use crate::core::planar::PlanarProblem;
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
    /// What kind of file the base is.
    pub kind: BaseKind,
    /// The base problem as read (None for a scene or planar problem): cells that only set named parameters to
    /// floats start from it instead of reading the base's text again.
    base: Option<Problem>,
}

/// What kind of problem file a grid's base is (each is read by its own reader, and its
/// cells answered by its own engines).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BaseKind {
    /// A single-obstacle problem on the line.
    Problem,
    /// A scene: several obstacles and lanes on the line.
    Scene,
    /// A planar problem (a `[plane]` table: docs/semantics.md §13).
    Planar,
}

impl BaseKind {
    /// How a report names the base: `problem`, `scene`, `planar problem`.
    pub fn as_str(self) -> &'static str {
        match self {
            BaseKind::Problem => "problem",
            BaseKind::Scene => "scene",
            BaseKind::Planar => "planar problem",
        }
    }
}

/// What one cell analyses.
#[derive(Clone, Debug)]
pub enum CellInput {
    /// A single-obstacle problem.
    Problem(Problem),
    /// A scene.
    Scene(Scene),
    /// A planar problem.
    Planar(Box<PlanarProblem>),
}

impl Grid {
    /// Loads a grid file and its base problem (validated).
    pub fn load(path: &Path) -> Result<Grid, GridError> {
        let shown = path.display().to_string();
        let text =
            crate::core::text_file::read_text(path, crate::core::text_file::MAX_PROBLEM_BYTES)
                .map_err(|source| GridError::Read {
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
        let base_text = crate::core::text_file::read_text(
            &base_path,
            crate::core::text_file::MAX_PROBLEM_BYTES,
        )
        .map_err(|source| GridError::Read {
            path: format!("{shown}: base = {:?} ({})", file.base, base_path.display()),
            source,
        })?;
        let origin = base_path.display().to_string();
        let (kind, base) = if PlanarProblem::is_planar(&base_text) {
            PlanarProblem::from_toml_str(&base_text, &origin)?;
            (BaseKind::Planar, None)
        } else {
            match Problem::from_toml_str(&base_text, &origin) {
                Ok(p) => (BaseKind::Problem, Some(p)),
                Err(e) => {
                    // Not a problem file: a scene, or the problem reader's error stands.
                    Scene::from_toml_str(&base_text, &origin).map_err(|_| e)?;
                    (BaseKind::Scene, None)
                }
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
            kind,
            base,
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

    /// What a cell with these axis values analyses.
    pub(crate) fn input_with(
        &self,
        values: &[(String, toml::Value)],
    ) -> Result<CellInput, ProblemError> {
        if let Some(p) = self.quick_input(values) {
            return Ok(CellInput::Problem(p));
        }
        let sets: Vec<String> = values.iter().map(|(k, v)| format!("{k}={v}")).collect();
        let origin = self.base_path.display().to_string();
        match self.kind {
            BaseKind::Scene => Scene::from_toml_str_with_overrides(&self.base_text, &origin, &sets)
                .map(CellInput::Scene),
            BaseKind::Planar => {
                PlanarProblem::from_toml_str_with_overrides(&self.base_text, &origin, &sets)
                    .map(|p| CellInput::Planar(Box::new(p)))
            }
            BaseKind::Problem => {
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
    }

    /// The cell's problem without reading the base's text again, when that gives what reading
    /// it with the cell's overrides gives: every value a float for a named parameter
    /// ([`Parameter::set_in`] sets the field the key names), a point start, and a valid
    /// result. Anything else (and every error, whose message names the override) takes the
    /// reader's path. A sweep spent a tenth of its time parsing the base per cell.
    fn quick_input(&self, values: &[(String, toml::Value)]) -> Option<Problem> {
        let mut p = self.base.clone()?;
        for (key, value) in values {
            let (Some(parameter), toml::Value::Float(x)) = (Parameter::from_key(key), value) else {
                return None;
            };
            parameter.set_in(&mut p, *x);
        }
        (!p.environment.initial_gap.is_range() && p.validate("").is_ok()).then_some(p)
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
            CellInput::Planar(_) => Err(ProblemError::Invalid {
                origin: self.base_path.display().to_string(),
                key: "plane".into(),
                value: String::new(),
                reason: "the base is a planar problem, not a problem on the line".into(),
                location: None,
            }),
        }
    }

    /// What a cell analyses.
    pub fn input(&self, cell: usize) -> Result<CellInput, ProblemError> {
        self.input_with(&self.cell_values(cell))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every cell that takes the quick path is exactly the problem the reader makes of the
    /// base with the cell's overrides, over every named parameter (two values each, one of
    /// them a noise that creates `[sensing]`); integers, an invalid combination and a key
    /// that is no named parameter take the reader's path.
    #[test]
    fn the_quick_cell_is_the_problem_the_reader_makes() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems");
        let axes: Vec<String> = Parameter::ALL
            .iter()
            .map(|p| {
                let (a, b) = match p {
                    Parameter::ObstacleSpeed | Parameter::AssumedObstacleSpeed => (0.1, 0.25),
                    Parameter::ReactionRadius => (1.2, 1.45),
                    Parameter::InitialGap => (9.5, 12.25),
                    Parameter::FirstDetectionGap => (1.5, 2.0),
                    Parameter::SpeedNoise => (0.0, 0.01),
                    _ => (0.0, 0.05),
                };
                format!("\"{}\" = [{a:?}, {b:?}]", p.key())
            })
            .collect();
        let text = format!("base = \"seed.toml\"\n[axes]\n{}\n", axes.join("\n"));
        let grid = Grid::from_toml_str(&text, &root.join("quick-grid.toml")).expect("loads");
        let origin = grid.base_path.display().to_string();
        let mut quick = 0;
        for cell in 0..grid.len() {
            let values = grid.cell_values(cell);
            let sets: Vec<String> = values.iter().map(|(k, v)| format!("{k}={v}")).collect();
            let read = Problem::from_toml_str_with_overrides(&grid.base_text, &origin, &sets);
            match grid.quick_input(&values) {
                Some(p) => {
                    quick += 1;
                    assert_eq!(Ok(p), read.map_err(|e| e.to_string()), "cell {cell}");
                }
                None => assert!(read.is_err(), "cell {cell} is valid: it should be quick"),
            }
        }
        assert!(quick > 100, "{quick} of {} cells quick", grid.len());
        let int = vec![(
            "controller.reaction_radius".to_string(),
            toml::Value::Integer(2),
        )];
        assert!(grid.quick_input(&int).is_none());
        let other = vec![("robot.braking".to_string(), toml::Value::Float(0.1))];
        assert!(grid.quick_input(&other).is_none());
        let bad = vec![(
            "controller.reaction_radius".to_string(),
            toml::Value::Float(-1.0),
        )];
        assert!(grid.quick_input(&bad).is_none());
    }
}
