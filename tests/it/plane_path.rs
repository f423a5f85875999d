//! The analysed planar path (issue 36, `core::plane::rational_path`) against the file's path
//! computed independently in floats: every point within the proved drift, the drift no
//! looser than the directions' and lengths' own errors, and exact where the file's path is.

use dashu_ratio::RBig;
use safereach::core::num::Exact;
use safereach::core::plane::path::Path;
use safereach::core::plane::point::Point;
use safereach::core::plane::rational_path::RationalPath;

use crate::common::split_mix::SplitMix;

fn p(x: i64, y: i64) -> Point {
    Point::new(Exact::from(x), Exact::from(y))
}

/// The file's path at arc length s, in floats, from its vertices alone.
fn float_point(vertices: &[(f64, f64)], s: f64) -> (f64, f64) {
    let mut left = s;
    for w in vertices.windows(2) {
        let (dx, dy) = (w[1].0 - w[0].0, w[1].1 - w[0].1);
        let len = dx.hypot(dy);
        if left <= len {
            return (w[0].0 + dx * left / len, w[0].1 + dy * left / len);
        }
        left -= len;
    }
    // s = the whole length, up to the rounding of the sum of lengths: the path's end.
    assert!(left < 1e-9, "s within the path");
    *vertices.last().expect("a vertex")
}

#[test]
fn analysed_points_lie_within_the_proved_drift_of_the_file_path() {
    let mut rng = SplitMix(36);
    let delta = RBig::from(1) / RBig::from(1_000_000); // large enough to see above f64 noise
    let mut paths = 0;
    while paths < 150 {
        // A wandering polyline: first segment along +x, then random rational turns.
        let mut vs = vec![
            p(0, 0),
            Point::new(
                RBig::from((rng.next() % 40 + 1) as i64) / RBig::from(4),
                Exact::ZERO,
            ),
        ];
        for _ in 0..(rng.next() % 5) {
            let last = vs.last().expect("a vertex").clone();
            let step = |r: u64| RBig::from(r as i64 % 81 - 40) / RBig::from(7);
            vs.push(&last + &Point::new(step(rng.next()), step(rng.next())));
        }
        let Ok(path) = Path::new(vs.clone()) else {
            continue;
        };
        paths += 1;
        let analysed = RationalPath::new(&path, &delta).expect("analysable");
        let floats: Vec<(f64, f64)> = vs.iter().map(Point::to_f64).collect();
        let total: f64 = floats
            .windows(2)
            .map(|w| (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1))
            .sum();
        let drift = analysed.drift().to_f64().value();
        // The drift is the directions' chord error over the length, plus length errors.
        assert!(
            drift <= total * 1e-6 * (1.0 + 1e-9) + 1e-9,
            "{drift} for {total} m"
        );
        let reach = total.min(analysed.length().to_f64().value());
        for k in 0..=64 {
            let s = RBig::try_from(reach * k as f64 / 64.0).expect("finite");
            let (qx, qy) = analysed.point_at(&s).to_f64();
            let (px, py) = float_point(&floats, s.to_f64().value().min(total));
            let off = (qx - px).hypot(qy - py);
            assert!(off <= drift + 1e-12, "s = {s}: off {off} > drift {drift}");
        }
    }
}

#[test]
fn a_path_of_rational_lengths_is_analysed_exactly() {
    // Lengths 3, 4, 5 and axis directions or (−3/5, 4/5): nothing to round.
    let path = Path::new(vec![p(0, 0), p(3, 0), p(3, 4), p(0, 8)]).expect("a path");
    let analysed =
        RationalPath::new(&path, &(RBig::from(1) / RBig::from(1_000_000_000))).expect("ok");
    assert_eq!(analysed.drift(), &Exact::ZERO);
    assert_eq!(analysed.length(), Exact::from(12));
    let arcs: Vec<Exact> = analysed.vertex_arcs().cloned().collect();
    assert_eq!(arcs, vec![Exact::from(3), Exact::from(7)]);
    // At a vertex the robot is on the segment it leaves by.
    assert_eq!(analysed.segment_index(&Exact::from(3)), 1);
    assert_eq!(analysed.point_at(&Exact::from(3)), p(3, 0));
    assert_eq!(analysed.point_at(&Exact::from(7)), p(3, 4));
    assert_eq!(analysed.point_at(&Exact::from(12)), p(0, 8));
    let half = RBig::from(19) / RBig::from(2); // 2.5 m into the last segment
    assert_eq!(
        analysed.point_at(&half),
        Point::new(RBig::from(3) / RBig::from(2), Exact::from(6))
    );
    assert_eq!(
        analysed.heading_at(&Exact::from(8)).unit(),
        &Point::new(
            RBig::from(-3) / RBig::from(5),
            RBig::from(4) / RBig::from(5)
        )
    );
}
