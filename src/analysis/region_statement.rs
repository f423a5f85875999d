//! Region statements for `radius` and `max-speed`: "certified for every W ≤ W0 at every
//! ρ ≥ ρ0", where a point answer says only "at W0, from ρ0 on (as far as the search
//! looked)".
//!
//! Two facts of the semantics (docs/reductions.md §9) turn that unbounded quarter-plane into
//! one finite map:
//! 1. **Slower worlds are sub-worlds.** W enters a single-obstacle problem only as the bound
//!    on the obstacle's speed in each period (the controller reads V_a, never W), so every
//!    behaviour under W ≤ W0 is a behaviour under W0: certified at W0 is certified below it.
//! 2. **Radii beyond the farthest reading are all alike.** The gap never grows, so every
//!    observed gap is at most g0 + σ_g (g0's upper end); ρ enters the step only through
//!    `gap ≤ ρ` and `min(d, ρ)` compared with or clamped to observed gaps, which are decided
//!    alike by every ρ ≥ ρ_sat = g0 + σ_g. Every ρ ≥ ρ_sat has ρ_sat's behaviours.
//!
//! So the statement holds iff the map of ρ ∈ [ρ0, max(ρ0, ρ_sat)] at W = W0 is certified
//! leaf by leaf, which [`check_map`](crate::proof::region_check::check_map) re-verifies.

use crate::analysis::region_search::{RegionError, RegionOptions, map_region};
use crate::core::model::Problem;
use crate::core::num::{Exact, exact_decimal, f64_at_most};
use crate::core::param_box::{Axis, ParamBox};
use crate::core::parameter::Parameter;
use crate::proof::region_map::{LeafVerdict, RegionMap};

/// Splits allowed on the way to a leaf: the ρ axis is one-dimensional, so this is a leaf
/// width of 2⁻⁴⁸ of the range at worst, reached only near the few radii where a guard's
/// entry step changes.
pub const STATEMENT_DEPTH: u32 = 48;

/// The map behind a region statement, and what it establishes.
#[derive(Clone, Debug)]
pub struct RegionStatement {
    /// W0 (m/s): the statement covers every W ≤ W0.
    pub speed: f64,
    /// ρ0 (m): the statement covers every ρ ≥ ρ0.
    pub radius: f64,
    /// ρ_sat = g0 + σ_g (m), rounded up: radii beyond it are decided as it is.
    pub saturation: f64,
    /// The map of ρ ∈ [ρ0, max(ρ0, ρ_sat)] at W = W0.
    pub map: RegionMap,
}

impl RegionStatement {
    /// Whether the statement holds: every leaf of the map is certified.
    pub fn holds(&self) -> bool {
        self.map.all_certified()
    }

    /// One line for people.
    pub fn describe(&self) -> String {
        let top = self.map.ranges[0].hi;
        let count = |v| self.map.leaves.iter().filter(|l| l.verdict == v).count();
        let leaves = match self.map.leaves.len() {
            1 => "1 leaf".to_string(),
            n => format!("{n} leaves"),
        };
        if self.holds() {
            format!(
                "certified for every W <= {} m/s at every rho >= {} m (one map of rho in [{}, \
                 {top}] m at W = {} m/s, {leaves}, all certified; below W0 the obstacle has \
                 fewer behaviours, beyond rho = {} m = g0 + sigma_g no reading differs)",
                self.speed, self.radius, self.radius, self.speed, self.saturation
            )
        } else {
            format!(
                "not established for every rho >= {} m at W = {} m/s: the map of rho in [{}, \
                 {top}] m has {leaves}, {} certified, {} refuted, {} undecided ({:.4}% of the \
                 range not certified)",
                self.radius,
                self.speed,
                self.radius,
                count(LeafVerdict::Certified),
                count(LeafVerdict::Refuted),
                count(LeafVerdict::Undecided),
                100.0 * (1.0 - self.map.coverage.certified),
            )
        }
    }
}

/// ρ_sat = g0 (its upper end) + σ_g, as the least float whose decimal form is at least the
/// exact sum (box ends are read as their shortest decimals).
pub fn saturation_radius(problem: &Problem) -> f64 {
    let exact =
        exact_decimal(problem.environment.initial_gap.max()) + exact_decimal(problem.gap_noise());
    // From below: the float whose shortest decimal is the sum itself, when there is one.
    let mut x = f64_at_most(&exact);
    while exact_decimal(x) < exact {
        x = x.next_up();
    }
    x
}

/// Decimals the statement's W0 and ρ0 are given to: a search's probe such as
/// 1.0700009999506659 is stated as ρ ≥ 1.070001.
pub const STATEMENT_DECIMALS: usize = 9;

/// The decimal `x` denotes (its shortest form, as box ends are read) rounded down or `up` to
/// [`STATEMENT_DECIMALS`] decimals, as the float that denotes the result.
fn at_decimals(x: f64, up: bool) -> f64 {
    let scaled = exact_decimal(x) * Exact::from(10u64.pow(STATEMENT_DECIMALS as u32));
    let whole = if up { scaled.ceil() } else { scaled.floor() };
    format!("{whole}e-{STATEMENT_DECIMALS}")
        .parse()
        .expect("a decimal reads back")
}

/// The region statement for `problem` at W0 = `speed` and ρ0 = `radius` (the other keys as
/// in `problem`): maps ρ ∈ [ρ0, max(ρ0, ρ_sat)] at W0 (see the module docs). W0 is first
/// rounded down and ρ0 up to [`STATEMENT_DECIMALS`] decimals: each only narrows the claim.
pub fn region_statement(
    problem: &Problem,
    speed: f64,
    radius: f64,
) -> Result<RegionStatement, RegionError> {
    let (speed, radius) = (at_decimals(speed, false), at_decimals(radius, true));
    let mut at = problem.clone();
    at.environment.obstacle_speed = speed;
    at.controller.reaction_radius = radius;
    let saturation = saturation_radius(&at);
    let whole = ParamBox::new(vec![Axis::new(
        Parameter::ReactionRadius,
        radius,
        radius.max(saturation),
    )])
    .map_err(RegionError::Refused)?;
    let options = RegionOptions {
        depth: STATEMENT_DEPTH,
        ..RegionOptions::default()
    };
    let map = map_region(&at, &whole, &options, &|_| {})?;
    Ok(RegionStatement {
        speed,
        radius,
        saturation,
        map,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_saturation_radius_is_at_least_the_farthest_reading() {
        for (g0, sigma) in [
            (10.0, 0.0),
            (10.0, 0.002),
            (0.1, 0.2),
            (7.3, 0.07),
            (1e3, 1e-9),
        ] {
            let mut p = Problem::shipped_seed();
            p.environment.initial_gap = crate::core::model::Position::At(g0);
            p.sensing.get_or_insert_with(Default::default).gap_noise = Some(sigma);
            let x = saturation_radius(&p);
            let exact = exact_decimal(g0) + exact_decimal(sigma);
            assert!(exact_decimal(x) >= exact, "{g0} + {sigma}: {x}");
            if (g0, sigma) == (10.0, 0.01) {
                assert_eq!(x, 10.01, "the sum itself when a float denotes it");
            }
            assert!(
                x.next_down() < g0 + sigma + 1e-9 * (g0 + sigma),
                "tight: {x}"
            );
        }
    }

    #[test]
    fn statements_round_outwards_of_the_claim_only() {
        assert_eq!(at_decimals(0.15, false), 0.15);
        assert_eq!(at_decimals(0.15, true), 0.15);
        assert_eq!(at_decimals(1.0700009999506659, true), 1.070001);
        assert_eq!(at_decimals(1.0700009999506659, false), 1.070000999);
        assert_eq!(at_decimals(0.22857042852126275, false), 0.228570428);
        assert_eq!(at_decimals(1e-12, true), 1e-9);
    }
}
