//! Numbers shown to people, honestly. A bound is rounded in its own direction at the digits
//! shown: a lower bound down ([`down`]), an upper bound up ([`up`]), so the printed number
//! is still a bound ("rigorous lower bound 0.329999999" for 0.3299999999993427, never
//! 0.330000000). Every other number — a time, a measured value, a slack — is shown as the
//! shortest decimal that reads back as it once the last-bit noise of float arithmetic is
//! gone ([`value`]: `t=2.3`, never `t=2.3000000000000003`). Every human output goes through
//! these three.

use dashu_int::IBig;

use crate::core::num::{Exact, exact_float};

/// Significant digits a shown value keeps: an `f64` holds 15 exactly; the 16th and 17th
/// carry the noise of the arithmetic that produced it.
const SIGNIFICANT: usize = 15;

/// `x` at `decimals` decimals, rounded towards −∞: a lower bound stays a lower bound.
/// (Non-finite numbers are shown as [`value`] shows them.)
pub fn down(x: f64, decimals: usize) -> String {
    rounded(x, decimals, false)
}

/// `x` at `decimals` decimals, rounded towards +∞: an upper bound stays an upper bound.
pub fn up(x: f64, decimals: usize) -> String {
    rounded(x, decimals, true)
}

/// `x` without float noise: rounded to 15 significant digits, then the shortest decimal
/// that reads back as that (scientific below 10⁻⁴ and from 10¹⁵ on, so a slack of
/// −7·10⁻¹⁶ is not a line of zeros). Zero is `0`, whatever its sign.
pub fn value(x: f64) -> String {
    let y = denoised(x);
    if y == 0.0 {
        return "0".into();
    }
    let a = y.abs();
    if a.is_finite() && !(1e-4..1e15).contains(&a) {
        format!("{y:e}")
    } else {
        format!("{y}")
    }
}

/// `x` with the noise of float arithmetic removed: the float nearest to `x` rounded to 15
/// significant digits (2.3000000000000003 → 2.3; a decimal such as 0.1 stays itself).
pub fn denoised(x: f64) -> f64 {
    if !x.is_finite() || x == 0.0 {
        return x;
    }
    format!("{x:.*e}", SIGNIFICANT - 1).parse().unwrap_or(x)
}

/// The exact value of `x` scaled by 10^`decimals`, rounded up or down, as a decimal.
fn rounded(x: f64, decimals: usize, towards_up: bool) -> String {
    if !x.is_finite() {
        return value(x);
    }
    let scale = Exact::from(IBig::from(10).pow(decimals));
    let scaled = exact_float(x) * scale;
    let n: IBig = if towards_up {
        scaled.ceil()
    } else {
        scaled.floor()
    };
    let text = n.to_string();
    let (sign, magnitude) = match text.strip_prefix('-') {
        Some(m) => ("-", m),
        None => ("", text.as_str()),
    };
    let digits = format!("{magnitude:0>width$}", width = decimals + 1);
    let (whole, fraction) = digits.split_at(digits.len() - decimals);
    if decimals == 0 {
        format!("{sign}{whole}")
    } else {
        format!("{sign}{whole}.{fraction}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shown decimal, read exactly.
    fn exact_text(text: &str) -> Exact {
        crate::core::num::exact_decimal(text.parse().unwrap())
    }

    #[test]
    fn bounds_round_in_their_own_direction() {
        let lb = 0.3299999999993427;
        assert_eq!(down(lb, 9), "0.329999999");
        assert_eq!(up(lb, 9), "0.330000000");
        assert_eq!(down(0.330000102352, 9), "0.330000102");
        assert_eq!(up(0.330000102352, 9), "0.330000103");
        assert_eq!(down(-1.560000000000015, 6), "-1.560001");
        assert_eq!(up(-1.560000000000015, 6), "-1.560000");
        assert_eq!(down(-0.0000001, 3), "-0.001");
        assert_eq!(up(-0.0000001, 3), "0.000");
        assert_eq!(down(2.0, 0), "2");
        assert_eq!(up(2.5, 0), "3");
        // A decimal the float stands for exactly enough is shown as itself both ways.
        assert_eq!(down(0.5, 3), "0.500");
        assert_eq!(up(0.5, 3), "0.500");
    }

    #[test]
    fn a_shown_bound_is_still_a_bound() {
        for x in [
            0.1,
            1.0 / 3.0,
            -2.0 / 3.0,
            0.3299999999993427,
            1e-12,
            -4.1,
            123.456,
        ] {
            for d in [0, 3, 6, 9, 12] {
                let (lo, hi) = (exact_text(&down(x, d)), exact_text(&up(x, d)));
                assert!(lo <= exact_float(x) && exact_float(x) <= hi, "{x} at {d}");
                // And no more than one unit of the last digit away.
                let unit = Exact::from(IBig::from(10).pow(d));
                assert!((hi - lo) * unit <= Exact::ONE, "{x} at {d}");
            }
        }
    }

    #[test]
    fn values_lose_their_float_noise() {
        assert_eq!(value(23.0 * 0.1), "2.3");
        assert_eq!(value(0.1 + 0.2), "0.3");
        assert_eq!(value(20.200000000000003), "20.2");
        assert_eq!(value(0.15 - 0.1), "0.05");
        assert_eq!(value(0.21810514529192612), "0.218105145291926");
        assert_eq!(value(1.4), "1.4");
        assert_eq!(value(0.0), "0");
        assert_eq!(value(-0.0), "0");
        assert_eq!(value(-7.008282842946301e-16), "-7.0082828429463e-16");
        assert_eq!(value(3e20), "3e20");
        assert_eq!(value(f64::INFINITY), "inf");
        // Shown values read back as the denoised number.
        for x in [23.0 * 0.1, 1.0 / 3.0, 8.600000000000001, 1e-9 * 3.0] {
            assert_eq!(value(x).parse::<f64>().unwrap(), denoised(x));
        }
    }
}
