//! Occlusion with the wrong-assumption guard active: the pieces of an obstacle that is first
//! seen *inside* the reaction area some steps before the robot brakes.
//!
//! Without the wrong-assumption guard, an obstacle first seen at K < T has the visible
//! schedule's rows from K on, so the visible pieces cover it (docs/semantics.md §12). With
//! the guard active, the in-area pieces also bound the obstacle's *observed* speeds by V_a
//! from their entry E on, and start with "outside at E−1". Take a behaviour first seen at
//! K and braking at T, and let E be the first step at which every error shows it inside
//! (true gap ≤ ρ − σ_g):
//!
//! - **K < E** (first seen where an error can show it outside): every step from E on is
//!   observed, so its speeds there are seen ≤ V_a, and step E−1 ≥ K can be seen outside —
//!   the visible in-area piece of (E, T) holds it. (An early piece's prefix only needs the
//!   speeds of steps that end inside the area bounded, and those are observed.)
//! - **K = T**: hidden until T and the guard fires at T — occlusion's own pieces
//!   ([`crate::proof::schedule::Piece::detected`] without an entry), now with all three
//!   endings.
//! - **E ≤ K < T**: first seen inside the area before T. These are the *detected twins* of
//!   the in-area pieces: entry K, with the row "outside at K−1" replaced by "true gap at K
//!   ≥ d_det" (nothing was seen before K, so nothing else constrains the prefix), and every
//!   other row the same (in the area from K on, clear of danger at T−1 — hence at every
//!   in-area step, by the monotonicity of o − d —, observed speeds ≤ V_a from K on, the
//!   ending at T). K = T−1 is one twin per brake step. Every K ≤ T−2 shares the rows
//!   from T−2 on with the visible early piece, and the earlier ones constrain only the
//!   gap u at the anchor T−2−L, through the lowest gap the prefix can reach: one *early
//!   twin* per brake step, whose u has the box [lowest, g0 − P_m] described next.
//!
//! Including more than the E ≤ K case in a twin is harmless (every solution of its rows is
//! still a behaviour of the model, first seen at K with a true gap ≥ d_det, quiet until T),
//! which is why the twins do not ask for "inside at K".
//!
//! # The lowest gap of an early twin
//! First seen at gap index j = K − L ≤ m (m = T−2−L, the anchor): the speeds w_0..w_{j−2}
//! are unobserved (≤ W), w_{j−1} .. w_{m−1} are observed from K on and must be seen
//! ≤ V_a, so are ≤ V' = min(W, V_a + σ_w), and the true gap at the sighting is g_j ≥ d_det.
//! For fixed j the lowest sighting gap is G(j) = max(d_det, g0 − P_j − dt·(W·(j−1) + V'))
//! (g0 at j = 0: nothing moved), reachable iff the robot alone leaves g0 − P_j ≥ d_det, and
//! then u_j(m) = G(j) − (P_m − P_j) − dt·V'·(m − j). While the max takes its second side,
//! u_j decreases in j by dt·(W − V') per step; once it takes d_det, u_j increases in j. So
//! the least over j ≤ m is at j_c − 1 or j_c, where j_c is the first j at which
//! g0 − P_j − dt·(W·(j−1) + V') ≤ d_det (one number for the whole decomposition), or at m if
//! j_c > m. Every gap between that least and g0 − P_m is reached by scaling those speeds by
//! λ ≤ 1: the sighting gap only grows and the observed speeds stay ≤ V'. The box's width
//! g0 − P_m − lowest(m) never shrinks as m grows (lowest(m+1) ≤ u_{j*}(m+1) = lowest(m) −
//! (P_{m+1} − P_m) − dt·V'), so shifted early twins merge, exactly as the visible ones, from
//! the first cruising brake step whose width reaches v_max·dt.

use crate::core::model::Params;
use crate::core::num::{Exact, Scalar};
use crate::proof::approach_closed_form::{Approach, slowest_fast};
use crate::proof::schedule::{Decomposition, Ending};

impl Decomposition {
    /// Whether an obstacle may be first seen where every error shows it inside the area
    /// (d_det ≤ ρ − σ_g). If not, every sighting could be shown outside, and the visible
    /// in-area pieces cover what follows it (see the module docs).
    pub(crate) fn inside_sighting_possible(&self) -> bool {
        let p = &self.params;
        p.d_det
            .as_ref()
            .is_some_and(|d| *d <= p.rho.clone() - p.sigma_g.clone())
    }

    /// j_c: the first gap index at which the obstacle, unobserved at W and observed at V'
    /// in the step before, would be seen below d_det (see the module docs).
    pub(crate) fn find_sighting_cross(&self) -> usize {
        let p = &self.params;
        let Some(d_det) = &p.d_det else { return 0 };
        let dt = p.dt.clone();
        let fast = slowest_fast(p);
        let a = |k: usize, dec: &Self| {
            p.g0.clone()
                - dec.position(k)
                - (p.W.clone() * (Exact::from(k) - Exact::ONE) + fast.clone()) * dt.clone()
        };
        let c = self.cruise_from;
        // Past the cruise onset A falls by (v_max + W)·dt per step.
        let steps = (a(c, self) - d_det.clone()) / ((p.v_max.clone() + p.W.clone()) * dt.clone());
        self.first_index(|k, dec| a(k, dec) <= *d_det, steps)
    }

    /// The lowest true gap at which an obstacle first seen at gap index j can be seen
    /// (G(j) of the module docs), if it can be seen there at all.
    fn sighting_gap<N: Approach>(&self, s: &Params<N>, j: usize) -> Option<N> {
        let d_det = s.d_det.clone()?;
        let reach = s.g0.clone() - N::lift(&self.position(j));
        if reach < d_det {
            return None;
        }
        if j == 0 {
            return Some(s.g0.clone());
        }
        let covered =
            (s.W.times(&Exact::from(j - 1)) + slowest_fast(s)).times(&self.params.dt.clone());
        let a = reach - covered;
        Some(if a > d_det { a } else { d_det })
    }

    /// The lowest gap at anchor m of an early twin, and the gap index of the sighting that
    /// reaches it; None if no sighting by m is possible.
    pub(crate) fn detected_lowest_gap<N: Approach>(
        &self,
        s: &Params<N>,
        m: usize,
    ) -> Option<(N, usize)> {
        let top = self.sighting_cross.min(m);
        let dt = &self.params.dt;
        let mut best: Option<(N, usize)> = None;
        for j in [top.checked_sub(1), Some(top)].into_iter().flatten() {
            let Some(g) = self.sighting_gap(s, j) else {
                continue;
            };
            let u = g
                - N::lift(&(self.position(m) - self.position(j)))
                - slowest_fast(s).times(&(dt.clone() * Exact::from(m - j)));
            if best.as_ref().is_none_or(|(b, _)| u < *b) {
                best = Some((u, j));
            }
        }
        best
    }

    /// The speeds over steps 0..m that reach an early twin's lowest gap at anchor m, that
    /// gap, and the step K at which the obstacle is first seen (module docs).
    pub fn detected_fastest_approach(&self, m: usize) -> Option<(Vec<Exact>, Exact, usize)> {
        let p = &self.params;
        let (lowest, j) = self.detected_lowest_gap(p, m)?;
        let seen_at = self.sighting_gap(p, j)?;
        let fast = slowest_fast(p);
        let mut speeds = vec![Exact::ZERO; m];
        if j >= 1 {
            // w_0 .. w_{j−1} cover g0 − P_j − G(j): the last (observed) one at most V', the
            // unobserved ones at most W, fastest first.
            let mut total = (p.g0.clone() - self.position(j) - seen_at) / p.dt.clone();
            let last = Exact::min_of(fast.clone(), total.clone());
            total -= last.clone();
            speeds[j - 1] = last;
            for w in &mut speeds[..j - 1] {
                let x = Exact::min_of(p.W.clone(), total.clone());
                total -= x.clone();
                *w = x;
            }
            debug_assert!(total == Exact::ZERO);
        }
        for w in &mut speeds[j..] {
            *w = fast.clone();
        }
        Some((speeds, lowest, j + p.L))
    }

    /// The brake step from which shifted early twins merge: the first at or after `t0`
    /// (where the visible pieces merge: cruising, shifts overlap in the rest) at which the
    /// box of u is at least v_max·dt wide. The width never shrinks, so a binary search.
    fn detected_early_merge_step(&self, t0: usize) -> Option<usize> {
        let p = &self.params;
        let l = p.L;
        let need = p.v_max.clone() * p.dt.clone();
        let wide = |t: usize| {
            let m = t - 2 - l;
            self.detected_lowest_gap(p, m)
                .is_some_and(|(lowest, _)| p.g0_max.clone() - self.position(m) - lowest >= need)
        };
        let (mut lo, mut hi) = (t0, self.last_brake);
        if lo >= hi || !wide(hi - 1) {
            return None;
        }
        while lo < hi - 1 {
            let mid = lo + (hi - 1 - lo) / 2;
            if wide(mid) {
                hi = mid + 1;
            } else {
                lo = mid + 1;
            }
        }
        wide(lo).then_some(lo)
    }

    /// The detected twins of the in-area pieces: first seen inside the area at T−1, or at
    /// T−2 or earlier (one early twin), per brake step, each with every ending.
    pub(crate) fn list_detected_in_area_pieces(&mut self, merge_at: Option<usize>) {
        if !self.inside_sighting_possible() {
            return;
        }
        let all = [Ending::Danger, Ending::WrongAssumption, Ending::PassThrough];
        let l = self.params.L;
        let first = self.first_brake.max(l);
        let last = merge_at.unwrap_or(self.last_brake);
        let early_merge_at = merge_at.and_then(|t0| self.detected_early_merge_step(t0));
        let early_last = early_merge_at.unwrap_or(self.last_brake);
        let early_possible = |dec: &Self, t: usize, merged: bool| {
            dec.early_entry_possible(first, t, merged)
                && dec.detected_lowest_gap(&dec.params, t - 2 - l).is_some()
        };
        for t in first..last.max(early_last) {
            if t < last && t > 0 && self.recent_entries(first, t, false).contains(&(t - 1)) {
                self.push_detected_entry(t - 1, t, false, false, &all);
            }
            if t < early_last && early_possible(self, t, false) {
                self.push_detected_entry(t - 2, t, false, true, &all);
            }
        }
        if let Some(t) = merge_at
            && self.recent_entries(first, t, true).contains(&(t - 1))
        {
            self.push_detected_entry(t - 1, t, true, false, &all);
        }
        if let Some(t) = early_merge_at
            && early_possible(self, t, true)
        {
            self.push_detected_entry(t - 2, t, true, true, &all);
        }
    }

    fn push_detected_entry(
        &mut self,
        e: usize,
        t: usize,
        merged: bool,
        early: bool,
        endings: &[Ending],
    ) {
        let new = self.push_entry(e, t, merged, early, endings);
        for piece in &mut self.pieces[new] {
            piece.detected = true;
        }
    }
}
