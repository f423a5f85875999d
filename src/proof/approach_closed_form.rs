//! The area-respecting fastest approach in closed form (docs/reductions.md, Lemma 8a).
//!
//! An early piece's anchor gap u = g_m has the box [F_m, g0 − P_m], where F_m is the gap at
//! step m of the *fastest approach that respects the area* (Lemma 8): each step at speed W
//! while that ends outside the area's inner edge ρ − σ_g, else at the slowest in-area speed
//! V' = min(W, V_a + σ_w) — or, if that would stay outside, exactly onto the edge. Stepping
//! it costs one exact step per anchor step, and every early piece of a long-latency robot
//! asked for it anew (O(latency · steps) per piece: 34 s for one certificate).
//!
//! The approach has only three phases, so F_m has a closed form. Let
//! G_k = g0 − P_k − W·dt·k (the obstacle at W throughout) and k* the first index with
//! G_k ≤ ρ − σ_g. Then
//!
//! - F_m = G_m for m < k* (outside the edge, at W);
//! - F_{k*} = ρ − σ_g if G_{k*−1} − c − V'·dt > ρ − σ_g (landing on the edge needs a speed
//!   above V'), else G_{k*−1} − c − V'·dt, where c = P_{k*} − P_{k*−1} (F_0 = g0 if k* = 0);
//! - F_m = F_{k*} − (P_m − P_{k*}) − V'·dt·(m − k*) for m ≥ k* (inside for good, at V').
//!
//! Every branch is decided at the problem's values, exactly as a step-by-step run decides
//! it, so the affine numbers (values and slopes) are the stepped run's, exactly; the stepped
//! definition stays as the unit tests' independent answer.

use crate::core::model::Params;
use crate::core::num::Exact;
use crate::core::parameter::{ParamAffine, symbolic};
use crate::proof::schedule::Decomposition;

/// The fastest speed an obstacle inside the area may have without the wrong-assumption
/// guard firing for every error: min(W, V_a + σ_w).
pub(crate) fn slowest_fast<N: Approach>(s: &Params<N>) -> N {
    let seen = s.V_a.clone() + s.sigma_w.clone();
    if seen > s.W { s.W.clone() } else { seen }
}

/// The numbers the area-respecting approach is computed in: exact values at a point (the
/// slowest in-area speed, occlusion's lowest sighting gap) or affine in the parameters (an
/// early piece's box end, with its slopes).
pub(crate) trait Approach:
    Clone + PartialOrd + std::ops::Add<Output = Self> + std::ops::Sub<Output = Self>
{
    /// A constant.
    fn lift(x: &Exact) -> Self;
    /// `self · k`.
    fn times(&self, k: &Exact) -> Self;
}

impl Approach for Exact {
    fn lift(x: &Exact) -> Self {
        x.clone()
    }
    fn times(&self, k: &Exact) -> Self {
        self * k
    }
}

impl Approach for ParamAffine {
    fn lift(x: &Exact) -> Self {
        ParamAffine::constant(x.clone())
    }
    fn times(&self, k: &Exact) -> Self {
        self.scaled(k)
    }
}

impl Decomposition {
    /// k*: the first gap index at which the obstacle, at speed W from the start, is at or
    /// inside the area's inner edge ρ − σ_g (at the values of `s`).
    fn edge_crossing(&self, s: &Params<ParamAffine>) -> usize {
        let dt = &self.params.dt;
        let edge = s.rho.value.clone() - s.sigma_g.value.clone();
        let (g0, w) = (&s.g0.value, &s.W.value);
        let at_w = |k: usize, dec: &Self| {
            g0.clone() - dec.position(k) - w.clone() * dt.clone() * Exact::from(k)
        };
        let c = self.cruise_from;
        // Past the cruise onset the gap at W falls by (v_max + W)·dt per step.
        let steps =
            (at_w(c, self) - edge.clone()) / ((self.params.v_max.clone() + w.clone()) * dt.clone());
        self.first_index(|k, dec| at_w(k, dec) <= edge, steps)
    }

    /// G_k = g0 − P_k − W·dt·k: the gap at step k of the obstacle at W throughout.
    fn gap_at_w(&self, s: &Params<ParamAffine>, k: usize) -> ParamAffine {
        s.g0.clone()
            - ParamAffine::constant(self.position(k))
            - s.W.scaled(&(self.params.dt.clone() * Exact::from(k)))
    }

    /// F_{k*}: the gap after the step that crosses the area's inner edge (module docs).
    fn gap_after_crossing(&self, s: &Params<ParamAffine>, k: usize) -> ParamAffine {
        let slow = slowest_fast(s);
        if k == 0 {
            return s.g0.clone();
        }
        let closing = ParamAffine::constant(self.position(k) - self.position(k - 1));
        let at_slow = self.gap_at_w(s, k - 1) - closing - slow.scaled(&self.params.dt);
        let edge = s.rho.clone() - s.sigma_g.clone();
        // (A tie takes the slow side: landing on the edge needs no speed above V'.)
        if at_slow > edge { edge } else { at_slow }
    }

    /// F_m, the lowest gap an early piece's prefix reaches by its anchor m: the gap at step
    /// m of the fastest approach that respects the area, affine in the parameters (each
    /// branch taken at the values of `s`), in closed form (module docs).
    pub(crate) fn fastest_gap(&self, s: &Params<ParamAffine>, m: usize) -> ParamAffine {
        let k = self.edge_crossing(s);
        self.fastest_gap_crossing_at(s, k, m)
    }

    /// F_m given k* = `k`.
    fn fastest_gap_crossing_at(&self, s: &Params<ParamAffine>, k: usize, m: usize) -> ParamAffine {
        if m < k {
            return self.gap_at_w(s, m);
        }
        let inside = ParamAffine::constant(self.position(m) - self.position(k));
        let slow = slowest_fast(s).scaled(&(self.params.dt.clone() * Exact::from(m - k)));
        self.gap_after_crossing(s, k) - inside - slow
    }

    /// The obstacle's fastest approach over steps 0..m for an early piece: speed W while
    /// that keeps it outside the reaction area, then at most V_a, because every speed whose
    /// step ends inside the area is observed before the brake step and must not exceed V_a.
    /// Returns the speeds and the gap at step m, the lowest reachable (as a closure: a step
    /// may end exactly on ρ). Any gap between it and g0 − P_m is reached by scaling these
    /// speeds down by a factor λ ≤ 1: the scaled path is farther out at every step, so it is
    /// inside the area at fewer steps, and there its speed is a fraction of one ≤ V_a.
    pub fn fastest_approach(&self, m: usize) -> (Vec<Exact>, Exact) {
        let s = symbolic(&self.params);
        let k = self.edge_crossing(&s);
        let p = &self.params;
        let slow = slowest_fast(p);
        let speeds = (0..m)
            .map(|j| {
                if j + 1 < k {
                    p.W.clone()
                } else if j + 1 == k {
                    // The crossing step: from G_{k−1} to F_k.
                    let before = self.gap_at_w(&s, j).value;
                    let after = self.gap_after_crossing(&s, k).value;
                    (before - after - (self.position(k) - self.position(j))) / p.dt.clone()
                } else {
                    slow.clone()
                }
            })
            .collect();
        (speeds, self.fastest_gap_crossing_at(&s, k, m).value)
    }

    /// The first anchor m ≥ `from` at which the fastest approach (see
    /// [`Decomposition::fastest_approach`]) at the point `p` has covered at least `need`, if
    /// any before `last_brake`. What it has covered, g0 − P_m − F_m (the obstacle's own
    /// travel), never shrinks in m, so the first is found by bisection.
    pub(crate) fn first_fast_cover(
        &self,
        p: &Params<Exact>,
        from: usize,
        need: &Exact,
    ) -> Option<usize> {
        let s = symbolic(p);
        let k = self.edge_crossing(&s);
        let covered = |m: usize| {
            p.g0.clone() - self.position(m) - self.fastest_gap_crossing_at(&s, k, m).value >= *need
        };
        let end = self.last_brake;
        if from >= end || !covered(end - 1) {
            return None;
        }
        // The first covered index in [from, end − 1]: hi is covered, lo is not (or from).
        if covered(from) {
            return Some(from);
        }
        let (mut lo, mut hi) = (from, end - 1);
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if covered(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        Some(hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::proof::schedule::tests::problem;

    /// The definition (docs/reductions.md, Lemma 8): the approach stepped one step at a
    /// time, each step's speed chosen at the values of `s` — W while that step ends outside
    /// the inner edge, else onto the edge if that needs more than V', else V'. Returns the
    /// gaps F_0..=F_m and how many steps met a tie (ending exactly on the edge at W, or
    /// landing on it needing exactly V').
    fn stepped(
        dec: &Decomposition,
        s: &Params<ParamAffine>,
        m: usize,
    ) -> (Vec<ParamAffine>, usize) {
        let dt = &dec.params.dt;
        let edge = s.rho.clone() - s.sigma_g.clone();
        let slow = slowest_fast(s);
        let mut gaps = vec![s.g0.clone()];
        let mut ties = 0;
        for j in 0..m {
            let gap = gaps[j].clone();
            let closing = ParamAffine::constant(dec.position(j + 1) - dec.position(j));
            let at_w = gap.clone() - closing.clone() - s.W.scaled(dt);
            let w = if at_w > edge {
                s.W.clone()
            } else {
                let to_edge =
                    (gap.clone() - closing.clone() - edge.clone()).scaled(&(Exact::ONE / dt));
                ties += usize::from(at_w.value == edge.value || to_edge.value == slow.value);
                let w = if to_edge > slow {
                    to_edge
                } else {
                    slow.clone()
                };
                if w > s.W { s.W.clone() } else { w }
            };
            gaps.push(gap - closing - w.scaled(dt));
        }
        (gaps, ties)
    }

    /// A small deterministic generator (no dependency; the same points every run).
    struct Draw(u64);

    impl Draw {
        /// A number in [0, n).
        fn below(&mut self, n: u64) -> u64 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (self.0 >> 33) % n
        }
        /// One of `options`.
        fn pick<T: Copy>(&mut self, options: &[T]) -> T {
            options[self.below(options.len() as u64) as usize]
        }
        /// n/100 for n in [lo, hi].
        fn hundredths(&mut self, lo: u64, hi: u64) -> Exact {
            Exact::from(lo + self.below(hi - lo + 1)) / Exact::from(100)
        }
    }

    /// The closed form's gaps (values and slopes), its witness speeds and its first covers
    /// equal the stepped definition exactly, on 300 random exact points: with and without
    /// noise σ_g, σ_w, V' = V_a + σ_w below and at W, accelerating and cruising robots, a
    /// start inside the edge, and starts chosen so that a step lands exactly on the edge at W
    /// or needs exactly V' to land on it (both ties are counted, so the draw cannot miss
    /// them).
    #[test]
    fn the_closed_form_fastest_approach_is_the_stepped_definition() {
        let mut draw = Draw(37);
        let (mut ties, mut from_inside, mut cases) = (0, 0, 0);
        for case in 0..300 {
            let (v, a, dt) = (
                draw.pick(&[0.2, 0.5, 1.0]),
                draw.pick(&[0.1, 0.5, 5.0]),
                draw.pick(&[0.1, 0.05, 0.02]),
            );
            let base = Decomposition::new(&problem(v, a, 0.5, dt)).params;
            let mut p = base.clone();
            p.W = draw.hundredths(1, 60);
            p.V_a = draw.hundredths(0, 40);
            p.rho = draw.hundredths(10, 300);
            p.sigma_g = if draw.below(2) == 0 {
                Exact::ZERO
            } else {
                draw.hundredths(1, 9)
            };
            p.sigma_w = if draw.below(2) == 0 {
                Exact::ZERO
            } else {
                draw.hundredths(1, 20)
            };
            p.g0 = draw.hundredths(50, 600);
            p.g0_max = p.g0.clone();
            let dec = Decomposition::from_params(p.clone());
            // A start whose W run lands exactly on the edge at step k, or whose crossing step
            // at k needs exactly V' to land on it (module docs: G_{k−1} − c − V'·dt = edge).
            let k = 1 + draw.below(200) as usize;
            let edge = p.rho.clone() - p.sigma_g.clone();
            let w_dt = |n: usize| p.W.clone() * p.dt.clone() * Exact::from(n);
            match case % 3 {
                1 => p.g0 = edge.clone() + dec.position(k) + w_dt(k),
                2 => {
                    p.g0 = edge.clone()
                        + dec.position(k)
                        + w_dt(k - 1)
                        + slowest_fast(&p) * p.dt.clone()
                }
                _ => {}
            }
            p.g0_max = p.g0.clone();
            let dec = Decomposition::from_params(p.clone());
            let s = symbolic(&p);
            let m = dec.last_brake.max(k + 20);
            let (gaps, tied) = stepped(&dec, &s, m);
            ties += usize::from(tied > 0);
            from_inside += usize::from(p.g0 <= edge);
            cases += 1;
            for (i, gap) in gaps.iter().enumerate() {
                assert_eq!(dec.fastest_gap(&s, i), *gap, "case {case}, step {i}: {p:?}");
            }
            // The witness's speeds move the obstacle from each gap to the next.
            let (speeds, last) = dec.fastest_approach(m);
            assert_eq!(last, gaps[m].value, "case {case}");
            for (j, w) in speeds.iter().enumerate() {
                let closing = dec.position(j + 1) - dec.position(j);
                let moved = gaps[j].value.clone() - closing - gaps[j + 1].value.clone();
                assert_eq!(w.clone() * p.dt.clone(), moved, "case {case}, speed {j}");
            }
            // First covers: a scan of the stepped gaps, for covers at every step's boundary
            // and just past it, from several anchors.
            let covered: Vec<Exact> = (0..dec.last_brake)
                .map(|j| p.g0.clone() - dec.position(j) - gaps[j].value.clone())
                .collect();
            let tiny = Exact::ONE / Exact::from(1_000_000_000_000u64);
            let mut needs = vec![Exact::ZERO, p.g0.clone()];
            needs.extend(covered.iter().step_by(7).cloned());
            needs.extend(covered.iter().step_by(5).map(|c| c.clone() + tiny.clone()));
            for need in &needs {
                for from in [0, 3, dec.cruise_from, k, dec.last_brake / 2, dec.last_brake] {
                    let scan = (from..dec.last_brake).find(|&j| covered[j] >= *need);
                    assert_eq!(
                        dec.first_fast_cover(&p, from, need),
                        scan,
                        "case {case}, from {from}"
                    );
                }
            }
        }
        assert!(ties >= cases / 2, "only {ties} of {cases} cases met a tie");
        assert!(
            from_inside >= 5,
            "only {from_inside} cases start inside the edge"
        );
    }
}
