//! The worst case of a planar problem seen from above (issue 36): the path, the robot's
//! disc every few steps and at the closest instant, the danger zone when the robot brakes,
//! each obstacle's trajectory and disc, the closest approach, a scale bar and a legend.
//! Equal scales on both axes, x to the right and y up, in metres; positions are the exact
//! replay's, rounded to floats for drawing (the robot between step starts is interpolated
//! linearly, which the figure says).

use crate::analysis::planar::PlanarTraceRow;
use crate::core::planar::{DangerZone, PlanarParams};

use super::svg::{END, MIDDLE, Svg};

const WIDTH: u32 = 820;
const HEIGHT: u32 = 620;
const LEFT: f64 = 60.0;
const RIGHT: f64 = 210.0;
const TOP: f64 = 44.0;
const BOTTOM: f64 = 64.0;
const ROBOT: &str = "#3b6fb6";
const OBSTACLES: [&str; 4] = ["#c53030", "#2f855a", "#b7791f", "#6b46c1"];
const ZONE: &str = "#dd6b20";
const PATH: &str = "#808080";

/// What the figure shows besides the trace.
pub struct TopViewLabels<'a> {
    /// The title (the problem and its verdict).
    pub title: &'a str,
    /// The closest obstacle's index and instant (s), with its separation (m).
    pub closest: Option<(usize, f64, f64)>,
    /// The step the robot braked at.
    pub brake_step: Option<usize>,
}

/// The top view of the replay `rows` of `params` (see the module docs) as SVG.
pub fn top_view(params: &PlanarParams, rows: &[PlanarTraceRow], labels: &TopViewLabels) -> String {
    let n = params.obstacles.len().max(1);
    let steps: Vec<&[PlanarTraceRow]> = rows.chunks(n).collect();
    let rr = params.robot_radius.to_f64().value();
    let radii: Vec<f64> = params
        .obstacles
        .iter()
        .map(|o| o.radius.to_f64().value())
        .collect();
    let big = radii.iter().fold(rr, |a, b| a.max(*b));
    // The world box: everything drawn, with the largest disc around it. The path is drawn
    // near what moves only (the seed's runs along the x axis for 10⁵ m).
    let mut xs: Vec<f64> = Vec::new();
    let mut ys: Vec<f64> = Vec::new();
    for r in rows {
        xs.extend([r.robot_x, r.x]);
        ys.extend([r.robot_y, r.y]);
    }
    let path = clipped(&path_points(params), &near(&xs, &ys));
    for &(x, y) in path.iter().flatten() {
        xs.push(x);
        ys.push(y);
    }
    let lo = |v: &[f64]| v.iter().cloned().fold(f64::INFINITY, f64::min) - big - 0.5;
    let hi = |v: &[f64]| v.iter().cloned().fold(f64::NEG_INFINITY, f64::max) + big + 0.5;
    let (x0, x1, y0, y1) = (lo(&xs), hi(&xs), lo(&ys), hi(&ys));
    let plot_w = f64::from(WIDTH) - LEFT - RIGHT;
    let plot_h = f64::from(HEIGHT) - TOP - BOTTOM;
    let scale = (plot_w / (x1 - x0)).min(plot_h / (y1 - y0));
    let px = |x: f64| LEFT + (x - x0) * scale;
    let py = |y: f64| TOP + plot_h - (y - y0) * scale;
    let mut svg = Svg::new(WIDTH, HEIGHT);
    svg.title(LEFT + plot_w / 2.0, labels.title);
    svg.area(LEFT, TOP, plot_w, plot_h, "none", " stroke=\"#cccccc\"");
    // The path.
    for piece in &path {
        let d = polyline(piece.iter().map(|&(x, y)| (px(x), py(y))));
        svg.path(
            &d,
            &format!(" fill=\"none\" stroke=\"{PATH}\" stroke-dasharray=\"6 4\""),
        );
    }
    // The danger zone at the brake step, about the robot's centre then.
    if let Some(k) = labels.brake_step
        && let Some(at) = steps.get(k).and_then(|s| s.first())
    {
        zone(&mut svg, params, at, &px, &py, scale);
    }
    // Discs every few steps, then the trajectories over them.
    let every = (steps.len() / 12).max(1);
    for s in steps.iter().step_by(every) {
        let Some(first) = s.first() else { continue };
        let stroke = format!(" stroke=\"{ROBOT}\" stroke-opacity=\"0.5\"");
        svg.disc(
            px(first.robot_x),
            py(first.robot_y),
            rr * scale,
            "none",
            &stroke,
        );
        for (i, row) in s.iter().enumerate() {
            let c = OBSTACLES[i % OBSTACLES.len()];
            let stroke = format!(" stroke=\"{c}\" stroke-opacity=\"0.5\"");
            svg.disc(px(row.x), py(row.y), radii[i] * scale, "none", &stroke);
        }
    }
    let robot_track = polyline(
        steps
            .iter()
            .filter_map(|s| s.first())
            .map(|r| (px(r.robot_x), py(r.robot_y))),
    );
    svg.path(
        &robot_track,
        &format!(" fill=\"none\" stroke=\"{ROBOT}\" stroke-width=\"2\""),
    );
    for i in 0..params.obstacles.len() {
        let c = OBSTACLES[i % OBSTACLES.len()];
        let track = polyline(
            steps
                .iter()
                .filter_map(|s| s.get(i))
                .map(|r| (px(r.x), py(r.y))),
        );
        svg.path(
            &track,
            &format!(" fill=\"none\" stroke=\"{c}\" stroke-width=\"2\""),
        );
    }
    // The closest instant: both discs filled, their centres joined.
    if let Some((i, t, sep)) = labels.closest
        && let Some((robot, obstacle)) = at_instant(&steps, i, t, params.motion.dt.to_f64().value())
    {
        let c = OBSTACLES[i % OBSTACLES.len()];
        svg.disc(
            px(robot.0),
            py(robot.1),
            rr * scale,
            ROBOT,
            " fill-opacity=\"0.45\"",
        );
        svg.disc(
            px(obstacle.0),
            py(obstacle.1),
            radii[i] * scale,
            c,
            " fill-opacity=\"0.45\"",
        );
        let d = format!(
            "M{:.1} {:.1} L{:.1} {:.1}",
            px(robot.0),
            py(robot.1),
            px(obstacle.0),
            py(obstacle.1)
        );
        svg.path(&d, " stroke=\"black\" stroke-width=\"1.5\"");
        svg.text(
            LEFT + plot_w / 2.0,
            f64::from(HEIGHT) - 12.0,
            MIDDLE,
            &format!("closest: separation {sep:.4} m at t = {t:.3} s (robot between step starts drawn linearly)"),
        );
    }
    scale_bar(&mut svg, scale, LEFT, TOP + plot_h + 30.0);
    axis_ticks(
        &mut svg,
        (x0, x1),
        (y0, y1),
        &px,
        &py,
        (LEFT, TOP, plot_w, plot_h),
    );
    legend(&mut svg, params, labels, LEFT + plot_w + 20.0);
    svg.finish()
}

fn path_points(params: &PlanarParams) -> Vec<(f64, f64)> {
    let mut out = vec![(0.0, 0.0)];
    let mut s = crate::core::num::Exact::ZERO;
    for arc in params.path.vertex_arcs() {
        s = arc.clone();
        let p = params.path.point_at(&s).to_f64();
        out.push(p);
    }
    let end = params.path.length();
    if end > s {
        out.push(params.path.point_at(&end).to_f64());
    }
    out
}

/// The box (x0, x1, y0, y1) the path is drawn in: the points' box grown by half its
/// larger side, at least 2 m.
fn near(xs: &[f64], ys: &[f64]) -> (f64, f64, f64, f64) {
    let span = |v: &[f64]| {
        let lo = v.iter().cloned().fold(f64::INFINITY, f64::min);
        let hi = v.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        if lo <= hi { (lo, hi) } else { (0.0, 0.0) }
    };
    let ((x0, x1), (y0, y1)) = (span(xs), span(ys));
    let grow = (0.5 * (x1 - x0).max(y1 - y0)).max(2.0);
    (x0 - grow, x1 + grow, y0 - grow, y1 + grow)
}

/// The polyline `points` cut to the box `b` (x0, x1, y0, y1): its pieces inside, in order.
fn clipped(points: &[(f64, f64)], b: &(f64, f64, f64, f64)) -> Vec<Vec<(f64, f64)>> {
    let mut pieces: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut open = false;
    for w in points.windows(2) {
        let Some((p, q)) = clip_segment(w[0], w[1], b) else {
            open = false;
            continue;
        };
        match pieces.last_mut() {
            Some(piece) if open && piece.last() == Some(&p) => piece.push(q),
            _ => pieces.push(vec![p, q]),
        }
        // The piece continues only when the segment ends inside the box.
        open = q == w[1];
    }
    pieces
}

/// The part of segment p–q inside the box `b` (Liang–Barsky), if any.
fn clip_segment(
    p: (f64, f64),
    q: (f64, f64),
    &(x0, x1, y0, y1): &(f64, f64, f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (q.0 - p.0, q.1 - p.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (d, room) in [
        (-dx, p.0 - x0),
        (dx, x1 - p.0),
        (-dy, p.1 - y0),
        (dy, y1 - p.1),
    ] {
        if d == 0.0 {
            if room < 0.0 {
                return None;
            }
        } else {
            let t = room / d;
            if d < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    let at = |t: f64| {
        if t == 0.0 {
            p
        } else if t == 1.0 {
            q
        } else {
            (p.0 + t * dx, p.1 + t * dy)
        }
    };
    (t0 <= t1).then(|| (at(t0), at(t1)))
}

fn polyline(points: impl Iterator<Item = (f64, f64)>) -> String {
    let mut d = String::new();
    for (k, (x, y)) in points.enumerate() {
        d += &format!("{}{x:.1} {y:.1} ", if k == 0 { "M" } else { "L" });
    }
    d.trim_end().to_string()
}

/// The robot's and obstacle `i`'s centres at instant `t`, interpolated between step starts.
fn at_instant(
    steps: &[&[PlanarTraceRow]],
    i: usize,
    t: f64,
    dt: f64,
) -> Option<((f64, f64), (f64, f64))> {
    let k = ((t / dt).floor().max(0.0) as usize).min(steps.len().saturating_sub(1));
    let a = steps.get(k)?.get(i)?;
    let b = steps.get(k + 1).and_then(|s| s.get(i)).unwrap_or(a);
    let f = ((t - a.t) / dt).clamp(0.0, 1.0);
    let mix = |u: f64, v: f64| u + (v - u) * f;
    Some((
        (mix(a.robot_x, b.robot_x), mix(a.robot_y, b.robot_y)),
        (mix(a.x, b.x), mix(a.y, b.y)),
    ))
}

fn zone(
    svg: &mut Svg,
    params: &PlanarParams,
    at: &PlanarTraceRow,
    px: &dyn Fn(f64) -> f64,
    py: &dyn Fn(f64) -> f64,
    scale: f64,
) {
    let outline = format!(" fill-opacity=\"0.12\" stroke=\"{ZONE}\" stroke-dasharray=\"4 3\"");
    match &params.zone {
        DangerZone::Disc => {
            let rho = params.motion.rho.to_f64().value();
            svg.disc(px(at.robot_x), py(at.robot_y), rho * scale, ZONE, &outline);
        }
        DangerZone::Polygon(q) => {
            // The zone in the robot's frame then: rotated by the path's heading.
            let (c, s) = heading_at(params, at);
            let points = q.vertices().iter().map(|v| {
                let (vx, vy) = v.to_f64();
                (
                    px(at.robot_x + c * vx - s * vy),
                    py(at.robot_y + s * vx + c * vy),
                )
            });
            let d = polyline(points) + " Z";
            svg.path(&d, &format!(" fill=\"{ZONE}\"{outline}"));
        }
    }
}

/// The path's heading (cos, sin) at the robot's centre in `at` (the nearest segment).
fn heading_at(params: &PlanarParams, at: &PlanarTraceRow) -> (f64, f64) {
    let points = path_points(params);
    let mut best = (f64::INFINITY, (1.0, 0.0));
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = dx.hypot(dy);
        if len == 0.0 {
            continue;
        }
        let u = (((at.robot_x - a.0) * dx + (at.robot_y - a.1) * dy) / (len * len)).clamp(0.0, 1.0);
        let d = (at.robot_x - a.0 - u * dx).hypot(at.robot_y - a.1 - u * dy);
        if d < best.0 {
            best = (d, (dx / len, dy / len));
        }
    }
    best.1
}

/// A bar of a round length (1, 2 or 5 × 10ⁿ m) near 1/5 of the plot's width.
fn scale_bar(svg: &mut Svg, scale: f64, x: f64, y: f64) {
    let target = 150.0 / scale;
    let p = 10f64.powf(target.log10().floor());
    let len = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .rfind(|l| *l <= target)
        .unwrap_or(p);
    let w = len * scale;
    svg.path(
        &format!("M{x:.1} {y:.1} L{:.1} {y:.1}", x + w),
        " stroke=\"black\" stroke-width=\"3\"",
    );
    svg.text(x + w / 2.0, y - 6.0, MIDDLE, &format!("{len} m"));
}

fn axis_ticks(
    svg: &mut Svg,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    px: &dyn Fn(f64) -> f64,
    py: &dyn Fn(f64) -> f64,
    (left, top, w, h): (f64, f64, f64, f64),
) {
    let step = |span: f64| {
        let raw = span / 8.0;
        let p = 10f64.powf(raw.log10().floor());
        [1.0, 2.0, 5.0, 10.0]
            .into_iter()
            .map(|m| m * p)
            .find(|s| *s >= raw)
            .unwrap_or(p)
    };
    let sx = step(x1 - x0);
    let mut x = (x0 / sx).ceil() * sx;
    while x <= x1 {
        svg.text(
            format!("{:.1}", px(x)),
            format!("{:.1}", top + h + 14.0),
            MIDDLE,
            &format!("{x}"),
        );
        x += sx;
    }
    let sy = step(y1 - y0);
    let mut y = (y0 / sy).ceil() * sy;
    while y <= y1 {
        svg.text(
            format!("{:.1}", left - 6.0),
            format!("{:.1}", py(y) + 4.0),
            END,
            &format!("{y}"),
        );
        y += sy;
    }
    svg.text(
        format!("{:.1}", left + w - 4.0),
        format!("{:.1}", top + h - 6.0),
        END,
        "x (m)",
    );
    svg.text(
        format!("{:.1}", left + 6.0),
        format!("{:.1}", top + 14.0),
        "",
        "y (m)",
    );
}

fn legend(svg: &mut Svg, params: &PlanarParams, labels: &TopViewLabels, x: f64) {
    let mut y = TOP + 10.0;
    let mut item = |svg: &mut Svg, color: &str, dashed: bool, text: &str| {
        let dash = if dashed {
            " stroke-dasharray=\"6 4\""
        } else {
            ""
        };
        svg.path(
            &format!("M{x:.1} {y:.1} L{:.1} {y:.1}", x + 24.0),
            &format!(" stroke=\"{color}\" stroke-width=\"2\"{dash}"),
        );
        svg.text(
            format!("{:.1}", x + 30.0),
            format!("{:.1}", y + 4.0),
            "",
            text,
        );
        y += 20.0;
    };
    item(svg, PATH, true, "path");
    item(svg, ROBOT, false, "robot centre, disc every few steps");
    for (i, o) in params.obstacles.iter().enumerate() {
        item(svg, OBSTACLES[i % OBSTACLES.len()], false, &o.name);
    }
    if labels.brake_step.is_some() {
        let what = match params.zone {
            DangerZone::Disc => "reaction radius at the brake",
            DangerZone::Polygon(_) => "stop polygon at the brake",
        };
        item(svg, ZONE, true, what);
    }
    if labels.closest.is_some() {
        item(svg, "black", false, "closest approach (filled discs)");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A path inside the box is drawn whole; one that runs far out is cut at the box's edge,
    /// and one that leaves and comes back is drawn as two pieces.
    #[test]
    fn the_path_is_cut_to_the_box_it_is_drawn_in() {
        let b = (-1.0, 11.0, -2.0, 2.0);
        let inside = [(0.0, 0.0), (5.0, 0.0), (5.0, 1.0)];
        assert_eq!(clipped(&inside, &b), vec![inside.to_vec()]);
        let seed = [(0.0, 0.0), (100_000.0, 0.0)];
        assert_eq!(clipped(&seed, &b), vec![vec![(0.0, 0.0), (11.0, 0.0)]]);
        let out_and_back = [(0.0, 0.0), (0.0, 4.0), (4.0, 4.0), (4.0, 0.0)];
        assert_eq!(
            clipped(&out_and_back, &b),
            vec![vec![(0.0, 0.0), (0.0, 2.0)], vec![(4.0, 2.0), (4.0, 0.0)]]
        );
        assert!(clipped(&[(20.0, 0.0), (30.0, 0.0)], &b).is_empty());
    }
}
