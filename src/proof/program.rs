//! Conic programs in exact arithmetic, and the bounds their dual multipliers prove.
//!
//! A [`Program`] is `min c·x + c0` subject to `b − A·x ∈ K` and a box `l ≤ x ≤ u`, stated in
//! exact rationals, where K is a product of cones listed block by block ([`ConeBlock`]):
//! the zero cone (equalities `a·x = b`), the nonnegative cone (`a·x ≤ b`) and second-order
//! cones (`(b − A·x)_0 ≥ ‖(b − A·x)_{1..}‖`). Nonnegative rows that stand for a strict
//! inequality of the model (`>`) are closed and marked [`Row::strict`]: closing can only add
//! boundary behaviours, so bounds stay sound.
//!
//! Right-hand sides, variable bounds and the objective's constant are [`ParamAffine`]:
//! exact numbers with their exact derivatives in the problem's named parameters (W, ρ,
//! V_a, buffer, initial gap). The matrix and the objective's coefficients never depend on
//! them.
//!
//! **Bounds without trusting the solver** (Neumaier–Shcherbina). For any multipliers z in
//! the dual cone K* (free on zero rows, ≥ 0 on nonnegative rows, head ≥ ‖tail‖ on a
//! second-order block), z·(b − A·x) ≥ 0 for every feasible x, so with the residual
//! r = c + Aᵀz
//!
//! > c·x + c0 = r·x − z·A·x + c0 ≥ c0 − z·b + Σ_j min(r_j l_j, r_j u_j).
//!
//! So any z — however inaccurate the solver that produced it — proves a rigorous lower
//! bound once it is moved into K* ([`Program::dual_in_cone`]) and r is computed exactly.
//! For fixed z the sides picked in the last sum depend only on the signs of r, which no
//! parameter moves: the bound is an exact affine function of the parameters
//! ([`Program::bound_affine`]). With c = 0 the same number being positive proves the rows
//! infeasible (a Farkas certificate); being zero, with positive weight on a strict row, it
//! proves the *strict* system infeasible: the closure holds only on a guard's boundary,
//! which the semantics excludes.

use serde::{Deserialize, Serialize};

use crate::core::num::{Exact, exact_float};
use crate::core::parameter::ParamAffine;

/// One decision variable with its box.
#[derive(Clone, Debug, PartialEq)]
pub struct Var {
    /// Name, for messages and witnesses (e.g. `w[41]`, `g[40]`).
    pub name: String,
    /// Lower bound.
    pub lower: ParamAffine,
    /// Upper bound.
    pub upper: ParamAffine,
}

/// One row of `b − A·x ∈ K`; what it says depends on its cone block.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// What the row says in the model's words.
    pub label: String,
    /// Coefficients, one per variable.
    pub a: Vec<Exact>,
    /// Right-hand side.
    pub b: ParamAffine,
    /// The model's inequality is strict (`a·x < b`); the program uses its closure. Only
    /// rows of a nonnegative block can be strict.
    pub strict: bool,
}

/// The kind of cone a block of rows lies in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum Cone {
    /// `a·x = b` for each row; dual multipliers are free.
    Zero,
    /// `a·x ≤ b` for each row; dual multipliers are ≥ 0.
    Nonnegative,
    /// The block's slacks s = b − A·x satisfy s_0 ≥ ‖s_{1..}‖; the dual cone is the same
    /// cone (self-dual).
    SecondOrder,
}

/// A run of consecutive rows in one cone.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ConeBlock {
    /// The cone.
    pub cone: Cone,
    /// How many consecutive rows it covers.
    pub rows: usize,
}

/// A conic program in exact rationals.
#[derive(Clone, Debug, PartialEq)]
pub struct Program {
    /// Variables and their boxes.
    pub vars: Vec<Var>,
    /// Constraint rows, block after block.
    pub rows: Vec<Row>,
    /// The cone blocks, in row order; their sizes add up to the number of rows.
    pub cones: Vec<ConeBlock>,
    /// Objective coefficients (`None`: a feasibility question).
    pub objective: Option<Vec<Exact>>,
    /// Objective constant.
    pub constant: ParamAffine,
}

/// What a set of multipliers proves about a program.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum ProofKind {
    /// Every feasible point has objective ≥ the bound.
    Bound,
    /// No point is feasible.
    Infeasible,
}

impl Program {
    /// A linear program: every row `a·x ≤ b` (one nonnegative block).
    pub fn linear(
        vars: Vec<Var>,
        rows: Vec<Row>,
        objective: Option<Vec<Exact>>,
        constant: ParamAffine,
    ) -> Self {
        let cones = if rows.is_empty() {
            Vec::new()
        } else {
            vec![ConeBlock {
                cone: Cone::Nonnegative,
                rows: rows.len(),
            }]
        };
        Program {
            vars,
            rows,
            cones,
            objective,
            constant,
        }
    }

    /// Number of variables.
    pub fn n(&self) -> usize {
        self.vars.len()
    }

    /// The cone of each row, in row order.
    fn row_cones(&self) -> impl Iterator<Item = Cone> + '_ {
        self.cones
            .iter()
            .flat_map(|block| std::iter::repeat_n(block.cone, block.rows))
    }

    /// Whether the blocks cover the rows exactly and only nonnegative rows are strict.
    pub fn is_well_formed(&self) -> bool {
        let covered: usize = self.cones.iter().map(|b| b.rows).sum();
        covered == self.rows.len()
            && self
                .rows
                .iter()
                .zip(self.row_cones())
                .all(|(row, cone)| !row.strict || cone == Cone::Nonnegative)
            && self.rows.iter().all(|row| row.a.len() == self.n())
            && self.cones.iter().all(|b| b.rows > 0)
    }

    /// Multipliers `z` (floats from a solver) moved exactly into the dual cone K*: free on
    /// zero rows, negative entries clipped to 0 on nonnegative rows, and on a second-order
    /// block the head raised to a rational no smaller than the tail's Euclidean norm.
    /// `None` if `z` has the wrong length or a non-finite entry, or the program is malformed.
    pub fn dual_in_cone(&self, z: &[f64]) -> Option<Vec<Exact>> {
        if z.len() != self.rows.len() || z.iter().any(|x| !x.is_finite()) || !self.is_well_formed()
        {
            return None;
        }
        let mut out = Vec::with_capacity(z.len());
        let mut start = 0;
        for block in &self.cones {
            let zb = &z[start..start + block.rows];
            match block.cone {
                Cone::Zero => out.extend(zb.iter().map(|&x| exact_float(x))),
                Cone::Nonnegative => {
                    out.extend(zb.iter().map(|&x| exact_float(x.max(0.0))));
                }
                Cone::SecondOrder => out.extend(second_order_dual(zb)),
            }
            start += block.rows;
        }
        Some(out)
    }

    /// The exact Neumaier–Shcherbina bound proved by multipliers `z`, as an affine function
    /// of the named parameters (see the module docs). With `objective = false` the objective
    /// is taken as 0: a positive result then proves infeasibility. `None` when `z` is
    /// unusable ([`Program::dual_in_cone`]).
    pub fn bound_affine(&self, z: &[f64], objective: bool) -> Option<ParamAffine> {
        let z = self.dual_in_cone(z)?;
        let r = self.reduced_costs(&z, objective);
        let zero = Exact::ZERO;
        let mut total = if objective {
            self.constant.clone()
        } else {
            ParamAffine::constant(zero.clone())
        };
        for (row, zi) in self.rows.iter().zip(&z) {
            if *zi != zero {
                total = total - row.b.scaled(zi);
            }
        }
        for (rj, var) in r.iter().zip(&self.vars) {
            if *rj > zero {
                total = total + var.lower.scaled(rj);
            } else if *rj < zero {
                total = total + var.upper.scaled(rj);
            }
        }
        Some(total)
    }

    /// c − Aᵀz (with c = 0 when `objective` is false): what each variable's box must pay.
    fn reduced_costs(&self, z: &[Exact], objective: bool) -> Vec<Exact> {
        let zero = Exact::ZERO;
        let mut r: Vec<Exact> = match (&self.objective, objective) {
            (Some(c), true) => c.clone(),
            _ => vec![zero.clone(); self.n()],
        };
        for (row, zi) in self.rows.iter().zip(z) {
            if *zi == zero {
                continue;
            }
            for (rj, aij) in r.iter_mut().zip(&row.a) {
                if *aij != zero {
                    *rj += zi * aij;
                }
            }
        }
        r
    }

    /// The exact bound proved by multipliers `z` at the problem's parameters
    /// ([`Program::bound_affine`]'s value, without its slopes: point analyses ask for
    /// thousands of these).
    pub fn bound(&self, z: &[f64], objective: bool) -> Option<Exact> {
        let z = self.dual_in_cone(z)?;
        let r = self.reduced_costs(&z, objective);
        let zero = Exact::ZERO;
        let mut total = if objective {
            self.constant.value.clone()
        } else {
            zero.clone()
        };
        for (row, zi) in self.rows.iter().zip(&z) {
            if *zi != zero {
                total -= zi * &row.b.value;
            }
        }
        for (rj, var) in r.iter().zip(&self.vars) {
            if *rj > zero {
                total += rj * &var.lower.value;
            } else if *rj < zero {
                total += rj * &var.upper.value;
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

    /// A nonnegative row that no point of the box satisfies (a strict row: not even on its
    /// boundary), if there is one: its unit multiplier proves emptiness without a solver.
    pub fn infeasible_row(&self) -> Option<usize> {
        let cones: Vec<Cone> = self.row_cones().collect();
        self.rows.iter().enumerate().position(|(i, row)| {
            if cones.get(i) != Some(&Cone::Nonnegative) {
                return false;
            }
            let mut least = Exact::ZERO;
            for (a, var) in row.a.iter().zip(&self.vars) {
                if *a > Exact::ZERO {
                    least += a * &var.lower.value;
                } else if *a < Exact::ZERO {
                    least += a * &var.upper.value;
                }
            }
            least > row.b.value || (row.strict && least == row.b.value)
        })
    }
}

/// A second-order block's multipliers, exactly in the cone: the tail as given, the head
/// raised (if needed) to a rational h ≥ 0 with h² ≥ ‖tail‖², so z·s ≥ 0 for every slack s in
/// the cone (Cauchy–Schwarz).
fn second_order_dual(z: &[f64]) -> Vec<Exact> {
    let Some((&head, tail)) = z.split_first() else {
        return Vec::new();
    };
    let tail: Vec<Exact> = tail.iter().map(|&x| exact_float(x)).collect();
    let norm2 = tail.iter().fold(Exact::ZERO, |acc, t| acc + t * t);
    let mut h = exact_float(head.max(0.0));
    if &h * &h < norm2 {
        // A float just above the norm, stepped up until its square covers the norm exactly.
        let mut f = norm2.to_f64().value().sqrt().max(head);
        loop {
            h = exact_float(f);
            if &h * &h >= norm2 {
                break;
            }
            f = f.next_up();
        }
    }
    std::iter::once(h).chain(tail).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::parameter::Parameter;

    fn q(n: i64, d: i64) -> Exact {
        Exact::from(n) / Exact::from(d)
    }

    fn c(n: i64, d: i64) -> ParamAffine {
        ParamAffine::constant(q(n, d))
    }

    fn var(name: &str, lower: ParamAffine, upper: ParamAffine) -> Var {
        Var {
            name: name.into(),
            lower,
            upper,
        }
    }

    fn row(a: &[i64], b: ParamAffine, strict: bool) -> Row {
        Row {
            label: String::new(),
            a: a.iter().map(|&x| Exact::from(x)).collect(),
            b,
            strict,
        }
    }

    /// min x + y s.t. x + y ≥ 1 (−x − y ≤ −1), x, y ∈ [0, 2]: optimum 1.
    fn simplex() -> Program {
        Program::linear(
            vec![var("x", c(0, 1), c(2, 1)), var("y", c(0, 1), c(2, 1))],
            vec![row(&[-1, -1], c(-1, 1), false)],
            Some(vec![Exact::ONE, Exact::ONE]),
            c(0, 1),
        )
    }

    #[test]
    fn the_optimal_multiplier_proves_the_optimum() {
        assert_eq!(simplex().bound(&[1.0], true), Some(q(1, 1)));
    }

    #[test]
    fn any_multiplier_proves_a_valid_bound() {
        // z = 0: r = (1, 1), bound = 0 + 0 = 0 (the box alone). z = 0.5: r = (0.5, 0.5),
        // bound = 0.5 + 0 = 0.5. z = 3: r = (−2, −2), bound = 3 − 2·2 − 2·2 = −5.
        let p = simplex();
        assert_eq!(p.bound(&[0.0], true), Some(q(0, 1)));
        assert_eq!(p.bound(&[0.5], true), Some(q(1, 2)));
        assert_eq!(p.bound(&[3.0], true), Some(q(-5, 1)));
        // A negative multiplier on an inequality is clipped to 0, never trusted.
        assert_eq!(p.bound(&[-7.0], true), Some(q(0, 1)));
    }

    #[test]
    fn unusable_multipliers_prove_nothing() {
        let p = simplex();
        assert_eq!(p.bound(&[], true), None);
        assert_eq!(p.bound(&[f64::NAN], true), None);
        assert_eq!(p.bound(&[f64::INFINITY], true), None);
    }

    #[test]
    fn equality_multipliers_are_free() {
        // min x s.t. x − y = 1 (zero cone), x ∈ [0, 5], y ∈ [0, 5]: optimum 1 at y = 0.
        // z = −1 on the equality: r = (1 − 1, 0 + 1) = (0, 1), bound = −(−1)(1) + 1·0 = 1.
        let p = Program {
            vars: vec![var("x", c(0, 1), c(5, 1)), var("y", c(0, 1), c(5, 1))],
            rows: vec![row(&[1, -1], c(1, 1), false)],
            cones: vec![ConeBlock {
                cone: Cone::Zero,
                rows: 1,
            }],
            objective: Some(vec![Exact::ONE, Exact::ZERO]),
            constant: c(0, 1),
        };
        assert_eq!(p.bound(&[-1.0], true), Some(q(1, 1)));
        // The same row as an inequality clips the multiplier: only the box is left.
        let mut ineq = p.clone();
        ineq.cones[0].cone = Cone::Nonnegative;
        assert_eq!(ineq.bound(&[-1.0], true), Some(q(0, 1)));
    }

    #[test]
    fn farkas_multipliers_prove_emptiness() {
        // x ≤ 1 and −x ≤ −2 (x ≥ 2): z = (1, 1) sums to 0 ≤ −1, a contradiction of size 1.
        let p = Program::linear(
            vec![var("x", c(-10, 1), c(10, 1))],
            vec![row(&[1], c(1, 1), false), row(&[-1], c(-2, 1), false)],
            None,
            c(0, 1),
        );
        assert_eq!(p.proves_empty(&[1.0, 1.0]), Some(q(1, 1)));
        assert_eq!(p.proves_empty(&[1.0, 0.0]), None);
    }

    #[test]
    fn a_strict_row_closes_a_boundary_contradiction() {
        // x ≤ 1 and x > 1 (closed: −x ≤ −1): the Farkas sum is exactly 0, which proves the
        // strict system empty only because the weight sits on the strict row.
        let rows = |strict| vec![row(&[1], c(1, 1), false), row(&[-1], c(-1, 1), strict)];
        let x = || vec![var("x", c(-10, 1), c(10, 1))];
        let strict = Program::linear(x(), rows(true), None, c(0, 1));
        assert_eq!(strict.proves_empty(&[1.0, 1.0]), Some(q(0, 1)));
        let closed = Program::linear(x(), rows(false), None, c(0, 1));
        assert_eq!(closed.proves_empty(&[1.0, 1.0]), None);
    }

    #[test]
    fn infeasible_rows_are_found_from_the_box_alone() {
        let p = Program::linear(
            vec![var("x", c(2, 1), c(3, 1))],
            vec![row(&[1], c(5, 1), false), row(&[1], c(1, 1), false)],
            None,
            c(0, 1),
        );
        assert_eq!(p.infeasible_row(), Some(1));
        // A strict row is infeasible even when the box touches its boundary.
        let touch = Program::linear(
            vec![var("x", c(2, 1), c(3, 1))],
            vec![row(&[1], c(2, 1), true)],
            None,
            c(0, 1),
        );
        assert_eq!(touch.infeasible_row(), Some(0));
    }

    /// The value-only bound is the affine bound's value, on the seed's programs (noise and
    /// the wrong-assumption guard on: every row kind) for many multiplier vectors, with and
    /// without the objective.
    #[test]
    fn the_bound_is_the_affine_bounds_value() {
        use crate::core::model::{Problem, Sensing};
        let mut problems = Vec::new();
        for (w, latency, noise) in [
            (0.1, 1, 0.0),
            (0.3, 1, 0.05),
            (0.25, 3, 0.0),
            (0.3, 2, 0.02),
        ] {
            let mut p = Problem::shipped_seed();
            p.environment.obstacle_speed = w;
            p.robot.latency = latency;
            p.sensing = Some(Sensing {
                gap_noise: Some(noise),
                speed_noise: Some(noise / 5.0),
                first_detection_gap: None,
            });
            problems.push(p);
        }
        let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            // Multipliers in [0, 3), a quarter of them exactly 0.
            let u = (state >> 11) as f64 / (1u64 << 53) as f64;
            if u < 0.25 { 0.0 } else { 4.0 * (u - 0.25) }
        };
        let mut compared = 0;
        for d in problems
            .iter()
            .map(crate::proof::schedule::Decomposition::new)
        {
            for piece in d.pieces.iter().take(40) {
                let p = d.program(piece);
                for _ in 0..20 {
                    let z: Vec<f64> = (0..p.rows.len()).map(|_| next()).collect();
                    for objective in [true, false] {
                        let affine = p.bound_affine(&z, objective).map(|b| b.value);
                        assert_eq!(p.bound(&z, objective), affine, "{}", piece.describe());
                        compared += usize::from(affine.is_some());
                    }
                }
            }
        }
        assert!(compared > 200, "{compared} bounds compared");
    }

    #[test]
    fn second_order_multipliers_are_moved_into_the_cone() {
        // min t s.t. t ≥ ‖(x, y)‖ with x = 3, y = 4 fixed by the box: optimum 5.
        // Rows: s = (t, x, y) − 0 ∈ SOC, written b − A·(t, x, y) with A = −I, b = 0.
        let p = Program {
            vars: vec![
                var("t", c(0, 1), c(100, 1)),
                var("x", c(3, 1), c(3, 1)),
                var("y", c(4, 1), c(4, 1)),
            ],
            rows: vec![
                row(&[-1, 0, 0], c(0, 1), false),
                row(&[0, -1, 0], c(0, 1), false),
                row(&[0, 0, -1], c(0, 1), false),
            ],
            cones: vec![ConeBlock {
                cone: Cone::SecondOrder,
                rows: 3,
            }],
            objective: Some(vec![Exact::ONE, Exact::ZERO, Exact::ZERO]),
            constant: c(0, 1),
        };
        // The optimal dual is z = (1, −3/5, −4/5): r = (0, 3/5, 4/5), bound = 9/5 + 16/5 = 5.
        assert_eq!(
            p.bound(&[1.0, -0.6, -0.8], true)
                .map(|b| b > q(49999, 10000)),
            Some(true)
        );
        // A solver's slightly infeasible head is raised, never trusted: the bound stays valid.
        let z = p.dual_in_cone(&[0.9, -0.6, -0.8]).expect("usable");
        assert!(&z[0] * &z[0] >= &z[1] * &z[1] + &z[2] * &z[2]);
        let b = p.bound(&[0.9, -0.6, -0.8], true).expect("a bound");
        assert!(b <= q(5, 1), "a valid bound never exceeds the optimum: {b}");
    }

    #[test]
    fn bounds_are_affine_in_the_parameters() {
        // min x s.t. x ≥ ρ − 1 (−x ≤ 1 − ρ), x ∈ [0, W]: with z = 1 the bound is ρ − 1,
        // whose slope in ρ is exactly 1; the box's upper end W does not enter (r = 0).
        let problem = crate::core::model::Problem::shipped_seed();
        let params = problem.params::<Exact>();
        let rho = ParamAffine::parameter(Parameter::ReactionRadius, &params);
        let w = ParamAffine::parameter(Parameter::ObstacleSpeed, &params);
        let p = Program::linear(
            vec![var("x", c(0, 1), w)],
            vec![row(&[-1], c(1, 1) - rho, false)],
            Some(vec![Exact::ONE]),
            c(0, 1),
        );
        let b = p.bound_affine(&[1.0], true).expect("a bound");
        assert_eq!(b.value, &params.rho - Exact::ONE);
        assert_eq!(b.slope(Parameter::ReactionRadius), Exact::ONE);
        assert_eq!(b.slope(Parameter::ObstacleSpeed), Exact::ZERO);
        // With z = 0 the bound is the box's lower end, 0, which no parameter moves; with
        // an objective −x it is −W, slope −1 in W.
        let mut neg = p.clone();
        neg.objective = Some(vec![-Exact::ONE]);
        let nb = neg.bound_affine(&[0.0], true).expect("a bound");
        assert_eq!(nb.slope(Parameter::ObstacleSpeed), -Exact::ONE);
        assert_eq!(nb.value, -params.W.clone());
    }

    #[test]
    fn malformed_cone_blocks_prove_nothing() {
        let mut p = simplex();
        p.cones[0].rows = 2;
        assert!(!p.is_well_formed());
        assert_eq!(p.bound(&[1.0], true), None);
        let mut q = simplex();
        q.cones[0].cone = Cone::Zero;
        q.rows[0].strict = true;
        assert!(!q.is_well_formed());
    }
}
