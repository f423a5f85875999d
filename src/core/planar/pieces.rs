//! A period's motion cut where the robot crosses a path vertex ([`path_pieces`]), so that on
//! each piece its centre is one polynomial of degree ≤ 2 in τ per coordinate
//! (docs/semantics.md §13.1).
//!
//! **Crossings.** Within a motion phase the arc length s(τ) is strictly increasing (the
//! robot moves at every inner instant), so it meets a vertex's arc length at most once.
//! While cruising s is affine and the crossing instant is rational; while accelerating or
//! braking it solves a quadratic, and is rational exactly when the discriminant is a
//! rational square. Otherwise it is a quadratic surd, and the piece boundary is not a
//! rational number: Sturm bisection ([`Polynomial::isolate_roots`]) isolates it in a
//! rational interval [c_lo, c_hi] of width ≤ 2⁻⁶⁰ whose ends are not the crossing. On
//! [from, c_lo] the robot is on the segment before the vertex, on [c_hi, to] on the one
//! after; the interval itself is a [`PathPiece::Straddle`] on which the robot is, at each
//! instant, on one of the segments from the one holding s(c_lo) to the one holding s(c_hi)
//! (s is monotone). Overlapping straddles (vertices closer than the robot travels in 2⁻⁶⁰ s)
//! merge into one, with every segment in between.

use crate::core::num::Exact;
use crate::core::plane::direction::rational_sqrt;
use crate::core::plane::rational_path::RationalPath;
use crate::core::polynomial::Polynomial;

use super::phases::Phase;

/// A piece of one period's motion (instants τ since the period's start).
#[derive(Clone, Debug, PartialEq)]
pub enum PathPiece {
    /// On [from, to] the robot is on `segment` (at the piece's ends possibly at a vertex of
    /// it), at arc length `arc(τ)`.
    On {
        /// First instant.
        from: Exact,
        /// Last instant.
        to: Exact,
        /// The segment's index in the path.
        segment: usize,
        /// s(τ).
        arc: Polynomial,
        /// The robot comes to rest at `to`, so `to` is not a moving instant.
        rests_at_end: bool,
    },
    /// A tiny rational interval around surd vertex crossings: at each instant the robot is
    /// on one of `segments` at arc length `arc(τ)`.
    Straddle {
        /// First instant.
        from: Exact,
        /// Last instant.
        to: Exact,
        /// The first and last segment it may be on.
        segments: (usize, usize),
        /// s(τ).
        arc: Polynomial,
    },
}

/// How narrow a surd crossing's interval is: 2⁻⁶⁰ s.
fn crossing_width() -> Exact {
    Exact::ONE / Exact::from(1u64 << 60)
}

/// Where one crossing lies.
enum Cut {
    At(Exact),
    Within(Exact, Exact),
}

/// The pieces of `phases` (one period's, [`super::phases::motion_phases`]) on `path`, in time
/// order.
pub fn path_pieces(path: &RationalPath, phases: &[Phase]) -> Vec<PathPiece> {
    let mut pieces = Vec::new();
    for phase in phases {
        let (s_from, s_to) = (phase.arc.eval(&phase.from), phase.arc.eval(&phase.to));
        let cuts: Vec<Cut> = path
            .vertex_arcs()
            .filter(|v| s_from < **v && **v < s_to)
            .map(|v| crossing(phase, v))
            .collect();
        let segment = |tau: &Exact| path.segment_index(&phase.arc.eval(tau));
        let mut cursor = phase.from.clone();
        let push_on = |pieces: &mut Vec<PathPiece>, from: &Exact, to: &Exact, rests: bool| {
            if from < to {
                let mid = (from + to) / Exact::from(2);
                pieces.push(PathPiece::On {
                    from: from.clone(),
                    to: to.clone(),
                    segment: segment(&mid),
                    arc: phase.arc.clone(),
                    rests_at_end: rests,
                });
            }
        };
        for cut in cuts {
            match cut {
                Cut::At(t) if t > cursor => {
                    push_on(&mut pieces, &cursor, &t, false);
                    cursor = t;
                }
                Cut::At(_) => {} // inside the straddle before it, which covers it
                Cut::Within(lo, hi) => {
                    let (lo, hi) = if lo < cursor {
                        // Overlaps the straddle just pushed: merge into it.
                        match pieces.pop() {
                            Some(PathPiece::Straddle { from, to, .. }) => {
                                (from, if hi > to { hi } else { to })
                            }
                            other => {
                                pieces.extend(other);
                                (cursor.clone(), hi)
                            }
                        }
                    } else {
                        push_on(&mut pieces, &cursor, &lo, false);
                        (lo, hi)
                    };
                    pieces.push(PathPiece::Straddle {
                        segments: (segment(&lo), segment(&hi)),
                        from: lo,
                        to: hi.clone(),
                        arc: phase.arc.clone(),
                    });
                    cursor = hi;
                }
            }
        }
        push_on(&mut pieces, &cursor, &phase.to, phase.rests_at_end);
    }
    pieces
}

/// The instant in (phase.from, phase.to) at which s(τ) = `vertex` (module docs).
fn crossing(phase: &Phase, vertex: &Exact) -> Cut {
    let q = &phase.arc - &Polynomial::constant(vertex.clone());
    let c = q.coefficients();
    let inside = |t: &Exact| phase.from < *t && *t < phase.to;
    match c.len() {
        2 => return Cut::At(-&c[0] / &c[1]),
        3 => {
            let disc = &c[1] * &c[1] - Exact::from(4) * &c[2] * &c[0];
            if let Some(root) = rational_sqrt(&disc) {
                let two_a = &c[2] * Exact::from(2);
                for r in [(-&c[1] + &root) / &two_a, (-&c[1] - &root) / &two_a] {
                    if inside(&r) {
                        return Cut::At(r);
                    }
                }
            }
        }
        _ => {}
    }
    let found = q.isolate_roots(&phase.from, &phase.to, &crossing_width());
    match found.into_iter().find(|(lo, hi)| inside(lo) || inside(hi)) {
        Some((lo, hi)) if lo == hi => Cut::At(lo),
        Some((lo, hi)) => Cut::Within(lo, hi),
        None => unreachable!("s(τ) is continuous and passes the vertex inside the phase"),
    }
}
