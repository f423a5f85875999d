//! Decimal numbers to `f64`, correctly rounded, in place on the bytes of a line.
//!
//! Traces hold short decimals and the 17 digits of a shortest round-trip double; both are
//! converted here without leaving the line: Clinger's fast path for an integer times a power
//! of ten, else Eisel–Lemire with a 128-bit table of powers of five. Anything else (more
//! than 19 digits, large exponents, `inf`, `nan`) goes to the standard library.

use super::trim;

/// Powers of ten exactly representable as `f64`.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// Smallest and largest decimal exponent of the table below.
const Q_MIN: i32 = -27;
const Q_MAX: i32 = 55;

/// 5^q for q in [`Q_MIN`, `Q_MAX`] as a 128-bit number with its top bit set: exact for q ≥ 0
/// (5^55 < 2^128), and ⌊2^(z+127) / 5^−q⌋ + 1 for q < 0, z the bit length of 5^−q. In
/// this range a product with a 64-bit significand decides the correctly rounded double
/// (Lemire, "Number parsing at a gigabyte per second", 2021, §§ 5, 8, 9), so the parser
/// never needs a slow path for it.
const POW5: [u128; (Q_MAX - Q_MIN + 1) as usize] = pow5_table();

const fn pow5_table() -> [u128; (Q_MAX - Q_MIN + 1) as usize] {
    let mut table = [0u128; (Q_MAX - Q_MIN + 1) as usize];
    let mut q = Q_MIN;
    while q <= Q_MAX {
        let entry = if q >= 0 {
            let p = 5u128.pow(q as u32);
            p << p.leading_zeros()
        } else {
            let d = 5u128.pow((-q) as u32); // < 2^63 for q ≥ −27
            let z = 128 - d.leading_zeros(); // 2^(z−1) < d < 2^z
            // ⌊2^(z+127) / d⌋ by long division, one bit at a time.
            let mut quotient = 0u128;
            let mut remainder = 0u128;
            let mut bit = 0;
            while bit < z + 128 {
                remainder = (remainder << 1) | (bit == 0) as u128;
                quotient <<= 1;
                if remainder >= d {
                    remainder -= d;
                    quotient |= 1;
                }
                bit += 1;
            }
            quotient + 1
        };
        table[(q - Q_MIN) as usize] = entry;
        q += 1;
    }
    table
}

/// The correctly rounded double nearest w·10^q for w > 0 and q in [`Q_MIN`, `Q_MAX`]
/// (Eisel–Lemire: one or two 64×64-bit products with the truncated 5^q decide it).
#[inline(always)]
fn eisel_lemire(w: u64, q: i32) -> f64 {
    let lz = w.leading_zeros();
    let w = w << lz;
    let t = POW5[(q - Q_MIN) as usize];
    let (t_hi, t_lo) = ((t >> 64) as u64, t as u64);
    let p = u128::from(w) * u128::from(t_hi);
    let (mut lo, mut hi) = (p as u64, (p >> 64) as u64);
    // 52 explicit bits, one hidden, one to round, one for a leading zero: 55 bits must be
    // exact; when the bits below them are all ones, refine with the low half of 5^q.
    const MASK: u64 = u64::MAX >> 55;
    if hi & MASK == MASK {
        let low = ((u128::from(w) * u128::from(t_lo)) >> 64) as u64;
        lo = lo.wrapping_add(low);
        if low > lo {
            hi += 1;
        }
    }
    let upper = (hi >> 63) as i32;
    let mut mantissa = hi >> (upper + 9);
    // ⌊log2(10^q)⌋ + 63 = ((217706·q) >> 16) + 63; the biased exponent of the result.
    let mut power2 = ((q * 217_706) >> 16) + 63 + upper - lz as i32 + 1023;
    // An exact halfway case rounds to even (only possible for small q).
    if lo <= 1 && (-4..=23).contains(&q) && mantissa & 3 == 1 && (mantissa << (upper + 9)) == hi {
        mantissa &= !1;
    }
    mantissa += mantissa & 1;
    mantissa >>= 1;
    if mantissa >= 2 << 52 {
        mantissa = 1 << 52;
        power2 += 1;
    }
    mantissa &= !(1 << 52);
    f64::from_bits(mantissa | ((power2 as u64) << 52))
}

/// How many of the eight bytes of `chunk`, from the lowest, are ASCII digits.
#[inline]
fn leading_digits(chunk: u64) -> usize {
    const ZERO: u64 = 0x3030_3030_3030_3030;
    // A byte is a digit iff its high nibble is 3 and its low nibble at most 9 (adding 6
    // keeps the high nibble); bytes after the first non-digit may be garbled by a carry,
    // which does not matter.
    let not_digit = ((chunk & 0xF0F0_F0F0_F0F0_F0F0) ^ ZERO)
        | ((chunk.wrapping_add(0x0606_0606_0606_0606) & 0xF0F0_F0F0_F0F0_F0F0) ^ ZERO);
    (not_digit.trailing_zeros() / 8) as usize
}

/// The value of eight ASCII digits, the first in the lowest byte (three multiplications
/// instead of eight).
#[inline]
fn eight_digits_value(chunk: u64) -> u64 {
    let v = chunk - 0x3030_3030_3030_3030;
    let v = v.wrapping_mul(10) + (v >> 8); // pairs of digits
    let v1 = (v & 0x0000_00FF_0000_00FF).wrapping_mul(100 + (1_000_000 << 32));
    let v2 = ((v >> 16) & 0x0000_00FF_0000_00FF).wrapping_mul(1 + (10_000 << 32));
    (v1.wrapping_add(v2)) >> 32
}

/// 10^k for k ≤ 8.
const POW10_INT: [u64; 9] = [
    1,
    10,
    100,
    1_000,
    10_000,
    100_000,
    1_000_000,
    10_000_000,
    100_000_000,
];

/// Appends the decimal digits of `s` from `i` on to `w` (wrapping: the caller bounds the
/// count); returns where they end. Eight bytes at a time while the line has them.
#[inline(always)]
fn digits(s: &[u8], mut i: usize, w: &mut u64) -> usize {
    while let Some(bytes) = s.get(i..i + 8) {
        let chunk = u64::from_le_bytes([
            bytes[0], bytes[1], bytes[2], bytes[3], bytes[4], bytes[5], bytes[6], bytes[7],
        ]);
        let k = leading_digits(chunk);
        if k == 0 {
            return i;
        }
        // The k digits, moved to the top and preceded by '0's, read as eight digits.
        let padded = if k == 8 {
            chunk
        } else {
            (chunk << (8 * (8 - k))) | (0x3030_3030_3030_3030 >> (8 * k))
        };
        *w = w
            .wrapping_mul(POW10_INT[k])
            .wrapping_add(eight_digits_value(padded));
        i += k;
        if k < 8 {
            return i;
        }
    }
    while let Some(&c) = s.get(i) {
        if !c.is_ascii_digit() {
            break;
        }
        *w = w.wrapping_mul(10).wrapping_add(u64::from(c - b'0'));
        i += 1;
    }
    i
}

/// Reads a decimal number at the start of `s` (optional sign, digits with an optional
/// point, optional exponent) and returns it with the number of bytes read; `None` when there
/// is no such number or it needs the standard library (more than 19 digits, leading zeros
/// included; an
/// exponent outside [−27, 55] after normalisation, `inf`, `nan`).
#[inline(always)]
pub(super) fn scan_number(s: &[u8]) -> Option<(f64, usize)> {
    let n = s.len();
    let mut i = 0;
    let negative = match s.first() {
        Some(b'-') => {
            i = 1;
            true
        }
        Some(b'+') => {
            i = 1;
            false
        }
        _ => false,
    };
    let mut w: u64 = 0;
    let start = i;
    i = digits(s, i, &mut w);
    let mut count = i - start;
    let mut q: i32 = 0;
    if i < n && s[i] == b'.' {
        i += 1;
        let fraction = i;
        i = digits(s, i, &mut w);
        q = -((i - fraction) as i32);
        count += i - fraction;
    }
    // At most 19 digits (leading zeros included) cannot overflow 64 bits.
    if count == 0 || count > 19 {
        return None;
    }
    if i < n && (s[i] | 0x20) == b'e' {
        i += 1;
        let negative_exp = match s.get(i) {
            Some(b'-') => {
                i += 1;
                true
            }
            Some(b'+') => {
                i += 1;
                false
            }
            _ => false,
        };
        let digits = i;
        let mut e: i32 = 0;
        while i < n && s[i].is_ascii_digit() {
            if i - digits >= 4 {
                return None;
            }
            e = e * 10 + i32::from(s[i] - b'0');
            i += 1;
        }
        if i == digits {
            return None;
        }
        q += if negative_exp { -e } else { e };
    }
    let x = if w == 0 {
        0.0
    } else if w <= 1 << 53 && (0..=22).contains(&q) {
        // Both operands exact: the one rounding is the correct one (Clinger's fast path).
        // (For q < 0 it would divide, which is slower than Eisel–Lemire's multiplications.)
        w as f64 * POW10[q as usize]
    } else if (Q_MIN..=Q_MAX).contains(&q) {
        eisel_lemire(w, q)
    } else {
        return None;
    };
    Some((if negative { -x } else { x }, i))
}

/// Parses a decimal number (as Rust's `f64::from_str` does: optional sign, digits with an
/// optional point, optional exponent, or `inf`/`infinity`/`nan` in any case), correctly
/// rounded. Surrounding spaces are ignored. `None` if it is not a number.
///
/// Numbers of up to 19 digits with a moderate exponent — what traces hold, including the 17
/// digits of a shortest round-trip double — are converted here, exactly (Clinger's fast path
/// for integers times a power of ten, else Eisel–Lemire); the rest by the standard library.
#[inline]
pub fn parse_f64(s: &[u8]) -> Option<f64> {
    let s = trim(s);
    if let Some((x, len)) = scan_number(s)
        && len == s.len()
    {
        return Some(x);
    }
    std::str::from_utf8(s).ok()?.parse::<f64>().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_path_agrees_with_the_standard_parser() {
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
    fn powers_of_five() {
        assert_eq!(POW5[(0 - Q_MIN) as usize], 1 << 127);
        assert_eq!(POW5[(1 - Q_MIN) as usize], 5 << 125);
        // 1/5 = 0.110011001100…₂: 0xCCCC…CCCD after rounding up.
        assert_eq!(
            POW5[(-1 - Q_MIN) as usize],
            0xCCCC_CCCC_CCCC_CCCC_CCCC_CCCC_CCCC_CCCD
        );
        assert!(POW5.iter().all(|t| t.leading_zeros() == 0));
    }

    #[test]
    fn eisel_lemire_agrees_with_the_standard_library() {
        // Every exponent of the table, significands of every length up to 19 digits, ties.
        let mut w: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut checked = 0;
        for q in Q_MIN..=Q_MAX {
            for k in 0..2000u64 {
                w = w.rotate_left(17) ^ w.wrapping_mul(0x2545_F491_4F6C_DD1D);
                let digits = 1 + (k % 19) as u32;
                let m = (w % 10u64.pow(digits)).max(1);
                for m in [m, (1 << 53) + 1, 9_007_199_254_740_993 * 10, u64::MAX / 2] {
                    let expected: f64 = format!("{m}e{q}").parse().unwrap();
                    assert_eq!(eisel_lemire(m, q).to_bits(), expected.to_bits(), "{m}e{q}");
                    checked += 1;
                }
            }
        }
        assert!(checked > 600_000);
    }
}
