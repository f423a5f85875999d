//! The explorer's actions: the finite set of obstacle speeds it chooses from each period,
//! read from `--speeds` exactly (a count, decimals or fractions), and exact numbers shown as
//! the decimals or fractions they are.

use std::fmt;

use super::{ExploreError, MAX_SPEEDS};
use crate::core::num::{Exact, exact_decimal};

/// The finite set of obstacle speeds the explorer chooses from each period: distinct, exact,
/// within [0, W], in ascending order (the fixed action order).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SpeedSet {
    speeds: Vec<Exact>,
}

impl SpeedSet {
    /// `n` evenly spaced speeds from 0 to W, both included: {0, W/(n−1), …, W} (n ≥ 2;
    /// with W = 0 the set is {0}).
    pub fn evenly_spaced(w: &Exact, n: usize) -> Result<SpeedSet, ExploreError> {
        let spec = n.to_string();
        if n < 2 {
            return Err(ExploreError::Speeds {
                spec,
                reason: "a count must be at least 2 (0 and W); for one explicit speed write \
                         it with a decimal point, e.g. --speeds 0.0"
                    .into(),
            });
        }
        if n > MAX_SPEEDS {
            return Err(ExploreError::Speeds {
                spec,
                reason: format!("at most {MAX_SPEEDS} speeds"),
            });
        }
        let step = w.clone() / Exact::from(n - 1);
        let speeds = (0..n).map(|i| step.clone() * Exact::from(i)).collect();
        Self::from_list(w, speeds, &spec)
    }

    /// An explicit set (sorted and deduplicated here); every speed must lie in [0, W].
    pub fn from_list(
        w: &Exact,
        mut speeds: Vec<Exact>,
        spec: &str,
    ) -> Result<SpeedSet, ExploreError> {
        if speeds.is_empty() {
            return Err(ExploreError::Speeds {
                spec: spec.into(),
                reason: "no speeds given".into(),
            });
        }
        if let Some(bad) = speeds.iter().find(|s| **s < Exact::ZERO || *s > w) {
            return Err(ExploreError::Speeds {
                spec: spec.into(),
                reason: format!(
                    "speed {} m/s is outside [0, W] = [0, {}] m/s (environment.obstacle_speed)",
                    show_exact(bad),
                    show_exact(w)
                ),
            });
        }
        speeds.sort();
        speeds.dedup();
        if speeds.len() > MAX_SPEEDS {
            return Err(ExploreError::Speeds {
                spec: spec.into(),
                reason: format!("at most {MAX_SPEEDS} speeds"),
            });
        }
        Ok(SpeedSet { speeds })
    }

    /// Reads `--speeds`: a bare whole number N is a count (N evenly spaced speeds from 0 to
    /// W); anything else is a comma-separated list of speeds in m/s, each a decimal (`0.05`,
    /// read as the decimal it is, like problem files) or a fraction (`3/80`).
    pub fn parse(spec: &str, w: &Exact) -> Result<SpeedSet, ExploreError> {
        let text = spec.trim();
        let bad = |reason: String| ExploreError::Speeds {
            spec: spec.to_string(),
            reason,
        };
        if !text.is_empty() && text.bytes().all(|b| b.is_ascii_digit()) {
            let n: usize = text
                .parse()
                .map_err(|_| bad(format!("count too large (at most {MAX_SPEEDS})")))?;
            return Self::evenly_spaced(w, n).map_err(|e| match e {
                ExploreError::Speeds { reason, .. } => bad(reason),
                other => other,
            });
        }
        let mut speeds = Vec::new();
        for (i, item) in text.split(',').map(str::trim).enumerate() {
            // An empty element (`0,,0.15`) is a typo, not nothing: refused, not skipped.
            if item.is_empty() {
                return Err(bad(format!("element {} is empty", i + 1)));
            }
            speeds.push(parse_speed(item).map_err(|reason| bad(format!("`{item}`: {reason}")))?);
        }
        Self::from_list(w, speeds, spec)
    }

    /// The speeds, ascending.
    pub fn speeds(&self) -> &[Exact] {
        &self.speeds
    }

    /// Number of speeds (actions per state).
    pub fn len(&self) -> usize {
        self.speeds.len()
    }

    /// Always false: a speed set has at least one speed.
    pub fn is_empty(&self) -> bool {
        self.speeds.is_empty()
    }
}

impl fmt::Display for SpeedSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let items: Vec<String> = self.speeds.iter().map(show_exact).collect();
        write!(f, "{{{}}}", items.join(", "))
    }
}

pub(super) fn parse_speed(item: &str) -> Result<Exact, String> {
    if let Some((num, den)) = item.split_once('/') {
        let n: Exact = num
            .trim()
            .parse()
            .map_err(|_| "not a number (write a decimal like 0.05 or a fraction like 3/80)")?;
        let d: Exact = den
            .trim()
            .parse()
            .map_err(|_| "not a number (write a decimal like 0.05 or a fraction like 3/80)")?;
        if d == Exact::ZERO {
            return Err("division by zero".into());
        }
        return Ok(n / d);
    }
    let x: f64 = item
        .parse()
        .map_err(|_| "not a number (write a decimal like 0.05 or a fraction like 3/80)")?;
    if !x.is_finite() {
        return Err("must be finite".into());
    }
    Ok(exact_decimal(x))
}

/// An exact number as text: a terminating decimal when it is one (`0.0375`), else the
/// reduced fraction (`1/30`).
pub fn show_exact(x: &Exact) -> String {
    let den = x.denominator().clone();
    let mut d = den.clone();
    let (two, five) = (dashu_int::UBig::from(2u8), dashu_int::UBig::from(5u8));
    let mut digits = 0usize;
    let mut twos = 0usize;
    let mut fives = 0usize;
    while (&d % &two) == dashu_int::UBig::ZERO {
        d /= &two;
        twos += 1;
    }
    while (&d % &five) == dashu_int::UBig::ZERO {
        d /= &five;
        fives += 1;
    }
    if d != dashu_int::UBig::ONE || twos.max(fives) > 30 {
        return x.to_string();
    }
    digits += twos.max(fives);
    let scaled = x.numerator().clone() * dashu_int::IBig::from(10u8).pow(digits)
        / dashu_int::IBig::from(den);
    let negative = scaled < dashu_int::IBig::ZERO;
    let mut s = if negative {
        (-scaled).to_string()
    } else {
        scaled.to_string()
    };
    if digits > 0 {
        if s.len() <= digits {
            s = format!("{}{s}", "0".repeat(digits + 1 - s.len()));
        }
        s.insert(s.len() - digits, '.');
    }
    if negative {
        s.insert(0, '-');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_numbers_show_as_decimals_when_they_terminate() {
        let q = |n: i64, d: i64| Exact::from(n) / Exact::from(d);
        assert_eq!(show_exact(&q(3, 80)), "0.0375");
        assert_eq!(show_exact(&q(-58, 100)), "-0.58");
        assert_eq!(show_exact(&q(1, 30)), "1/30");
        assert_eq!(show_exact(&q(7, 1)), "7");
        assert_eq!(show_exact(&Exact::ZERO), "0");
        assert_eq!(show_exact(&q(-1, 200)), "-0.005");
    }
}
