//! Reports: a sweep's cells as a Markdown table, a verdict heat map and the safe-radius
//! curve ρ*(W) as SVG, and the seed paper's findings checked against the cells.
//!
//! The SVG is written by hand: a few rectangles, lines and labels. That keeps the output
//! byte-for-byte reproducible (CI regenerates `reports/` and compares it with what is
//! committed) and needs no font files at build or run time.
//!
//! One idea per file: `markdown` assembles the page, `findings` checks the paper's claims,
//! `heat_map` and `curve_plot` draw the two figures with the small writer in `svg` and the
//! verdict colours in `palette`; `cells` reads and prints one cell's values for all of them.

mod cells;
mod curve_plot;
mod findings;
mod heat_map;
mod markdown;
mod palette;
mod svg;

pub use markdown::grid_report;

use crate::analysis::radius;
use crate::analysis::sweep::Grid;
use crate::core::model::Problem;

const SPEED_KEY: &str = "environment.obstacle_speed";
const RADIUS_KEY: &str = "controller.reaction_radius";
const ASSUMED_KEY: &str = "controller.assumed_obstacle_speed";

/// A generated report: the Markdown page and its figures (file name, SVG text).
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// The page.
    pub markdown: String,
    /// Figures referenced by the page.
    pub figures: Vec<(String, String)>,
}

/// One point of the safe-radius curve: W and ρ*(W) (None: no radius is certified).
pub type CurvePoint = (f64, Option<f64>);

/// ρ*(W) for the grid's base problem at each speed (the assumed bound taken from the grid
/// when it has a single value for it).
pub fn radius_curve(grid: &Grid, speeds: &[f64]) -> Result<Vec<CurvePoint>, String> {
    let mut sets: Vec<String> = Vec::new();
    if let Some((_, values)) = grid
        .axes
        .iter()
        .find(|(k, v)| k == ASSUMED_KEY && v.len() == 1)
    {
        sets.push(format!("{ASSUMED_KEY}={}", values[0]));
    }
    let origin = grid.base_path.display().to_string();
    speeds
        .iter()
        .map(|&w| {
            let mut s = sets.clone();
            s.push(format!("{SPEED_KEY}={w}"));
            let p = Problem::from_toml_str_with_overrides(&grid.base_text, &origin, &s)
                .map_err(|e| e.to_string())?;
            let b = radius::safe_radius(&p).map_err(|e| e.to_string())?;
            Ok((w, b.value))
        })
        .collect()
}
