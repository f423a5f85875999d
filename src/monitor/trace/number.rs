//! Decimal numbers to `f64`, correctly rounded, in place on the bytes of a line.
//!
//! The conversion is `lexical-core`'s: on the numbers traces hold (shortest round-trip
//! doubles of up to 17 digits, and short fixed decimals) it was as fast as or faster than the
//! Eisel–Lemire parser written here before, and bit-identical to the standard library on
//! random and hard cases (`benches/trace_reader.rs` measures both). The syntax is Rust's
//! `f64::from_str`: optional sign, digits with an optional point, optional exponent, or
//! `inf`/`infinity`/`nan` in any case.

use super::trim;

/// Reads a number at the start of `s` and returns it with the number of bytes read; `None`
/// when `s` does not start with one. The caller checks what follows (a CSV field ends at a
/// comma).
#[inline]
pub(super) fn scan_number(s: &[u8]) -> Option<(f64, usize)> {
    lexical_core::parse_partial::<f64>(s).ok()
}

/// Parses a decimal number (as Rust's `f64::from_str` does: optional sign, digits with an
/// optional point, optional exponent, or `inf`/`infinity`/`nan` in any case), correctly
/// rounded. Surrounding spaces are ignored. `None` if it is not a number.
#[inline]
pub fn parse_f64(s: &[u8]) -> Option<f64> {
    lexical_core::parse::<f64>(trim(s)).ok()
}

/// Parses a lane number: an optional sign and decimal digits that fit an `i32`. Surrounding
/// spaces are ignored. `None` if it is not one (a lane is an integer, not `1.0`).
#[inline]
pub(super) fn parse_lane(s: &[u8]) -> Option<i32> {
    std::str::from_utf8(trim(s)).ok()?.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agrees_with_the_standard_parser() {
        for s in [
            "0",
            "-0",
            "1",
            "0.1",
            "12.5",
            "-3.25",
            "1e3",
            "1.5E-3",
            "+7",
            ".5",
            "5.",
            "123456789012345",
            "0.000000000000000000001",
            "1e22",
            "1e-22",
            "9007199254740993",
            "4.35e-3",
            "inf",
            "Infinity",
            "1e400",
            "0.1000000000000000055511151231257827021181583404541015625",
        ] {
            assert_eq!(
                parse_f64(s.as_bytes()).map(f64::to_bits),
                s.parse::<f64>().ok().map(f64::to_bits),
                "{s}"
            );
        }
        for bad in [
            "", ".", "-", "1e", "1e+", "e5", "1.2.3", "0x10", "1,5", "--1",
        ] {
            assert_eq!(parse_f64(bad.as_bytes()), None, "{bad}");
        }
        assert!(parse_f64(b"NaN").unwrap().is_nan());
        assert_eq!(parse_f64(b"-inf"), Some(f64::NEG_INFINITY));
        assert_eq!(parse_f64(b" 2.5 "), Some(2.5));
    }

    #[test]
    fn lanes_are_integers() {
        for (text, lane) in [("0", 0), ("-1", -1), ("+2", 2), (" 3 ", 3)] {
            assert_eq!(parse_lane(text.as_bytes()), Some(lane), "{text}");
        }
        for bad in ["", "1.0", "1e0", "one", "--1", "2147483648"] {
            assert_eq!(parse_lane(bad.as_bytes()), None, "{bad}");
        }
    }

    #[test]
    fn a_number_and_where_it_ends() {
        assert_eq!(scan_number(b"0.25,drive"), Some((0.25, 4)));
        assert_eq!(scan_number(b"-1e3 ,"), Some((-1000.0, 4)));
        assert_eq!(scan_number(b",1"), None);
        assert_eq!(scan_number(b""), None);
    }
}
