//! From the hybrid model to finitely many linear programs: the schedule decomposition.
//!
//! # Notation
//! Step k covers [k·dt, (k+1)·dt]. The obstacle holds speed w_k ∈ [0, W] in step k.
//! Along the *drive profile* (the robot never braking) the robot is at P_k with speed v_k at
//! step k's start. The gap is g_k = g0 − P_k − dt·Σ_{j<k} w_j. At step k ≥ L the robot sees
//! o_k = g_{k−L} and the speed w_{k−L−1} (0 before the first step). Thresholds:
//! d_k = d_coll(v_k) (∞ for the `area` rule) and θ_k = min(ρ, d_k).
//!
//! Two monotonicity facts (see [`crate::core::semantics`]) carry the whole reduction:
//! g_k is nonincreasing in k for every behaviour, and v_k, hence d_k and θ_k, is
//! nondecreasing along the drive profile.
//!
//! # Pieces
//! Every behaviour has a *brake step* T (the guard fires at T's start) or never brakes. A
//! robot that never brakes keeps moving, so the gap falls below every bound: there is a last
//! step whose observed gap is positive, and the next one T has o_T ≤ 0 — the obstacle
//! *passed through* the reaction area between two observations. So behaviours split into
//! pieces (T, ending) with ending ∈ {danger, wrong assumption, pass-through}.
//!
//! **Without the wrong-assumption guard** (off, or W ≤ V_a so no observed speed exceeds V_a),
//! not firing at k is o_k ≤ 0 ∨ o_k > θ_k. Before a brake step T, o_k ≤ 0 is impossible
//! (o would stay ≤ 0 and never fire), and o_k − θ_k is nonincreasing, so "no fire before T"
//! is the single row o_{T−1} > θ_{T−1}. A piece is
//! - danger: o_{T−1} > θ_{T−1}, 0 < o_T ≤ θ_T;
//! - pass-through: o_{T−1} > θ_{T−1}, o_T ≤ 0.
//!
//! **With it** (on and W > V_a) a piece also fixes the *entry* E ≤ T, the first step whose
//! observation lies in (0, ρ]: o_{E−1} > ρ, and if E < T, o_E ≤ ρ, o_{T−1} > d_{T−1} (all
//! in-area steps clear of danger, by the same monotonicity) and w_{k−L−1} ≤ V_a for
//! k ∈ [E, T) (no wrong assumption seen). The endings add o_T ∈ (0, ρ] with o_T ≤ d_T
//! (danger) or w_{T−L−1} > V_a (wrong assumption), or o_T ≤ 0 (pass-through).
//! In-area runs end: once ρ − (P_{T−1−L} − P_{E−L}) ≤ d_{T−1}, no longer E..T is possible.
//! Entries E ≤ T−2 need no piece each: their rows from step T−2 on are the same (entered by
//! T−2, clear of danger at T−1, observed speed at T−1 ≤ V_a), and the earlier rows only
//! constrain speeds that enter the gap at T−2 through their sum. One *early* piece per T
//! (o_{T−2} ≤ ρ, anchored at T−2) stands for all of them. The lowest gap its prefix can
//! reach is that of the fastest approach that respects the area — W while outside, at most
//! V_a once inside ([`Decomposition::fastest_approach`], in closed form:
//! [`crate::proof::approach_closed_form`]) — and every gap above it is reached
//! by scaling those speeds down (docs/reductions.md, Lemmas 8 and 8a). So each brake step has at most three entries: T, T−1,
//! and "T−2 or earlier".
//!
//! Each piece's rows are necessary and sufficient for its schedule (the converse direction
//! uses the same monotonicity), so the decomposition is exact: the pieces partition the
//! behaviours up to the boundaries where two pieces meet.
//!
//! # Variables
//! A piece's rows mention gaps from an *anchor* index m on (the first gap any row uses)
//! and speeds w_m..w_{n−1}, n = T − L. Speeds before m enter only through their sum, so
//! they become one variable u = g_m with the box [g0 − P_m − W·dt·m, g0 − P_m] (any value
//! in it is reached by a constant speed ≤ W). Speeds from n on appear in no row; the gap at
//! rest falls with each, so the worst case holds them at W. A danger or wrong-assumption
//! piece's objective is the gap when the robot comes to rest after braking at T — the
//! worst-case separation, since the gap falls while the robot moves. Pass-through pieces
//! are feasibility questions: any such behaviour collides.
//!
//! # Finitely many pieces: the shift
//! Once the robot cruises at v_max from the anchor on, shifting T (and E) by one step
//! changes nothing in the rows but u's box, which slides down by v_max·dt while its width
//! W·dt·m grows. When W·m ≥ v_max consecutive boxes overlap, so their union over all later
//! shifts is (−∞, g0 − P_m], and intersected with the rows (which force u > 0) it is
//! (0, g0 − P_m]. One *merged* piece with u ∈ [0, g0 − P_m] therefore stands exactly for
//! the piece and all its shifts. Before that point pieces are listed one by one; they end
//! for good at the step T_end where g0 − P_{T−1−L} ≤ 0 (the robot alone has reached the
//! obstacle's start, so no later observation can be positive).
//!
//! A robot that never moves (braking at step 0 at rest) cannot collide: such a piece is
//! left out.
//!
//! # Sensing noise
//! With observed gaps off by up to σ_g and measured speeds by up to σ_w, chosen by the
//! environment per observation, every row above is the true gap's condition for *some*
//! error to give its observation what the row asks (an error enters only its own
//! observation's guard, so it projects out exactly): "seen > θ" becomes g > θ − σ_g,
//! "seen ≤ θ" g ≤ θ + σ_g, "seen > 0" g > −σ_g, "seen ≤ 0" g ≤ σ_g, "seen ≤ V_a" w ≤ V_a + σ_w
//! and "seen > V_a" w > V_a − σ_w. Monotonicity, the entries and the shift are unchanged
//! (docs/semantics.md §12).

mod drive_profile;
mod piece;
mod rows;

pub use piece::{Ending, Piece};
pub(crate) use rows::min_opt;

use crate::core::model::{Params, Problem};
use crate::core::num::Exact;
use crate::core::param_box::ParamBox;
use crate::core::parameter::Parameter;
use crate::core::semantics::danger_distance;

use drive_profile::{Profile, shared_drive_profile, stopping};

/// The exact drive profile of a problem and its pieces.
#[derive(Clone, Debug)]
pub struct Decomposition {
    /// The problem's exact numbers.
    pub params: Params<Exact>,
    /// Robot state at each step's start along the drive profile, up to the cruise onset;
    /// later states follow from it (see [`Decomposition::drive`]).
    profile: Profile,
    /// v_max·dt: how far each cruising step goes.
    cruise_step: Exact,
    /// First step at whose start the robot cruises at v_max.
    pub cruise_from: usize,
    /// First brake step any piece can have: before it even the fastest obstacle is
    /// observed outside the reaction area.
    pub first_brake: usize,
    /// No piece brakes at or after this step: the robot alone has reached the obstacle's
    /// start by then, or (with `cut`) the robot has braked for another reason. (Merged
    /// pieces stand for every later shift below it.)
    pub(crate) last_brake: usize,
    /// The limit that cut `last_brake` short (a scene's T_max), if it did: a merged piece's
    /// shifts then stop at it, which raises the lower end of its anchor gap (Lemma 11).
    pub(crate) cut: Option<usize>,
    /// All pieces, in a fixed order (the certificate lists proofs in this order).
    pub pieces: Vec<Piece>,
    /// Time and distance to stop when braking from v_max (shared by every cruising piece).
    cruise_stop: (Exact, Exact),
    /// For a region certificate, the box of parameter values the pieces must cover: every
    /// decision that depends on a named parameter is then made for the whole box
    /// ([`crate::proof::region_schedule`]); `params` is the box's centre.
    pub(crate) region: Option<ParamBox>,
    /// The point where in-area runs are longest (`params` itself for a point; computed once,
    /// every listed step asks).
    pub(crate) widest_area: Params<Exact>,
    /// Whether the wrong-assumption guard can fire somewhere (computed once).
    pub(crate) guard_active: bool,
    /// With occlusion and the guard active: the gap index j_c around which an early twin's
    /// sighting reaches the lowest gap ([`crate::proof::occlusion_schedule`]; computed once).
    pub(crate) sighting_cross: usize,
}

impl Decomposition {
    /// Builds the drive profile and lists the pieces of `problem` (which must be valid).
    pub fn new(problem: &Problem) -> Self {
        Self::from_params(problem.params())
    }

    /// As [`Decomposition::new`], from exact parameters.
    pub fn from_params(params: Params<Exact>) -> Self {
        Self::from_params_until(params, None, true)
    }

    /// As [`Decomposition::from_params`], keeping only pieces whose brake step is at most
    /// `limit` (in a scene, the robot has braked for another reason by then). Pieces are
    /// merged over shifts when `merge` allows it: a merged piece stands for every later
    /// shift below `last_brake` (up to the limit, when it cuts).
    pub fn from_params_until(params: Params<Exact>, limit: Option<usize>, merge: bool) -> Self {
        Self::build(params, limit, merge, None)
    }

    /// The decomposition at `params`, or for every point of `region` (then `params` is its
    /// centre).
    pub(crate) fn build(
        params: Params<Exact>,
        limit: Option<usize>,
        merge: bool,
        region: Option<ParamBox>,
    ) -> Self {
        let profile = shared_drive_profile(&params);
        let mut d = Decomposition {
            cruise_step: params.v_max.clone() * params.dt.clone(),
            cruise_stop: stopping(&params, params.v_max.clone()),
            cruise_from: profile.len() - 1,
            profile,
            widest_area: params.clone(),
            params,
            first_brake: 0,
            last_brake: 0,
            pieces: Vec::new(),
            cut: None,
            region,
            guard_active: false,
            sighting_cross: 0,
        };
        d.widest_area = d.widest_area_corner();
        d.guard_active = d.guard_active_somewhere();
        d.find_brake_range();
        d.cut = limit.filter(|&t| t.saturating_add(1) < d.last_brake);
        if let Some(t) = d.cut {
            d.last_brake = t + 1;
        }
        let merge_at = if merge { d.merge_step() } else { None };
        if d.wrong_assumption_active() {
            d.list_in_area_pieces(merge_at);
        } else {
            d.list_pieces(merge_at);
        }
        if d.params.d_det.is_some() {
            d.list_detected_pieces(merge_at);
            if d.wrong_assumption_active() {
                // (Region certificates refuse this combination before they get here.)
                debug_assert!(d.region.is_none());
                d.sighting_cross = d.find_sighting_cross();
                d.list_detected_in_area_pieces(merge_at);
            }
        }
        d
    }

    /// Occlusion's pieces: hidden at every step before T, first seen at T at a true gap
    /// ≥ d_det, and the guard fires there. (Pieces first seen *before* T are the ones
    /// above: their rows from the first sighting on are the visible schedule's, and a
    /// visible start is the weaker constraint; see docs/semantics.md §12. With the
    /// wrong-assumption guard active, an obstacle first seen inside the area before T has
    /// its own pieces too: [`crate::proof::occlusion_schedule`].)
    fn list_detected_pieces(&mut self, merge_at: Option<usize>) {
        // First seen already passed (a true gap in [d_det, σ_g] seen ≤ 0) is a pass-through
        // no visible piece holds: its earlier rows are hidden.
        let endings: &[Ending] = if self.wrong_assumption_active() {
            &[Ending::Danger, Ending::WrongAssumption, Ending::PassThrough]
        } else {
            &[Ending::Danger, Ending::PassThrough]
        };
        let l = self.params.L;
        let last = merge_at.unwrap_or(self.last_brake);
        let before = self.pieces.len();
        for t in self.first_brake.max(l)..last {
            self.push_endings(None, t, false, endings);
        }
        if let Some(t) = merge_at {
            self.push_endings(None, t, true, endings);
        }
        for piece in &mut self.pieces[before..] {
            piece.detected = true;
        }
    }

    /// Sets `first_brake` (before it even the fastest obstacle is observed outside ρ) and
    /// `last_brake` (from it on the robot alone has reached the obstacle's start).
    fn find_brake_range(&mut self) {
        (self.first_brake, self.last_brake) = match &self.region {
            None => self.brake_range(&self.params),
            Some(_) => (
                self.brake_range(&self.earliest_reach_corner()).0,
                self.brake_range(&self.farthest_start_corner()).1,
            ),
        };
    }

    /// (first_brake, last_brake) at the point `p` (whose robot is this decomposition's).
    fn brake_range(&self, p: &Params<Exact>) -> (usize, usize) {
        let p = p.clone();
        let per_step = p.v_max.clone() * p.dt.clone();
        // n_end: first gap index the robot alone reaches the obstacle's farthest start
        // (g0_max − P ≤ 0).
        // With noise an observation can still be positive until the gap is ≤ −σ_g.
        let beyond = p.g0_max.clone() + p.sigma_g.clone();
        let n_end = self.first_index(
            |k, dec| dec.position(k) >= beyond,
            (beyond.clone() - self.position(self.cruise_from)) / per_step,
        );
        // n_start: first gap index the fastest obstacle can be observed within ρ.
        let closing = (p.v_max.clone() + p.W.clone()) * p.dt.clone();
        let c = self.cruise_from;
        // (Seen within ρ for some error: a true gap ≤ ρ + σ_g.)
        let reach = p.rho.clone() + p.sigma_g.clone();
        let far = p.g0.clone()
            - self.position(c)
            - p.W.clone() * p.dt.clone() * Exact::from(c)
            - reach.clone();
        let n_start = self.first_index(
            |k, dec| {
                p.g0.clone() - dec.position(k) - p.W.clone() * p.dt.clone() * Exact::from(k)
                    <= reach
            },
            far / closing,
        );
        (n_start + p.L, n_end + 1 + p.L)
    }

    /// The brake step from which shifted pieces merge (cruising, and the boxes of
    /// consecutive shifts overlap), if it comes before `last_brake`.
    pub(crate) fn merge_step(&self) -> Option<usize> {
        let p = &self.params;
        // (Over a box: its slowest obstacle needs the longest anchor.)
        let w = self.least(Parameter::ObstacleSpeed);
        if w <= Exact::ZERO {
            return None;
        }
        // Anchors sit at T−1−L, or T−2−L for the entries E = T−1 and E ≤ T−2.
        let reach = if self.wrong_assumption_active() { 2 } else { 1 };
        let need = usize::try_from((p.v_max.clone() / w).ceil()).unwrap_or(usize::MAX);
        let t = self
            .cruise_from
            .max(need)
            .max(1)
            .saturating_add(reach + p.L);
        Some(t.max(self.first_brake)).filter(|&t| t < self.last_brake)
    }

    /// The pieces without the wrong-assumption guard: one per brake step and ending.
    fn list_pieces(&mut self, merge_at: Option<usize>) {
        let endings = [Ending::Danger, Ending::PassThrough];
        let last = merge_at.unwrap_or(self.last_brake);
        for t in self.first_brake.max(self.params.L)..last {
            self.push_endings(None, t, false, &endings);
        }
        if let Some(t) = merge_at {
            self.push_endings(None, t, true, &endings);
        }
    }

    /// The pieces with the wrong-assumption guard: per brake step t, entries at t, at t−1,
    /// and at t−2 or earlier (one early piece), each with every ending.
    fn list_in_area_pieces(&mut self, merge_at: Option<usize>) {
        let all = [Ending::Danger, Ending::WrongAssumption, Ending::PassThrough];
        let l = self.params.L;
        let first = self.first_brake.max(l);
        let last = merge_at.unwrap_or(self.last_brake);
        // Early pieces merge only once the area-respecting fastest approach can cover
        // v_max·dt before the anchor: then the reachable gaps of consecutive shifts
        // overlap (see `fastest_approach`); until then they are listed one by one.
        let early_merge_at = merge_at.and_then(|t0| {
            let need = self.params.v_max.clone() * self.params.dt.clone();
            self.first_fast_cover(&self.slowest_approach_corner(), t0 - 2 - l, &need)
                .map(|m| m + 2 + l)
                .filter(|&t| t < self.last_brake)
        });
        let early_last = early_merge_at.unwrap_or(self.last_brake);
        for t in first..last.max(early_last) {
            if t < last {
                for e in self.recent_entries(first, t, false) {
                    self.push_entry(e, t, false, false, &all);
                }
            }
            if t < early_last && self.early_entry_possible(first, t, false) {
                self.push_entry(t - 2, t, false, true, &all);
            }
        }
        if let Some(t) = merge_at {
            for e in self.recent_entries(first, t, true) {
                self.push_entry(e, t, true, false, &all);
            }
        }
        if let Some(t) = early_merge_at
            && self.early_entry_possible(first, t, true)
        {
            self.push_entry(t - 2, t, true, true, &all);
        }
    }

    /// Entries of brake step t at t and at t−1. Individual pieces need their entry at or
    /// after the first possible brake step `first`; a merged piece stands for all later
    /// shifts, so it keeps all of its entries.
    pub(crate) fn recent_entries(&self, first: usize, t: usize, merged: bool) -> Vec<usize> {
        let l = self.params.L;
        let mut out = vec![t];
        if (merged || t > first) && t > l && self.in_area_possible(t - 1, t) {
            out.push(t - 1);
        }
        out
    }

    /// The bystander pieces of brake step t (see [`Ending::Bystander`]): the robot brakes
    /// at t while this obstacle fired at no earlier step. Without the wrong-assumption guard
    /// one piece (o_{t−1} > θ_{t−1}); with it one per entry: not yet in the area (entry t),
    /// entered at t−1, or at t−2 or earlier, exactly as for the pieces that fire at t.
    pub fn bystander_pieces(&self, t: usize) -> Vec<Piece> {
        let l = self.params.L;
        let piece = |entry, early| Piece {
            entry,
            brake: t,
            ending: Ending::Bystander,
            merged: false,
            early,
            detected: false,
        };
        if !self.wrong_assumption_active() || t <= l {
            return vec![piece(None, false)];
        }
        let first = self.first_brake.max(l);
        let mut out: Vec<Piece> = self
            .recent_entries(first, t, false)
            .into_iter()
            .map(|e| piece(Some(e), false))
            .collect();
        if self.early_entry_possible(first, t, false) {
            out.push(piece(Some(t - 2), true));
        }
        out
    }

    /// Whether brake step t has an early piece (entry at t−2 or before).
    pub(crate) fn early_entry_possible(&self, first: usize, t: usize, merged: bool) -> bool {
        let l = self.params.L;
        (merged || t > first + 1) && t > l + 1 && self.in_area_possible(t - 2, t)
    }

    /// Whether the robot can spend steps E..T−1 in the area without danger: the robot alone
    /// closes ρ − (P_{T−1−L} − P_{E−L}) and d_{T−1} must stay below the observed gap.
    fn in_area_possible(&self, e: usize, t: usize) -> bool {
        let l = self.params.L;
        let closed = self.position(t - 1 - l) - self.position(e - l);
        // (Over a box: possible at some point, the widest area with the least danger.)
        let p = &self.widest_area;
        match danger_distance(p, self.speed(t - 1)) {
            None => false,
            Some(d) => p.rho.clone() - closed > d,
        }
    }

    /// Pushes the pieces of entry e and brake step t; returns where they sit in `pieces`.
    pub(crate) fn push_entry(
        &mut self,
        e: usize,
        t: usize,
        merged: bool,
        early: bool,
        endings: &[Ending],
    ) -> std::ops::Range<usize> {
        let before = self.pieces.len();
        self.push_endings(Some(e), t, merged, endings);
        for piece in &mut self.pieces[before..] {
            piece.early = early;
        }
        before..self.pieces.len()
    }

    fn push_endings(&mut self, entry: Option<usize>, t: usize, merged: bool, endings: &[Ending]) {
        for &ending in endings {
            if ending != Ending::PassThrough && *self.speed(t) == Exact::ZERO {
                continue; // the robot never moves
            }
            if ending == Ending::WrongAssumption && t < self.params.L + 1 {
                continue; // nothing observed moving yet: observed speed is 0 ≤ V_a
            }
            self.pieces.push(Piece {
                entry,
                brake: t,
                ending,
                merged,
                early: false,
                detected: false,
            });
        }
    }

    /// The brake steps a piece stands for: its own, and for a merged piece every later
    /// shift's below `last_brake` (Lemma 11; later shifts are empty, or cut off).
    pub fn brake_steps(&self, piece: &Piece) -> std::ops::Range<usize> {
        if piece.merged {
            piece.brake..self.last_brake.max(piece.brake + 1)
        } else {
            piece.brake..piece.brake + 1
        }
    }

    /// Where a merged piece's optimum u* = g_m lies: the shift j ≥ 0 whose box contains it
    /// (boxes of consecutive shifts overlap, see the module docs).
    pub fn shift_for(&self, piece: &Piece, u: &Exact) -> usize {
        if !piece.merged {
            return 0;
        }
        let p = &self.params;
        let hi = p.g0_max.clone() - self.position(self.anchor(piece));
        let step = p.v_max.clone() * p.dt.clone();
        let j = ((hi - u.clone()) / step).floor();
        let j = usize::try_from(j).unwrap_or(0);
        // A cut piece's u is at least the last shift's lower end, which lies in that shift's
        // box (every later h_j is above it, consecutive boxes overlapping).
        match self.cut {
            Some(c) if !piece.detected => j.min(c - piece.brake),
            _ => j,
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The seed's problem with the robot's v_max, a, b and dt (other modules' tests too).
    pub(crate) fn problem(v: f64, a: f64, b: f64, dt: f64) -> Problem {
        let text = format!(
            "name = \"t\"\n[robot]\nmax_speed = {v}\nacceleration = {a}\nbraking = {b}\ncontrol_period = {dt}\n\
             latency = 1\nclearance = 0.0\n[controller]\nassumed_obstacle_speed = 0.2\nreaction_radius = 1.4\n\
             danger_rule = \"paper\"\nbuffer = 0.1\nwrong_assumption_brake = true\n[environment]\n\
             obstacle_speed = 0.15\ninitial_gap = 10.0\n"
        );
        Problem::from_toml_str(&text, "test").expect("valid")
    }
}
