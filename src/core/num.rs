//! Numbers the semantics is written over.
//!
//! The model's step function is generic over [`Scalar`] so that one piece of code serves
//! every engine: the Monte Carlo simulator runs it in `f64`, while the analyser, the
//! certificate checker and witness replay run it in exact rationals ([`Exact`]). Every
//! quantity of the model (positions, times, stopping distances, step counts) is rational
//! when the problem's numbers are, so no engine ever needs a square root.

use std::fmt::Debug;
use std::ops::{Add, Div, Mul, Neg, Sub};

use dashu_int::IBig;
use dashu_ratio::RBig;

/// Exact rational number used wherever a decision must not depend on rounding.
pub type Exact = RBig;

/// A number type the semantics can be evaluated in.
pub trait Scalar:
    Clone
    + Debug
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Additive identity.
    fn zero() -> Self;
    /// A small integer.
    fn int(i: i64) -> Self;
    /// The value a problem file means by `x`: for exact numbers the shortest decimal that
    /// round-trips to `x` (so `0.1` is one tenth), for `f64` the float itself.
    fn decimal(x: f64) -> Self;
    /// An `f64` within a few ulps (for display and traces; decisions never use it).
    fn as_f64(&self) -> f64;
    /// The `f64` a trace shows: exact numbers carry no arithmetic noise, so it is
    /// [`Scalar::as_f64`]; a float computed in floats (k·dt = 2.3000000000000003) has it
    /// removed ([`crate::core::show::denoised`]).
    fn shown_f64(&self) -> f64 {
        self.as_f64()
    }
    /// The smaller of two numbers.
    fn min_of(a: Self, b: Self) -> Self {
        if b < a { b } else { a }
    }
    /// The larger of two numbers.
    fn max_of(a: Self, b: Self) -> Self {
        if b > a { b } else { a }
    }
}

impl Scalar for f64 {
    fn shown_f64(&self) -> f64 {
        crate::core::show::denoised(*self)
    }
    fn zero() -> Self {
        0.0
    }
    fn int(i: i64) -> Self {
        i as f64
    }
    fn decimal(x: f64) -> Self {
        x
    }
    fn as_f64(&self) -> f64 {
        *self
    }
}

impl Scalar for RBig {
    fn zero() -> Self {
        RBig::ZERO
    }
    fn int(i: i64) -> Self {
        RBig::from(i)
    }
    fn decimal(x: f64) -> Self {
        exact_decimal(x)
    }
    fn as_f64(&self) -> f64 {
        self.to_f64_fast()
    }
}

/// The exact rational a decimal literal denotes: the shortest decimal representation of
/// `x` that reads back as `x` (Rust's `Display`), e.g. `0.15` gives 15/100 exactly.
///
/// # Panics
/// If `x` is not finite; callers validate first.
pub fn exact_decimal(x: f64) -> Exact {
    assert!(x.is_finite(), "exact_decimal of a non-finite number");
    let text = format!("{x:e}");
    let (mantissa, exponent) = text.split_once('e').expect("{:e} always has an exponent");
    let exponent: isize = exponent.parse().expect("exponent is an integer");
    let (sign, digits) = match mantissa.strip_prefix('-') {
        Some(rest) => (-1, rest),
        None => (1, mantissa),
    };
    let (int_part, frac_part) = digits.split_once('.').unwrap_or((digits, ""));
    let all_digits: String = format!("{int_part}{frac_part}");
    let scale = exponent - frac_part.len() as isize;
    // The usual case — at most 17 digits, within 10^±38 — in machine words: problem files
    // are read into exact numbers once per sweep cell.
    if let Ok(n) = all_digits.parse::<u64>()
        && let Ok(shift) = u32::try_from(scale.unsigned_abs())
        && shift <= 38
    {
        let n = i128::from(n) * i128::from(sign);
        let power = 10u128.pow(shift);
        if scale < 0 {
            return RBig::from_parts(IBig::from(n), dashu_int::UBig::from(power));
        }
        if let Some(whole) = i128::try_from(power).ok().and_then(|p| n.checked_mul(p)) {
            return RBig::from(IBig::from(whole));
        }
    }
    let n: IBig = all_digits.parse::<IBig>().expect("digits") * IBig::from(sign);
    let ten = RBig::from(10);
    RBig::from(n) * ten.pow(scale)
}

/// The exact value of a float (every finite `f64` is a dyadic rational).
///
/// # Panics
/// If `x` is not finite.
pub fn exact_float(x: f64) -> Exact {
    RBig::try_from(x).expect("finite float converts exactly")
}

/// The largest `f64` not above `r`: used where a float must stay inside an exact bound
/// (an obstacle speed written into a witness must not exceed the bound W).
pub fn f64_at_most(r: &Exact) -> f64 {
    let x = r.to_f64().value();
    if x.is_finite() && exact_float(x) > *r {
        x.next_down()
    } else {
        x
    }
}

/// The least `f64` not below `r`: where a float must stay outside an exact bound from above
/// (a width declared for an exact interval must not understate it).
pub fn f64_at_least(r: &Exact) -> f64 {
    let x = r.to_f64().value();
    if x.is_finite() && exact_float(x) < *r {
        x.next_up()
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimals_are_read_as_written() {
        assert_eq!(exact_decimal(0.1), RBig::from_parts(1.into(), 10u8.into()));
        assert_eq!(exact_decimal(0.15) * RBig::from(20), RBig::from(3));
        assert_eq!(
            exact_decimal(-2.5e-3),
            RBig::from_parts((-25).into(), 10000u16.into())
        );
        assert_eq!(exact_decimal(1e20), RBig::from(10).pow(20));
        assert_eq!(exact_decimal(0.0), RBig::ZERO);
    }

    /// The machine-word path is the general one: every decimal the float prints as, times a
    /// power of ten, read as big integers (the reference), for values from 1e-45 to 1e45 of
    /// both signs and 1 to 17 significant digits.
    #[test]
    fn decimals_in_machine_words_are_the_general_reading() {
        let reference = |x: f64| {
            let text = format!("{x:e}");
            let (mantissa, exponent) = text.split_once('e').expect("an exponent");
            let (int_part, frac_part) = mantissa.split_once('.').unwrap_or((mantissa, ""));
            let digits: IBig = format!("{int_part}{frac_part}").parse().expect("digits");
            let scale = exponent.parse::<isize>().expect("integer") - frac_part.len() as isize;
            RBig::from(digits) * RBig::from(10).pow(scale)
        };
        let mut state: u64 = 0x2545_f491_4f6c_dd1d;
        for _ in 0..20_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let digits = 1 + (state % 17) as i32;
            let mantissa = (state >> 8) as f64 / (1u64 << 56) as f64;
            let exponent = ((state >> 40) % 91) as i32 - 45;
            let x = format!(
                "{:.*e}",
                (digits - 1) as usize,
                mantissa * 10f64.powi(exponent)
            )
            .parse::<f64>()
            .expect("a float");
            for v in [x, -x] {
                assert_eq!(exact_decimal(v), reference(v), "{v:e}");
            }
        }
    }

    #[test]
    fn rounding_directions_hold() {
        for x in [0.1, 0.15, 0.2, 0.3, 1.0 / 3.0, 0.7] {
            let r = exact_decimal(x);
            assert!(exact_float(f64_at_most(&r)) <= r);
            assert!(exact_float(f64_at_most(&r).next_up()) > r);
            assert!(exact_float(f64_at_least(&r)) >= r);
            assert!(exact_float(f64_at_least(&r).next_down()) < r);
        }
    }
}
