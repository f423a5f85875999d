//! The plane's exact geometry (docs/semantics.md §13; issue 36): points, convex polygons,
//! the robot's path, and directions as rational unit vectors.
//!
//! Every decision the plane's engines make — a guard on a seen centre, a collision inside a
//! step, whether a polygon is convex or a path crosses itself — is a sign of a polynomial in
//! rational coordinates, so it is made exactly here, as on the line. The one number the
//! plane adds that is not rational is a length: a segment from (0, 0) to (1, 1) is √2 long,
//! and a robot driving along it at a rational arc length sits at an irrational point. The
//! plane keeps "no engine needs a square root" ([`crate::core::num`]) by giving every
//! direction as a *rational unit vector* (x² + y² = 1 exactly, [`direction`]): they are dense
//! on the circle, so any heading is one within 10⁻⁹ rad, and the deviation is proved
//! exactly, not estimated.

pub mod direction;
pub mod path;
pub mod point;
pub mod polygon;
pub mod rational_path;
