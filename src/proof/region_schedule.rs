//! The schedule decomposition for a whole box of parameter values (region certificates).
//!
//! A piece's program depends on the named parameters (W, ρ, V_a, buffer, initial gap,
//! clearance, σ_g, σ_w) in two ways: affinely through right-hand sides, variable bounds and
//! the objective's constant, and through *decisions* — which pieces exist, where shifted
//! pieces merge, and which side of a `min` a threshold takes. A box decomposition takes its
//! programs at the box's centre and makes every decision so that it holds for every point
//! of the box (docs/reductions.md §8 proves each):
//!
//! - **Which pieces**: the union over the box. The first brake step is the earliest of any
//!   point (the corner with the fastest obstacle, the widest area, the nearest start, the
//!   most noise), the last the latest (the farthest start, the most noise); the in-area
//!   listing is used when the wrong-assumption guard is active anywhere (it is exact also
//!   where the guard cannot fire, whose rows `w ≤ V_a + σ_w` are then vacuous); an in-area
//!   run is listed when it is possible at some point (widest area, least danger distance).
//!   A piece listed for the box that a point does not have only adds rows' solutions: the
//!   bound stays a lower bound.
//! - **Merging**: shifted pieces merge from the step where every point's merge is valid
//!   (the slowest obstacle needs the longest anchor; the early pieces' fastest approach
//!   covers least at the corner that slows it most). Below it pieces stay listed one by one.
//! - **Thresholds**: where `min(ρ, d_coll)` takes the same side at every point it is that
//!   side, exactly; where it does not, the no-fire row `o > min(ρ, d)` is relaxed to the
//!   least value of the min over the box (a constant below it everywhere), and the fire row
//!   `o ≤ min(ρ, d)` becomes the two rows `o ≤ ρ`, `o ≤ d`, which say exactly the same.
//!   An in-area speed limit `min(W, V_a + σ_w)` that changes side becomes W (above it).
//!   An early piece's lowest reachable gap becomes the least over the box (a constant).
//!
//! Each program of the box is then, at every point of the box, a relaxation of that point's
//! own program for the same piece (or of a piece the point does not need), so a dual
//! vector's affine bound, least at a vertex, bounds s* below at every point.

use crate::core::model::{Params, Problem};
use crate::core::num::Exact;
use crate::core::param_box::{End, ParamBox};
use crate::core::parameter::{ParamAffine, Parameter, symbolic};
use crate::proof::approach_closed_form::slowest_fast;
use crate::proof::schedule::{Decomposition, min_opt};

impl Decomposition {
    /// The pieces of every point of `region` for the (valid, point-start) `problem`, whose
    /// unranged numbers stay as they are; programs are taken at the box's centre.
    pub fn for_box(problem: &Problem, region: &ParamBox) -> Self {
        let params = region.center(&problem.params());
        Self::build(params, None, true, Some(region.clone()))
    }

    /// The box this decomposition covers (None: one point).
    pub fn region(&self) -> Option<&ParamBox> {
        self.region.as_ref()
    }

    /// The least value of parameter `p` over the box (its value at a point).
    pub(crate) fn least(&self, p: Parameter) -> Exact {
        match self.region.as_ref().and_then(|b| b.axis(p)) {
            Some(a) => a.lo_exact(),
            None => p.value(&self.params).clone(),
        }
    }

    /// The point of the box that takes, on each ranged axis, the end `pick` names.
    fn corner(&self, pick: impl Fn(Parameter) -> End) -> Params<Exact> {
        match &self.region {
            None => self.params.clone(),
            Some(b) => b.corner(&self.params, pick),
        }
    }

    /// Whether the wrong-assumption guard can fire at some point of the box (at the point).
    pub(crate) fn wrong_assumption_active(&self) -> bool {
        self.guard_active
    }

    /// Whether the wrong-assumption guard can fire at some point: fastest obstacle, most
    /// speed noise, least assumed speed.
    pub(crate) fn guard_active_somewhere(&self) -> bool {
        self.corner(|p| match p {
            Parameter::ObstacleSpeed | Parameter::SpeedNoise => End::High,
            _ => End::Low,
        })
        .wrong_assumption_active()
    }

    /// The point whose obstacle is first observed in the area earliest: fastest, widest
    /// area, nearest start, most gap noise.
    pub(crate) fn earliest_reach_corner(&self) -> Params<Exact> {
        self.corner(|p| match p {
            Parameter::ObstacleSpeed | Parameter::ReactionRadius | Parameter::GapNoise => End::High,
            _ => End::Low,
        })
    }

    /// The point whose observations stay positive longest: farthest start, most gap noise.
    pub(crate) fn farthest_start_corner(&self) -> Params<Exact> {
        self.corner(|p| match p {
            Parameter::InitialGap | Parameter::GapNoise => End::High,
            _ => End::Low,
        })
    }

    /// The point where in-area runs are longest: widest area, least danger distance (the
    /// danger distance grows with V_a and the buffer).
    pub(crate) fn widest_area_corner(&self) -> Params<Exact> {
        self.corner(|p| match p {
            Parameter::ReactionRadius => End::High,
            _ => End::Low,
        })
    }

    /// The point whose area-respecting fastest approach covers least at every step: slowest
    /// obstacle, least assumed speed and speed noise, widest area, least gap noise, nearest
    /// start (each step's gap is monotone in each of them, see docs/reductions.md §8).
    pub(crate) fn slowest_approach_corner(&self) -> Params<Exact> {
        self.corner(|p| match p {
            Parameter::ReactionRadius => End::High,
            _ => End::Low,
        })
    }

    /// The lowest gap an early piece's prefix reaches by its anchor m: exact and affine at
    /// a point; over a box the least over it, at the corner that speeds the approach most.
    pub(crate) fn early_lowest_gap(&self, s: &Params<ParamAffine>, m: usize) -> ParamAffine {
        if self.region.is_none() {
            return self.fastest_gap(s, m);
        }
        let fastest = self.corner(|p| match p {
            Parameter::ObstacleSpeed
            | Parameter::AssumedObstacleSpeed
            | Parameter::SpeedNoise
            | Parameter::GapNoise => End::High,
            _ => End::Low,
        });
        let gap = self.fastest_gap(&symbolic(&fastest), m);
        ParamAffine::constant(gap.value)
    }

    /// The threshold of a no-fire row `o > min(ρ, d)`: the min itself where it takes one
    /// side over the whole box, else the least value of the min over the box.
    pub(crate) fn no_fire_threshold(
        &self,
        s: &Params<ParamAffine>,
        d: Option<ParamAffine>,
    ) -> ParamAffine {
        let Some(b) = &self.region else {
            return min_opt(&s.rho, d);
        };
        match (self.uniform_side(s, d.as_ref()), d) {
            (Some(side), _) => side,
            (None, Some(d)) => {
                let least_rho = b.min_of(&s.rho, &self.params);
                let least_d = b.min_of(&d, &self.params);
                ParamAffine::constant(if least_d < least_rho {
                    least_d
                } else {
                    least_rho
                })
            }
            (None, None) => s.rho.clone(),
        }
    }

    /// The thresholds of a fire row `o ≤ min(ρ, d)`, with their names: the min where it
    /// takes one side over the whole box, else both ρ and d (the same condition).
    pub(crate) fn fire_thresholds(
        &self,
        s: &Params<ParamAffine>,
        d: Option<ParamAffine>,
    ) -> Vec<(ParamAffine, &'static str)> {
        if self.region.is_none() {
            return vec![(min_opt(&s.rho, d), "min(rho, d_coll)")];
        }
        match (self.uniform_side(s, d.as_ref()), d) {
            (Some(side), _) => vec![(side, "min(rho, d_coll)")],
            (None, Some(d)) => vec![(s.rho.clone(), "rho"), (d, "d_coll")],
            (None, None) => vec![(s.rho.clone(), "rho")],
        }
    }

    /// min(ρ, d) when the same side is least at every point of the box (None: it changes).
    fn uniform_side(
        &self,
        s: &Params<ParamAffine>,
        d: Option<&ParamAffine>,
    ) -> Option<ParamAffine> {
        let (Some(b), Some(d)) = (&self.region, d) else {
            return Some(s.rho.clone());
        };
        let excess = d.clone() - s.rho.clone();
        if b.min_of(&excess, &self.params) >= Exact::ZERO {
            Some(s.rho.clone())
        } else if b.max_of(&excess, &self.params) <= Exact::ZERO {
            Some(d.clone())
        } else {
            None
        }
    }

    /// The in-area speed limit min(W, V_a + σ_w): exact where it takes one side over the
    /// whole box, else W (never below it).
    pub(crate) fn in_area_speed_limit(&self, s: &Params<ParamAffine>) -> ParamAffine {
        let Some(b) = &self.region else {
            return slowest_fast(s);
        };
        let excess = s.V_a.clone() + s.sigma_w.clone() - s.W.clone();
        if b.max_of(&excess, &self.params) <= Exact::ZERO {
            s.V_a.clone() + s.sigma_w.clone()
        } else {
            s.W.clone()
        }
    }
}
