//! The robot's path: a polyline from the origin (the robot's start; its first segment is
//! the robot's initial heading, in any direction: docs/semantics.md §13.1), with no segment
//! of length 0 and no point visited twice. Validated exactly on the decimals a problem file gives.

use std::cmp::Ordering;
use std::fmt;

use super::point::{Point, orientation, segments_meet};
use crate::core::num::Exact;

/// A validated path: vertices from (0, 0), simple.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Path {
    vertices: Vec<Point>,
}

/// Why a list of vertices is not a path, in the problem file's terms (vertices and
/// segments numbered from 0 as written; segment i runs from vertex i to vertex i + 1).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PathError {
    /// Fewer than two vertices.
    TooFewVertices(usize),
    /// The first vertex is not (0, 0).
    NotFromOrigin,
    /// A segment of length 0.
    ZeroLength(usize),
    /// A segment doubles back along the one before it.
    Reverses(usize),
    /// Two segments that are not neighbours meet: the path crosses or touches itself.
    Crosses(usize, usize),
}

impl fmt::Display for PathError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PathError::TooFewVertices(n) => {
                write!(f, "a path needs at least 2 vertices, this one has {n}")
            }
            PathError::NotFromOrigin => {
                write!(f, "the path must start at [0, 0], the robot's start")
            }
            PathError::ZeroLength(i) => {
                write!(f, "segment {i} (vertices {i} and {}) has length 0", i + 1)
            }
            PathError::Reverses(i) => write!(f, "segment {i} doubles back along segment {}", i - 1),
            PathError::Crosses(i, j) => write!(f, "segments {i} and {j} cross or touch"),
        }
    }
}

impl std::error::Error for PathError {}

impl Path {
    /// The path through these vertices, if it is one (module docs).
    pub fn new(vertices: Vec<Point>) -> Result<Self, PathError> {
        let n = vertices.len();
        if n < 2 {
            return Err(PathError::TooFewVertices(n));
        }
        if vertices[0] != Point::origin() {
            return Err(PathError::NotFromOrigin);
        }
        let seg = |i: usize| (&vertices[i], &vertices[i + 1]);
        for i in 0..n - 1 {
            if vertices[i] == vertices[i + 1] {
                return Err(PathError::ZeroLength(i));
            }
        }
        for i in 1..n - 1 {
            // Neighbours share a vertex; they overlap beyond it only by doubling back.
            let (a, b) = seg(i - 1);
            let c = &vertices[i + 1];
            if orientation(a, b, c) == Ordering::Equal && (b - a).dot(&(c - b)) < Exact::ZERO {
                return Err(PathError::Reverses(i));
            }
        }
        for i in 0..n - 1 {
            for j in i + 2..n - 1 {
                let ((a, b), (c, d)) = (seg(i), seg(j));
                if segments_meet(a, b, c, d) {
                    return Err(PathError::Crosses(i, j));
                }
            }
        }
        Ok(Path { vertices })
    }

    /// The vertices, from the origin.
    pub fn vertices(&self) -> &[Point] {
        &self.vertices
    }

    /// The segments as (start, end), in order.
    pub fn segments(&self) -> impl Iterator<Item = (&Point, &Point)> {
        self.vertices.windows(2).map(|w| (&w[0], &w[1]))
    }
}
