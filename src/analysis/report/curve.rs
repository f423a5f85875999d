//! The safe-radius curves ρ*(W) a report draws: for a single obstacle over its speed bound W
//! (`safereach radius` per point), one curve per slice of the grid's other axes (each with
//! that slice's values applied to the base, so a curve and the cells drawn on it are the
//! same problems); for a scene over the one obstacle bound W_i its grid varies (the scene
//! radius search per point), or the reason a scene grid has none.

use rayon::prelude::*;

use super::axes::{Slice, obstacle_field, slices};
use super::{CurvePoint, MAX_MAPS, RADIUS_KEY, SPEED_KEY};
use crate::analysis::radius;
use crate::analysis::scene_radius::scene_radius;
use crate::analysis::sweep::Grid;
use crate::core::grid::BaseKind;
use crate::core::model::Problem;
use crate::core::scene::Scene;

/// What a report says about ρ*.
#[derive(Clone, Debug, PartialEq)]
pub enum Curve {
    /// ρ*(W) over the speed bound on axis `key`, one curve per slice of the grid's other
    /// axes (the first `MAX_MAPS` of `total`).
    Radius {
        /// The speed-bound axis (`environment.obstacle_speed`, `obstacle.1.max_speed`).
        key: String,
        /// The curves, one per slice, in cell order.
        slices: Vec<SliceCurve>,
        /// How many slices the grid has (more than `slices` holds when it has more than
        /// `MAX_MAPS`).
        total: usize,
    },
    /// A scene grid without a curve, and why (the page says it).
    NotApplicable(String),
    /// A single-obstacle grid without a speed axis: no curve, nothing said (as always).
    None,
}

/// ρ*(W) for one slice: the base with the slice's values applied.
#[derive(Clone, Debug, PartialEq)]
pub struct SliceCurve {
    /// The value of every axis other than W and ρ (empty when there are none).
    pub slice: Vec<(String, serde_json::Value)>,
    /// W and ρ*(W), ascending in W.
    pub points: Vec<CurvePoint>,
}

/// Largest number of steps a scene curve takes: each point is a whole radius search (some
/// 25 scene analyses), so a scene curve is coarser than a single obstacle's.
const SCENE_POINTS: f64 = 8.0;

/// The curves of a grid: ρ*(W) from 0 to a little past the grid's fastest W, for the base
/// problem or scene with one slice's values of the other axes applied, per slice (the
/// first `MAX_MAPS`). Single-obstacle points are 0.01 m/s apart; a scene's at most 9,
/// at a round step (0.05 m/s for W up to 0.35).
pub fn radius_curve(grid: &Grid) -> Result<Curve, String> {
    if grid.kind == BaseKind::Planar {
        return Ok(Curve::NotApplicable(
            "a planar ρ* is a bisection of a dozen or so planar certifications (about a second \
             each), too many to draw a curve of in a report; `safereach radius` on the planar \
             problem, with the slice's keys set, finds each point, certified; the certified \
             map of the (W, ρ) plane above bounds the curve between its certified and refuted \
             leaves"
                .into(),
        ));
    }
    let key = match speed_axis(grid) {
        Ok(Some(k)) => k,
        Ok(None) => return Ok(Curve::None),
        Err(why) => return Ok(Curve::NotApplicable(why)),
    };
    let top = grid
        .axes
        .iter()
        .filter(|(k, _)| *k == key)
        .flat_map(|(_, v)| v.iter().filter_map(number))
        .fold(0.0, f64::max);
    if top <= 0.0 {
        return Ok(if grid.kind == BaseKind::Scene {
            Curve::NotApplicable(format!("`{key}` takes no value above 0"))
        } else {
            Curve::None
        });
    }
    let step = if grid.kind == BaseKind::Scene {
        round_step((top + 0.05) / SCENE_POINTS)
    } else {
        0.01
    };
    let steps = ((top + 0.05) / step).round() as usize;
    let speeds: Vec<f64> = (0..=steps)
        .map(|i| (i as f64 * step * 1000.0).round() / 1000.0)
        .collect();
    let all = slices(grid, &key, RADIUS_KEY);
    let total = all.len();
    let drawn: Vec<Slice> = all.into_iter().take(MAX_MAPS).collect();
    let jobs: Vec<(usize, f64)> = (0..drawn.len())
        .flat_map(|s| speeds.iter().map(move |&w| (s, w)))
        .collect();
    let rhos = jobs
        .par_iter()
        .map(|&(s, w)| {
            let mut sets = overrides(&drawn[s]);
            sets.push(format!("{key}={w}"));
            point(grid, &sets)
        })
        .collect::<Result<Vec<_>, String>>()?;
    let mut rhos = rhos.into_iter();
    let slices = drawn
        .into_iter()
        .map(|slice| SliceCurve {
            slice,
            points: speeds.iter().map(|&w| (w, rhos.next().flatten())).collect(),
        })
        .collect();
    Ok(Curve::Radius { key, slices, total })
}

/// A slice's values as `--set` overrides.
fn overrides(slice: &Slice) -> Vec<String> {
    slice.iter().map(|(k, v)| format!("{k}={v}")).collect()
}

/// ρ* of the base with `sets` applied.
fn point(grid: &Grid, sets: &[String]) -> Result<Option<f64>, String> {
    let origin = grid.base_path.display().to_string();
    if grid.kind == BaseKind::Scene {
        let s = Scene::from_toml_str_with_overrides(&grid.base_text, &origin, sets)
            .map_err(|e| e.to_string())?;
        Ok(scene_radius(&s).map_err(|e| e.to_string())?.value)
    } else {
        let p = Problem::from_toml_str_with_overrides(&grid.base_text, &origin, sets)
            .map_err(|e| e.to_string())?;
        Ok(radius::safe_radius(&p).map_err(|e| e.to_string())?.value)
    }
}

/// A TOML number as f64.
fn number(v: &toml::Value) -> Option<f64> {
    v.as_float().or_else(|| v.as_integer().map(|i| i as f64))
}

/// The smallest of 0.01, 0.02, 0.025, 0.05, 0.1, 0.2, 0.25, 0.5, 1, … at least `raw`.
fn round_step(raw: f64) -> f64 {
    let mut p = 0.01;
    loop {
        for m in [1.0, 2.0, 2.5, 5.0] {
            if m * p >= raw {
                return m * p;
            }
        }
        p *= 10.0;
    }
}

/// The axis the curve runs along; Ok(None) for a single-obstacle grid without one, Err
/// with the reason for a scene grid that has no curve.
fn speed_axis(grid: &Grid) -> Result<Option<String>, String> {
    if grid.kind != BaseKind::Scene {
        let has = grid.axes.iter().any(|(k, _)| k == SPEED_KEY);
        return Ok(has.then(|| SPEED_KEY.to_string()));
    }
    let bounds: Vec<&String> = grid
        .axes
        .iter()
        .map(|(k, _)| k)
        .filter(|k| obstacle_field(k).is_some_and(|(_, f)| f == "max_speed"))
        .collect();
    let Some(key) = bounds.first() else {
        return Err(
            "the grid varies no obstacle's speed bound (`obstacle.<index>.max_speed`), so there \
             is no ρ*(W) to draw"
                .into(),
        );
    };
    let scene = Scene::from_toml_str(&grid.base_text, "base").map_err(|e| e.to_string())?;
    if let Some((i, _)) = obstacle_field(key)
        && scene.obstacles.get(i).is_some_and(|o| o.is_static)
    {
        return Err(format!(
            "`{key}` is the bound of a static obstacle, which the controller knows never moves"
        ));
    }
    let varied: Vec<String> = grid
        .axes
        .iter()
        .filter(|(k, v)| v.len() > 1 && k != *key && k != RADIUS_KEY)
        .map(|(k, _)| format!("`{k}`"))
        .collect();
    if !varied.is_empty() {
        return Err(format!(
            "ρ*(W) over `{key}` holds every other key at one value, but the grid also varies {}; \
             the cells at its other values would not lie on one curve",
            varied.join(", ")
        ));
    }
    Ok(Some((*key).clone()))
}
