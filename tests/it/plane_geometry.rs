//! The plane's exact geometry (issue 36, docs/semantics.md §13) against independent answers:
//! segment meeting against an exact parametric solve, convexity against Andrew's monotone
//! chain, containment against triangle areas, distances against the closed form of a
//! rotated box, rational directions against `atan2`.

use dashu_ratio::RBig;
use safereach::core::num::Exact;
use safereach::core::plane::direction::{DirectionError, RationalDirection};
use safereach::core::plane::path::{Path, PathError};
use safereach::core::plane::point::{Point, segments_meet};
use safereach::core::plane::polygon::{ConvexPolygon, PolygonError};

/// The cases' generator (with `int` and `rational` from `common::rational_draws`).
use crate::common::split_mix::SplitMix as Rng;

fn p(x: i64, y: i64) -> Point {
    Point::new(Exact::from(x), Exact::from(y))
}

fn q(num: i64, den: i64) -> Exact {
    RBig::from(num) / RBig::from(den)
}

/// Whether the closed segments meet, by solving a + s·(b − a) = c + t·(d − c) exactly
/// (Cramer's rule) or, when parallel, comparing their extents on the common line.
fn segments_meet_by_solving(a: &Point, b: &Point, c: &Point, d: &Point) -> bool {
    let (r, s) = (b - a, d - c);
    let ac = c - a;
    let det = r.cross(&s);
    let unit = |x: &Exact| *x >= Exact::ZERO && *x <= Exact::ONE;
    if det != Exact::ZERO {
        let t_ab = ac.cross(&s) / &det;
        let t_cd = ac.cross(&r) / &det;
        return unit(&t_ab) && unit(&t_cd);
    }
    if ac.cross(&r) != Exact::ZERO {
        return false; // parallel, not on one line
    }
    // One line: the parameters of c and d along a→b (a point segment a = b handled too).
    let len2 = r.norm_squared();
    if len2 == Exact::ZERO {
        let t = |x: &Point| (x - c).dot(&s);
        let l2 = s.norm_squared();
        let ta = t(a);
        if (a - c).cross(&s) != Exact::ZERO {
            return false; // a point off the other segment's line
        }
        return if l2 == Exact::ZERO {
            a == c
        } else {
            ta >= Exact::ZERO && ta <= l2
        };
    }
    let t = |x: &Point| (x - a).dot(&r) / &len2;
    let (tc, td) = (t(c), t(d));
    let (lo, hi) = if tc <= td { (tc, td) } else { (td, tc) };
    hi >= Exact::ZERO && lo <= Exact::ONE
}

#[test]
fn segments_meet_exactly_where_the_parametric_solve_says() {
    let mut rng = Rng(36);
    let mut met = 0;
    for case in 0..4000 {
        // Small lattices make touching, collinear and overlapping cases common.
        let lim = if case % 2 == 0 { 3 } else { 50 };
        let mut pt = || {
            Point::new(
                Exact::from(rng.int(-lim, lim)),
                Exact::from(rng.int(-lim, lim)),
            )
        };
        let (a, b, c, d) = (pt(), pt(), pt(), pt());
        let expected = segments_meet_by_solving(&a, &b, &c, &d);
        assert_eq!(
            segments_meet(&a, &b, &c, &d),
            expected,
            "{a:?} {b:?} {c:?} {d:?}"
        );
        assert_eq!(segments_meet(&c, &d, &a, &b), expected, "symmetric");
        met += usize::from(expected);
    }
    assert!(
        met > 400 && met < 3600,
        "both answers well represented: {met}"
    );
    // The cases a scan of random lattices might miss, stated by hand.
    assert!(
        segments_meet(&p(0, 0), &p(2, 0), &p(2, 0), &p(3, 5)),
        "touching at an end"
    );
    assert!(segments_meet(&p(0, 0), &p(4, 0), &p(2, 0), &p(2, 3)), "a T");
    assert!(
        segments_meet(&p(0, 0), &p(4, 0), &p(3, 0), &p(6, 0)),
        "collinear overlap"
    );
    assert!(
        !segments_meet(&p(0, 0), &p(2, 0), &p(3, 0), &p(6, 0)),
        "collinear apart"
    );
    assert!(
        !segments_meet(&p(0, 0), &p(2, 0), &p(0, 1), &p(2, 1)),
        "parallel"
    );
}

/// The convex hull by Andrew's monotone chain, counter-clockwise, collinear points dropped.
fn hull(mut pts: Vec<Point>) -> Vec<Point> {
    pts.sort_by(|a, b| a.x.cmp(&b.x).then(a.y.cmp(&b.y)));
    pts.dedup();
    let turn = |o: &Point, a: &Point, b: &Point| (a - o).cross(&(b - o));
    let mut lower: Vec<Point> = Vec::new();
    for x in &pts {
        while lower.len() >= 2
            && turn(&lower[lower.len() - 2], &lower[lower.len() - 1], x) <= Exact::ZERO
        {
            lower.pop();
        }
        lower.push(x.clone());
    }
    let mut upper: Vec<Point> = Vec::new();
    for x in pts.iter().rev() {
        while upper.len() >= 2
            && turn(&upper[upper.len() - 2], &upper[upper.len() - 1], x) <= Exact::ZERO
        {
            upper.pop();
        }
        upper.push(x.clone());
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// Twice the signed area (shoelace).
fn twice_area(vs: &[Point]) -> Exact {
    (0..vs.len())
        .map(|i| vs[i].cross(&vs[(i + 1) % vs.len()]))
        .fold(Exact::ZERO, |s, t| s + t)
}

#[test]
fn polygons_are_convex_exactly_when_they_are_their_hull_in_order() {
    let mut rng = Rng(7);
    let (mut accepted, mut rejected) = (0, 0);
    for _ in 0..600 {
        let n = rng.int(3, 9) as usize;
        let pts: Vec<Point> = (0..n)
            .map(|_| Point::new(rng.rational(4), rng.rational(4)))
            .collect();
        let h = hull(pts);
        if h.len() < 3 {
            continue;
        }
        // The hull in order, either way round and from any vertex, is convex.
        let start = rng.int(0, h.len() as i64 - 1) as usize;
        let mut ordered: Vec<Point> = h[start..].iter().chain(&h[..start]).cloned().collect();
        if rng.int(0, 1) == 1 {
            ordered.reverse();
        }
        let poly = ConvexPolygon::new(ordered.clone()).expect("a hull in order is convex");
        assert!(
            twice_area(poly.vertices()) > Exact::ZERO,
            "stored counter-clockwise"
        );
        accepted += 1;
        // Any other cyclic order of points in convex position is no convex polygon: swapping
        // the first two vertices makes vertex 0 the neighbour of vertex 2, which the hull
        // has apart once there are four.
        if h.len() >= 4 {
            let mut swapped = ordered.clone();
            swapped.swap(0, 1);
            assert!(
                matches!(
                    ConvexPolygon::new(swapped),
                    Err(PolygonError::NotConvex { .. })
                ),
                "a crossed quadrilateral or worse"
            );
            rejected += 1;
        }
        // A point strictly inside added as a vertex makes a reflex corner.
        let centroid = &h.iter().fold(Point::origin(), |s, v| &s + v) * &q(1, h.len() as i64);
        let mut dented = ordered.clone();
        dented.insert(1, centroid);
        assert!(ConvexPolygon::new(dented).is_err(), "a dent is not convex");
    }
    assert!(accepted > 400 && rejected > 200, "{accepted} {rejected}");
    // A pentagram turns the same way at every corner and still is no convex polygon.
    let star = vec![p(0, 10), p(6, -8), p(-10, 3), p(10, 3), p(-6, -8)];
    assert!(matches!(
        ConvexPolygon::new(star),
        Err(PolygonError::NotConvex { .. })
    ));
    assert_eq!(
        ConvexPolygon::new(vec![p(0, 0), p(1, 0)]),
        Err(PolygonError::TooFewVertices(2))
    );
    assert_eq!(
        ConvexPolygon::new(vec![p(0, 0), p(1, 0), p(1, 0), p(0, 1)]),
        Err(PolygonError::RepeatedVertex(1))
    );
    assert_eq!(
        ConvexPolygon::new(vec![p(0, 0), p(1, 0), p(2, 0), p(0, 1)]),
        Err(PolygonError::Collinear(1))
    );
}

#[test]
fn containment_is_the_triangle_fan_covering_the_area() {
    let mut rng = Rng(11);
    let mut inside = 0;
    for _ in 0..300 {
        let pts: Vec<Point> = (0..7)
            .map(|_| Point::new(rng.rational(3), rng.rational(3)))
            .collect();
        let h = hull(pts);
        if h.len() < 3 {
            continue;
        }
        let poly = ConvexPolygon::new(h.clone()).expect("convex");
        let area = twice_area(&h);
        for _ in 0..20 {
            let x = Point::new(rng.rational(4), rng.rational(4));
            // x is in the closed polygon iff the triangles x, v_i, v_{i+1} tile it exactly.
            let fan: Exact = (0..h.len())
                .map(|i| {
                    let t = (&h[i] - &x).cross(&(&h[(i + 1) % h.len()] - &x));
                    if t < Exact::ZERO { -t } else { t }
                })
                .fold(Exact::ZERO, |s, t| s + t);
            assert_eq!(poly.contains(&x), fan == area, "{x:?}");
            assert_eq!(poly.distance_squared(&x) == Exact::ZERO, fan == area);
            inside += usize::from(fan == area);
        }
    }
    assert!(inside > 100, "{inside}");
}

#[test]
fn distances_to_a_rotated_box_are_its_closed_form() {
    // The box [−a, a] × [−c, c] rotated by rational unit vectors: in the box's own frame the
    // distance is the closed form |(max(0, |x| − a), max(0, |y| − c))|².
    let mut rng = Rng(5);
    let (a, c) = (q(3, 2), q(1, 2));
    let corners = [(1, 1), (-1, 1), (-1, -1), (1, -1)];
    for (tn, td) in [(0, 1), (1, 2), (1, 3), (-2, 7), (5, 3)] {
        let turn = RationalDirection::from_half_angle_tangent(&q(tn, td));
        let boxed: Vec<Point> = corners
            .iter()
            .map(|&(sx, sy)| turn.rotate(&Point::new(&a * Exact::from(sx), &c * Exact::from(sy))))
            .collect();
        let poly = ConvexPolygon::new(boxed).expect("a rotated box is convex");
        for _ in 0..200 {
            let local = Point::new(rng.rational(4), rng.rational(4));
            let out = |v: &Exact, half: &Exact| {
                let m = if *v < Exact::ZERO {
                    -v.clone()
                } else {
                    v.clone()
                } - half;
                if m > Exact::ZERO { m } else { Exact::ZERO }
            };
            let (dx, dy) = (out(&local.x, &a), out(&local.y, &c));
            let expected = &dx * &dx + &dy * &dy;
            let world = turn.rotate(&local);
            assert_eq!(
                poly.distance_squared(&world),
                expected,
                "{local:?} turned by {tn}/{td}"
            );
            assert_eq!(poly.meets_disc(&world, &q(1, 4)), expected <= q(1, 16));
        }
    }
}

#[test]
fn rational_directions_are_unit_vectors_within_the_proved_tolerance() {
    let mut rng = Rng(3);
    let delta = q(1, 1_000_000_000);
    for case in 0..2000 {
        let d = if case < 8 {
            [
                p(1, 0),
                p(0, 1),
                p(-1, 0),
                p(0, -1),
                p(3, 4),
                p(-5, -12),
                p(1, 1),
                p(-7, 2),
            ][case]
                .clone()
        } else {
            Point::new(rng.rational(20), rng.rational(20))
        };
        if d == Point::origin() {
            assert_eq!(
                RationalDirection::near(&d, &delta),
                Err(DirectionError::Zero)
            );
            continue;
        }
        let u = RationalDirection::near(&d, &delta).expect("a direction");
        assert_eq!(u.unit().norm_squared(), Exact::ONE, "exactly a unit vector");
        // Independent: the angle between them by atan2 in floats.
        let (dx, dy) = d.to_f64();
        let (ux, uy) = u.unit().to_f64();
        let mut gap = (uy.atan2(ux) - dy.atan2(dx)).abs();
        if gap > std::f64::consts::PI {
            gap = 2.0 * std::f64::consts::PI - gap;
        }
        assert!(gap <= 1e-9 * (1.0 + 1e-6) + 1e-15, "{d:?}: {gap}");
        // Directions with a rational length come out exact: u·|d| = d.
        let length = [1, 1, 1, 1, 5, 13].get(case).map(|&n| Exact::from(n));
        if let Some(n) = length {
            assert_eq!(u.unit() * &n, d, "exactly the direction of {d:?}");
        }
    }
    assert_eq!(
        RationalDirection::near(&p(1, 1), &Exact::ZERO),
        Err(DirectionError::Tolerance)
    );
}

#[test]
fn rotations_by_rational_directions_keep_lengths_and_compose() {
    let mut rng = Rng(9);
    for _ in 0..300 {
        let (s, t) = (rng.rational(5), rng.rational(5));
        let (u, v) = (
            RationalDirection::from_half_angle_tangent(&s),
            RationalDirection::from_half_angle_tangent(&t),
        );
        let x = Point::new(rng.rational(9), rng.rational(9));
        assert_eq!(u.rotate(&x).norm_squared(), x.norm_squared());
        assert_eq!(&u.rotate(&p(1, 0)), u.unit());
        // Rotating by u then v is rotating by v's rotation of u.
        let uv = v.rotate(u.unit());
        assert_eq!(uv.norm_squared(), Exact::ONE);
        let composed = Point::new(&uv.x * &x.x - &uv.y * &x.y, &uv.y * &x.x + &uv.x * &x.y);
        assert_eq!(v.rotate(&u.rotate(&x)), composed);
    }
}

#[test]
fn paths_are_rejected_for_the_reason_the_file_has() {
    let path = |vs: &[(i64, i64)]| Path::new(vs.iter().map(|&(x, y)| p(x, y)).collect());
    assert!(path(&[(0, 0), (5, 0)]).is_ok());
    let l_turn = path(&[(0, 0), (5, 0), (5, 5), (-2, 5)]).expect("an L and a U are paths");
    assert_eq!(l_turn.segments().count(), 3);
    assert_eq!(path(&[(0, 0)]), Err(PathError::TooFewVertices(1)));
    assert_eq!(path(&[(1, 0), (5, 0)]), Err(PathError::NotFromOrigin));
    // The first segment is the robot's initial heading, whichever way it points.
    assert!(path(&[(0, 0), (3, 4)]).is_ok());
    assert!(path(&[(0, 0), (-3, 0), (-3, -2)]).is_ok());
    assert_eq!(
        path(&[(0, 0), (5, 0), (5, 0), (5, 3)]),
        Err(PathError::ZeroLength(1))
    );
    assert_eq!(path(&[(0, 0), (5, 0), (2, 0)]), Err(PathError::Reverses(1)));
    // A spiral that comes back across its first segment, and one that only touches it.
    assert_eq!(
        path(&[(0, 0), (4, 0), (4, 4), (2, 4), (2, -1)]),
        Err(PathError::Crosses(0, 3))
    );
    assert_eq!(
        path(&[(0, 0), (4, 0), (4, 4), (2, 4), (2, 0)]),
        Err(PathError::Crosses(0, 3))
    );
    // Going straight on through a vertex is fine.
    assert!(path(&[(0, 0), (2, 0), (4, 0), (4, 1)]).is_ok());
    // Messages name the segments as the file numbers them.
    assert_eq!(
        PathError::Crosses(0, 3).to_string(),
        "segments 0 and 3 cross or touch"
    );
}
