//! The certified map a report draws for a single-obstacle grid over W and ρ: the region map
//! of the plane the grid's cells span ([`map_region`]), with every other axis at its one
//! value, the cells overlaid as dots.

use super::{RADIUS_KEY, SPEED_KEY};
use crate::analysis::region_search::{RegionOptions, map_region};
use crate::analysis::sweep::Grid;
use crate::core::model::Problem;
use crate::core::param_box::{Axis, ParamBox};
use crate::core::parameter::Parameter;
use crate::proof::region_map::RegionMap;

/// Cuts on the way to a leaf: leaves along the boundary are then about 1/100 of each range.
pub const DEPTH: u32 = 16;

/// The certified map of the grid's (W, ρ) plane; None when the grid is a scene or planar, lacks
/// either axis, or varies another key (the map holds every other key at one value).
pub fn certified_map(grid: &Grid) -> Result<Option<RegionMap>, String> {
    if grid.kind != crate::core::grid::BaseKind::Problem {
        return Ok(None);
    }
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
    let (Some(w), Some(rho)) = (span(SPEED_KEY), span(RADIUS_KEY)) else {
        return Ok(None);
    };
    let others = grid
        .axes
        .iter()
        .filter(|(k, _)| k != SPEED_KEY && k != RADIUS_KEY);
    if others.clone().any(|(_, v)| v.len() > 1) {
        return Ok(None);
    }
    let sets: Vec<String> = others.map(|(k, v)| format!("{k}={}", v[0])).collect();
    let origin = grid.base_path.display().to_string();
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
