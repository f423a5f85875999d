//! A piece's linear program: its variables (the anchor gap u and the speeds after it), its
//! schedule and ending rows, and the objective, all affine in the named parameters.

use super::{Decomposition, Ending, Piece};
use crate::core::model::Params;
use crate::core::num::Exact;
use crate::core::parameter::{ParamAffine, symbolic};
use crate::core::semantics::danger_distance;
use crate::proof::program::{Program, Row, Var};

/// An affine expression over a piece's variables.
#[derive(Clone, Debug)]
struct Affine {
    coef: Vec<Exact>,
    constant: Exact,
}

impl Decomposition {
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
