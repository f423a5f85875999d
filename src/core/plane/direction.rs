//! Directions as rational unit vectors, so that a robot at a rational arc length along a
//! segment, an obstacle moving at a rational speed in a fixed direction, and a rotated
//! problem all stay at rational points.
//!
//! Every rational point on the unit circle is ((1 − t²)/(1 + t²), 2t/(1 + t²)) for a rational
//! t = tan(θ/2) (or (−1, 0)), and those points are dense. [`RationalDirection::near`] picks t
//! as a dyadic rational close to the direction's half-angle tangent, then *proves* the
//! result within the asked chord distance δ of the exact direction, in rationals:
//! |u − d/|d||² = 2 − 2·(u·d)/|d| ≤ δ² ⟺ u·d ≥ 0 and (u·d)² ≥ |d|²·(1 − δ²/2)² (for δ ≤ √2).
//! The float only proposes; the check decides, and t is refined until it holds.

use std::fmt;

use dashu_int::ops::{SquareRoot, UnsignedAbs};

use super::point::Point;
use crate::core::num::{Exact, exact_float};

/// A unit vector with rational coordinates: x² + y² = 1 exactly.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RationalDirection {
    unit: Point,
}

/// Why no direction could be given.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum DirectionError {
    /// The vector (0, 0) has no direction.
    Zero,
    /// The asked tolerance is not in (0, 1].
    Tolerance,
}

impl fmt::Display for DirectionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DirectionError::Zero => write!(f, "the vector (0, 0) has no direction"),
            DirectionError::Tolerance => write!(f, "a direction's tolerance must be in (0, 1]"),
        }
    }
}

impl std::error::Error for DirectionError {}

impl RationalDirection {
    /// The unit vector with half-angle tangent `t`: ((1 − t²)/(1 + t²), 2t/(1 + t²)).
    pub fn from_half_angle_tangent(t: &Exact) -> Self {
        let t2 = t * t;
        let den = &t2 + Exact::ONE;
        RationalDirection {
            unit: Point::new((Exact::ONE - &t2) / &den, (t * Exact::from(2)) / den),
        }
    }

    /// A rational unit vector within chord distance `delta` (0 < δ ≤ 1; 10⁻⁹ m per metre is
    /// 10⁻⁹ rad) of the direction of `d`, proved exactly (module docs). Axis directions and
    /// directions that are already rational unit vectors up to scale, such as (3, 4), are
    /// found exactly.
    pub fn near(d: &Point, delta: &Exact) -> Result<Self, DirectionError> {
        if d.x == Exact::ZERO && d.y == Exact::ZERO {
            return Err(DirectionError::Zero);
        }
        if *delta <= Exact::ZERO || *delta > Exact::ONE {
            return Err(DirectionError::Tolerance);
        }
        // Work with x ≥ 0 (half-angle tangent in [−1, 1]) and turn the result back.
        if d.x < Exact::ZERO {
            return Self::near(&-d, delta).map(|u| RationalDirection { unit: -&u.unit });
        }
        // t = y / (|d| + x) exactly when |d| is rational: try that first.
        let n2 = d.norm_squared();
        if let Some(n) = rational_sqrt(&n2) {
            return Ok(Self::from_half_angle_tangent(&(&d.y / (n + &d.x))));
        }
        let (x, y) = d.to_f64();
        let t = y / (x.hypot(y) + x);
        let bound = Exact::ONE - delta * delta / Exact::from(2);
        let bound2 = &n2 * &bound * &bound;
        for bits in (16..=62).step_by(2) {
            let scale = (1u64 << bits) as f64;
            let candidate =
                Self::from_half_angle_tangent(&exact_float((t * scale).round() / scale));
            let along = candidate.unit.dot(d);
            if along >= Exact::ZERO && &along * &along >= bound2 {
                return Ok(candidate);
            }
        }
        // The float proposal is off by more than 2⁻⁶⁰: only a tolerance below what f64 can
        // see (≈ 10⁻¹⁵) ends here, and asking for it is the caller's error.
        Err(DirectionError::Tolerance)
    }

    /// The unit vector.
    pub fn unit(&self) -> &Point {
        &self.unit
    }

    /// `p` rotated by this direction's angle about the origin (exact: a rotation matrix with
    /// rational entries).
    pub fn rotate(&self, p: &Point) -> Point {
        let (c, s) = (&self.unit.x, &self.unit.y);
        Point::new(c * &p.x - s * &p.y, s * &p.x + c * &p.y)
    }
}

/// The rational square root of `r`, if it has one.
pub(crate) fn rational_sqrt(r: &Exact) -> Option<Exact> {
    if *r < Exact::ZERO {
        return None;
    }
    let root = |n: &dashu_int::UBig| {
        let s = n.sqrt();
        (&s * &s == *n).then_some(s)
    };
    let (num, den) = (r.numerator().unsigned_abs(), r.denominator().clone());
    Some(Exact::from_parts(root(&num)?.into(), root(&den)?))
}

/// Rationals lo ≤ √x ≤ hi for x ≥ 0, equal when x is a rational square, else 2⁻⁸⁰/den
/// apart: √(n/d) = √(n·d·4⁸⁰)/(d·2⁸⁰), with the integer square root taken down and up.
pub(crate) fn sqrt_bounds(x: &Exact) -> (Exact, Exact) {
    if let Some(root) = rational_sqrt(x) {
        return (root.clone(), root);
    }
    let (n, d) = (x.numerator().unsigned_abs(), x.denominator().clone());
    let scaled = (&n * &d) << 160;
    let s = scaled.sqrt();
    let den = &d << 80;
    (
        Exact::from_parts(s.clone().into(), den.clone()),
        Exact::from_parts((s + 1u8).into(), den),
    )
}
