//! Exact points and vectors of the plane, and the orientation test every other shape is
//! built on.

use std::cmp::Ordering;
use std::ops::{Add, Mul, Neg, Sub};

use crate::core::num::{Exact, exact_decimal};

/// A point (or a vector) with exact rational coordinates, in metres.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Point {
    /// x: along the robot's initial heading.
    pub x: Exact,
    /// y: to the robot's left.
    pub y: Exact,
}

impl Point {
    /// The point with these coordinates.
    pub fn new(x: Exact, y: Exact) -> Self {
        Point { x, y }
    }

    /// The point a problem file's decimals denote (`0.1` is one tenth; see
    /// [`exact_decimal`]). The caller has checked that both are finite.
    pub fn decimal(x: f64, y: f64) -> Self {
        Point::new(exact_decimal(x), exact_decimal(y))
    }

    /// The origin.
    pub fn origin() -> Self {
        Point::new(Exact::ZERO, Exact::ZERO)
    }

    /// The dot product of two vectors.
    pub fn dot(&self, other: &Point) -> Exact {
        &self.x * &other.x + &self.y * &other.y
    }

    /// The cross product (the z component): positive when `other` lies to the left of
    /// `self`.
    pub fn cross(&self, other: &Point) -> Exact {
        &self.x * &other.y - &self.y * &other.x
    }

    /// The squared length of a vector (rational, unlike its length).
    pub fn norm_squared(&self) -> Exact {
        self.dot(self)
    }

    /// The squared distance between two points.
    pub fn distance_squared(&self, other: &Point) -> Exact {
        (other - self).norm_squared()
    }

    /// The coordinates as floats (for messages and plots; no decision uses them).
    pub fn to_f64(&self) -> (f64, f64) {
        (self.x.to_f64().value(), self.y.to_f64().value())
    }
}

impl Add for &Point {
    type Output = Point;
    fn add(self, other: &Point) -> Point {
        Point::new(&self.x + &other.x, &self.y + &other.y)
    }
}

impl Sub for &Point {
    type Output = Point;
    fn sub(self, other: &Point) -> Point {
        Point::new(&self.x - &other.x, &self.y - &other.y)
    }
}

impl Mul<&Exact> for &Point {
    type Output = Point;
    fn mul(self, k: &Exact) -> Point {
        Point::new(&self.x * k, &self.y * k)
    }
}

impl Neg for &Point {
    type Output = Point;
    fn neg(self) -> Point {
        Point::new(-&self.x, -&self.y)
    }
}

/// Which way the path a → b → c turns: `Greater` left (counter-clockwise), `Less` right,
/// `Equal` when the three points are collinear. Exact: the sign of a 2×2 determinant.
pub fn orientation(a: &Point, b: &Point, c: &Point) -> Ordering {
    (b - a).cross(&(c - a)).cmp(&Exact::ZERO)
}

/// Whether the closed segments [a, b] and [c, d] have a point in common (touching at an end
/// or overlapping along a line counts). The textbook test: they cross properly when each
/// segment's ends lie strictly on opposite sides of the other's line; otherwise they meet
/// only where an end lies on the other segment.
pub fn segments_meet(a: &Point, b: &Point, c: &Point, d: &Point) -> bool {
    let (o1, o2) = (orientation(a, b, c), orientation(a, b, d));
    let (o3, o4) = (orientation(c, d, a), orientation(c, d, b));
    if o1 != o2 && o3 != o4 && [o1, o2, o3, o4].iter().all(|o| *o != Ordering::Equal) {
        return true;
    }
    (o1 == Ordering::Equal && within_box(c, a, b))
        || (o2 == Ordering::Equal && within_box(d, a, b))
        || (o3 == Ordering::Equal && within_box(a, c, d))
        || (o4 == Ordering::Equal && within_box(b, c, d))
}

/// Whether `p`, known to be collinear with a and b, lies on the closed segment [a, b].
fn within_box(p: &Point, a: &Point, b: &Point) -> bool {
    let between = |v: &Exact, s: &Exact, t: &Exact| (s <= v && v <= t) || (t <= v && v <= s);
    between(&p.x, &a.x, &b.x) && between(&p.y, &a.y, &b.y)
}

/// The squared distance from `p` to the closed segment [a, b] (a = b allowed), exactly:
/// the nearest point's parameter (p − a)·(b − a)/|b − a|² is rational.
pub fn segment_distance_squared(p: &Point, a: &Point, b: &Point) -> Exact {
    let ab = b - a;
    let len2 = ab.norm_squared();
    if len2 == Exact::ZERO {
        return p.distance_squared(a);
    }
    let t = (p - a).dot(&ab) / &len2;
    let t = if t < Exact::ZERO {
        Exact::ZERO
    } else if t > Exact::ONE {
        Exact::ONE
    } else {
        t
    };
    p.distance_squared(&(a + &(&ab * &t)))
}
