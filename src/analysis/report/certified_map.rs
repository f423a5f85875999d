//! The certified map a report draws for a grid over W and ρ: the region map of the plane
//! the grid's cells span ([`map_region`] for a single-obstacle base, [`map_planar_region`]
//! for a planar base over one obstacle's `obstacle.<i>.max_speed`), with every other axis at
//! its one value, the cells overlaid as dots.

use super::{RADIUS_KEY, SPEED_KEY};
use crate::analysis::region_search::{RegionOptions, map_planar_region, map_region};
use crate::analysis::sweep::Grid;
use crate::core::grid::BaseKind;
use crate::core::model::Problem;
use crate::core::param_box::{Axis, ParamBox};
use crate::core::parameter::Parameter;
use crate::core::planar::PlanarProblem;
use crate::proof::region_map::RegionMap;

/// Cuts on the way to a leaf: leaves along the boundary are then about 1/100 of each range.
pub const DEPTH: u32 = 16;

/// Cuts of a planar map: each box costs two bound-only planar certifications (about 0.2 s
/// each on the seed), so the planar map stops coarser (about 1/16 of each range: the
/// seed-in-plane grid's map takes about 15 s on 2 cores).
pub const PLANAR_DEPTH: u32 = 8;

/// The certified map of the grid's (W, ρ) plane; None when the grid is a scene, lacks
/// either axis (a planar grid: exactly one `obstacle.<i>.max_speed` axis), or varies another
/// key (the map holds every other key at one value).
pub fn certified_map(grid: &Grid) -> Result<Option<RegionMap>, String> {
    let speed_key = match grid.kind {
        BaseKind::Problem => SPEED_KEY.to_string(),
        BaseKind::Planar => {
            let speeds: Vec<&String> = grid
                .axes
                .iter()
                .map(|(k, _)| k)
                .filter(|k| k.starts_with("obstacle.") && k.ends_with(".max_speed"))
                .collect();
            match speeds.as_slice() {
                [one] => (*one).clone(),
                _ => return Ok(None),
            }
        }
        BaseKind::Scene => return Ok(None),
    };
    let speed_key = speed_key.as_str();
    let span = |key: &str| -> Option<(f64, f64)> {
        let (_, values) = grid.axes.iter().find(|(k, _)| k == key)?;
        let numbers: Vec<f64> = values
            .iter()
            .filter_map(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)))
            .collect();
        let lo = numbers.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = numbers.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (numbers.len() == values.len() && lo < hi).then_some((lo, hi))
    };
    let (Some(w), Some(rho)) = (span(speed_key), span(RADIUS_KEY)) else {
        return Ok(None);
    };
    let others = grid
        .axes
        .iter()
        .filter(|(k, _)| k != speed_key && k != RADIUS_KEY);
    if others.clone().any(|(_, v)| v.len() > 1) {
        return Ok(None);
    }
    let sets: Vec<String> = others.map(|(k, v)| format!("{k}={}", v[0])).collect();
    let origin = grid.base_path.display().to_string();
    if grid.kind == BaseKind::Planar {
        let problem = PlanarProblem::from_toml_str_with_overrides(&grid.base_text, &origin, &sets)
            .map_err(|e| e.to_string())?;
        let speed = Axis::for_key(speed_key, w.0, w.1)?;
        let whole = ParamBox::new(vec![
            speed,
            Axis::new(Parameter::ReactionRadius, rho.0, rho.1),
        ])?;
        let options = RegionOptions {
            depth: PLANAR_DEPTH,
            ..RegionOptions::default()
        };
        return map_planar_region(&grid.base_text, &sets, &problem, &whole, &options, &|_| {})
            .map(Some)
            .map_err(|e| e.to_string());
    }
    let problem = Problem::from_toml_str_with_overrides(&grid.base_text, &origin, &sets)
        .map_err(|e| e.to_string())?;
    if problem.environment.initial_gap.is_range() {
        return Ok(None);
    }
    let whole = ParamBox::new(vec![
        Axis::new(Parameter::ObstacleSpeed, w.0, w.1),
        Axis::new(Parameter::ReactionRadius, rho.0, rho.1),
    ])?;
    let options = RegionOptions {
        depth: DEPTH,
        min_width: 0.0,
        ..RegionOptions::default()
    };
    map_region(&problem, &whole, &options, &|_| {})
        .map(Some)
        .map_err(|e| e.to_string())
}
