//! The safe-radius curve ρ*(W) of one slice with that slice's cells overlaid as dots
//! coloured by verdict: the slice under the title, axes with round ticks, the assumed speed
//! V_a as a dashed line, and a short legend. W is the single obstacle's bound, or the bound
//! W_i of the scene obstacle the grid varies.

use std::fmt::Write as _;

use super::CurvePoint;
use super::RADIUS_KEY;
use super::axes::AxisLabel;
use super::cells::{axis_value, sorted_values};
use super::palette::{self, CERTIFIED, NONE};
use super::svg::{END, MIDDLE, Svg, d1};
use crate::analysis::sweep::CellResult;

/// Figure width, in pixels.
const WIDTH: f64 = 640.0;
/// Figure height.
const HEIGHT: f64 = 420.0;
/// Left margin (room for the ρ ticks and title).
const LEFT: f64 = 70.0;
/// Right margin.
const RIGHT: f64 = 30.0;
/// Top margin (room for the title), before the slice's lines.
const TOP: f64 = 40.0;
/// Height of a line of the slice under the title.
const LINE: f64 = 16.0;
/// Bottom margin (room for the W ticks and title).
const BOTTOM: f64 = 60.0;

/// One curve figure: the curve of a slice, and what it holds.
pub(super) struct CurveFigure<'a> {
    /// W and ρ*(W) of the slice.
    pub(super) curve: &'a [CurvePoint],
    /// The speed axis W runs along.
    pub(super) speed: &'a AxisLabel,
    /// The assumed speed V_a in the slice, drawn as a dashed line.
    pub(super) assumed: Option<f64>,
    /// The slice as `label = value` lines (empty when the grid has no other axes).
    pub(super) slice: &'a [String],
}

/// The safe-radius curve of a slice with that slice's cells (`results`) overlaid.
pub(super) fn curve_plot(results: &[CellResult], fig: &CurveFigure) -> String {
    let (curve, speed) = (fig.curve, fig.speed);
    let frame = Frame::new(results, curve, speed, fig.slice.len());
    let w = speed.symbol.as_deref().unwrap_or("W");
    let mut svg = Svg::new(WIDTH as u32, frame.height as u32);
    svg.title(
        WIDTH / 2.0,
        &format!("Smallest certified reaction radius ρ*({w})"),
    );
    for (k, line) in fig.slice.iter().enumerate() {
        let y = TOP + LINE * k as f64 + 4.0;
        svg.text(WIDTH / 2.0, y, MIDDLE, &format!("slice: {line}"));
    }
    axes(&mut svg, &frame);
    let assumed = fig.assumed;
    if let Some(va) = assumed.filter(|va| *va <= frame.wmax) {
        assumption_line(&mut svg, &frame, va);
    }
    curve_line(&mut svg, &frame, curve);
    cell_dots(&mut svg, &frame, results);
    legend(&mut svg, &frame, w);
    svg.finish()
}

/// The data ranges and their mapping to pixels (W to the right, ρ upwards), W's axis, and
/// where the plot starts under the title and the slice's lines.
struct Frame<'a> {
    wmax: f64,
    rmax: f64,
    speed: &'a AxisLabel,
    /// Top edge of the plot.
    top: f64,
    /// Height of the figure.
    height: f64,
}

impl Frame<'_> {
    /// Ranges covering the curve and the cells, ρ with 15% headroom rounded up to 0.1.
    fn new<'a>(
        results: &[CellResult],
        curve: &[CurvePoint],
        speed: &'a AxisLabel,
        slice_lines: usize,
    ) -> Frame<'a> {
        let wmax = curve
            .iter()
            .map(|c| c.0)
            .chain(sorted_values(results, &speed.key))
            .fold(0.0, f64::max);
        let rmax_data = curve
            .iter()
            .filter_map(|c| c.1)
            .chain(sorted_values(results, RADIUS_KEY))
            .fold(0.0, f64::max);
        let rmax = (rmax_data * 1.15 * 10.0).ceil() / 10.0;
        let below = LINE * slice_lines as f64;
        Frame {
            wmax,
            rmax,
            speed,
            top: TOP + below,
            height: HEIGHT + below,
        }
    }

    fn sx(&self, w: f64) -> f64 {
        LEFT + (WIDTH - LEFT - RIGHT) * w / self.wmax.max(1e-9)
    }

    fn sy(&self, r: f64) -> f64 {
        self.height - BOTTOM - (HEIGHT - TOP - BOTTOM) * r / self.rmax.max(1e-9)
    }
}

/// Both axes with their ticks, horizontal grid lines and titles.
fn axes(svg: &mut Svg, f: &Frame) {
    let (top, bottom, right) = (f.top, f.height - BOTTOM, WIDTH - RIGHT);
    svg.path(
        &format!("M{LEFT} {top} V{bottom} H{right}"),
        " fill=\"none\" stroke=\"black\"",
    );
    for w in ticks(f.wmax) {
        svg.text(d1(f.sx(w)), bottom + 18.0, MIDDLE, &tick_label(w));
    }
    for r in ticks(f.rmax) {
        svg.text(LEFT - 6.0, d1(f.sy(r) + 4.0), END, &tick_label(r));
        svg.path(
            &format!("M{LEFT} {} H{right}", d1(f.sy(r))),
            " stroke=\"#e0e0e0\"",
        );
    }
    let centre = (LEFT + right) / 2.0;
    svg.text(centre, f.height - 18.0, MIDDLE, &f.speed.titled());
    svg.vertical_label((top + bottom) / 2.0, "reaction radius ρ (m)");
}

/// The curve through the certified points, and a × at the top where none is certified.
fn curve_line(svg: &mut Svg, f: &Frame, curve: &[CurvePoint]) {
    let mut d = String::new();
    for (w, r) in curve {
        match r {
            Some(r) => {
                let step = if d.is_empty() { "M" } else { "L" };
                let _ = write!(d, "{step}{} {} ", d1(f.sx(*w)), d1(f.sy(*r)));
            }
            None => {
                let attrs = format!("{MIDDLE} fill=\"{NONE}\"");
                svg.text(d1(f.sx(*w)), d1(f.top + 10.0), &attrs, "×");
            }
        }
    }
    let attrs = format!(" fill=\"none\" stroke=\"{CERTIFIED}\" stroke-width=\"2.5\"");
    svg.path(d.trim_end(), &attrs);
}

/// The assumed speed V_a as a dashed vertical line, labelled at the top.
fn assumption_line(svg: &mut Svg, f: &Frame, va: f64) {
    let x = f.sx(va);
    svg.path(
        &format!("M{} {} V{}", d1(x), f.top, f.height - BOTTOM),
        " stroke=\"#888\" stroke-dasharray=\"4 4\"",
    );
    svg.text(d1(x + 4.0), f.top + 12.0, " fill=\"#555\"", "V_a");
}

/// Each cell of the slice on the (W, ρ) plane as a dot in its verdict colour.
fn cell_dots(svg: &mut Svg, f: &Frame, results: &[CellResult]) {
    for r in results {
        if let (Some(w), Some(rho)) = (axis_value(r, &f.speed.key), axis_value(r, RADIUS_KEY)) {
            let (cx, cy) = (d1(f.sx(w)), d1(f.sy(rho)));
            let ring = " stroke=\"black\" stroke-width=\"0.5\"";
            svg.circle(cx, cy, 5, palette::color(r), ring);
        }
    }
}

/// What the line, the crosses and the dots mean, top left inside the axes.
fn legend(svg: &mut Svg, f: &Frame, w: &str) {
    let (lx, top) = (LEFT + 12.0, f.top);
    let certified = format!(" fill=\"{CERTIFIED}\"");
    let none = format!(" fill=\"{NONE}\"");
    svg.text(
        lx,
        top + 14.0,
        &certified,
        &format!("— ρ*({w}): certified above the curve"),
    );
    svg.text(lx, top + 30.0, &none, "× no radius is certified");
    let dots = if f.top > TOP {
        "● the slice's cells, coloured by verdict"
    } else {
        "● grid cells, coloured by verdict"
    };
    svg.text(lx, top + 46.0, "", dots);
}

/// Round tick values from 0 to `max`: steps of 1, 2 or 5 times a power of ten, at most 8.
fn ticks(max: f64) -> Vec<f64> {
    if max.is_nan() || max <= 0.0 {
        return vec![0.0];
    }
    let raw = max / 8.0;
    let p = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * p)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * p);
    (0..)
        .map(|i| f64::from(i) * step)
        .take_while(|v| *v <= max * (1.0 + 1e-9))
        .collect()
}

/// A tick value with at most three decimals and no trailing zeros.
fn tick_label(v: f64) -> String {
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}
