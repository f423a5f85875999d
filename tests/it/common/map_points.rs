//! Points of region maps for tests that hold maps against point analysers: random points of
//! the whole box, and the leaves that hold a point.

use safereach::proof::region_map::{Leaf, RegionMap};

/// A random point of the map's box from `uniform` draws in [0, 1), each value rounded to
/// `decimals` decimals (short numbers keep exact arithmetic quick, and faces and corners get
/// hit now and then).
pub fn random_point(m: &RegionMap, mut uniform: impl FnMut() -> f64, decimals: i32) -> Vec<f64> {
    let scale = 10f64.powi(decimals);
    m.ranges
        .iter()
        .map(|a| {
            let v = a.lo + uniform() * (a.hi - a.lo);
            ((v * scale).round() / scale).clamp(a.lo, a.hi)
        })
        .collect()
}

/// Every leaf whose box holds the point (faces included), one value per ranged axis.
pub fn leaves_holding<'m>(m: &'m RegionMap, values: &[f64]) -> impl Iterator<Item = &'m Leaf> {
    let values = values.to_vec();
    m.leaves.iter().filter(move |l| {
        m.ranges.iter().zip(&values).all(|(a, v)| {
            let [lo, hi] = l.bounds[&a.key()];
            lo <= *v && *v <= hi
        })
    })
}
