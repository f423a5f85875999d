//! A piece's box program with the ranged parameters as variables ("lifted"): the best
//! multipliers for a whole box in one solve.
//!
//! Parameters enter a box program only through right-hand sides, variable bounds and the
//! objective's constant, affinely. Making each ranged parameter θ a variable on its
//! interval turns "the least, over the box, of the piece's worst case" into one linear
//! program. Its row multipliers are what a region proof needs: for multipliers z the proved
//! bound, minimised over the box, is the Lagrangian of the lifted program relaxing only the
//! rows (the variables' and parameters' boxes kept), and for a linear program that partial
//! dual is tight. So the lifted optimum is the best bound any single set of multipliers
//! proves over the box, and a lifted program that is empty is empty at every point of the
//! box. (The proof is still checked on the original program: these are only candidates.)

use crate::core::model::Params;
use crate::core::num::Exact;
use crate::core::param_box::ParamBox;
use crate::core::parameter::ParamAffine;
use crate::proof::program::{Cone, ConeBlock, Program, Row, Var};

/// The lifted program of `program` (taken at `at`, a point of `b`) with `less` (affine in
/// the parameters, e.g. the clearance) subtracted from its objective: one more variable per
/// ranged parameter, its offset from `at` on the box's interval; rows and parametric
/// variable bounds become rows in the variables and offsets. Its first `program.rows.len()`
/// multipliers are candidates for `program` over `b`.
pub fn lifted(program: &Program, b: &ParamBox, at: &Params<Exact>, less: &ParamAffine) -> Program {
    let n = program.n();
    let axes: Vec<_> = b.axes.iter().filter(|a| a.obstacle.is_none()).collect();
    // −∂/∂θ of an affine number, per axis: its coefficients on the offsets in `a`.
    let offsets = |f: &ParamAffine, sign: &Exact| -> Vec<Exact> {
        axes.iter()
            .map(|a| -(f.slope(a.parameter) * sign))
            .collect()
    };
    let mut vars = program.vars.clone();
    let mut extra: Vec<Row> = Vec::new();
    for (j, v) in program.vars.iter().enumerate() {
        let unit = |s: i32| {
            let mut a = vec![Exact::ZERO; n];
            a[j] = Exact::from(s);
            a
        };
        if !v.lower.is_constant() {
            // −x + ∂lower·θ ≤ −lower(at)
            let mut a = unit(-1);
            a.extend(offsets(&v.lower, &-Exact::ONE));
            extra.push(row(&v.name, a, -v.lower.value.clone()));
            vars[j].lower = ParamAffine::constant(b.min_of(&v.lower, at));
        }
        if !v.upper.is_constant() {
            // x − ∂upper·θ ≤ upper(at)
            let mut a = unit(1);
            a.extend(offsets(&v.upper, &Exact::ONE));
            extra.push(row(&v.name, a, v.upper.value.clone()));
            vars[j].upper = ParamAffine::constant(b.max_of(&v.upper, at));
        }
    }
    for a in &axes {
        let here = a.parameter.value(at);
        vars.push(Var {
            name: a.key(),
            lower: ParamAffine::constant(a.lo_exact() - here),
            upper: ParamAffine::constant(a.hi_exact() - here),
        });
    }
    let mut rows: Vec<Row> = program
        .rows
        .iter()
        .map(|r| {
            let mut a = r.a.clone();
            a.extend(offsets(&r.b, &Exact::ONE));
            Row {
                label: r.label.clone(),
                a,
                b: ParamAffine::constant(r.b.value.clone()),
                strict: r.strict,
            }
        })
        .collect();
    let mut cones = program.cones.clone();
    if !extra.is_empty() {
        cones.push(ConeBlock {
            cone: Cone::Nonnegative,
            rows: extra.len(),
        });
        rows.extend(extra);
    }
    let constant = program.constant.clone() - less.clone();
    let objective = program.objective.as_ref().map(|c| {
        let mut c = c.clone();
        c.extend(axes.iter().map(|a| constant.slope(a.parameter)));
        c
    });
    Program {
        vars,
        rows,
        cones,
        objective,
        constant: ParamAffine::constant(constant.value),
    }
}

fn row(name: &str, a: Vec<Exact>, b: Exact) -> Row {
    Row {
        label: format!("bound of {name} over the box"),
        a,
        b: ParamAffine::constant(b),
        strict: false,
    }
}
