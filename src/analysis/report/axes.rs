//! What a grid's axes mean in a figure: each dotted key's meaning and unit (an obstacle's
//! named by its index and its name in the base scene or planar problem), and which two axes
//! a heat map spans.

use crate::analysis::sweep::Grid;
use crate::core::grid::BaseKind;
use crate::core::model::keys::key_spec;
use crate::core::planar::PlanarProblem;
use crate::core::planar::keys as planar_keys;
use crate::core::scene::Scene;
use crate::core::scene::keys::{OBSTACLE_KEYS, SCENE_KEYS};

use super::{RADIUS_KEY, SPEED_KEY};

/// An axis as a figure shows it.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct AxisLabel {
    /// The dotted key.
    pub(super) key: String,
    /// What it is, with its symbol: `obstacle 1 ("second") max speed W_1`.
    pub(super) meaning: String,
    /// Its unit (empty for counts of nothing, lanes).
    pub(super) unit: String,
    /// Its symbol where it has one (`W_1`, `ρ`), for short cell names.
    pub(super) symbol: Option<String>,
}

impl AxisLabel {
    /// The meaning with the unit in parentheses: `reaction radius ρ (m)`.
    pub(super) fn titled(&self) -> String {
        if self.unit.is_empty() {
            self.meaning.clone()
        } else {
            format!("{} ({})", self.meaning, self.unit)
        }
    }

    /// A value with its unit: `0.25 m/s`.
    pub(super) fn value(&self, v: &str) -> String {
        if self.unit.is_empty() {
            v.to_string()
        } else {
            format!("{v} {}", self.unit)
        }
    }
}

/// An obstacle's key: its index and the field after it (`obstacle.1.max_speed`).
pub(super) fn obstacle_field(key: &str) -> Option<(usize, &str)> {
    let rest = key.strip_prefix("obstacle.")?;
    let (index, field) = rest.split_once('.')?;
    Some((index.parse().ok()?, field))
}

/// Whether the key is an obstacle's speed bound (W, or an obstacle's W_i).
pub(super) fn is_speed_bound(key: &str) -> bool {
    key == SPEED_KEY || obstacle_field(key).is_some_and(|(_, f)| f == "max_speed")
}

/// The unit the file reader gives a key (empty when it has none or is unknown).
fn unit(key: &str) -> String {
    let spec = match obstacle_field(key) {
        Some((_, field)) => OBSTACLE_KEYS
            .iter()
            .chain(planar_keys::OBSTACLE_KEYS)
            .find(|s| s.key == field)
            .copied(),
        None => key_spec(key).or_else(|| {
            SCENE_KEYS
                .iter()
                .chain(planar_keys::PLANAR_KEYS)
                .find(|s| s.key == key)
                .copied()
        }),
    };
    match spec.map(|s| s.unit) {
        Some("control periods") => "periods".into(),
        Some(u) => u.into(),
        None => String::new(),
    }
}

/// A plain key's meaning and symbol.
fn plain(key: &str) -> Option<(&'static str, Option<&'static str>)> {
    Some(match key {
        SPEED_KEY => ("obstacle speed bound W", Some("W")),
        RADIUS_KEY => ("reaction radius ρ", Some("ρ")),
        "controller.assumed_obstacle_speed" => ("assumed obstacle speed V_a", Some("V_a")),
        "controller.buffer" => ("buffer", None),
        "robot.max_speed" => ("robot top speed v_max", Some("v_max")),
        "robot.acceleration" => ("robot acceleration a", Some("a")),
        "robot.braking" => ("robot braking b", Some("b")),
        "robot.control_period" => ("control period dt", Some("dt")),
        "robot.latency" => ("latency L", Some("L")),
        "robot.clearance" => ("clearance", None),
        "environment.initial_gap" => ("initial gap g0", Some("g0")),
        "robot.goal" => ("destination x", None),
        "robot.sensing_range" => ("sensing range R", Some("R")),
        "controller.lane_change_periods" => ("lane change duration", None),
        "controller.lane_change_rear_gap" => ("lane change rear gap", None),
        "controller.lane_change" => ("lane changes allowed", None),
        "controller.danger_rule" => ("danger rule", None),
        "controller.wrong_assumption_brake" => ("brake when seen faster than V_a", None),
        "robot.braking_min" => ("robot least braking b_min", Some("b_min")),
        "robot.initial_speed" => ("robot start speed v0", Some("v0")),
        "sensing.gap_noise" => ("gap noise σ_g", Some("σ_g")),
        "sensing.speed_noise" => ("speed noise σ_w", Some("σ_w")),
        "sensing.first_detection_gap" => ("first detection gap d_det", Some("d_det")),
        "scene.lanes" => ("lanes", None),
        "robot.radius" => ("robot radius r_R", Some("r_R")),
        "robot.path_tolerance" => ("path tolerance", None),
        "controller.danger_zone" => ("danger zone", None),
        "sensing.position_noise" => ("position noise σ_p", Some("σ_p")),
        "sensing.velocity_noise" => ("velocity noise σ_w", Some("σ_w")),
        "sensing.first_detection" => ("first detection distance d_det", Some("d_det")),
        "sensing.range" => ("sensing range R", Some("R")),
        "sensing.field_of_view" => ("field of view θ", Some("θ")),
        _ => return None,
    })
}

/// The label of `key` in `grid` (obstacles named from its base scene).
pub(super) fn label(grid: &Grid, key: &str) -> AxisLabel {
    let (meaning, symbol) = match (plain(key), obstacle_field(key)) {
        (Some((m, s)), _) => (m.to_string(), s.map(str::to_string)),
        (None, Some((i, field))) => obstacle_meaning(grid, i, field),
        (None, None) => (key.to_string(), None),
    };
    AxisLabel {
        key: key.to_string(),
        meaning,
        unit: unit(key),
        symbol,
    }
}

/// `obstacle 1 ("second") max speed W_1`, and its symbol.
fn obstacle_meaning(grid: &Grid, index: usize, field: &str) -> (String, Option<String>) {
    let name = match grid.kind {
        BaseKind::Planar => PlanarProblem::from_toml_str(&grid.base_text, "base")
            .ok()
            .and_then(|p| p.obstacles.get(index).map(|o| o.name.clone())),
        _ => Scene::from_toml_str(&grid.base_text, "base")
            .ok()
            .and_then(|s| s.obstacles.get(index).map(|o| o.name.clone())),
    };
    let who = match name {
        Some(n) => format!("obstacle {index} (\"{n}\")"),
        None => format!("obstacle {index}"),
    };
    let (what, symbol) = match field {
        "max_speed" => (format!("max speed W_{index}"), Some(format!("W_{index}"))),
        "position" => ("start x".to_string(), None),
        "radius" => (format!("radius r_{index}"), Some(format!("r_{index}"))),
        other => (other.to_string(), None),
    };
    (format!("{who} {what}"), symbol)
}

/// Whether every value of an axis is a number.
fn numeric(values: &[toml::Value]) -> bool {
    values.iter().all(|v| v.is_float() || v.is_integer())
}

/// The two axes a heat map spans, x then y, or why there is none.
///
/// A single-obstacle grid with both W and ρ axes has one over (W, ρ), as it always had.
/// Any other grid takes an obstacle's speed bound across and the radius up when it varies
/// them, else the first numeric axes with more than one value.
pub(super) fn heat_map_axes(grid: &Grid) -> Result<(String, String), String> {
    let has = |key: &str| grid.axes.iter().any(|(k, _)| k == key);
    if grid.kind == BaseKind::Problem && has(SPEED_KEY) && has(RADIUS_KEY) {
        return Ok((SPEED_KEY.into(), RADIUS_KEY.into()));
    }
    let varied: Vec<&String> = grid
        .axes
        .iter()
        .filter(|(_, v)| v.len() > 1 && numeric(v))
        .map(|(k, _)| k)
        .collect();
    let x = varied
        .iter()
        .position(|k| is_speed_bound(k))
        .or_else(|| varied.iter().position(|k| k.as_str() != RADIUS_KEY));
    let y = varied
        .iter()
        .position(|k| k.as_str() == RADIUS_KEY)
        .filter(|&j| Some(j) != x)
        .or_else(|| (0..varied.len()).find(|&j| Some(j) != x));
    match (x, y) {
        (Some(x), Some(y)) => Ok((varied[x].clone(), varied[y].clone())),
        _ => Err(format!(
            "a heat map needs two axes of numbers with more than one value each; this grid has {}",
            varied.len()
        )),
    }
}

/// One slice of a grid: the value of every axis a figure does not span.
pub(super) type Slice = Vec<(String, serde_json::Value)>;

/// The slices of `grid` across the axes other than `x` and `y`, in cell order (the last
/// axis varying fastest); one empty slice when there are no other axes.
pub(super) fn slices(grid: &Grid, x: &str, y: &str) -> Vec<Slice> {
    let mut out: Vec<Slice> = vec![Vec::new()];
    for (key, values) in grid.axes.iter().filter(|(k, _)| k != x && k != y) {
        out = out
            .into_iter()
            .flat_map(|slice| {
                values.iter().map(move |v| {
                    let mut s = slice.clone();
                    let json = serde_json::to_value(v).unwrap_or(serde_json::Value::Null);
                    s.push((key.clone(), json));
                    s
                })
            })
            .collect();
    }
    out
}

/// Whether a cell lies in a slice.
pub(super) fn in_slice(r: &crate::analysis::sweep::CellResult, slice: &Slice) -> bool {
    slice.iter().all(|(k, v)| r.axes.get(k) == Some(v))
}
