//! Convex covers of the outside of a disc (docs/reductions.md Lemma P3(2)): arcs of
//! directions, each giving three half-planes whose intersection holds every point outside
//! the disc in that arc's sector. Refining an arc halves it; the cover's loss falls by
//! about four.
//!
//! Directions are rational unit vectors parametrised by the half-angle tangent t ∈ [−1, 1]
//! (angles in [−90°, 90°]), and their negatives for the back half: dir(t) =
//! ((1 − t²)/(1 + t²), 2t/(1 + t²)), whose angle 2·atan(t) increases with t, so an arc
//! [t_lo, t_hi] runs counter-clockwise from dir(t_lo) to dir(t_hi) and its mid direction
//! dir((t_lo + t_hi)/2) lies on it.

use crate::core::num::Exact;
use crate::core::plane::direction::{RationalDirection, sqrt_bounds};
use crate::core::plane::point::Point;
use crate::core::plane::polygon::ConvexPolygon;

/// A closed half-plane {x : normal·x ≥ offset}.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HalfPlane {
    /// Its inner normal (any length).
    pub normal: Point,
    /// Its offset.
    pub offset: Exact,
}

impl HalfPlane {
    /// Whether `p` lies in it.
    pub fn contains(&self, p: &Point) -> bool {
        self.normal.dot(p) >= self.offset
    }
}

/// An arc of directions: dir(t) for t ∈ [lo, hi] ⊆ [−1, 1], negated when `back`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Arc {
    /// The back half of the circle (directions negated).
    pub back: bool,
    /// The least half-angle tangent.
    pub lo: Exact,
    /// The greatest half-angle tangent.
    pub hi: Exact,
}

impl Arc {
    /// Four quarter-turn arcs that cover the circle.
    pub fn quarters() -> Vec<Arc> {
        let (m1, z, p1) = (-Exact::ONE, Exact::ZERO, Exact::ONE);
        [false, true]
            .into_iter()
            .flat_map(|back| {
                [
                    Arc {
                        back,
                        lo: m1.clone(),
                        hi: z.clone(),
                    },
                    Arc {
                        back,
                        lo: z.clone(),
                        hi: p1.clone(),
                    },
                ]
            })
            .collect()
    }

    fn direction(&self, t: &Exact) -> Point {
        let u = RationalDirection::from_half_angle_tangent(t).unit().clone();
        if self.back { -&u } else { u }
    }

    /// The arc's two halves.
    pub fn halves(&self) -> [Arc; 2] {
        let mid = (&self.lo + &self.hi) / Exact::from(2);
        [
            Arc {
                back: self.back,
                lo: self.lo.clone(),
                hi: mid.clone(),
            },
            Arc {
                back: self.back,
                lo: mid,
                hi: self.hi.clone(),
            },
        ]
    }

    /// The three half-planes holding every x with ‖x − centre‖ > radius whose direction
    /// from `centre` lies on the arc: a × (x − c) ≥ 0, (x − c) × b ≥ 0 and
    /// m·(x − c) ≥ radius·min(m·a, m·b) (Lemma P3(2); arcs here span at most a quarter
    /// turn, so m·a and m·b are ≥ 0).
    pub fn half_planes(&self, centre: &Point, radius: &Exact) -> [HalfPlane; 3] {
        let a = self.direction(&self.lo);
        let b = self.direction(&self.hi);
        let m = self.direction(&((&self.lo + &self.hi) / Exact::from(2)));
        let least = {
            let (ma, mb) = (m.dot(&a), m.dot(&b));
            if ma < mb { ma } else { mb }
        };
        let after_a = Point::new(-a.y.clone(), a.x.clone());
        let before_b = Point::new(b.y.clone(), -b.x.clone());
        [
            HalfPlane {
                offset: after_a.dot(centre),
                normal: after_a,
            },
            HalfPlane {
                offset: before_b.dot(centre),
                normal: before_b,
            },
            HalfPlane {
                offset: m.dot(centre) + radius * least,
                normal: m,
            },
        ]
    }

    /// How much the arc's cover can lose against the disc: radius·(1 − min(m·a, m·b)).
    pub fn loss(&self, radius: &Exact) -> Exact {
        let a = self.direction(&self.lo);
        let b = self.direction(&self.hi);
        let m = self.direction(&((&self.lo + &self.hi) / Exact::from(2)));
        let (ma, mb) = (m.dot(&a), m.dot(&b));
        radius * (Exact::ONE - if ma < mb { ma } else { mb })
    }
}

/// The exact cover of Lemma P3(3): every feasible x lies on the line p + w·d (a
/// fixed-direction obstacle from a start point), and the line meets the disc B̄(c, R) in the
/// interval w ∈ [w_c − h, w_c + h], w_c = d·(c − p), h = √(R² − dist(c, line)²). The two
/// half-planes d·(x − p) ≥ w_c + h′ and d·(x − p) ≤ w_c − h′ with a rational h′ ≤ h (h itself when it
/// is rational, else within 2⁻⁸⁰/den) hold every point of the line outside the disc. None: the line misses the open
/// disc, and the anchor constrains nothing on it.
pub fn line_sides(p: &Point, d: &Point, centre: &Point, radius: &Exact) -> Option<[HalfPlane; 2]> {
    let rel = centre - p;
    let w_c = d.dot(&rel);
    // d is a unit vector: the squared distance from c to the line is |rel|² − w_c².
    let inside = radius * radius - (rel.norm_squared() - &w_c * &w_c);
    if inside <= Exact::ZERO {
        return None;
    }
    // Exact when h is rational (a centre on the line: h = R), so that a start exactly on
    // the threshold is seen there, as the guard sees it.
    let h = sqrt_bounds(&inside).0;
    let base = d.dot(p);
    Some([
        HalfPlane {
            normal: d.clone(),
            offset: &base + &w_c + &h,
        },
        HalfPlane {
            normal: -d,
            offset: -(base + w_c - h),
        },
    ])
}

/// Half-planes that hold every centre *outside* the field of view of a robot at `centre`
/// heading along the unit `heading`, the view's half-angle α having cos α = `cos_half`
/// (Lemma P1(3), with P3's cover of a cone's outside). For α ≤ 90° the view contains the
/// cone of a rational half-angle α′ ≤ α (tan(α′/2) rounded down), whose outside is the two
/// half-planes beyond its rays; for α > 90° it contains the half-plane ahead, whose
/// outside is the one behind. Empty when the view is all round (cos α ≤ −1).
pub fn outside_view(centre: &Point, heading: &Point, cos_half: &Exact) -> Vec<HalfPlane> {
    let beyond = |normal: Point| HalfPlane {
        offset: normal.dot(centre),
        normal,
    };
    if *cos_half <= -Exact::ONE {
        return Vec::new();
    }
    if *cos_half < Exact::ZERO {
        return vec![beyond(-heading)];
    }
    // tan²(α/2) = (1 − cos α)/(1 + cos α); a smaller tangent gives a narrower cone.
    let t2 = (Exact::ONE - cos_half) / (Exact::ONE + cos_half);
    let t = sqrt_bounds(&t2).0;
    let left = RationalDirection::from_half_angle_tangent(&t).rotate(heading);
    let right = RationalDirection::from_half_angle_tangent(&-t).rotate(heading);
    vec![
        // Beyond the left ray: its left normal; beyond the right ray: its right normal.
        beyond(Point::new(-left.y.clone(), left.x.clone())),
        beyond(Point::new(right.y.clone(), -right.x.clone())),
    ]
}

/// Half-planes that hold every centre outside the convex polygon `zone` (given in the
/// robot's frame: origin at its centre, x along its heading) shrunk by `inset` ≥ 0, for a
/// robot at `centre` heading along the unit `heading` (Lemma P1(5) and P3(1)): one per
/// edge, beyond the edge moved inwards by at least `inset` (its normal's length rounded
/// up, so the shrunk polygon is never larger than the exact inner parallel body).
pub fn outside_polygon(
    zone: &ConvexPolygon,
    inset: &Exact,
    centre: &Point,
    heading: &RationalDirection,
) -> Vec<HalfPlane> {
    super::leaf::region_half_planes(zone)
        .into_iter()
        .map(|inner| {
            let length = sqrt_bounds(&inner.normal.norm_squared()).1;
            let normal = heading.rotate(&inner.normal);
            let offset = inner.offset + inset * &length + normal.dot(centre);
            HalfPlane {
                normal: -&normal,
                offset: -offset,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every point outside the disc lies in the cover of some quarter, at every refinement,
    /// and a point strictly inside the disc by more than the loss lies in none: the cover
    /// is sound (Lemma P3) and its loss bound is right.
    /// The line's two sides hold every point of the line outside the disc and no point of
    /// the line deeper inside than 2⁻⁴⁰; a line that misses the disc gets no sides.
    #[test]
    fn line_sides_cover_the_line_outside_the_disc() {
        let p = Point::decimal(4.0, 1.0);
        let d = RationalDirection::from_half_angle_tangent(&crate::core::num::exact_decimal(3.0))
            .unit()
            .clone();
        let centre = Point::decimal(1.0, 2.0);
        let radius = crate::core::num::exact_decimal(1.5);
        let sides = line_sides(&p, &d, &centre, &radius).expect("the line meets the disc");
        let mut outside = 0;
        for i in -400..400 {
            let w = crate::core::num::exact_decimal(f64::from(i) / 50.0);
            let x = &p + &(&d * &w);
            let rel = &x - &centre;
            let covered = sides.iter().any(|h| h.contains(&x));
            if rel.norm_squared() > &radius * &radius {
                outside += 1;
                assert!(covered, "uncovered outside point at w = {i}/50");
            } else if rel.norm_squared() < (&radius - Exact::from(1) / Exact::from(1 << 20)).pow(2)
            {
                assert!(!covered, "covered inside point at w = {i}/50");
            }
        }
        assert!(outside > 100);
        let far = Point::decimal(1.0, 40.0);
        assert!(line_sides(&far, &Point::decimal(1.0, 0.0), &centre, &radius).is_none());
    }

    #[test]
    fn arcs_cover_the_outside_of_the_disc_and_no_more_than_the_loss() {
        let centre = Point::decimal(0.3, -0.7);
        let radius = crate::core::num::exact_decimal(1.25);
        let mut arcs = Arc::quarters();
        for _ in 0..3 {
            arcs = arcs.iter().flat_map(|a| a.halves()).collect();
        }
        let loss = arcs
            .iter()
            .map(|a| a.loss(&radius))
            .fold(Exact::ZERO, |m, l| if l > m { l } else { m });
        for i in 0..720 {
            let angle = (i as f64) * std::f64::consts::PI / 360.0;
            for scale in [1.0001, 1.3, 4.0] {
                let r = 1.25 * scale;
                let x = Point::decimal(0.3 + r * angle.cos(), -0.7 + r * angle.sin());
                let rel = &x - &centre;
                if rel.norm_squared() <= &radius * &radius {
                    continue; // the float placed it on the rim or inside
                }
                assert!(
                    arcs.iter().any(|a| a
                        .half_planes(&centre, &radius)
                        .iter()
                        .all(|h| h.contains(&x))),
                    "uncovered at angle {angle}, scale {scale}"
                );
            }
            let inner = 1.25 * 0.5;
            let x = Point::decimal(0.3 + inner * angle.cos(), -0.7 + inner * angle.sin());
            if Exact::from(1) - crate::core::num::exact_decimal(0.5) > &loss / &radius {
                assert!(
                    !arcs.iter().any(|a| a
                        .half_planes(&centre, &radius)
                        .iter()
                        .all(|h| h.contains(&x))),
                    "a point well inside is covered at angle {angle}"
                );
            }
        }
    }
}
