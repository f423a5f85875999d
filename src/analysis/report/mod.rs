//! Reports: a sweep's cells as a Markdown table, verdict heat maps and the safe-radius
//! curve ρ*(W) as SVG, the seed paper's findings checked against the cells and, for a scene
//! grid, which obstacle is the worst case where and why the robot braked.
//!
//! The SVG is written by hand: a few rectangles, lines and labels. That keeps the output
//! byte-for-byte reproducible (CI regenerates `reports/` and compares it with what is
//! committed) and needs no font files at build or run time.
//!
//! One idea per file: `markdown` assembles the page, `findings` checks the paper's claims
//! and names the worst cases, `heat_map` and `curve_plot` draw the figures with the small
//! writer in `svg` and the verdict colours in `palette`; `axes` labels the axes and picks a
//! heat map's two, `curve` computes ρ*(W); `cells` reads and prints one cell's values for
//! all of them; `certified_map` maps the (W, ρ) plane with region certificates and
//! `region_plot` draws a region map.

mod axes;
mod cells;
mod certified_map;
mod curve;
mod curve_plot;
mod findings;
mod heat_map;
mod markdown;
mod palette;
pub mod region_plot;
mod svg;

pub use certified_map::certified_map;
pub use curve::{Curve, radius_curve};
pub use markdown::grid_report;

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
