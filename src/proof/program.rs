//! Linear programs in exact arithmetic, and the bounds their dual multipliers prove.
//!
//! A [`Program`] is `min c·x + c0` subject to rows `a_i·x ≤ b_i` and a box `l ≤ x ≤ u`,
//! stated in exact rationals. Rows that stand for a strict inequality of the model (`>`)
//! are closed and marked [`Row::strict`]: closing can only add boundary behaviours, so
//! bounds stay sound.
//!
//! **Bounds without trusting the solver** (Neumaier–Shcherbina). For any multipliers
//! z ≥ 0 on the rows, with residual r = c + Σ z_i a_i, every feasible x satisfies
//!
//! > c·x + c0 = r·x − Σ z_i a_i·x + c0 ≥ c0 − z·b + Σ_j min(r_j l_j, r_j u_j).
//!
//! So any z — however inaccurate the solver that produced it — proves a rigorous lower
//! bound once r is computed exactly. With c = 0 the same number being positive proves the
//! rows infeasible (a Farkas certificate); being zero, with positive weight on a strict row,
//! it proves the *strict* system infeasible: the closure holds only on a guard's boundary,
//! which the semantics excludes.

use serde::{Deserialize, Serialize};

use crate::core::num::{Exact, exact_float};

/// One decision variable with its box.
#[derive(Clone, Debug, PartialEq)]
pub struct Var {
    /// Name, for messages and witnesses (e.g. `w[41]`, `g[40]`).
    pub name: String,
    /// Lower bound.
    pub lower: Exact,
    /// Upper bound.
    pub upper: Exact,
}

/// One constraint `a·x ≤ b`.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// What the row says in the model's words.
    pub label: String,
    /// Coefficients, one per variable.
    pub a: Vec<Exact>,
    /// Right-hand side.
    pub b: Exact,
    /// The model's inequality is strict (`a·x < b`); the program uses its closure.
    pub strict: bool,
}

/// A linear program in exact rationals.
#[derive(Clone, Debug, PartialEq)]
pub struct Program {
    /// Variables and their boxes.
    pub vars: Vec<Var>,
    /// Constraint rows.
    pub rows: Vec<Row>,
    /// Objective coefficients (`None`: a feasibility question).
    pub objective: Option<Vec<Exact>>,
    /// Objective constant.
    pub constant: Exact,
}

/// What a set of multipliers proves about a program.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ProofKind {
    /// Every feasible point has objective ≥ the bound.
    Bound,
    /// No point is feasible.
    Infeasible,
}

impl Program {
    /// Number of variables.
    pub fn n(&self) -> usize {
        self.vars.len()
    }

    /// The exact Neumaier–Shcherbina bound proved by multipliers `z` (negative entries are
    /// clipped to 0). With `objective = false` the objective is taken as 0: a positive
    /// result then proves infeasibility. Returns `None` if the bound is −∞ (a residual on
    /// an unbounded side) or `z` has the wrong length or a non-finite entry.
    pub fn bound(&self, z: &[f64], objective: bool) -> Option<Exact> {
        if z.len() != self.rows.len() || z.iter().any(|x| !x.is_finite()) {
            return None;
        }
        let zero = Exact::ZERO;
        let mut r: Vec<Exact> = match (&self.objective, objective) {
            (Some(c), true) => c.clone(),
            _ => vec![zero.clone(); self.n()],
        };
        let mut total = if objective {
            self.constant.clone()
        } else {
            zero.clone()
        };
        for (row, &zi) in self.rows.iter().zip(z) {
            if zi <= 0.0 {
                continue;
            }
            let zi = exact_float(zi);
            for (rj, aij) in r.iter_mut().zip(&row.a) {
                if *aij != zero {
                    *rj += &zi * aij;
                }
            }
            total -= &zi * &row.b;
        }
        for (rj, var) in r.iter().zip(&self.vars) {
            if *rj > zero {
                total += rj * &var.lower;
            } else if *rj < zero {
                total += rj * &var.upper;
            }
        }
        Some(total)
    }

    /// Whether multipliers `z` prove that no point satisfies the rows *as the model states
    /// them* (strict rows strict): the Farkas bound is positive, or it is zero and some
    /// strict row has positive weight (then any solution would give 0 > 0). Returns the
    /// exact bound when they do.
    pub fn proves_empty(&self, z: &[f64]) -> Option<Exact> {
        let b = self.bound(z, false)?;
        let strict_weight = self
            .rows
            .iter()
            .zip(z)
            .any(|(row, &zi)| row.strict && zi > 0.0);
        (b > Exact::ZERO || (b == Exact::ZERO && strict_weight)).then_some(b)
    }

    /// A row that no point of the box satisfies (a strict row: not even on its boundary),
    /// if there is one: its unit multiplier proves emptiness without a solver.
    pub fn infeasible_row(&self) -> Option<usize> {
        self.rows.iter().position(|row| {
            let mut least = Exact::ZERO;
            for (a, var) in row.a.iter().zip(&self.vars) {
                if *a > Exact::ZERO {
                    least += a * &var.lower;
                } else if *a < Exact::ZERO {
                    least += a * &var.upper;
                }
            }
            least > row.b || (row.strict && least == row.b)
        })
    }
}
