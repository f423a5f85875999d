//! The verdict heat map over (W, ρ): one tile per pair with the verdict, s* and the Monte
//! Carlo record; speeds left to right, radii bottom to top, a colour legend on the right.

use super::cells::{axis_value, collisions_per_runs, separation, sorted_values};
use super::palette::{self, LEGEND};
use super::svg::{END, MIDDLE, Svg};
use super::{RADIUS_KEY, SPEED_KEY};
use crate::analysis::Verdict;
use crate::analysis::sweep::CellResult;

/// Tile width, in pixels.
const CW: u32 = 130;
/// Tile height.
const CH: u32 = 64;
/// Left margin (room for the radius labels).
const LEFT: u32 = 90;
/// Top margin (room for the title).
const TOP: u32 = 50;

/// Verdict heat map over (W, ρ): one tile per (W, ρ) pair (the first cell found for it).
pub(super) fn heat_map(results: &[CellResult], assumed: Option<f64>) -> String {
    let tiles = Tiles {
        ws: sorted_values(results, SPEED_KEY),
        rs: sorted_values(results, RADIUS_KEY),
    };
    let mut svg = Svg::new(LEFT + tiles.width() + 170, TOP + tiles.height() + 70);
    svg.title(
        LEFT + tiles.width() / 2,
        "Verdict per cell (Monte Carlo collisions / runs)",
    );
    for (j, rho) in tiles.rs.iter().enumerate() {
        let y = tiles.row_top(j);
        svg.text(LEFT - 8, y + CH / 2 + 4, END, &format!("{rho} m"));
        for (i, w) in tiles.ws.iter().enumerate() {
            let found = results.iter().find(|r| {
                axis_value(r, SPEED_KEY) == Some(*w) && axis_value(r, RADIUS_KEY) == Some(*rho)
            });
            if let Some(r) = found {
                tile(&mut svg, LEFT + CW * i as u32, y, r);
            }
        }
    }
    axis_labels(&mut svg, &tiles, assumed);
    legend(&mut svg, LEFT + tiles.width() + 20);
    svg.finish()
}

/// The grid of tiles: the distinct speeds (columns) and radii (rows), ascending.
struct Tiles {
    ws: Vec<f64>,
    rs: Vec<f64>,
}

impl Tiles {
    fn width(&self) -> u32 {
        CW * self.ws.len() as u32
    }

    fn height(&self) -> u32 {
        CH * self.rs.len() as u32
    }

    /// Top edge of row `j` (the largest radius at the top, like the paper's axes).
    fn row_top(&self, j: usize) -> u32 {
        TOP + CH * (self.rs.len() - 1 - j) as u32
    }
}

/// One cell's tile at (x, y): its colour, verdict, s* and collisions / runs.
fn tile(svg: &mut Svg, x: u32, y: u32, r: &CellResult) {
    svg.rect(
        x,
        y,
        CW,
        CH,
        palette::color(r),
        " stroke=\"white\" stroke-width=\"2\"",
    );
    let fg = if r.verdict == Verdict::Certified {
        "white"
    } else {
        "black"
    };
    let cx = x + CW / 2;
    let attrs = format!("{MIDDLE} fill=\"{fg}\"");
    svg.text(
        cx,
        y + 20,
        &format!("{attrs} font-weight=\"bold\""),
        r.verdict.as_str(),
    );
    svg.text(cx, y + 36, &attrs, &format!("s* = {}", separation(r)));
    svg.text(
        cx,
        y + 52,
        &attrs,
        &collisions_per_runs(r).unwrap_or_default(),
    );
}

/// Speed under each column (marked when beyond the assumption) and both axis titles.
fn axis_labels(svg: &mut Svg, tiles: &Tiles, assumed: Option<f64>) {
    let base = TOP + tiles.height();
    for (i, w) in tiles.ws.iter().enumerate() {
        let mark = if assumed.is_some_and(|va| *w > va) {
            " (> V_a)"
        } else {
            ""
        };
        let x = LEFT + CW * i as u32 + CW / 2;
        svg.text(x, base + 18, MIDDLE, &format!("{w} m/s{mark}"));
    }
    let centre = LEFT + tiles.width() / 2;
    svg.text(centre, base + 40, MIDDLE, "obstacle speed bound W");
    svg.vertical_label(TOP + tiles.height() / 2, "reaction radius ρ");
}

/// The colour legend, a swatch and a label per line, from (lx, TOP).
fn legend(svg: &mut Svg, lx: u32) {
    for (k, (c, label)) in LEGEND.iter().enumerate() {
        let y = TOP + 22 * k as u32;
        svg.rect(lx, y, 14, 14, c, "");
        svg.text(lx + 20, y + 11, "", label);
    }
}
