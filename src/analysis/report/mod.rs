//! Reports: a sweep's cells as a Markdown table, verdict heat maps and the safe-radius
//! curves ρ*(W) as SVG (one per slice of the other axes), the seed paper's findings checked
//! against the cells and, for a scene grid, which obstacle is the worst case where and why
//! the robot braked.
//!
//! The SVG is written by hand: a few rectangles, lines and labels. That keeps the output
//! byte-for-byte reproducible (CI regenerates `reports/` and compares it with what is
//! committed) and needs no font files at build or run time.
//!
//! One idea per file: `markdown` assembles the page, `base_values` lists what the cells
//! hold fixed, `findings` checks the paper's claims and names the worst cases, `figures`
//! draws one figure per slice of the axes a figure does not span (so nothing drawn mixes
//! slices), `heat_map` and `curve_plot` draw them with the small writer in `svg` and the
//! verdict colours in `palette`; `axes` labels the axes, picks a heat map's two and cuts a
//! grid into slices, `curve` computes ρ*(W) per slice; `cells` reads and prints one cell's
//! values for all of them; `certified_map` maps the (W, ρ) plane with region certificates
//! and `region_plot` draws a region map; `planar_views` draws a planar grid's worst cases
//! from above with `top_view`.

mod axes;
mod base_values;
mod cells;
mod certified_map;
mod curve;
mod curve_plot;
mod figures;
mod findings;
mod heat_map;
mod markdown;
mod palette;
mod planar_views;
pub mod region_plot;
mod svg;
mod top_view;

pub use certified_map::certified_map;
pub use curve::{Curve, SliceCurve, radius_curve};
pub use markdown::grid_report;
pub use planar_views::{PlanarView, planar_views, witness_view};
pub use top_view::{TopViewLabels, top_view};

const SPEED_KEY: &str = "environment.obstacle_speed";
const RADIUS_KEY: &str = "controller.reaction_radius";
const ASSUMED_KEY: &str = "controller.assumed_obstacle_speed";

/// Most figures of a kind one report draws (heat maps, radius curves): one per slice of
/// the axes they do not span, the first this many.
const MAX_MAPS: usize = 12;

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
