//! A report's figures, one per slice: the verdict heat maps over two axes (one per slice of
//! the axes they do not span) and the safe-radius curves (one per slice of the axes other
//! than W and ρ), each drawing only its own slice's cells and naming the slice; and the
//! page's lines linking them, or saying why there is no heat map.

use std::fmt::Write as _;

use super::axes::{AxisLabel, Slice, heat_map_axes, in_slice, label, slices};
use super::curve_plot::{CurveFigure, curve_plot};
use super::heat_map::{HeatMap, heat_map};
use super::{ASSUMED_KEY, Curve, MAX_MAPS, RADIUS_KEY, SPEED_KEY};
use crate::analysis::sweep::{CellResult, Grid};

/// Draws the heat maps and the curves, links them from the page, and returns them (file
/// name, SVG). A grid without two numeric axes of more than one value says why it has no
/// heat map.
pub(super) fn write_figures(
    md: &mut String,
    grid: &Grid,
    results: &[CellResult],
    curve: &Curve,
    assumed: Option<f64>,
) -> Vec<(String, String)> {
    let mut figures = Vec::new();
    match heat_map_axes(grid) {
        Ok((x, y)) => {
            let (xl, yl) = (label(grid, &x), label(grid, &y));
            // The paper's (W, ρ) maps keep units in their ticks only, as they always had.
            let titled = grid.kind != crate::core::grid::BaseKind::Problem
                || (x.as_str(), y.as_str()) != (SPEED_KEY, RADIUS_KEY);
            let all = slices(grid, &x, &y);
            let drawn: Vec<Slice> = all.iter().take(MAX_MAPS).cloned().collect();
            let kind = Kind {
                file: "verdicts",
                alt: "verdicts per cell",
            };
            let mut draw = |slice: &Slice, lines: &[String]| {
                let map = HeatMap {
                    x: &xl,
                    y: &yl,
                    slice: lines.to_vec(),
                    titled,
                    assumed: slice_assumed(slice).or(assumed),
                };
                heat_map(&slice_cells(results, slice), &map)
            };
            let series = (drawn.as_slice(), all.len());
            per_slice(md, grid, &kind, series, &mut figures, &mut draw);
        }
        Err(why) => {
            let _ = writeln!(md, "\nNo heat map: {why}.\n");
        }
    }
    if let Curve::Radius { key, slices, total } = curve {
        let speed: AxisLabel = label(grid, key);
        let drawn: Vec<Slice> = slices.iter().map(|c| c.slice.clone()).collect();
        let kind = Kind {
            file: "radius",
            alt: "safe radius curve",
        };
        let mut curves = slices.iter();
        let mut draw = |slice: &Slice, lines: &[String]| {
            let points = curves.next().map(|c| c.points.as_slice()).unwrap_or(&[]);
            let fig = CurveFigure {
                curve: points,
                speed: &speed,
                assumed: slice_assumed(slice).or(assumed),
                slice: lines,
            };
            curve_plot(&slice_cells(results, slice), &fig)
        };
        let series = (drawn.as_slice(), *total);
        per_slice(md, grid, &kind, series, &mut figures, &mut draw);
    }
    figures
}

/// What a series of per-slice figures is called: its file name part and its alt text.
struct Kind {
    file: &'static str,
    alt: &'static str,
}

/// One figure per slice in `drawn` (the first of `total`), drawn by `draw` from the slice
/// and its lines, linked from the page; the page says when some are left out.
fn per_slice(
    md: &mut String,
    grid: &Grid,
    kind: &Kind,
    (drawn, total): (&[Slice], usize),
    figures: &mut Vec<(String, String)>,
    draw: &mut dyn FnMut(&Slice, &[String]) -> String,
) {
    let name = &grid.name;
    for (k, slice) in drawn.iter().enumerate() {
        let lines = slice_lines(grid, slice);
        let (file, alt) = if total == 1 {
            (format!("{name}-{}.svg", kind.file), kind.alt.to_string())
        } else {
            (
                format!("{name}-{}-{}.svg", kind.file, k + 1),
                format!("{}, slice {}", kind.alt, lines.join(", ")),
            )
        };
        figures.push((file.clone(), draw(slice, &lines)));
        let gap = if k == 0 && !md.ends_with("\n\n") {
            "\n"
        } else {
            ""
        };
        let _ = writeln!(md, "{gap}![{alt}]({file})\n");
    }
    if total > drawn.len() {
        let _ = writeln!(
            md,
            "The grid has {total} slices across its other axes; the first {} are drawn, the \
             table below has every cell.\n",
            drawn.len()
        );
    }
}

/// The cells of a slice, in cell order.
fn slice_cells(results: &[CellResult], slice: &Slice) -> Vec<CellResult> {
    results
        .iter()
        .filter(|r| in_slice(r, slice))
        .cloned()
        .collect()
}

/// A slice as `meaning = value unit` lines, one per axis it holds.
pub(super) fn slice_lines(grid: &Grid, slice: &Slice) -> Vec<String> {
    slice
        .iter()
        .map(|(k, v)| {
            let l: AxisLabel = label(grid, k);
            format!("{} = {}", l.meaning, l.value(&v.to_string()))
        })
        .collect()
}

/// The assumed speed a slice holds, when it holds one.
fn slice_assumed(slice: &Slice) -> Option<f64> {
    slice
        .iter()
        .find(|(k, _)| k == ASSUMED_KEY)
        .and_then(|(_, v)| v.as_f64())
}
