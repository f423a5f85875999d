//! The path the engines analyse: the file's path with every segment's direction a rational
//! unit vector and every length rational, so that the robot at a rational arc length is at
//! a rational point, and a proved bound on how far it lies from the file's path.
//!
//! **The drift bound.** Let the file's segment j run from V_j with exact length ℓ_j
//! (irrational in general) and unit direction e_j, the analysed one from W_j with rational
//! length λ_j and rational unit direction u_j, where |u_j − e_j| ≤ δ and |λ_j − ℓ_j| ≤ ε_j
//! (both proved in rationals). Write a_j = (λ_j + ε_j)·δ + ε_j ≥ |ℓ_j·e_j − λ_j·u_j|,
//! A = Σ a_j and B = Σ ε_j. Then at every arc length s that both paths reach,
//! |P(s) − Q(s)| ≤ D := A + 3·B, P and Q the points at arc length s on the file's path and
//! on the analysed one.
//!
//! *Proof.* By induction |V_j − W_j| ≤ Σ_{m<j} a_m ≤ A and the arc lengths of the vertices
//! differ by at most B. Where s lies on segment j of both paths,
//! P(s) − Q(s) = (V_j − W_j) + (s − S_j)·(e_j − u_j) + (Σ_j − S_j)·u_j, of norm at most
//! Σ_{m<j} a_m + ℓ_j·δ + B ≤ A + B. Elsewhere s is within B of such a point t (each segment
//! is longer than 2B, checked, so the two paths' stretches of segment j overlap), and both
//! P and Q are 1-Lipschitz in s, so |P(s) − Q(s)| ≤ |P(t) − Q(t)| + 2B. ∎
//!
//! A planar engine that analyses this path stays sound for the file's path by adding D to
//! the robot's radius (every separation is off by at most D) and to the position noise
//! (every relative position the controller sees is off by at most D), docs/semantics.md
//! §13.

use super::direction::{DirectionError, RationalDirection, rational_sqrt};
use super::path::Path;
use super::point::Point;
use crate::core::num::{Exact, exact_float};

/// One segment of the analysed path.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RationalSegment {
    /// Where it starts.
    pub start: Point,
    /// Its direction, a rational unit vector.
    pub direction: RationalDirection,
    /// Its rational length (m).
    pub length: Exact,
    /// The arc length at its start (m).
    pub arc_start: Exact,
}

/// The analysed path and its proved drift from the file's path (module docs).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RationalPath {
    segments: Vec<RationalSegment>,
    drift: Exact,
}

impl RationalPath {
    /// The analysed path of `path`, each direction within chord distance `delta` (0 < δ ≤ 1)
    /// of the file's. Fails only for a δ beyond what the float proposals can reach, or for
    /// a segment shorter than twice the accumulated length error (≈ 10⁻¹² m).
    pub fn new(path: &Path, delta: &Exact) -> Result<Self, DirectionError> {
        let mut segments = Vec::new();
        let (mut at, mut arc) = (Point::origin(), Exact::ZERO);
        let (mut a_sum, mut b_sum) = (Exact::ZERO, Exact::ZERO);
        for (from, to) in path.segments() {
            let d = to - from;
            let direction = RationalDirection::near(&d, delta)?;
            let (length, eps) = rational_length(&d.norm_squared());
            // A segment whose direction and length came out exact adds no drift.
            let exact = eps == Exact::ZERO && direction.unit() * &length == d;
            if !exact {
                a_sum += (&length + &eps) * delta + &eps;
            }
            b_sum += &eps;
            let next = &at + &(direction.unit() * &length);
            segments.push(RationalSegment {
                start: at,
                direction,
                length: length.clone(),
                arc_start: arc.clone(),
            });
            at = next;
            arc += length;
        }
        let twice_b = &b_sum * Exact::from(2);
        if segments.iter().any(|s| s.length <= twice_b) {
            return Err(DirectionError::Tolerance);
        }
        Ok(RationalPath {
            segments,
            drift: a_sum + b_sum * Exact::from(3),
        })
    }

    /// The same path with its drift grown by `e` ≥ 0: every engine that is sound for a robot
    /// within D of the analysed path is then sound for one within D + e of it (a robot that
    /// tracks its path to within `e`).
    pub fn widened(mut self, e: &Exact) -> Self {
        self.drift += e;
        self
    }

    /// The segments, in order.
    pub fn segments(&self) -> &[RationalSegment] {
        &self.segments
    }

    /// D: at every arc length both paths reach, the analysed point is within D of the
    /// file's (proved, module docs).
    pub fn drift(&self) -> &Exact {
        &self.drift
    }

    /// The analysed path's length (m).
    pub fn length(&self) -> Exact {
        let last = self.segments.last().expect("a path has a segment");
        &last.arc_start + &last.length
    }

    /// The index of the segment the robot is on at arc length `s`: at a vertex the one it
    /// leaves by, past the end the last one.
    pub fn segment_index(&self, s: &Exact) -> usize {
        self.segments
            .partition_point(|seg| seg.arc_start <= *s)
            .saturating_sub(1)
    }

    /// The point at arc length `s` ≥ 0 (past the end: on the last segment's line).
    pub fn point_at(&self, s: &Exact) -> Point {
        let seg = &self.segments[self.segment_index(s)];
        &seg.start + &(seg.direction.unit() * &(s - &seg.arc_start))
    }

    /// The heading at arc length `s`: the direction of [`RationalPath::segment_index`]'s
    /// segment.
    pub fn heading_at(&self, s: &Exact) -> &RationalDirection {
        &self.segments[self.segment_index(s)].direction
    }

    /// The arc lengths of the inner vertices, where a step's motion must be split
    /// (docs/semantics.md §13.1).
    pub fn vertex_arcs(&self) -> impl Iterator<Item = &Exact> {
        self.segments.iter().skip(1).map(|s| &s.arc_start)
    }
}

/// A rational λ and a proved ε with |λ − √n2| ≤ ε: exact (ε = 0) when √n2 is rational,
/// else the float square root and the least power of two that brackets it exactly.
fn rational_length(n2: &Exact) -> (Exact, Exact) {
    if let Some(root) = rational_sqrt(n2) {
        return (root, Exact::ZERO);
    }
    let length = exact_float(n2.to_f64().value().sqrt());
    let mut eps = &length * exact_float(2f64.powi(-48));
    loop {
        let lo = &length - &eps;
        let hi = &length + &eps;
        if lo >= Exact::ZERO && &lo * &lo <= *n2 && *n2 <= &hi * &hi {
            return (length, eps);
        }
        eps *= Exact::from(2);
    }
}
