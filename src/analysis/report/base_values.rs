//! What the cells hold fixed: the base problem's, scene's or planar problem's keys as the
//! report lists them under the axes — the robot, the controller, the environment (and a
//! scene's lanes and obstacles, a planar problem's path, zone, sensing and obstacles) — each with its meaning and unit from the same tables the figures use, the
//! keys the grid varies marked.

use std::fmt::Write as _;

use super::axes::label;
use crate::analysis::sweep::Grid;
use crate::core::grid::BaseKind;
use crate::core::model::keys::KEYS;
use crate::core::planar::keys::PLANAR_KEYS;
use crate::core::planar::{PlanarObstacleFile, PlanarProblem, StartFile};
use crate::core::scene::keys::SCENE_KEYS;
use crate::core::scene::{Obstacle, Scene};

/// The marker of a key the grid gives more than one value.
const VARIED: &str = "(varied: see axes)";

/// Writes the base's keys as a table (every key its file sets or an axis names, in file
/// order), then a scene's obstacles.
pub(super) fn write_base_values(md: &mut String, grid: &Grid, file: &str) {
    let Ok(doc) = grid.base_text.parse::<toml::Table>() else {
        return;
    };
    let what = grid.kind.as_str();
    let _ = writeln!(
        md,
        "\nThe base {what} `{file}`: every key it sets (keys it leaves out take their \
         defaults); a key an axis names takes the axis' values instead.\n"
    );
    let _ = writeln!(md, "| key | meaning | value |\n|---|---|---|");
    let keys = KEYS
        .iter()
        .chain(SCENE_KEYS.iter().copied())
        .chain(PLANAR_KEYS.iter().copied());
    for key in keys.map(|s| s.key).filter(|k| *k != "name") {
        let axis = grid.axes.iter().find(|(k, _)| k == key).map(|(_, v)| v);
        let own = lookup(&doc, key);
        let l = label(grid, key);
        let value = match (axis, own) {
            (Some(values), _) if values.len() > 1 => VARIED.to_string(),
            (Some(values), _) => format!("{} (the axis' one value)", l.value(&shown(&values[0]))),
            (None, Some(v)) => l.value(&shown(v)),
            (None, None) => continue,
        };
        let _ = writeln!(md, "| `{key}` | {} | {value} |", l.meaning);
    }
    match grid.kind {
        BaseKind::Scene => {
            if let Ok(scene) = Scene::from_toml_str(&grid.base_text, file) {
                write_obstacles(md, grid, &scene.obstacles);
            }
        }
        BaseKind::Planar => {
            if let Ok(problem) = PlanarProblem::from_toml_str(&grid.base_text, file) {
                write_planar_obstacles(md, grid, &problem.obstacles);
            }
        }
        BaseKind::Problem => {}
    }
}

/// The value an axis gives obstacle `i`'s `field`: the marker when it varies, its one value.
fn obstacle_axis(grid: &Grid, i: usize, field: &str) -> Option<String> {
    let key = format!("obstacle.{i}.{field}");
    let (_, values) = grid.axes.iter().find(|(k, _)| *k == key)?;
    Some(if values.len() > 1 {
        VARIED.to_string()
    } else {
        format!("{} (the axis' one value)", shown(&values[0]))
    })
}

/// A planar problem's obstacles: name, disc radius, start (point or box), speed bound,
/// direction (free or fixed) and region; a value an axis sets is marked.
fn write_planar_obstacles(md: &mut String, grid: &Grid, obstacles: &[PlanarObstacleFile]) {
    let _ = writeln!(
        md,
        "\nIts obstacles (`obstacle.<index>.<key>` in the axes):\n\n\
         | index | name | radius r_i (m) | start (m) | max speed W_i (m/s) | direction | region |\n\
         |---|---|---|---|---|---|---|"
    );
    let point = |p: &[f64; 2]| format!("({}, {})", p[0], p[1]);
    for (i, o) in obstacles.iter().enumerate() {
        let axis = |field: &str| obstacle_axis(grid, i, field);
        let start = match &o.start {
            StartFile::At(p) => point(p),
            StartFile::Box { min, max } => format!("box {} to {}", point(min), point(max)),
        };
        let start = axis("start")
            .or_else(|| {
                axis("start_min")
                    .or(axis("start_max"))
                    .map(|_| VARIED.to_string())
            })
            .unwrap_or(start);
        let direction = o
            .direction
            .as_ref()
            .map(|d| format!("fixed along {}", point(d)))
            .unwrap_or_else(|| "free".into());
        let region = o
            .region
            .as_ref()
            .map(|q| format!("{}-gon", q.len()))
            .unwrap_or_else(|| "the plane".into());
        let _ = writeln!(
            md,
            "| {i} | \"{}\" | {} | {start} | {} | {} | {} |",
            o.name.replace('|', "\\|"),
            axis("radius").unwrap_or_else(|| o.radius.to_string()),
            axis("max_speed").unwrap_or_else(|| o.max_speed.to_string()),
            axis("direction").unwrap_or(direction),
            axis("region").unwrap_or(region),
        );
    }
}

/// A scene's obstacles: name, lane, start, speed bound W_i and whether it is static; a
/// value an axis sets is marked.
fn write_obstacles(md: &mut String, grid: &Grid, obstacles: &[Obstacle]) {
    let _ = writeln!(
        md,
        "\nIts obstacles (`obstacle.<index>.<key>` in the axes):\n\n\
         | index | name | lane | start x (m) | max speed W_i (m/s) | static |\n\
         |---|---|---|---|---|---|"
    );
    for (i, o) in obstacles.iter().enumerate() {
        let axis = |field: &str| obstacle_axis(grid, i, field);
        let start = match o.position {
            crate::core::model::Position::At(x) => x.to_string(),
            crate::core::model::Position::Range(lo, hi) => format!("[{lo}, {hi}]"),
        };
        let name = o.name.replace('|', "\\|");
        let _ = writeln!(
            md,
            "| {i} | \"{name}\" | {} | {} | {} | {} |",
            axis("lane").unwrap_or_else(|| o.lane.to_string()),
            axis("position").unwrap_or(start),
            axis("max_speed").unwrap_or_else(|| o.max_speed.to_string()),
            axis("static").unwrap_or_else(|| o.is_static.to_string()),
        );
    }
}

/// The value at a dotted key of a TOML document.
fn lookup<'a>(doc: &'a toml::Table, key: &str) -> Option<&'a toml::Value> {
    let (table, rest) = key.split_once('.')?;
    doc.get(table)?.as_table()?.get(rest)
}

/// A TOML value as the page prints it (`|` escaped for the table).
fn shown(v: &toml::Value) -> String {
    v.to_string().replace('|', "\\|")
}
