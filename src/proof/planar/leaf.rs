//! One leaf of the planar bound (docs/reductions.md Lemma P4) as a second-order cone
//! program in exact rationals: the least distance from a robot centre to where the obstacle
//! can be, given one anchor observation it left unfired, less a constant.
//!
//! Variables: e (the distance's epigraph), p (the start point, a box), x (the centre at the
//! anchor instant), y (the centre at the leaf's instant), and for a fixed-direction
//! obstacle the two distances w₁ (start to anchor) and w₂ (anchor to instant) along its
//! direction. Every variable has a finite box, as the Neumaier–Shcherbina bound needs
//! (`proof::program`).

use dashu_int::ops::Abs;

use crate::core::num::Exact;
use crate::core::parameter::ParamAffine;
use crate::core::planar::Start;
use crate::core::plane::point::Point;
use crate::core::plane::polygon::ConvexPolygon;
use crate::proof::program::{Cone, ConeBlock, Program, Row, Var};

use super::cover::HalfPlane;

/// How the obstacle may move between two instants.
#[derive(Clone, Debug, PartialEq)]
pub enum Travel {
    /// Any displacement of norm at most this (free direction: W_i times the time).
    Free(Exact),
    /// A displacement w·d along the unit direction d with w in [lo, hi].
    Along {
        /// The direction (a rational unit vector).
        direction: Point,
        /// The least signed distance.
        lo: Exact,
        /// The greatest signed distance.
        hi: Exact,
    },
}

/// One leaf: minimise ‖target − y‖ + constant over the obstacle's possible (p, x, y).
#[derive(Clone, Debug, PartialEq)]
pub struct Leaf {
    /// The robot's centre at the leaf's first instant, c^T(t₁).
    pub target: Point,
    /// The start set.
    pub start: Start,
    /// From the start to the anchor instant (x − p).
    pub to_anchor: Travel,
    /// From the anchor instant to the leaf's instants (y − x).
    pub to_instant: Travel,
    /// The region every centre lies in.
    pub region: Option<ConvexPolygon>,
    /// The cover set's half-planes that hold every centre of the set *strictly* (beyond a
    /// guard's threshold), on x.
    pub cover: Vec<HalfPlane>,
    /// The cover set's half-planes that hold its centres only in their closure, on x: an
    /// arc's sector. Neighbouring sectors share a ray, and a centre on it lies in neither
    /// interior, so these rows may not be strict: a start set on that ray (a start box
    /// of height 0 on the robot's line) would otherwise be proved empty in every sector.
    pub sector: Vec<HalfPlane>,
    /// Added to the distance: −(r_R + r_i) less the chord loss of Lemma P4.
    pub constant: Exact,
}

const E: usize = 0;
const P: usize = 1;
const X: usize = 3;
const Y: usize = 5;
const W1: usize = 7;

/// A coordinate interval.
#[derive(Clone, Debug)]
struct Span {
    lo: Exact,
    hi: Exact,
}

fn span_of(lo: Exact, hi: Exact) -> Span {
    Span { lo, hi }
}

/// The box of `base + travel` per coordinate.
fn widen(base: &[Span; 2], travel: &Travel) -> [Span; 2] {
    [0, 1].map(|i| match travel {
        Travel::Free(r) => span_of(&base[i].lo - r, &base[i].hi + r),
        Travel::Along { direction, lo, hi } => {
            let d = if i == 0 { &direction.x } else { &direction.y };
            let (a, b) = (d * lo, d * hi);
            let (a, b) = if a <= b { (a, b) } else { (b, a) };
            span_of(&base[i].lo + &a, &base[i].hi + &b)
        }
    })
}

impl Leaf {
    fn n_vars(&self) -> usize {
        W1 + self.along_count()
    }

    fn along_count(&self) -> usize {
        [&self.to_anchor, &self.to_instant]
            .iter()
            .filter(|t| matches!(t, Travel::Along { .. }))
            .count()
    }

    /// The leaf as a program whose optimum plus nothing is the leaf's value: `min e +
    /// constant` over the rows.
    pub fn program(&self) -> Program {
        let n = self.n_vars();
        let konst = |v: Exact| ParamAffine::constant(v);
        let (pmin, pmax) = match &self.start {
            Start::At(p) => (p.clone(), p.clone()),
            Start::Box { min, max } => (min.clone(), max.clone()),
        };
        let p_box = [
            span_of(pmin.x.clone(), pmax.x.clone()),
            span_of(pmin.y.clone(), pmax.y.clone()),
        ];
        let x_box = widen(&p_box, &self.to_anchor);
        let y_box = widen(&x_box, &self.to_instant);
        let far = [0, 1]
            .iter()
            .map(|&i| {
                let t = if i == 0 {
                    &self.target.x
                } else {
                    &self.target.y
                };
                let (a, b) = ((&y_box[i].lo - t).abs(), (&y_box[i].hi - t).abs());
                if a > b { a } else { b }
            })
            .fold(Exact::ONE, |s, d| s + d);
        let mut vars = Vec::with_capacity(n);
        vars.push(Var {
            name: "distance".into(),
            lower: konst(Exact::ZERO),
            upper: konst(far),
        });
        for (name, b) in [("p", &p_box), ("x", &x_box), ("y", &y_box)] {
            for (axis, s) in ["x", "y"].iter().zip(b.iter()) {
                vars.push(Var {
                    name: format!("{name}.{axis}"),
                    lower: konst(s.lo.clone()),
                    upper: konst(s.hi.clone()),
                });
            }
        }
        let mut along = Vec::new();
        for (name, travel) in [
            ("w_anchor", &self.to_anchor),
            ("w_instant", &self.to_instant),
        ] {
            if let Travel::Along { lo, hi, .. } = travel {
                along.push(vars.len());
                vars.push(Var {
                    name: name.into(),
                    lower: konst(lo.clone()),
                    upper: konst(hi.clone()),
                });
            }
        }
        let row = |label: &str, terms: &[(usize, Exact)], b: Exact| {
            let mut a = vec![Exact::ZERO; n];
            for (j, c) in terms {
                a[*j] += c;
            }
            Row {
                label: label.into(),
                a,
                b: konst(b),
                strict: false,
            }
        };
        let mut zero = Vec::new();
        let mut nonneg = Vec::new();
        let mut cones: Vec<[Row; 3]> = Vec::new();
        let one = Exact::ONE;
        // The distance: (e, target − y) in the cone.
        cones.push([
            row("distance", &[(E, -one.clone())], Exact::ZERO),
            row("distance.x", &[(Y, one.clone())], self.target.x.clone()),
            row("distance.y", &[(Y + 1, one.clone())], self.target.y.clone()),
        ]);
        let mut next_along = along.iter();
        for (label, from, to, travel) in [
            ("to anchor", P, X, &self.to_anchor),
            ("to instant", X, Y, &self.to_instant),
        ] {
            match travel {
                Travel::Free(r) if *r == Exact::ZERO => {
                    for i in 0..2 {
                        zero.push(row(
                            label,
                            &[(to + i, one.clone()), (from + i, -one.clone())],
                            Exact::ZERO,
                        ));
                    }
                }
                Travel::Free(r) => cones.push([
                    row(label, &[], r.clone()),
                    row(
                        label,
                        &[(to, -one.clone()), (from, one.clone())],
                        Exact::ZERO,
                    ),
                    row(
                        label,
                        &[(to + 1, -one.clone()), (from + 1, one.clone())],
                        Exact::ZERO,
                    ),
                ]),
                Travel::Along { direction, .. } => {
                    let w = *next_along.next().expect("one variable per fixed travel");
                    for (i, d) in [&direction.x, &direction.y].into_iter().enumerate() {
                        zero.push(row(
                            label,
                            &[
                                (to + i, one.clone()),
                                (from + i, -one.clone()),
                                (w, -d.clone()),
                            ],
                            Exact::ZERO,
                        ));
                    }
                }
            }
        }
        for h in &self.cover {
            // Strict: a guard that did not fire saw the centre strictly beyond its
            // threshold (Lemma P1), and these rows hold every such centre strictly.
            let mut r = row(
                "cover",
                &[(X, -h.normal.x.clone()), (X + 1, -h.normal.y.clone())],
                -h.offset.clone(),
            );
            r.strict = true;
            nonneg.push(r);
        }
        for h in &self.sector {
            nonneg.push(row(
                "sector",
                &[(X, -h.normal.x.clone()), (X + 1, -h.normal.y.clone())],
                -h.offset.clone(),
            ));
        }
        if let Some(q) = &self.region {
            for h in region_half_planes(q) {
                for at in [P, X, Y] {
                    nonneg.push(row(
                        "region",
                        &[(at, -h.normal.x.clone()), (at + 1, -h.normal.y.clone())],
                        -h.offset.clone(),
                    ));
                }
            }
        }
        let mut rows = Vec::new();
        let mut blocks = Vec::new();
        for (cone, list) in [(Cone::Zero, zero), (Cone::Nonnegative, nonneg)] {
            if !list.is_empty() {
                blocks.push(ConeBlock {
                    cone,
                    rows: list.len(),
                });
                rows.extend(list);
            }
        }
        for c in cones {
            blocks.push(ConeBlock {
                cone: Cone::SecondOrder,
                rows: 3,
            });
            rows.extend(c);
        }
        let mut objective = vec![Exact::ZERO; n];
        objective[E] = Exact::ONE;
        Program {
            vars,
            rows,
            cones: blocks,
            objective: Some(objective),
            constant: konst(self.constant.clone()),
        }
    }
}

/// A counter-clockwise convex polygon as the half-planes it is the intersection of.
pub fn region_half_planes(q: &ConvexPolygon) -> Vec<HalfPlane> {
    let v = q.vertices();
    (0..v.len())
        .map(|i| {
            let (a, b) = (&v[i], &v[(i + 1) % v.len()]);
            let edge = b - a;
            let normal = Point::new(-edge.y.clone(), edge.x.clone());
            HalfPlane {
                offset: normal.dot(a),
                normal,
            }
        })
        .collect()
}
