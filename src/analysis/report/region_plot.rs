//! The certified map of a plane: a region map's leaves as rectangles coloured by verdict, the
//! first ranged parameter across and the second up, with a legend, the shares of the plane
//! and the problem's fixed numbers in a caption. Point cells (a sweep's) can be overlaid as
//! dots coloured by their own verdict.
//!
//! With more than two ranged parameters the map is projected onto the plane: leaves are
//! painted certified first, then undecided, then refuted, so a colour shows the worst
//! verdict over the other parameters (the caption says so).

use super::palette::CERTIFIED;
use super::svg::{END, MIDDLE, Svg};
use crate::analysis::Verdict;
use crate::core::param_box::Axis;
use crate::proof::region_map::{LeafVerdict, RegionMap};

const REFUTED: &str = "#d64b2b";
const UNDECIDED: &str = "#b8b8b8";
/// Plot area, in pixels.
const W: f64 = 560.0;
const H: f64 = 420.0;
const LEFT: f64 = 80.0;
const TOP: f64 = 60.0;

/// A point cell drawn over the map: (x value, y value, its verdict).
pub type PointCell = (f64, f64, Verdict);

/// The map of the first two ranged parameters.
pub fn svg(map: &RegionMap) -> String {
    svg_with_points(map, &[])
}

/// The map with point cells overlaid.
pub fn svg_with_points(map: &RegionMap, points: &[PointCell]) -> String {
    let (xa, ya) = (map.ranges[0], map.ranges[1]);
    let caption = caption(map);
    let mut svg = Svg::new(
        (LEFT + W + 240.0) as u32,
        (TOP + H + 70.0) as u32 + 16 * caption.len() as u32,
    );
    svg.title(
        (LEFT + W / 2.0) as u32,
        &format!(
            "Region certificates over {} × {}: certified {:.1}%, refuted {:.1}%, undecided {:.1}%",
            symbol(&xa),
            symbol(&ya),
            100.0 * map.coverage.certified,
            100.0 * map.coverage.refuted,
            100.0 * map.coverage.undecided
        ),
    );
    let sx = |v: f64| LEFT + W * frac(v, &xa);
    let sy = |v: f64| TOP + H * (1.0 - frac(v, &ya));
    for pass in [
        LeafVerdict::Certified,
        LeafVerdict::Undecided,
        LeafVerdict::Refuted,
    ] {
        for leaf in map.leaves.iter().filter(|l| l.verdict == pass) {
            let [x0, x1] = leaf.bounds[&xa.key()];
            let [y0, y1] = leaf.bounds[&ya.key()];
            let fill = match pass {
                LeafVerdict::Certified => CERTIFIED,
                LeafVerdict::Refuted => REFUTED,
                LeafVerdict::Undecided => UNDECIDED,
            };
            svg.area(
                sx(x0),
                sy(y1),
                sx(x1) - sx(x0),
                sy(y0) - sy(y1),
                fill,
                " stroke=\"white\" stroke-width=\"0.3\"",
            );
        }
    }
    for &(x, y, verdict) in points {
        let fill = match verdict {
            Verdict::Certified => CERTIFIED,
            Verdict::Refuted => REFUTED,
            Verdict::Inconclusive => UNDECIDED,
        };
        svg.circle(
            format!("{:.1}", sx(x)),
            format!("{:.1}", sy(y)),
            5,
            fill,
            " stroke=\"black\" stroke-width=\"1.5\"",
        );
    }
    frame_and_ticks(&mut svg, &xa, &ya);
    legend(&mut svg, !points.is_empty());
    let mut y = TOP + H + 62.0;
    for line in caption {
        svg.text(LEFT as u32, y as u32, "", &line);
        y += 16.0;
    }
    svg.finish()
}

fn frac(v: f64, a: &Axis) -> f64 {
    if a.hi > a.lo {
        (v - a.lo) / (a.hi - a.lo)
    } else {
        0.5
    }
}

/// The axis's symbol: an obstacle's own numbers carry its index (W_1).
fn symbol(a: &Axis) -> String {
    match a.obstacle {
        Some(i) => format!("{}_{i}", a.parameter.symbol()),
        None => a.parameter.symbol().to_string(),
    }
}

fn label(a: &Axis) -> String {
    format!("{} {} ({})", a.key(), symbol(a), a.parameter.unit())
}

fn frame_and_ticks(svg: &mut Svg, xa: &Axis, ya: &Axis) {
    svg.path(
        &format!("M{LEFT} {TOP} h{W} v{H} h-{W} Z"),
        " fill=\"none\" stroke=\"black\"",
    );
    for k in 0..=4 {
        let f = f64::from(k) / 4.0;
        let xv = xa.lo + f * (xa.hi - xa.lo);
        let yv = ya.lo + f * (ya.hi - ya.lo);
        let (px, py) = (LEFT + W * f, TOP + H * (1.0 - f));
        svg.path(&format!("M{px:.1} {} v6", TOP + H), " stroke=\"black\"");
        svg.text(
            format!("{px:.1}"),
            (TOP + H + 20.0) as u32,
            MIDDLE,
            &tick(xv),
        );
        svg.path(&format!("M{} {py:.1} h-6", LEFT), " stroke=\"black\"");
        svg.text(
            (LEFT - 9.0) as u32,
            format!("{:.1}", py + 4.0),
            END,
            &tick(yv),
        );
    }
    svg.text(
        (LEFT + W / 2.0) as u32,
        (TOP + H + 42.0) as u32,
        MIDDLE,
        &label(xa),
    );
    svg.vertical_label((TOP + H / 2.0) as u32, &label(ya));
}

/// A tick value: up to four decimals, without trailing zeros.
fn tick(v: f64) -> String {
    let s = format!("{v:.4}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

fn legend(svg: &mut Svg, points: bool) {
    let x = (LEFT + W + 20.0) as u32;
    let mut y = TOP as u32;
    for (fill, what) in [
        (CERTIFIED, "certified (whole leaf)"),
        (REFUTED, "refuted (at a named point)"),
        (UNDECIDED, "undecided"),
    ] {
        svg.rect(x, y, 14, 14, fill, "");
        svg.text(x + 20, y + 11, "", what);
        y += 22;
    }
    if points {
        svg.circle(
            x + 7,
            y + 7,
            5,
            "white",
            " stroke=\"black\" stroke-width=\"1.5\"",
        );
        svg.text(x + 20, y + 11, "", "grid point (its verdict)");
    }
}

/// The problem's (or scene's) fixed numbers, and how more than two ranged parameters are
/// shown.
fn caption(map: &RegionMap) -> Vec<String> {
    let ranged = |key: &str| map.ranges.iter().any(|a| a.key() == key);
    let scene = map.scene.clone();
    let problem = map.problem.clone();
    let (robot, controller, kind) = match (&problem, &scene) {
        (Some(p), _) => (&p.robot, &p.controller, "problem"),
        (None, Some(s)) => (&s.robot, &s.controller, "scene"),
        (None, None) => return Vec::new(),
    };
    let p = (robot, controller);
    let robot_numbers = [
        format!("v_max = {} m/s", p.0.max_speed),
        format!("a = {} m/s²", p.0.acceleration),
        format!("b = {} m/s²", p.0.braking),
        format!("dt = {} s", p.0.control_period),
        format!("L = {} periods", p.0.latency),
    ];
    let mut named: Vec<(String, String)> = Vec::new();
    if let Some(pr) = &problem {
        named.push((
            "environment.obstacle_speed".into(),
            format!("W = {} m/s", pr.environment.obstacle_speed),
        ));
    }
    named.extend([
        (
            "controller.reaction_radius".to_string(),
            format!("ρ = {} m", p.1.reaction_radius),
        ),
        (
            "controller.assumed_obstacle_speed".into(),
            format!("V_a = {} m/s", p.1.assumed_obstacle_speed),
        ),
        (
            "controller.buffer".into(),
            format!("buffer = {} m", p.1.buffer),
        ),
    ]);
    if let Some(pr) = &problem {
        named.push((
            "environment.initial_gap".into(),
            format!("g0 = {} m", pr.environment.initial_gap.min()),
        ));
    }
    named.push((
        "robot.clearance".into(),
        format!("clearance = {} m", p.0.clearance),
    ));
    if let Some(sc) = &scene {
        for (i, o) in sc.obstacles.iter().enumerate() {
            named.push((
                format!("obstacle.{i}.position"),
                format!(
                    "{i} ({}) at x = {} m in lane {}",
                    o.name,
                    o.position.min(),
                    o.lane
                ),
            ));
            let speed = if o.is_static {
                "static".to_string()
            } else {
                format!("W_{i} = {} m/s", o.max_speed)
            };
            named.push((format!("obstacle.{i}.max_speed"), speed));
        }
    }
    let robot = robot_numbers;
    let p_name = map.name();
    let p_controller = p.1;
    let fixed: Vec<String> = named
        .into_iter()
        .filter(|(k, _)| !ranged(k))
        .map(|(_, v)| v)
        .collect();
    let mut lines = vec![
        format!("{kind} {p_name}: robot {}", robot.join(", ")),
        format!("fixed: {}", fixed.join(", ")),
        format!(
            "danger rule {:?}, wrong-assumption brake {}; {} leaves, depth ≤ {}",
            p_controller.danger_rule,
            if p_controller.wrong_assumption_brake {
                "on"
            } else {
                "off"
            },
            map.leaves.len(),
            map.depth
        )
        .to_lowercase(),
    ];
    if map.ranges.len() > 2 {
        let others: Vec<String> = map.ranges[2..]
            .iter()
            .map(|a| format!("{} in [{}, {}]", a.key(), a.lo, a.hi))
            .collect();
        lines.push(format!(
            "projected over {}: a colour is the worst verdict over them",
            others.join(", ")
        ));
    }
    lines
}
