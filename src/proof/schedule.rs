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

use std::sync::{Arc, Mutex};

use serde::{Deserialize, Serialize};

use crate::core::model::{Params, Problem};
use crate::core::num::{Exact, Scalar};
use crate::core::param_box::ParamBox;
use crate::core::parameter::{ParamAffine, Parameter, symbolic};
use crate::core::rational::Rational;
use crate::core::semantics::{Mode, RobotState, danger_distance, robot_motion};
use crate::proof::program::{Program, Row, Var};

/// How a piece's schedule ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum Ending {
    /// Brakes at T on collision danger.
    Danger,
    /// Brakes at T on seeing the obstacle faster than V_a.
    WrongAssumption,
    /// Never brakes: the observed gap jumps from outside the area to ≤ 0 at T.
    PassThrough,
    /// In a scene: the robot brakes at T for another reason (another obstacle fired, or
    /// the destination) while this obstacle fired at no step before T. Only schedule rows;
    /// the objective is this obstacle's gap when the robot rests.
    Bystander,
}

/// One schedule piece: a set of behaviours whose worst case is one linear program.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct Piece {
    /// First step whose observation is in the reaction area (only with the
    /// wrong-assumption guard active).
    pub entry: Option<usize>,
    /// The step T at whose start the robot brakes (pass-through: first observation ≤ 0).
    pub brake: usize,
    /// Why the schedule ends at T.
    pub ending: Ending,
    /// Stands for this piece and all its shifts by whole steps (T+j, E+j for j ≥ 0).
    pub merged: bool,
    /// The obstacle entered the area at `entry` *or earlier*: every entry E ≤ T−2 has the
    /// same rows from step T−2 on, so one piece stands for all of them.
    #[serde(default)]
    pub early: bool,
    /// Occlusion: the obstacle was hidden at every earlier step and is first seen at T, at
    /// a true gap ≥ d_det (`sensing.first_detection_gap`); no schedule rows before T.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub detected: bool,
}

impl Piece {
    /// The single piece a merged piece stands for at brake step `t` (its shift by
    /// t − brake), or None when `t` is not one of its shifts. An unmerged piece stands only
    /// for itself.
    pub fn shifted_to(&self, t: usize) -> Option<Piece> {
        let j = t.checked_sub(self.brake)?;
        if j > 0 && !self.merged {
            return None;
        }
        Some(Piece {
            brake: t,
            entry: self.entry.map(|e| e + j),
            merged: false,
            ..*self
        })
    }

    /// Whether the piece's objective is a separation (else it is a feasibility question).
    pub fn has_objective(&self) -> bool {
        self.ending != Ending::PassThrough
    }

    /// The piece in words, for messages: "braking on danger at step 253 (and every later
    /// shift)".
    pub fn describe(&self) -> String {
        let mut s = format!(
            "{} at step {}",
            match self.ending {
                Ending::Danger => "braking on danger",
                Ending::WrongAssumption => "braking on a wrong assumption",
                Ending::PassThrough => "passing through without braking",
                Ending::Bystander => "braking for another reason",
            },
            self.brake
        );
        if let Some(e) = self.entry {
            let when = if self.early { "by" } else { "at" };
            s += &format!(", in the area {when} step {e}");
        }
        if self.detected {
            s += if self.entry.is_some() {
                ", first seen in the area"
            } else {
                ", first seen then"
            };
        }
        if self.merged {
            s += " (and every later shift)";
        }
        s
    }
}

/// An affine expression over a piece's variables.
#[derive(Clone, Debug)]
struct Affine {
    coef: Vec<Exact>,
    constant: Exact,
}

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

/// Time and distance the robot needs to stop when it brakes from speed `v`: v/b_min and
/// v²/(2·b_min), exactly. The step function brakes at the constant rate b_min — a full
/// period from speed u covers u·dt − b_min·dt²/2 = (u² − (u − b_min·dt)²)/(2·b_min), the last
/// one, from u ≤ b_min·dt, covers u²/(2·b_min) in u/b_min — so the periods telescope to the
/// closed form (held equal to iterating the step function by a test). Iterating cost one
/// exact step per period per piece: 9 minutes for an accelerating robot at dt = 0.1 ms.
fn stopping(p: &Params<Exact>, v: Exact) -> (Exact, Exact) {
    if v <= Exact::zero() {
        return (Exact::zero(), Exact::zero());
    }
    let time = v.clone() / p.b_min.clone();
    let distance = v * time.clone() / Exact::from(2);
    (time, distance)
}

/// A drive profile: its states up to the cruise onset.
type Profile = Arc<Vec<RobotState<Exact>>>;

/// Profiles already stepped, by the numbers the drive depends on (v_max, a, dt, v0): a sweep
/// or a region map asks for one robot's profile thousands of times (2,000 exact steps at
/// 1 kHz). A few robots are kept; the list starts over when full.
static PROFILES: Mutex<Vec<([Exact; 4], Profile)>> = Mutex::new(Vec::new());

/// The longest profile [`PROFILES`] keeps (10,000 steps: v_max/a of 1 s at 0.1 ms).
const MAX_SHARED_STEPS: usize = 10_000;

/// The drive profile of `params`'s robot, stepped once per robot ([`PROFILES`]).
fn shared_drive_profile(params: &Params<Exact>) -> Profile {
    let key = [
        params.v_max.clone(),
        params.a.clone(),
        params.dt.clone(),
        params.v0.clone(),
    ];
    let known = PROFILES.lock().ok().and_then(|list| {
        list.iter()
            .find(|(k, _)| *k == key)
            .map(|(_, profile)| profile.clone())
    });
    if let Some(profile) = known {
        return profile;
    }
    let profile = Arc::new(drive_profile(params));
    // (A long profile is not kept past its use: its memory would outlive the analysis.)
    if profile.len() <= MAX_SHARED_STEPS
        && let Ok(mut list) = PROFILES.lock()
    {
        if list.len() >= 8 {
            list.clear();
        }
        list.push((key, profile.clone()));
    }
    profile
}

/// The drive profile up to the cruise onset, through the step function (in [`Rational`]).
fn drive_profile(params: &Params<Exact>) -> Vec<RobotState<Exact>> {
    let p: Params<Rational> = params.map(Rational::from_exact);
    let mut state = RobotState::initial(&p);
    let mut profile = Vec::new();
    loop {
        profile.push(RobotState {
            position: state.position.to_exact(),
            speed: state.speed.to_exact(),
            mode: state.mode,
        });
        if state.speed >= p.v_max {
            return profile;
        }
        state = robot_motion(&p, &state).end;
    }
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

    /// The first index k ≥ 0 where `reached(k)` holds, for a predicate that is monotone in k
    /// and, past the cruise onset, holds from `cruise_from + ceil(steps)` on (`steps` is the
    /// exact number of cruise steps still needed, as computed from the cruise state). Up to
    /// the cruise onset it is found by bisection (the onset is v_max/(a·dt) steps away: 2,000
    /// at 1 kHz), which monotonicity makes the first index a scan would find.
    pub(crate) fn first_index(
        &self,
        reached: impl Fn(usize, &Self) -> bool,
        steps: Exact,
    ) -> usize {
        let c = self.cruise_from;
        if reached(c, self) {
            // The first reached index in [0, c]: reached(hi), and lo is unreached or 0.
            if reached(0, self) {
                return 0;
            }
            let (mut lo, mut hi) = (0, c);
            while hi - lo > 1 {
                let mid = lo + (hi - lo) / 2;
                if reached(mid, self) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return hi;
        }
        let k = self.cruise_from + usize::try_from(steps.ceil()).unwrap_or(usize::MAX).max(1);
        debug_assert!(reached(k, self) && !reached(k - 1, self));
        k
    }

    /// Position along the drive profile at step k's start.
    pub fn position(&self, k: usize) -> Exact {
        match self.profile.get(k) {
            Some(s) => s.position.clone(),
            None => {
                self.profile[self.cruise_from].position.clone()
                    + Exact::from(k - self.cruise_from) * &self.cruise_step
            }
        }
    }

    /// Speed along the drive profile at step k's start.
    fn speed(&self, k: usize) -> &Exact {
        self.profile.get(k).map_or(&self.params.v_max, |s| &s.speed)
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

    /// The drive-profile state at step k's start. Past the cruise onset the robot drives
    /// at v_max, so the state is the cruise state moved k − cruise_from steps (what
    /// iterating [`robot_motion`] in Drive gives; a test holds the two equal).
    pub(crate) fn drive(&self, k: usize) -> RobotState<Exact> {
        match self.profile.get(k) {
            Some(s) => s.clone(),
            None => RobotState {
                position: self.position(k),
                speed: self.params.v_max.clone(),
                mode: Mode::Drive,
            },
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

    /// The anchor index m of a piece: the first gap index any of its rows mentions.
    pub(crate) fn anchor(&self, piece: &Piece) -> usize {
        let l = self.params.L;
        if piece.detected && piece.entry.is_none() {
            // Only the sighting's gap g_n, and for a wrong assumption the speed before it.
            let n = piece.brake - l;
            return if piece.ending == Ending::WrongAssumption {
                n - 1
            } else {
                n
            };
        }
        match piece.entry {
            // An early piece's rows start at o_E ≤ ρ, its own entry's at o_{E−1} > ρ.
            // (A detected twin's rows start at its sighting's speed w_{E−1−L}: the same.)
            Some(e) if piece.early => e - l,
            Some(e) if e > l => e - 1 - l,
            None if piece.brake > l => piece.brake - 1 - l,
            _ => 0,
        }
    }

    /// Time and position at which the robot comes to rest after braking at step T's start.
    pub fn rest(&self, t: usize) -> (Exact, Exact) {
        let start = self.drive(t);
        let (time, distance) = if t >= self.cruise_from {
            self.cruise_stop.clone()
        } else {
            stopping(&self.params, start.speed)
        };
        (
            Exact::from(t) * self.params.dt.clone() + time,
            start.position + distance,
        )
    }

    /// The linear program of a piece (see the module docs for its rows). Its right-hand
    /// sides, boxes and objective constant are affine in the named parameters, through the
    /// same formulas evaluated over [`ParamAffine`].
    pub fn program(&self, piece: &Piece) -> Program {
        let s = symbolic(&self.params);
        let m = self.anchor(piece);
        // A bystander's brake step may precede the first observation (n = 0 then).
        let n = piece.brake.saturating_sub(self.params.L);
        let mut vars = self.variables(&s, piece, m, n);
        let mut rows = Vec::new();
        let g_n = self.gap(m, n, vars.len());
        match (&s.d_det, piece.detected, piece.entry) {
            (Some(d_det), true, None) => at_least(
                &mut rows,
                format!("g[{n}] >= d_det (first seen)"),
                &g_n,
                d_det.clone(),
            ),
            (Some(d_det), true, Some(e)) => {
                // A detected twin: the in-area rows, first seen at E instead of outside at
                // E−1 (an early twin's sighting is in u's box).
                self.schedule_rows(&s, piece, m, &mut vars, &mut rows);
                if !piece.early {
                    let k = e - self.params.L;
                    at_least(
                        &mut rows,
                        format!("g[{k}] >= d_det (first seen)"),
                        &self.gap(m, k, vars.len()),
                        d_det.clone(),
                    );
                }
            }
            _ => self.schedule_rows(&s, piece, m, &mut vars, &mut rows),
        }
        if piece.ending != Ending::Bystander {
            self.ending_rows(&s, piece, m, &g_n, &mut rows);
        }
        let (objective, constant) = if piece.has_objective() {
            // Gap at rest = g_n − (P_rest − P_n) − W·(t_rest − n·dt).
            let (t_rest, p_rest) = self.rest(piece.brake);
            let tail = t_rest - Exact::from(n) * self.params.dt.clone();
            let moved = ParamAffine::constant(g_n.constant.clone() - (p_rest - self.position(n)));
            (Some(g_n.coef), moved - s.W.scaled(&tail))
        } else {
            (None, ParamAffine::constant(Exact::ZERO))
        };
        Program::linear(vars, rows, objective, constant)
    }

    /// Variables u = g_m, then w_m .. w_{n−1}, with their boxes.
    fn variables(&self, s: &Params<ParamAffine>, piece: &Piece, m: usize, n: usize) -> Vec<Var> {
        // From the farthest start with the obstacle standing still ...
        let hi = s.g0_max.clone() - ParamAffine::constant(self.position(m));
        // A merged piece cut short stands for the shifts up to the cut: the union of their
        // boxes ends below at the last shift's lower end (Lemma 11).
        let last_shift = self
            .cut
            .filter(|_| piece.merged && !piece.detected)
            .map(|c| m + (c - piece.brake));
        // The anchor whose lower end counts.
        let low = last_shift.unwrap_or(m);
        let lo = if piece.merged && last_shift.is_none() {
            // The rows force g_n > −σ_g (the observation at T positive for some error).
            -s.sigma_g.clone()
        } else if piece.early && piece.detected {
            // First seen by the anchor, inside the area, its observed speeds ≤ V_a since.
            self.detected_lowest_gap(s, low)
                .expect("early twins are listed only where a sighting is possible")
                .0
        } else if piece.early {
            // In the area before the anchor, the obstacle's observed speed is ≤ V_a.
            self.early_lowest_gap(s, low)
        } else {
            // ... to the nearest start with the obstacle at W throughout.
            s.g0.clone()
                - ParamAffine::constant(self.position(low))
                - s.W.scaled(&(self.params.dt.clone() * Exact::from(low)))
        };
        let mut vars = vec![Var {
            name: format!("g[{m}]"),
            lower: lo,
            upper: hi,
        }];
        vars.extend((m..n).map(|j| Var {
            name: format!("w[{j}]"),
            lower: ParamAffine::constant(Exact::ZERO),
            upper: s.W.clone(),
        }));
        vars
    }

    /// The gap g_i as an affine expression over the variables of a piece anchored at m:
    /// g_i = u − dt·Σ_{m≤j<i} w_j − (P_i − P_m).
    fn gap(&self, m: usize, i: usize, nv: usize) -> Affine {
        let mut coef = vec![Exact::ZERO; nv];
        coef[0] = Exact::ONE;
        for c in coef.iter_mut().skip(1).take(i.saturating_sub(m)) {
            *c = -self.params.dt.clone();
        }
        Affine {
            coef,
            constant: self.position(m) - self.position(i),
        }
    }

    /// Rows that fix when the guard logic begins: no fire before T, and for in-area pieces
    /// the entry and the observed speeds (≤ V_a) while in the area.
    fn schedule_rows(
        &self,
        s: &Params<ParamAffine>,
        piece: &Piece,
        m: usize,
        vars: &mut [Var],
        rows: &mut Vec<Row>,
    ) {
        let l = self.params.L;
        let t = piece.brake;
        let nv = vars.len();
        let gap = |i: usize| self.gap(m, i, nv);
        let sg = &s.sigma_g;
        match piece.entry {
            // With noise (σ_g, σ_w) each row is the true gap's condition for *some* error
            // within ±σ to give the observation its row asks for (see the module docs).
            None => {
                if t > l {
                    let theta = self.no_fire_threshold(s, self.danger(s, t - 1));
                    above(
                        rows,
                        format!("o[{}] > min(rho, d_coll)", t - 1),
                        &gap(t - 1 - l),
                        theta - sg.clone(),
                    );
                }
            }
            Some(e) => {
                if e > l && !piece.early && !piece.detected {
                    above(
                        rows,
                        format!("o[{}] > rho", e - 1),
                        &gap(e - 1 - l),
                        s.rho.clone() - sg.clone(),
                    );
                }
                if e < t {
                    at_most(
                        rows,
                        format!("o[{e}] <= rho"),
                        &gap(e - l),
                        s.rho.clone() - sg.clone(),
                    );
                    let dk = self
                        .danger(s, t - 1)
                        .expect("in-area pieces exist only with a finite danger distance");
                    above(
                        rows,
                        format!("o[{}] > d_coll", t - 1),
                        &gap(t - 1 - l),
                        dk - sg.clone(),
                    );
                    let seen_slow = self.in_area_speed_limit(s);
                    for k in e..t {
                        if k > l + m {
                            vars[1 + (k - l - 1) - m].upper = seen_slow.clone();
                        }
                    }
                }
            }
        }
    }

    /// Rows of the piece's ending at T: the guard fires (danger or wrong assumption) with
    /// the obstacle still ahead, or the observation has jumped to ≤ 0 (pass-through).
    fn ending_rows(
        &self,
        s: &Params<ParamAffine>,
        piece: &Piece,
        m: usize,
        g_n: &Affine,
        rows: &mut Vec<Row>,
    ) {
        let t = piece.brake;
        let sg = &s.sigma_g;
        match piece.ending {
            Ending::Danger | Ending::WrongAssumption => {
                above(rows, format!("o[{t}] > 0"), g_n, -sg.clone());
                if piece.ending == Ending::Danger {
                    for (theta, name) in self.fire_thresholds(s, self.danger(s, t)) {
                        at_most(rows, format!("o[{t}] <= {name}"), g_n, theta + sg.clone());
                    }
                } else {
                    at_most(
                        rows,
                        format!("o[{t}] <= rho"),
                        g_n,
                        s.rho.clone() + sg.clone(),
                    );
                    let n = t - self.params.L;
                    let mut coef = vec![Exact::ZERO; g_n.coef.len()];
                    coef[1 + (n - 1) - m] = Exact::ONE;
                    let e = Affine {
                        coef,
                        constant: Exact::ZERO,
                    };
                    above(
                        rows,
                        format!("w[{}] > V_a", n - 1),
                        &e,
                        s.V_a.clone() - s.sigma_w.clone(),
                    );
                }
            }
            Ending::PassThrough => at_most(rows, format!("o[{t}] <= 0"), g_n, sg.clone()),
            Ending::Bystander => {}
        }
    }

    /// d_coll at the drive profile's speed at step k (None for the `area` rule), affine in
    /// V_a and the buffer.
    fn danger(&self, s: &Params<ParamAffine>, k: usize) -> Option<ParamAffine> {
        danger_distance(s, &ParamAffine::constant(self.speed(k).clone()))
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

/// min(ρ, d), with d = None standing for ∞ (the `area` rule).
pub(crate) fn min_opt(rho: &ParamAffine, d: Option<ParamAffine>) -> ParamAffine {
    match d {
        Some(d) if d < *rho => d,
        _ => rho.clone(),
    }
}

/// Pushes the row `e ≥ bound` (not strict).
fn at_least(rows: &mut Vec<Row>, label: String, e: &Affine, bound: ParamAffine) {
    let negated = Affine {
        coef: e.coef.iter().map(|c| -c.clone()).collect(),
        constant: -e.constant.clone(),
    };
    at_most(rows, label, &negated, -bound);
}

/// Pushes the row `e ≤ bound`.
fn at_most(rows: &mut Vec<Row>, label: String, e: &Affine, bound: ParamAffine) {
    rows.push(Row {
        label,
        a: e.coef.clone(),
        b: bound - ParamAffine::constant(e.constant.clone()),
        strict: false,
    });
}

/// Pushes the strict row `e > bound`, closed as `−e ≤ −bound`.
fn above(rows: &mut Vec<Row>, label: String, e: &Affine, bound: ParamAffine) {
    rows.push(Row {
        label,
        a: e.coef.iter().map(|c| -c.clone()).collect(),
        b: ParamAffine::constant(e.constant.clone()) - bound,
        strict: true,
    });
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

    /// Decompositions share drive profiles by robot, never across robots: interleaved robots
    /// that differ in one number each (a, v_max, dt, v0) get their own profile.
    #[test]
    fn shared_drive_profiles_belong_to_their_robot() {
        let robots = [
            (0.2, 0.1, 0.1, None),
            (0.2, 0.05, 0.1, None),
            (0.3, 0.1, 0.1, None),
            (0.2, 0.1, 0.05, None),
            (0.2, 0.1, 0.1, Some(0.1)),
        ];
        for _ in 0..2 {
            for (v, a, dt, v0) in robots {
                let mut pr = problem(v, a, 0.05, dt);
                pr.robot.initial_speed = v0;
                let d = Decomposition::new(&pr);
                assert_eq!(
                    *d.profile,
                    drive_profile(&d.params),
                    "robot {v} {a} {dt} {v0:?}"
                );
            }
        }
    }

    /// The closed-form stop equals braking period by period through the step function,
    /// exactly: speeds that are whole multiples of b·dt, that stop inside the first period,
    /// that stop mid-period, zero, and a plant braking weaker than the controller assumes.
    #[test]
    fn stopping_in_closed_form_is_the_step_function_iterated() {
        for (v, b, dt, b_min) in [
            (0.2, 0.05, 0.1, None),
            (0.2, 0.5, 0.1, None),
            (0.37, 0.3, 0.07, None),
            (0.8, 0.5, 0.07, Some(0.13)),
        ] {
            let mut pr = problem(v, 0.1, b, dt);
            pr.robot.braking_min = b_min;
            let p = Decomposition::new(&pr).params;
            let v_max = p.v_max.clone();
            let b_dt = p.b_min.clone() * p.dt.clone();
            for speed in [
                v_max.clone(),
                v_max.clone() / Exact::from(3),
                b_dt.clone() * Exact::from(2),
                b_dt / Exact::from(2),
                Exact::ZERO,
            ] {
                let mut s = RobotState {
                    position: Exact::ZERO,
                    speed: speed.clone(),
                    mode: Mode::Brake,
                };
                let mut time = Exact::ZERO;
                while s.mode != Mode::Stop {
                    let m = robot_motion(&p, &s);
                    time += m.moving_for.clone();
                    s = m.end;
                }
                assert_eq!(
                    stopping(&p, speed.clone()),
                    (time, s.position),
                    "v_max {v}, b {b}, dt {dt}, b_min {b_min:?}, from {speed}"
                );
            }
        }
    }

    /// `drive(k)` past the cruise onset is the cruise state moved on: exactly what iterating
    /// the step function gives. `rest(t)` is exactly braking through the step function.
    /// Bisection up to the cruise onset finds the index a scan finds, for thresholds on the
    /// drive profile's position before, at and past the onset.
    #[test]
    fn first_index_bisects_as_a_scan_finds() {
        for (v, a, b, dt) in [
            (0.2, 0.1, 0.05, 0.1),
            (0.8, 0.3, 0.5, 0.007),
            (0.2, 0.1, 0.05, 0.001),
        ] {
            let dec = Decomposition::new(&problem(v, a, b, dt));
            let c = dec.cruise_from;
            let end = dec.position(c + 5);
            for i in 0..=40 {
                let x = end.clone() * Exact::from(i) / Exact::from(40);
                let reached = |k: usize, d: &Decomposition| d.position(k) >= x;
                let steps = (x.clone() - dec.position(c))
                    / (dec.params.v_max.clone() * dec.params.dt.clone());
                let scan = (0..).find(|&k| reached(k, &dec)).unwrap();
                assert_eq!(dec.first_index(reached, steps), scan, "{dt} {i}");
            }
        }
    }

    #[test]
    fn drive_profile_and_rest_are_the_step_function() {
        for (v, a, b, dt) in [
            (0.2, 0.1, 0.05, 0.1),
            (0.8, 0.3, 0.5, 0.07),
            (1.3, 2.9, 0.7, 0.2),
        ] {
            let dec = Decomposition::new(&problem(v, a, b, dt));
            let p = &dec.params;
            let mut state = RobotState {
                position: Exact::ZERO,
                speed: Exact::ZERO,
                mode: Mode::Accelerate,
            };
            for k in 0..dec.cruise_from + 60 {
                let d = dec.drive(k);
                assert_eq!(
                    (&d.position, &d.speed),
                    (&state.position, &state.speed),
                    "step {k}"
                );
                if k > 0 && k % 7 == 0 {
                    let (t_rest, p_rest) = dec.rest(k);
                    let mut s = RobotState {
                        mode: Mode::Brake,
                        ..state.clone()
                    };
                    let mut time = Exact::from(k) * p.dt.clone();
                    while s.mode != Mode::Stop {
                        let m = robot_motion(p, &s);
                        time += m.moving_for.clone();
                        s = m.end;
                    }
                    assert_eq!(
                        (t_rest, p_rest),
                        (time, s.position),
                        "rest after braking at {k}"
                    );
                }
                state = robot_motion(p, &state).end;
            }
        }
    }
}
