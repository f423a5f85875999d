//! Convex polygons: a danger zone in the robot's frame (a Nav2 stop polygon) or the region an
//! obstacle is confined to (a sidewalk, a crossing). Validated once, exactly, so every later
//! "does the seen disc meet the zone" is a rational comparison.

use std::cmp::Ordering;
use std::fmt;

use super::point::{Point, orientation, segment_distance_squared};
use crate::core::num::Exact;

/// A strictly convex polygon, vertices counter-clockwise.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ConvexPolygon {
    vertices: Vec<Point>,
}

/// Why a list of vertices is not a strictly convex polygon, in the problem file's terms
/// (vertices numbered from 0 as written).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PolygonError {
    /// Fewer than three vertices.
    TooFewVertices(usize),
    /// Two consecutive vertices coincide: an edge of length 0.
    RepeatedVertex(usize),
    /// Three consecutive vertices on a line (the middle one, and its neighbours).
    Collinear(usize),
    /// The polygon turns both ways, or winds round more than once (a star): not convex.
    /// The vertex that lies on the wrong side of an edge, and the edge's first vertex.
    NotConvex {
        /// The offending vertex.
        vertex: usize,
        /// The first vertex of the edge it lies outside of.
        edge: usize,
    },
}

impl fmt::Display for PolygonError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PolygonError::TooFewVertices(n) => {
                write!(f, "a polygon needs at least 3 vertices, this one has {n}")
            }
            PolygonError::RepeatedVertex(i) => write!(
                f,
                "vertices {i} and {} coincide (an edge of length 0)",
                i + 1
            ),
            PolygonError::Collinear(i) => write!(
                f,
                "vertex {i} lies on the line through its neighbours (drop it)"
            ),
            PolygonError::NotConvex { vertex, edge } => write!(
                f,
                "the polygon is not convex: vertex {vertex} lies outside the edge from vertex {edge}"
            ),
        }
    }
}

impl std::error::Error for PolygonError {}

impl ConvexPolygon {
    /// The polygon with these vertices, in either orientation (stored counter-clockwise),
    /// if it is strictly convex: every vertex strictly inside the half-plane of every edge it
    /// is not on. That rules out reflex vertices and stars (which turn one way throughout
    /// yet wind twice) alike.
    pub fn new(vertices: Vec<Point>) -> Result<Self, PolygonError> {
        let n = vertices.len();
        if n < 3 {
            return Err(PolygonError::TooFewVertices(n));
        }
        for i in 0..n {
            if vertices[i] == vertices[(i + 1) % n] {
                return Err(PolygonError::RepeatedVertex(i));
            }
        }
        for i in 0..n {
            let (prev, next) = (&vertices[(i + n - 1) % n], &vertices[(i + 1) % n]);
            if orientation(prev, &vertices[i], next) == Ordering::Equal {
                return Err(PolygonError::Collinear(i));
            }
        }
        // The first corner's turn fixes the orientation the rest must share.
        let turn = orientation(&vertices[n - 1], &vertices[0], &vertices[1]);
        for e in 0..n {
            let (a, b) = (&vertices[e], &vertices[(e + 1) % n]);
            for (v, p) in vertices.iter().enumerate() {
                if v != e && v != (e + 1) % n && orientation(a, b, p) != turn {
                    return Err(PolygonError::NotConvex { vertex: v, edge: e });
                }
            }
        }
        let mut vertices = vertices;
        if turn == Ordering::Less {
            vertices.reverse();
        }
        Ok(ConvexPolygon { vertices })
    }

    /// The vertices, counter-clockwise.
    pub fn vertices(&self) -> &[Point] {
        &self.vertices
    }

    /// The polygon's edges as (start, end), counter-clockwise.
    fn edges(&self) -> impl Iterator<Item = (&Point, &Point)> {
        let n = self.vertices.len();
        (0..n).map(move |i| (&self.vertices[i], &self.vertices[(i + 1) % n]))
    }

    /// Whether `p` lies in the closed polygon (on its boundary counts).
    pub fn contains(&self, p: &Point) -> bool {
        self.edges()
            .all(|(a, b)| orientation(a, b, p) != Ordering::Less)
    }

    /// The squared distance from `p` to the closed polygon: 0 inside, else the least
    /// squared distance to an edge. Exact: a disc of radius r centred at p meets the
    /// polygon iff this is ≤ r².
    pub fn distance_squared(&self, p: &Point) -> Exact {
        if self.contains(p) {
            return Exact::ZERO;
        }
        self.edges()
            .map(|(a, b)| segment_distance_squared(p, a, b))
            .min()
            .expect("at least three edges")
    }

    /// Whether the closed disc of radius `r` (≥ 0) about `centre` meets the polygon.
    pub fn meets_disc(&self, centre: &Point, r: &Exact) -> bool {
        self.distance_squared(centre) <= r * r
    }
}
