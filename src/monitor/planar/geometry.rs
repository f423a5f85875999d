//! The planar monitor's geometry in floats: where on its path the robot is, how far a point
//! is from a convex polygon or a box. The certificate's decisions are exact; the monitor's
//! are comparisons of measured numbers, each widened by its rounding (see `mod.rs`).

/// A point or vector (m, or m/s).
pub(super) type Xy = (f64, f64);

pub(super) fn sub(a: Xy, b: Xy) -> Xy {
    (a.0 - b.0, a.1 - b.1)
}

pub(super) fn dot(a: Xy, b: Xy) -> f64 {
    a.0 * b.0 + a.1 * b.1
}

pub(super) fn norm(a: Xy) -> f64 {
    a.0.hypot(a.1)
}

/// One segment of the path: start, unit direction, length (∞: the last segment of a path
/// that runs on) and the arc length at its start.
#[derive(Clone, Debug)]
struct Segment {
    start: Xy,
    unit: Xy,
    length: f64,
    arc: f64,
}

/// The certified (analysed) path as floats.
#[derive(Clone, Debug)]
pub(super) struct FloatPath {
    segments: Vec<Segment>,
    /// Its length (∞ when its last segment runs on; one that ends is still located on
    /// beyond its end).
    pub(super) length: f64,
}

/// Where a point is relative to the path: the arc length of its nearest path point, how far
/// it is from it, and the path's heading there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct OnPath {
    pub(super) arc: f64,
    pub(super) distance: f64,
    pub(super) heading: Xy,
}

impl FloatPath {
    /// The path of `segments` (start, unit direction, length, arc at start); `ends`: its last
    /// segment ends (else it runs on).
    pub(super) fn new(segments: impl Iterator<Item = (Xy, Xy, f64, f64)>, ends: bool) -> Self {
        let mut segments: Vec<Segment> = segments
            .map(|(start, unit, length, arc)| Segment {
                start,
                unit,
                length,
                arc,
            })
            .collect();
        let length = match segments.last_mut() {
            Some(last) => {
                let end = if ends {
                    last.arc + last.length
                } else {
                    f64::INFINITY
                };
                // A robot that overshoots its destination goes on along the last segment, as
                // the model's does (its guard fires at step starts only).
                last.length = f64::INFINITY;
                end
            }
            None => 0.0,
        };
        FloatPath { segments, length }
    }

    /// The nearest path point to `p`; among points (nearly) as near, the one whose arc is
    /// nearest `near` (the robot's arc at the previous instant: a path that comes back near
    /// itself is followed, not jumped).
    pub(super) fn locate(&self, p: Xy, near: f64) -> OnPath {
        let mut best: Option<OnPath> = None;
        for s in &self.segments {
            let along = dot(sub(p, s.start), s.unit).clamp(0.0, s.length);
            let q = (s.start.0 + along * s.unit.0, s.start.1 + along * s.unit.1);
            let here = OnPath {
                arc: s.arc + along,
                distance: norm(sub(p, q)),
                heading: s.unit,
            };
            best = Some(match best {
                None => here,
                Some(b) => {
                    let tie = 1e-9 * (1.0 + b.distance.max(here.distance));
                    if here.distance < b.distance - tie
                        || (here.distance <= b.distance + tie
                            && (here.arc - near).abs() < (b.arc - near).abs())
                    {
                        here
                    } else {
                        b
                    }
                }
            });
        }
        best.unwrap_or(OnPath {
            arc: 0.0,
            distance: norm(p),
            heading: (1.0, 0.0),
        })
    }
}

/// The distance from `p` to the convex polygon `vertices` (counter-clockwise or clockwise;
/// 0 inside).
pub(super) fn polygon_distance(vertices: &[Xy], p: Xy) -> f64 {
    let n = vertices.len();
    if n == 0 {
        return f64::INFINITY;
    }
    let mut inside = true;
    let mut sign = 0.0;
    let mut least = f64::INFINITY;
    for i in 0..n {
        let (a, b) = (vertices[i], vertices[(i + 1) % n]);
        let edge = sub(b, a);
        let cross = edge.0 * (p.1 - a.1) - edge.1 * (p.0 - a.0);
        if cross != 0.0 {
            if sign == 0.0 {
                sign = cross.signum();
            } else if cross.signum() != sign {
                inside = false;
            }
        }
        let l2 = dot(edge, edge);
        let t = if l2 > 0.0 {
            (dot(sub(p, a), edge) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = (a.0 + t * edge.0, a.1 + t * edge.1);
        least = least.min(norm(sub(p, q)));
    }
    if inside && n >= 3 { 0.0 } else { least }
}

/// The distance from `p` to the axis-parallel box [min, max] (0 inside).
pub(super) fn box_distance(min: Xy, max: Xy, p: Xy) -> f64 {
    let dx = (min.0 - p.0).max(p.0 - max.0).max(0.0);
    let dy = (min.1 - p.1).max(p.1 - max.1).max(0.0);
    dx.hypot(dy)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_measures_inside_as_zero_and_outside_to_its_nearest_edge_or_corner() {
        let square = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)];
        assert_eq!(polygon_distance(&square, (1.0, 1.0)), 0.0);
        assert_eq!(polygon_distance(&square, (3.0, 1.0)), 1.0);
        assert!((polygon_distance(&square, (3.0, 3.0)) - 2f64.sqrt()).abs() < 1e-15);
        let clockwise: Vec<Xy> = square.iter().rev().copied().collect();
        assert_eq!(polygon_distance(&clockwise, (1.0, 1.0)), 0.0);
        assert_eq!(polygon_distance(&clockwise, (1.0, -0.5)), 0.5);
    }

    #[test]
    fn a_box_measures_like_the_square_it_is() {
        assert_eq!(box_distance((0.0, 0.0), (2.0, 2.0), (1.0, 1.0)), 0.0);
        assert_eq!(box_distance((0.0, 0.0), (2.0, 2.0), (1.0, 5.0)), 3.0);
        assert_eq!(box_distance((1.0, 1.0), (1.0, 1.0), (4.0, 5.0)), 5.0);
    }

    #[test]
    fn the_robot_is_located_by_arc_and_a_path_that_returns_is_followed() {
        // Out along x to 4, up 1, back along x to 0: the two long legs are 1 m apart.
        let path = FloatPath::new(
            [
                ((0.0, 0.0), (1.0, 0.0), 4.0, 0.0),
                ((4.0, 0.0), (0.0, 1.0), 1.0, 4.0),
                ((4.0, 1.0), (-1.0, 0.0), 4.0, 5.0),
            ]
            .into_iter(),
            true,
        );
        assert_eq!(path.length, 9.0);
        let out = path.locate((2.0, 0.25), 2.0);
        assert_eq!((out.arc, out.distance), (2.0, 0.25));
        let back = path.locate((2.0, 0.75), 7.0);
        assert_eq!((back.arc, back.distance), (7.0, 0.25));
        // Halfway between the legs, the previous arc decides.
        assert_eq!(path.locate((2.0, 0.5), 1.5).arc, 2.0);
        assert_eq!(path.locate((2.0, 0.5), 6.5).arc, 7.0);
        let on = FloatPath::new([((0.0, 0.0), (1.0, 0.0), 1.0, 0.0)].into_iter(), false);
        assert_eq!(on.locate((10.0, 0.0), 0.0).arc, 10.0);
    }
}
