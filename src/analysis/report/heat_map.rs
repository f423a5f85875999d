//! The verdict heat map over two axes (W and ρ for a single obstacle; any two numeric axes
//! of a scene grid): one tile per pair with the verdict, s*, the Monte Carlo record and, for
//! a scene, the worst-case obstacle; the first axis left to right, the second bottom to top,
//! the slice of the other axes under the title, a colour legend on the right.

use super::axes::AxisLabel;
use super::cells::{axis_value, collisions_per_runs, separation, sorted_values};
use super::palette::{self, LEGEND};
use super::svg::{END, MIDDLE, Svg};
use crate::analysis::Verdict;
use crate::analysis::sweep::CellResult;

/// Tile width, in pixels.
const CW: u32 = 130;
/// Tile height (a line more for a scene's worst case).
const CH: u32 = 64;
/// Height of a line of text in a tile or under the title.
const LINE: u32 = 16;
/// Least left margin (room for the radius labels); longer row labels widen it.
const LEFT: u32 = 90;
/// Width of a character of a row label, a little more than the font's average.
const CHAR: u32 = 7;
/// Room left of the row labels for the vertical axis title.
const TITLE: u32 = 38;
/// Top margin (room for the title), before the slice's lines.
const TOP: u32 = 50;

/// What one heat map shows: its axes, the slice of the others, and how to title them.
pub(super) struct HeatMap<'a> {
    /// The axis across.
    pub(super) x: &'a AxisLabel,
    /// The axis up.
    pub(super) y: &'a AxisLabel,
    /// The other axes' values the map holds, as `label = value` lines.
    pub(super) slice: Vec<String>,
    /// Axis titles carry their unit (scene grids); single-obstacle maps keep the unit in
    /// the ticks only, as they always had.
    pub(super) titled: bool,
    /// The assumed speed V_a: x values beyond it are marked when x is a speed bound.
    pub(super) assumed: Option<f64>,
}

/// The heat map of `results` (the slice's cells): one tile per (x, y) pair (the first cell
/// found for it).
pub(super) fn heat_map(results: &[CellResult], map: &HeatMap) -> String {
    let scene = results.iter().any(|r| r.worst.is_some());
    let ys = sorted_values(results, &map.y.key);
    let longest = ys
        .iter()
        .map(|y| map.y.value(&y.to_string()).chars().count() as u32)
        .max()
        .unwrap_or(0);
    let tiles = Tiles {
        left: LEFT.max(TITLE + CHAR * longest),
        xs: sorted_values(results, &map.x.key),
        ys,
        top: TOP + LINE * map.slice.len() as u32,
        ch: if scene { CH + LINE } else { CH },
    };
    let mut svg = Svg::new(
        tiles.left + tiles.width() + 170,
        tiles.top + tiles.height() + 70,
    );
    svg.title(
        tiles.left + tiles.width() / 2,
        "Verdict per cell (Monte Carlo collisions / runs)",
    );
    for (k, line) in map.slice.iter().enumerate() {
        let y = TOP - 8 + LINE * k as u32;
        svg.text(
            tiles.left + tiles.width() / 2,
            y,
            MIDDLE,
            &format!("slice: {line}"),
        );
    }
    for (j, yv) in tiles.ys.iter().enumerate() {
        let y = tiles.row_top(j);
        let label = map.y.value(&yv.to_string());
        svg.text(tiles.left - 8, y + tiles.ch / 2 + 4, END, &label);
        for (i, xv) in tiles.xs.iter().enumerate() {
            let found = results.iter().find(|r| {
                axis_value(r, &map.x.key) == Some(*xv) && axis_value(r, &map.y.key) == Some(*yv)
            });
            if let Some(r) = found {
                tile(&mut svg, tiles.left + CW * i as u32, y, tiles.ch, r);
            }
        }
    }
    axis_labels(&mut svg, &tiles, map);
    legend(&mut svg, tiles.left + tiles.width() + 20, tiles.top);
    svg.finish()
}

/// The grid of tiles: the distinct x values (columns) and y values (rows), ascending.
struct Tiles {
    /// Left edge of the tiles (room for the row labels and the vertical title).
    left: u32,
    xs: Vec<f64>,
    ys: Vec<f64>,
    /// Top edge of the tiles.
    top: u32,
    /// Tile height.
    ch: u32,
}

impl Tiles {
    fn width(&self) -> u32 {
        CW * self.xs.len() as u32
    }

    fn height(&self) -> u32 {
        self.ch * self.ys.len() as u32
    }

    /// Top edge of row `j` (the largest value at the top, like the paper's axes).
    fn row_top(&self, j: usize) -> u32 {
        self.top + self.ch * (self.ys.len() - 1 - j) as u32
    }
}

/// One cell's tile at (x, y): its colour, verdict, s*, collisions / runs and, for a scene,
/// the worst-case obstacle.
fn tile(svg: &mut Svg, x: u32, y: u32, ch: u32, r: &CellResult) {
    svg.rect(
        x,
        y,
        CW,
        ch,
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
    if let Some(w) = &r.worst {
        let body = format!("\"{}\", lane {}", w.name, w.lane);
        svg.text(cx, y + 68, &attrs, &body);
    }
}

/// The x value under each column (marked when a speed beyond the assumption) and both
/// axis titles.
fn axis_labels(svg: &mut Svg, tiles: &Tiles, map: &HeatMap) {
    let base = tiles.top + tiles.height();
    let speeds = super::axes::is_speed_bound(&map.x.key);
    for (i, xv) in tiles.xs.iter().enumerate() {
        let mark = if speeds && map.assumed.is_some_and(|va| *xv > va) {
            " (> V_a)"
        } else {
            ""
        };
        let x = tiles.left + CW * i as u32 + CW / 2;
        let label = map.x.value(&xv.to_string());
        svg.text(x, base + 18, MIDDLE, &format!("{label}{mark}"));
    }
    let title = |a: &AxisLabel| {
        if map.titled {
            a.titled()
        } else {
            a.meaning.clone()
        }
    };
    let centre = tiles.left + tiles.width() / 2;
    svg.text(centre, base + 40, MIDDLE, &title(map.x));
    svg.vertical_label(tiles.top + tiles.height() / 2, &title(map.y));
}

/// The colour legend, a swatch and a label per line, from (lx, top).
fn legend(svg: &mut Svg, lx: u32, top: u32) {
    for (k, (c, label)) in LEGEND.iter().enumerate() {
        let y = top + 22 * k as u32;
        svg.rect(lx, y, 14, 14, c, "");
        svg.text(lx + 20, y + 11, "", label);
    }
}
