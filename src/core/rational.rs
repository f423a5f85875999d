//! A fast exact rational for long replays: `i128` numerator and denominator while they fit,
//! falling back to [`Exact`] (arbitrary precision) on any overflow, so it is exact always.
//!
//! Replaying a witness runs the step function hundreds of times in exact arithmetic; with
//! general big rationals every addition pays for allocation-free but generic multi-word
//! code and a big gcd. The replay's numbers are small (decimal parameters, speeds that are
//! multiples of 2⁻³⁰), so machine-word arithmetic with checked overflow does the same work
//! several times faster. Every operation falls back to [`Exact`] when a product or sum does
//! not fit, and tests hold the results equal to an all-[`Exact`] replay.

use std::cmp::Ordering;
use std::ops::{Add, Div, Mul, Neg, Sub};

use dashu_int::{IBig, UBig};

use crate::core::num::{Exact, Scalar, exact_decimal};

/// An exact rational: small (`n/d`, `d > 0`, in lowest terms) or big.
#[derive(Clone, Debug)]
pub enum Rational {
    /// n/d with d > 0 and gcd(|n|, d) = 1.
    Small(i128, i128),
    /// Anything else.
    Big(Exact),
}

/// gcd(a, b), in 64-bit words when both fit: the replay's numbers almost always do, and
/// 128-bit shifts and compares cost twice as much.
fn gcd(a: u128, b: u128) -> u128 {
    match (u64::try_from(a), u64::try_from(b)) {
        (Ok(a), Ok(b)) => u128::from(gcd64(a, b)),
        _ => gcd128(a, b),
    }
}

// Binary (Stein's) gcd at one width: shifts and subtractions, no division.
macro_rules! binary_gcd {
    ($name:ident, $t:ty) => {
        fn $name(mut a: $t, mut b: $t) -> $t {
            if a == 0 {
                return b;
            }
            if b == 0 {
                return a;
            }
            let shift = (a | b).trailing_zeros();
            a >>= a.trailing_zeros();
            loop {
                b >>= b.trailing_zeros();
                if a > b {
                    std::mem::swap(&mut a, &mut b);
                }
                b -= a;
                if b == 0 {
                    return a << shift;
                }
            }
        }
    };
}

binary_gcd!(gcd64, u64);
binary_gcd!(gcd128, u128);

/// `n / g` for a divisor `g` of `n` (g ≥ 1), in 64-bit words when both fit: a 128-bit
/// division is a call into a software routine (`__divti3`), ten times a hardware one.
fn div_exact(n: i128, g: i128) -> i128 {
    match (i64::try_from(n), i64::try_from(g)) {
        (Ok(n), Ok(g)) => i128::from(n / g),
        _ => n / g,
    }
}

/// Whether `x` fits in 64 bits: then a product of two such numbers, and a sum of two such
/// products, fits in 128 bits without a check.
fn fits64(x: i128) -> bool {
    x as i64 as i128 == x
}

impl Rational {
    /// n/d in lowest terms (d ≠ 0), small when it fits.
    fn small(n: i128, d: i128) -> Rational {
        debug_assert!(d != 0);
        let g = gcd(n.unsigned_abs(), d.unsigned_abs());
        let (n, d) = if g > 1 {
            (div_exact(n, g as i128), div_exact(d, g as i128))
        } else {
            (n, d)
        };
        if d < 0 {
            match (n.checked_neg(), d.checked_neg()) {
                (Some(n), Some(d)) => Rational::Small(n, d),
                _ => Rational::Big(Exact::from_parts_signed(IBig::from(n), IBig::from(d))),
            }
        } else {
            Rational::Small(n, d)
        }
    }

    /// The value as an arbitrary-precision rational.
    pub fn to_exact(&self) -> Exact {
        match self {
            Rational::Small(n, d) => {
                Exact::from_parts(IBig::from(*n), UBig::from(d.unsigned_abs()))
            }
            Rational::Big(r) => r.clone(),
        }
    }

    /// The same value, small when it fits.
    pub fn from_exact(r: &Exact) -> Rational {
        match (
            i128::try_from(r.numerator()),
            u128::try_from(r.denominator()),
        ) {
            (Ok(n), Ok(d)) if d <= i128::MAX as u128 => Rational::Small(n, d as i128),
            _ => Rational::Big(r.clone()),
        }
    }

    fn big(self, other: Rational, f: impl Fn(Exact, Exact) -> Exact) -> Rational {
        Rational::from_exact(&f(self.to_exact(), other.to_exact()))
    }
}

impl PartialEq for Rational {
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Rational::Small(a, b), Rational::Small(c, d)) => a == c && b == d,
            _ => self.to_exact() == other.to_exact(),
        }
    }
}

impl PartialOrd for Rational {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        if let (Rational::Small(a, b), Rational::Small(c, d)) = (self, other) {
            if b == d {
                return Some(a.cmp(c));
            }
            if fits64(*a) && fits64(*b) && fits64(*c) && fits64(*d) {
                return Some((a * d).cmp(&(c * b)));
            }
            if let (Some(x), Some(y)) = (a.checked_mul(*d), c.checked_mul(*b)) {
                return Some(x.cmp(&y));
            }
        }
        Some(self.to_exact().cmp(&other.to_exact()))
    }
}

impl Add for Rational {
    type Output = Rational;
    fn add(self, other: Rational) -> Rational {
        if let (Rational::Small(a, b), Rational::Small(c, d)) = (&self, &other) {
            // x + 0 and 0 + x: the searches add empty drifts and zero ends often.
            if *c == 0 {
                return self;
            }
            if *a == 0 {
                return other;
            }
            let sum = if b == d {
                a.checked_add(*c).map(|n| (n, *b))
            } else if fits64(*a) && fits64(*b) && fits64(*c) && fits64(*d) {
                Some((a * d + c * b, b * d))
            } else {
                match (a.checked_mul(*d), c.checked_mul(*b), b.checked_mul(*d)) {
                    (Some(x), Some(y), Some(den)) => x.checked_add(y).map(|n| (n, den)),
                    _ => None,
                }
            };
            if let Some((n, den)) = sum {
                return Rational::small(n, den);
            }
        }
        self.big(other, |x, y| x + y)
    }
}

impl Neg for Rational {
    type Output = Rational;
    fn neg(self) -> Rational {
        match self {
            Rational::Small(n, d) => match n.checked_neg() {
                Some(n) => Rational::Small(n, d),
                None => Rational::Big(-Rational::Small(n, d).to_exact()),
            },
            Rational::Big(r) => Rational::Big(-r),
        }
    }
}

impl Sub for Rational {
    type Output = Rational;
    fn sub(self, other: Rational) -> Rational {
        if let Rational::Small(c, _) = &other
            && *c != i128::MIN
        {
            return self + (-other);
        }
        self.big(other, |x, y| x - y)
    }
}

impl Mul for Rational {
    type Output = Rational;
    fn mul(self, other: Rational) -> Rational {
        if let (Rational::Small(a, b), Rational::Small(c, d)) = (&self, &other) {
            if *a == 0 || *c == 0 {
                return Rational::Small(0, 1);
            }
            if *b == 1
                && *d == 1
                && let Some(n) = a.checked_mul(*c)
            {
                return Rational::Small(n, 1);
            }
            // Cancel across first: keeps the products small and the result in lowest terms.
            let g1 = gcd(a.unsigned_abs(), d.unsigned_abs()).max(1) as i128;
            let g2 = gcd(c.unsigned_abs(), b.unsigned_abs()).max(1) as i128;
            let (a, b, c, d) = (
                div_exact(*a, g1),
                div_exact(*b, g2),
                div_exact(*c, g2),
                div_exact(*d, g1),
            );
            if let (Some(n), Some(den)) = (a.checked_mul(c), b.checked_mul(d)) {
                return Rational::small(n, den);
            }
        }
        self.big(other, |x, y| x * y)
    }
}

impl Div for Rational {
    type Output = Rational;
    fn div(self, other: Rational) -> Rational {
        match other {
            Rational::Small(c, d) if c != 0 && c != i128::MIN => self * Rational::small(d, c),
            other => self.big(other, |x, y| x / y),
        }
    }
}

impl Scalar for Rational {
    fn zero() -> Self {
        Rational::Small(0, 1)
    }
    fn int(i: i64) -> Self {
        Rational::Small(i128::from(i), 1)
    }
    fn decimal(x: f64) -> Self {
        Rational::from_exact(&exact_decimal(x))
    }
    fn as_f64(&self) -> f64 {
        match self {
            Rational::Small(n, d) => *n as f64 / *d as f64,
            Rational::Big(r) => r.to_f64_fast(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn any_exact() -> impl Strategy<Value = Exact> {
        prop_oneof![
            (-1000i64..1000, 1u64..1000)
                .prop_map(|(n, d)| Exact::from_parts(IBig::from(n), UBig::from(d))),
            (any::<i64>(), 1u64..u64::MAX)
                .prop_map(|(n, d)| Exact::from_parts(IBig::from(n), UBig::from(d))),
            (any::<i128>(), 1u128..u128::MAX)
                .prop_map(|(n, d)| Exact::from_parts(IBig::from(n), UBig::from(d))),
            // Either side of 2^63, where the 64-bit fast paths end.
            (-2000i128..2000, 0u128..2000, any::<bool>(), any::<bool>()).prop_map(
                |(dn, dd, neg, small_d)| {
                    let edge = 1i128 << 63;
                    let n = if neg { -edge - dn } else { edge + dn };
                    let d = if small_d {
                        1 + dd
                    } else {
                        (edge as u128) - 1000 + dd
                    };
                    Exact::from_parts(IBig::from(n), UBig::from(d))
                }
            ),
        ]
    }

    proptest! {
        /// Every operation equals the arbitrary-precision one, overflow or not.
        #[test]
        fn operations_equal_big_rationals(x in any_exact(), y in any_exact()) {
            let (a, b) = (Rational::from_exact(&x), Rational::from_exact(&y));
            prop_assert_eq!((a.clone() + b.clone()).to_exact(), x.clone() + y.clone());
            prop_assert_eq!((a.clone() - b.clone()).to_exact(), x.clone() - y.clone());
            prop_assert_eq!((a.clone() * b.clone()).to_exact(), x.clone() * y.clone());
            if y != Exact::ZERO {
                prop_assert_eq!((a.clone() / b.clone()).to_exact(), x.clone() / y.clone());
            }
            prop_assert_eq!((-a.clone()).to_exact(), -x.clone());
            prop_assert_eq!(a.partial_cmp(&b), Some(x.cmp(&y)));
            prop_assert_eq!(a == b, x == y);
        }
    }
}
