//! A dense two-phase simplex for the small linear programs that most pieces are.
//!
//! The seed's pieces are programs of 2 variables and 7 rows. Clarabel, an interior-point
//! method for conic programs of any size, spends ~155 k instructions on each (setup, an
//! ordering and a factorisation per iteration, its timers); a dense simplex on a tableau
//! this size pivots a handful of times. What comes out is used exactly as Clarabel's answer
//! is: the multipliers become bounds that [`Program::bound`](crate::proof::program::Program)
//! recomputes in exact arithmetic, the point becomes a witness that is replayed exactly. A
//! wrong answer here can therefore only cost tightness (a weaker bound, a witness that does
//! not replay), never soundness; anything the method is unsure of comes back as
//! [`SimplexOutcome::GaveUp`] and goes to Clarabel instead.
//!
//! Form: `min c·x` subject to `a_i·x ≤ b_i` (or `= b_i` on equality rows) and finite boxes
//! `l ≤ x ≤ u`. With `y = x − l` (fixed variables dropped), each row becomes
//! `σ_i (a_i·y + s_i) = σ_i β_i` with σ_i chosen so the right side is ≥ 0, and each box an
//! explicit row `y_j + t_j = u_j − l_j`. Rows without a +1 slack get an artificial; phase 1
//! drives the artificials to zero, phase 2 optimises. Multipliers are read off the reduced
//! costs of each row's initial identity column, in Clarabel's sign convention (z ≥ 0 on
//! inequality rows, `c + Aᵀz` absorbed by the boxes).

/// A linear program in floats, dense.
#[derive(Clone, Debug, Default)]
pub struct DenseLp {
    /// Row coefficients, one vector of `n` per row.
    pub rows: Vec<Vec<f64>>,
    /// Right-hand sides.
    pub rhs: Vec<f64>,
    /// Whether each row is an equality (`= b`) rather than `≤ b`.
    pub equality: Vec<bool>,
    /// Lower bounds of the variables (finite).
    pub lower: Vec<f64>,
    /// Upper bounds of the variables (finite, ≥ lower).
    pub upper: Vec<f64>,
    /// Objective coefficients (all zero for a feasibility question).
    pub cost: Vec<f64>,
}

/// What the simplex found.
#[derive(Clone, Debug, PartialEq)]
pub enum SimplexOutcome {
    /// An optimal vertex with its multipliers (one per row) and `c·x`.
    Optimal {
        /// The point.
        x: Vec<f64>,
        /// Multipliers, ≥ 0 on inequality rows.
        z: Vec<f64>,
        /// `c·x`.
        value: f64,
    },
    /// No point satisfies the rows and boxes; `z` is a Farkas certificate in the same sign
    /// convention.
    Infeasible {
        /// Farkas multipliers.
        z: Vec<f64>,
    },
    /// Too large, non-finite data, a tiny pivot or too many pivots: ask another solver.
    GaveUp,
}

/// Programs larger than this (tableau rows × columns) are left to Clarabel. Measured by
/// `cargo bench --bench certify` on dense random programs: 16× faster than Clarabel at 2
/// variables, 2.4× at 32 variables and 96 rows (~33 k cells), 1.4× at 64 and 192. Past
/// ~32 variables the margin shrinks, the schedule's structured programs are sparse (where
/// Clarabel's factorisation gains and a dense tableau does not) and rounding accumulates
/// over hundreds of pivots; no program the analyser builds today comes near (≤ 3 variables
/// and 6 rows in the shipped problems).
pub const MAX_TABLEAU: usize = 40_000;

/// Smallest pivot accepted; anything smaller is taken as zero.
const PIVOT_TOL: f64 = 1e-9;
/// Reduced costs below −this (relative to the costs' scale) still improve the objective.
const OPTIMALITY_TOL: f64 = 1e-11;
/// Phase 1's residual above this (relative to the right sides' scale) means infeasible.
const FEASIBILITY_TOL: f64 = 1e-11;

/// Solves `lp`, or gives up (see [`SimplexOutcome::GaveUp`]).
pub fn solve(lp: &DenseLp) -> SimplexOutcome {
    match Tableau::build(lp) {
        Some(mut t) => t.run(lp).unwrap_or(SimplexOutcome::GaveUp),
        None => SimplexOutcome::GaveUp,
    }
}

/// The tableau `[B⁻¹M | B⁻¹h]` with its reduced-cost row kept as row `height`.
struct Tableau {
    /// Variables left free (`l < u`), in order: column j of the tableau is `y` of `free[j]`.
    free: Vec<usize>,
    /// Number of program rows (the box rows follow).
    m: usize,
    /// Tableau rows (program rows, then one box row per free variable).
    height: usize,
    /// Columns: free variables, then one slack per inequality row, one box slack per free
    /// variable, one artificial per row that needs one; the right side is column `width`.
    width: usize,
    /// First artificial column (columns from here on never enter in phase 2).
    first_artificial: usize,
    /// Row-major, `(height + 1) × (width + 1)`.
    cells: Vec<f64>,
    /// Basic column of each row.
    basis: Vec<usize>,
    /// The column that was the identity's column for each row at the start.
    identity: Vec<usize>,
    /// The sign each program row was multiplied by so its right side is ≥ 0.
    sign: Vec<f64>,
}

impl Tableau {
    fn build(lp: &DenseLp) -> Option<Tableau> {
        let n = lp.lower.len();
        let m = lp.rows.len();
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if lp.upper.len() != n
            || lp.cost.len() != n
            || lp.rhs.len() != m
            || lp.equality.len() != m
            || lp.rows.iter().any(|r| r.len() != n || !finite(r))
            || !finite(&lp.rhs)
            || !finite(&lp.lower)
            || !finite(&lp.upper)
            || !finite(&lp.cost)
            || lp.lower.iter().zip(&lp.upper).any(|(l, u)| l > u)
        {
            return None;
        }
        let free: Vec<usize> = (0..n).filter(|&j| lp.lower[j] < lp.upper[j]).collect();
        let nf = free.len();
        let beta: Vec<f64> = (0..m)
            .map(|i| lp.rhs[i] - (0..n).map(|j| lp.rows[i][j] * lp.lower[j]).sum::<f64>())
            .collect();
        let sign: Vec<f64> = beta
            .iter()
            .map(|&b| if b < 0.0 { -1.0 } else { 1.0 })
            .collect();
        let slacks = lp.equality.iter().filter(|&&e| !e).count();
        let artificials = (0..m).filter(|&i| lp.equality[i] || sign[i] < 0.0).count();
        let height = m + nf;
        let first_artificial = nf + slacks + nf;
        let width = first_artificial + artificials;
        if (height + 1) * (width + 1) > MAX_TABLEAU {
            return None;
        }
        let stride = width + 1;
        let mut cells = vec![0.0; (height + 1) * stride];
        let mut identity = vec![0; height];
        let (mut slack, mut artificial) = (nf, first_artificial);
        for i in 0..m {
            let row = &mut cells[i * stride..(i + 1) * stride];
            for (col, &j) in free.iter().enumerate() {
                row[col] = sign[i] * lp.rows[i][j];
            }
            row[width] = sign[i] * beta[i];
            if !lp.equality[i] {
                row[slack] = sign[i];
                if sign[i] > 0.0 {
                    identity[i] = slack;
                }
                slack += 1;
            }
            if lp.equality[i] || sign[i] < 0.0 {
                row[artificial] = 1.0;
                identity[i] = artificial;
                artificial += 1;
            }
        }
        for (k, &j) in free.iter().enumerate() {
            let row = &mut cells[(m + k) * stride..(m + k + 1) * stride];
            row[k] = 1.0;
            row[nf + slacks + k] = 1.0;
            row[width] = lp.upper[j] - lp.lower[j];
            identity[m + k] = nf + slacks + k;
        }
        Some(Tableau {
            free,
            m,
            height,
            width,
            first_artificial,
            cells,
            basis: identity.clone(),
            identity,
            sign,
        })
    }

    fn at(&self, r: usize, c: usize) -> f64 {
        self.cells[r * (self.width + 1) + c]
    }

    /// Sets the reduced-cost row for column costs `cost` at the current basis.
    fn price(&mut self, cost: &[f64]) {
        let stride = self.width + 1;
        let (body, last) = self.cells.split_at_mut(self.height * stride);
        last[..self.width].copy_from_slice(cost);
        last[self.width] = 0.0;
        for (r, &b) in self.basis.iter().enumerate() {
            let cb = cost[b];
            if cb != 0.0 {
                for (d, t) in last.iter_mut().zip(&body[r * stride..(r + 1) * stride]) {
                    *d -= cb * t;
                }
            }
        }
    }

    fn pivot(&mut self, r: usize, c: usize) {
        let stride = self.width + 1;
        let p = self.at(r, c);
        for v in &mut self.cells[r * stride..(r + 1) * stride] {
            *v /= p;
        }
        let pivot_row = self.cells[r * stride..(r + 1) * stride].to_vec();
        for k in 0..=self.height {
            if k == r {
                continue;
            }
            let f = self.cells[k * stride + c];
            if f != 0.0 {
                for (v, t) in self.cells[k * stride..(k + 1) * stride]
                    .iter_mut()
                    .zip(&pivot_row)
                {
                    *v -= f * t;
                }
                self.cells[k * stride + c] = 0.0;
            }
        }
        self.basis[r] = c;
    }

    /// Pivots until no column below `enter_below` has a negative reduced cost. Dantzig's
    /// rule, with Bland's (lowest index) after a run of degenerate pivots so it cannot
    /// cycle. `None` if unbounded, stalled or out of pivots.
    fn optimise(&mut self, enter_below: usize, scale: f64) -> Option<()> {
        let tol = OPTIMALITY_TOL * scale.max(1.0);
        let mut degenerate_run = 0;
        for _ in 0..50 * (self.height + self.width) {
            let bland = degenerate_run > 2 * self.height;
            let mut enter = None;
            let mut best = -tol;
            for c in 0..enter_below {
                let d = self.at(self.height, c);
                if d < best {
                    enter = Some(c);
                    if bland {
                        break;
                    }
                    best = d;
                }
            }
            let Some(c) = enter else {
                return Some(());
            };
            let mut leave: Option<(usize, f64)> = None;
            for r in 0..self.height {
                let a = self.at(r, c);
                if a > PIVOT_TOL {
                    let ratio = self.at(r, self.width).max(0.0) / a;
                    let better = match leave {
                        None => true,
                        Some((lr, best)) => {
                            ratio < best || (ratio == best && self.basis[r] < self.basis[lr])
                        }
                    };
                    if better {
                        leave = Some((r, ratio));
                    }
                }
            }
            let (r, ratio) = leave?;
            degenerate_run = if ratio == 0.0 { degenerate_run + 1 } else { 0 };
            self.pivot(r, c);
        }
        None
    }

    /// Multipliers of the program rows, in Clarabel's convention, for the current
    /// reduced-cost row priced with `cost`.
    fn multipliers(&self, cost: &[f64]) -> Vec<f64> {
        (0..self.m)
            .map(|i| {
                let id = self.identity[i];
                let pi = cost[id] - self.at(self.height, id);
                -self.sign[i] * pi
            })
            .collect()
    }

    fn run(&mut self, lp: &DenseLp) -> Option<SimplexOutcome> {
        let h_scale = (0..self.height)
            .map(|r| self.at(r, self.width).abs())
            .fold(1.0, f64::max);
        if self.first_artificial < self.width {
            let mut phase1 = vec![0.0; self.width];
            phase1[self.first_artificial..].fill(1.0);
            self.price(&phase1);
            self.optimise(self.width, 1.0)?;
            let residual = -self.at(self.height, self.width);
            if residual > FEASIBILITY_TOL * h_scale {
                return Some(SimplexOutcome::Infeasible {
                    z: self.multipliers(&phase1),
                });
            }
            self.drive_out_artificials();
        }
        let mut phase2 = vec![0.0; self.width];
        for (col, &j) in self.free.iter().enumerate() {
            phase2[col] = lp.cost[j];
        }
        let c_scale = lp.cost.iter().map(|c| c.abs()).fold(0.0, f64::max);
        self.price(&phase2);
        self.optimise(self.first_artificial, c_scale)?;
        let mut x = lp.lower.clone();
        for (r, &b) in self.basis.iter().enumerate() {
            if b < self.free.len() {
                x[self.free[b]] += self.at(r, self.width).max(0.0);
            }
        }
        for ((x, &l), &u) in x.iter_mut().zip(&lp.lower).zip(&lp.upper) {
            *x = x.clamp(l, u);
        }
        let value = lp.cost.iter().zip(&x).map(|(c, x)| c * x).sum();
        Some(SimplexOutcome::Optimal {
            x,
            z: self.multipliers(&phase2),
            value,
        })
    }

    /// After phase 1 reached zero, swaps every artificial still basic (at level 0) for a
    /// structural column of its row, so phase 2 cannot raise it again. A row whose every
    /// other entry is zero is redundant and keeps its artificial, which then never moves.
    fn drive_out_artificials(&mut self) {
        for r in 0..self.height {
            if self.basis[r] < self.first_artificial {
                continue;
            }
            let best = (0..self.first_artificial)
                .map(|c| (c, self.at(r, c).abs()))
                .filter(|&(_, a)| a > PIVOT_TOL)
                .max_by(|a, b| a.1.total_cmp(&b.1));
            if let Some((c, _)) = best {
                self.pivot(r, c);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lp(rows: Vec<Vec<f64>>, rhs: Vec<f64>, lower: Vec<f64>, upper: Vec<f64>) -> DenseLp {
        let m = rows.len();
        let n = lower.len();
        DenseLp {
            rows,
            rhs,
            equality: vec![false; m],
            lower,
            upper,
            cost: vec![0.0; n],
        }
    }

    #[test]
    fn a_two_variable_program_reaches_its_vertex_and_its_multipliers() {
        // min −x − y s.t. x + 2y ≤ 4, 3x + y ≤ 6, x, y ∈ [0, 10]: optimum at (1.6, 1.2),
        // value −2.8, multipliers (0.4, 0.2) (c + Aᵀz = 0).
        let mut p = lp(
            vec![vec![1.0, 2.0], vec![3.0, 1.0]],
            vec![4.0, 6.0],
            vec![0.0, 0.0],
            vec![10.0, 10.0],
        );
        p.cost = vec![-1.0, -1.0];
        let SimplexOutcome::Optimal { x, z, value } = solve(&p) else {
            panic!("solves");
        };
        assert!(
            (x[0] - 1.6).abs() < 1e-12 && (x[1] - 1.2).abs() < 1e-12,
            "{x:?}"
        );
        assert!((value + 2.8).abs() < 1e-12);
        assert!(
            (z[0] - 0.4).abs() < 1e-12 && (z[1] - 0.2).abs() < 1e-12,
            "{z:?}"
        );
    }

    /// Beale's example, which cycles forever under Dantzig's rule alone: the switch to
    /// Bland's rule after a degenerate run must reach the optimum −1/20 at x = (1/25, 0, 1, 0).
    #[test]
    fn a_cycling_program_still_reaches_its_optimum() {
        let mut p = lp(
            vec![
                vec![0.25, -60.0, -0.04, 9.0],
                vec![0.5, -90.0, -0.02, 3.0],
                vec![0.0, 0.0, 1.0, 0.0],
            ],
            vec![0.0, 0.0, 1.0],
            vec![0.0; 4],
            vec![100.0; 4],
        );
        p.cost = vec![-0.75, 150.0, -0.02, 6.0];
        let SimplexOutcome::Optimal { x, value, .. } = solve(&p) else {
            panic!("solves");
        };
        assert!((value + 0.05).abs() < 1e-12, "{value} at {x:?}");
        assert!(
            (x[0] - 0.04).abs() < 1e-12 && (x[2] - 1.0).abs() < 1e-12,
            "{x:?}"
        );
    }

    #[test]
    fn an_empty_program_gets_a_farkas_certificate() {
        // x ≥ 3 (as −x ≤ −3) with x ∈ [0, 2]: z·(−x + 3) ≤ 0 contradicts the box.
        let p = lp(vec![vec![-1.0]], vec![-3.0], vec![0.0], vec![2.0]);
        let SimplexOutcome::Infeasible { z } = solve(&p) else {
            panic!("infeasible");
        };
        assert!(z[0] > 0.0, "{z:?}");
    }
}
