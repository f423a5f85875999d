//! The safe-radius curve ρ*(W) with the grid's cells overlaid as dots coloured by verdict:
//! axes with round ticks, the assumed speed V_a as a dashed line, and a short legend. W is
//! the single obstacle's bound, or the bound W_i of the scene obstacle the grid varies.

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
/// Top margin (room for the title).
const TOP: f64 = 40.0;
/// Bottom margin (room for the W ticks and title).
const BOTTOM: f64 = 60.0;

/// The safe-radius curve over the speed axis `speed` with the grid's cells overlaid.
pub(super) fn curve_plot(
    results: &[CellResult],
    curve: &[CurvePoint],
    speed: &AxisLabel,
    assumed: Option<f64>,
) -> String {
    let frame = Frame::new(results, curve, speed);
    let w = speed.symbol.as_deref().unwrap_or("W");
    let mut svg = Svg::new(WIDTH as u32, HEIGHT as u32);
    svg.title(
        WIDTH / 2.0,
        &format!("Smallest certified reaction radius ρ*({w})"),
    );
    axes(&mut svg, &frame);
    if let Some(va) = assumed.filter(|va| *va <= frame.wmax) {
        assumption_line(&mut svg, &frame, va);
    }
    curve_line(&mut svg, &frame, curve);
    cell_dots(&mut svg, &frame, results);
    legend(&mut svg, w);
    svg.finish()
}

/// The data ranges and their mapping to pixels (W to the right, ρ upwards), and W's axis.
struct Frame<'a> {
    wmax: f64,
    rmax: f64,
    speed: &'a AxisLabel,
}

impl Frame<'_> {
    /// Ranges covering the curve and the cells, ρ with 15% headroom rounded up to 0.1.
    fn new<'a>(results: &[CellResult], curve: &[CurvePoint], speed: &'a AxisLabel) -> Frame<'a> {
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
        Frame { wmax, rmax, speed }
    }

    fn sx(&self, w: f64) -> f64 {
        LEFT + (WIDTH - LEFT - RIGHT) * w / self.wmax.max(1e-9)
    }

    fn sy(&self, r: f64) -> f64 {
        HEIGHT - BOTTOM - (HEIGHT - TOP - BOTTOM) * r / self.rmax.max(1e-9)
    }
}

/// Both axes with their ticks, horizontal grid lines and titles.
fn axes(svg: &mut Svg, f: &Frame) {
    let (bottom, right) = (HEIGHT - BOTTOM, WIDTH - RIGHT);
    svg.path(
        &format!("M{LEFT} {TOP} V{bottom} H{right}"),
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
    svg.text(centre, HEIGHT - 18.0, MIDDLE, &f.speed.titled());
    svg.vertical_label((TOP + bottom) / 2.0, "reaction radius ρ (m)");
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
                svg.text(d1(f.sx(*w)), d1(TOP + 10.0), &attrs, "×");
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
        &format!("M{} {TOP} V{}", d1(x), HEIGHT - BOTTOM),
        " stroke=\"#888\" stroke-dasharray=\"4 4\"",
    );
    svg.text(d1(x + 4.0), TOP + 12.0, " fill=\"#555\"", "V_a");
}

/// Each cell on the (W, ρ) plane as a dot in its verdict colour.
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
fn legend(svg: &mut Svg, w: &str) {
    let lx = LEFT + 12.0;
    let certified = format!(" fill=\"{CERTIFIED}\"");
    let none = format!(" fill=\"{NONE}\"");
    svg.text(
        lx,
        TOP + 14.0,
        &certified,
        &format!("— ρ*({w}): certified above the curve"),
    );
    svg.text(lx, TOP + 30.0, &none, "× no radius is certified");
    svg.text(lx, TOP + 46.0, "", "● grid cells, coloured by verdict");
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
