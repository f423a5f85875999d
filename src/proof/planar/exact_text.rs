//! Exact rationals as certificate text: `"n"` or `"n/d"` in lowest terms, so a number the
//! checker must reproduce bit for bit (a goal, a bound, a witness's velocity) is stored
//! without a float's rounding.

use dashu_int::IBig;

use crate::core::num::Exact;
use crate::core::plane::point::Point;

/// `x` as text (`"-3/4"`, `"2"`).
pub fn write(x: &Exact) -> String {
    x.to_string()
}

/// The rational `text` states (`"n"` or `"n/d"`, d > 0), or None.
pub fn read(text: &str) -> Option<Exact> {
    let (n, d) = match text.split_once('/') {
        Some((n, d)) => (n, d),
        None => (text, "1"),
    };
    let n: IBig = n.parse().ok()?;
    let d: IBig = d.parse().ok()?;
    (d > IBig::ZERO).then(|| Exact::from_parts_signed(n, d))
}

/// A point as two texts.
pub fn write_point(p: &Point) -> [String; 2] {
    [write(&p.x), write(&p.y)]
}

/// The point two texts state, or None.
pub fn read_point(p: &[String; 2]) -> Option<Point> {
    Some(Point::new(read(&p[0])?, read(&p[1])?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rationals_survive_the_round_trip_and_bad_text_is_refused() {
        for (n, d) in [
            (0i64, 1i64),
            (-3, 4),
            (7, 1),
            (123_456_789_012, 1_000_000_007),
        ] {
            let x = Exact::from_parts_signed(IBig::from(n), IBig::from(d));
            assert_eq!(read(&write(&x)), Some(x));
        }
        assert_eq!(read("6/4"), Some(Exact::from(3) / Exact::from(2)));
        for bad in ["", "1/0", "1/-2", "a", "1/2/3", "0.5", "1 /2"] {
            assert_eq!(read(bad), None, "{bad:?}");
        }
    }
}
