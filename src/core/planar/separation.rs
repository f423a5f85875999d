//! One obstacle's separation over a run's moving instants (docs/semantics.md §13.5): the
//! squared centre distance D(τ) on each piece of each period, an exact bracket on its
//! minimum, and the exact collision decision ([`Track`]).
//!
//! **Why the bracket is sound.** On a [`PathPiece::On`] piece the robot's centre is
//! P + u·(s(τ) − A) (segment start P, rational unit direction u, arc start A) and the
//! obstacle's x + w·τ, so D(τ) is a polynomial of degree ≤ 4 with rational coefficients,
//! and [`Polynomial::minimum_on`] brackets its minimum exactly. On a
//! [`PathPiece::Straddle`] [c_lo, c_hi] (a surd vertex crossing) the robot is, at each
//! instant, on one of the listed segments, and D(τ) there equals that segment's polynomial
//! D_j(τ) (each extended over the whole interval). So D ≥ min_j min_{[c_lo, c_hi]} D_j, and
//! each D_j is bounded below by its Taylor form about the interval's centre t with radius ρ:
//! D_j(t + ρσ) = Σ d_k σ^k ≥ d₀ − Σ_{k≥1} |d_k| for σ ∈ [−1, 1]. No upper value is needed
//! there: c_lo and c_hi end the neighbouring pieces, whose attained values bound the minimum
//! from above, and because c_R is continuous at the vertex those values differ from D at
//! the crossing by at most max|D′|·2⁻⁶⁰. The moving instants of a period that ends at rest
//! τ_r are [0, τ_r); the infimum over them is the minimum over [0, τ_r] (continuity), which
//! is what the bracket bounds; only the collision decision tells the open end apart.
//!
//! Separations are σ = √D − r (r = r_R + r_i); the square root of each end of the bracket
//! is taken outwards in rationals (exactly when D is a rational square).

use dashu_int::ops::Abs;

use crate::core::num::{Exact, f64_at_least};
use crate::core::plane::direction::sqrt_bounds;
use crate::core::plane::point::Point;
use crate::core::plane::rational_path::RationalPath;
use crate::core::polynomial::Polynomial;

use super::pieces::PathPiece;

/// An exact bracket on one obstacle's least separation over a run's moving instants.
#[derive(Clone, Debug, PartialEq)]
pub struct Separation {
    /// Every moving instant's separation is ≥ this.
    pub lower: Exact,
    /// Some instant near `at` separates by at most this (≥ `lower`).
    pub upper: Exact,
    /// The closest instant (s since t = 0): D there is the bracket's upper end, or, when the
    /// minimum is contact (D = 0 at an irrational instant), a point within 2⁻⁹⁰ s of it.
    pub at: Exact,
}

/// How narrow D's bracket is made on each piece (m²).
fn width() -> Exact {
    Exact::ONE / Exact::from(2u128.pow(90))
}

/// One stored piece of D, for the collision decision.
#[derive(Clone, Debug)]
enum Stored {
    Exact {
        /// The period's start (s since t = 0); `from` and `to` are since it.
        t0: Exact,
        from: Exact,
        to: Exact,
        d: Polynomial,
        open_end: bool,
    },
    Bounded {
        lower: Exact,
    },
}

/// One obstacle's separation as the replay goes. The pieces are stored as they come and
/// bracketed only when asked, least-looking first (by a float estimate), so that a piece
/// whose sound Taylor bound is at least the best value attained is never minimised
/// exactly: a run of hundreds of periods minimises a handful of pieces, not every one.
#[derive(Clone, Debug)]
pub struct Track {
    radii: Exact,
    /// The least lower bound of the straddle pieces (bounded, never minimised).
    bounded: Option<Exact>,
    stored: Vec<Stored>,
    /// The bracket on D's minimum over every piece so far, once computed.
    bracket: std::cell::OnceCell<Bracket>,
}

/// An exact bracket on D's minimum: every instant's D is ≥ `lower`, and D at the instant
/// `upper.1` is `upper.0` (None: no moving instant yet).
#[derive(Clone, Debug)]
struct Bracket {
    lower: Option<Exact>,
    upper: Option<(Exact, Exact)>,
    /// The upper value rounded up to a float (+∞ before there is one).
    upper_float: f64,
}

impl Default for Bracket {
    fn default() -> Self {
        Bracket {
            lower: None,
            upper: None,
            upper_float: f64::INFINITY,
        }
    }
}

impl Bracket {
    fn lower_to(&mut self, value: &Exact) {
        if self.lower.as_ref().is_none_or(|l| value < l) {
            self.lower = Some(value.clone());
        }
    }

    fn upper_to(&mut self, value: &Exact, at: Exact) {
        if self.upper.as_ref().is_none_or(|(u, _)| value < u) {
            self.upper = Some((value.clone(), at));
            self.upper_float = f64_at_least(value);
        }
    }

    /// Brackets D's minimum on [from, to] of the period from `t0` into this one, skipping
    /// the work when a cheap bound shows the piece cannot hold the minimum (its Taylor
    /// bound is at least the best attained value, so it changes neither end of the final
    /// bracket: the lower end is at most that attained value).
    fn add(&mut self, d: &Polynomial, floats: &[f64], from: &Exact, to: &Exact, t0: &Exact) {
        if let Some((best, _)) = &self.upper {
            // The float bound first: most pieces are far above the best, and it is proved
            // to sit below the exact Taylor bound ([`float_taylor_lower`]).
            let (a, b) = (from.to_f64().value(), to.to_f64().value());
            if float_taylor_lower(floats, a, b) >= self.upper_float {
                return;
            }
            if taylor_lower(d, from, to) >= *best {
                return;
            }
        }
        let m = d.minimum_on(from, to, &width());
        if m.lower <= Exact::ZERO && d.min_at_most(&Exact::ZERO, from, to) {
            // Contact: D ≥ 0 is a sum of squares, so its minimum is exactly 0.
            let at = if d.eval(from).is_zero() {
                from.clone()
            } else {
                let roots = d.isolate_roots(from, to, &width());
                let (lo, hi) = roots.first().expect("a root, by min_at_most");
                (lo + hi) / Exact::from(2)
            };
            self.lower_to(&Exact::ZERO);
            self.upper_to(&Exact::ZERO, t0 + at);
            return;
        }
        self.lower_to(&m.lower.max(Exact::ZERO));
        self.upper_to(&m.upper, t0 + m.at);
    }
}

/// A float estimate of D's least value on [from, to] (its ends and middle): only an order
/// to bracket the pieces in, never a bound.
fn estimate(c: &[f64], from: &Exact, to: &Exact) -> f64 {
    // In floats throughout: exact evaluation cost more than the exact bracketing it orders.
    let eval = |t: f64| c.iter().rev().fold(0.0, |acc, a| acc * t + a);
    let (a, b) = (from.to_f64().value(), to.to_f64().value());
    [a, (a + b) / 2.0, b]
        .into_iter()
        .map(eval)
        .fold(f64::INFINITY, f64::min)
}

impl Track {
    /// An empty track for radii sum r = r_R + r_i.
    pub fn new(radii: Exact) -> Self {
        Track {
            radii,
            bounded: None,
            stored: Vec::new(),
            bracket: std::cell::OnceCell::new(),
        }
    }

    /// Adds one period's pieces: the period starts at `t0`, the obstacle is at `x` then and
    /// moves at `w`. Returns whether D ≤ `fall` somewhere on them (the occlusion test; a
    /// straddle whose bound reaches it counts, which only shows the obstacle earlier).
    pub fn add_period(
        &mut self,
        path: &RationalPath,
        pieces: &[PathPiece],
        t0: &Exact,
        x: &Point,
        w: &Point,
        fall: Option<&Exact>,
    ) -> bool {
        let mut fell = false;
        self.bracket = std::cell::OnceCell::new();
        for piece in pieces {
            match piece {
                PathPiece::On {
                    from,
                    to,
                    segment,
                    arc,
                    rests_at_end,
                } => {
                    let d = squared_distance(path, *segment, arc, x, w);
                    fell |= fall.is_some_and(|c| d.min_at_most(c, from, to));
                    self.stored.push(Stored::Exact {
                        t0: t0.clone(),
                        from: from.clone(),
                        to: to.clone(),
                        d,
                        open_end: *rests_at_end,
                    });
                }
                PathPiece::Straddle {
                    from,
                    to,
                    segments,
                    arc,
                } => {
                    let lower = (segments.0..=segments.1)
                        .map(|j| taylor_lower(&squared_distance(path, j, arc, x, w), from, to))
                        .min()
                        .expect("at least one segment");
                    let lower = lower.max(Exact::ZERO);
                    fell |= fall.is_some_and(|c| lower <= *c);
                    if self.bounded.as_ref().is_none_or(|b| lower < *b) {
                        self.bounded = Some(lower.clone());
                    }
                    self.stored.push(Stored::Bounded { lower });
                }
            }
        }
        fell
    }

    /// The bracket so far (None: no moving instant yet).
    pub fn separation(&self) -> Option<Separation> {
        let bracket = self.bracket.get_or_init(|| self.bracketed());
        let lower = bracket.lower.as_ref()?;
        let (upper, at) = bracket.upper.as_ref()?;
        Some(Separation {
            lower: sqrt_bounds(lower).0 - &self.radii,
            upper: sqrt_bounds(upper).1 - &self.radii,
            at: at.clone(),
        })
    }

    /// The bracket over every piece so far, the least-looking pieces first.
    fn bracketed(&self) -> Bracket {
        let mut bracket = Bracket::default();
        if let Some(b) = &self.bounded {
            bracket.lower_to(b);
        }
        let mut order: Vec<(f64, usize, Vec<f64>)> = self
            .stored
            .iter()
            .enumerate()
            .filter_map(|(k, s)| match s {
                Stored::Exact { from, to, d, .. } => {
                    let floats = d
                        .coefficients()
                        .iter()
                        .map(|x| x.to_f64().value())
                        .collect::<Vec<f64>>();
                    Some((estimate(&floats, from, to), k, floats))
                }
                Stored::Bounded { .. } => None,
            })
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for (_, k, floats) in order {
            if let Stored::Exact {
                t0, from, to, d, ..
            } = &self.stored[k]
            {
                bracket.add(d, &floats, from, to, t0);
            }
        }
        bracket
    }

    /// Whether some moving instant separates by ≤ `clearance`: decided exactly on every
    /// piece of a rational crossing (Sturm, [`Polynomial::min_at_most`]; at an end where the
    /// robot rests the instant itself does not count), and None only when the answer rests
    /// on a surd crossing's bound alone.
    pub fn collides(&self, clearance: &Exact) -> Option<bool> {
        let reach = clearance + &self.radii;
        if reach < Exact::ZERO {
            return Some(false); // σ ≥ −r always
        }
        if let Some(s) = self.separation() {
            if s.lower > *clearance {
                return Some(false);
            }
            if s.upper < *clearance {
                return Some(true);
            }
        }
        let c = &reach * &reach;
        let mut unsure = false;
        for piece in &self.stored {
            match piece {
                Stored::Exact {
                    from,
                    to,
                    d,
                    open_end,
                    ..
                } => {
                    if reaches(d, &c, from, to, *open_end) {
                        return Some(true);
                    }
                }
                Stored::Bounded { lower } => unsure |= *lower <= c,
            }
        }
        (!unsure).then_some(false)
    }
}

/// Whether d(τ) ≤ c at some τ of [from, to], or of [from, to) when `open_end`.
fn reaches(d: &Polynomial, c: &Exact, from: &Exact, to: &Exact, open_end: bool) -> bool {
    if !open_end {
        return d.min_at_most(c, from, to);
    }
    if d.min_below(c, from, to) {
        return true; // d < c at a point, hence on a neighbourhood, hence before `to`
    }
    // Now d ≥ c on [from, to]: does d touch c before `to`?
    let f = d - &Polynomial::constant(c.clone());
    if f.is_zero() || f.eval(from).is_zero() {
        return true;
    }
    let at_end = usize::from(f.eval(to).is_zero());
    f.count_distinct_roots(from, to) > at_end
}

/// D(τ) = ‖c_R(τ) − c_i(τ)‖² with the robot on `segment` at arc length `arc(τ)` and the
/// obstacle at x + w·τ.
fn squared_distance(
    path: &RationalPath,
    segment: usize,
    arc: &Polynomial,
    x: &Point,
    w: &Point,
) -> Polynomial {
    let seg = &path.segments()[segment];
    let u = seg.direction.unit();
    let along = arc - &Polynomial::constant(seg.arc_start.clone());
    let coordinate = |start: &Exact, dir: &Exact, at: &Exact, speed: &Exact| {
        let robot = &Polynomial::constant(start.clone()) + &along.scale(dir);
        let obstacle = Polynomial::new(vec![at.clone(), speed.clone()]);
        &robot - &obstacle
    };
    let dx = coordinate(&seg.start.x, &u.x, &x.x, &w.x);
    let dy = coordinate(&seg.start.y, &u.y, &x.y, &w.y);
    &(&dx * &dx) + &(&dy * &dy)
}

/// A float at most [`taylor_lower`] of the polynomial with coefficients `c` (each the
/// nearest float to an exact one) on [a, b] (the floats nearest the exact ends), or −∞.
///
/// *Why it is below.* The Taylor coefficients about m = (a + b)/2 with radius h are
/// d_k = Σ_{j≥k} c_j·C(j, k)·m^{j−k}·h^k; in floats each term is a product of at most
/// 2·deg + 2 roundings of relative error u = 2⁻⁵³ (the coefficients', the ends' and m's
/// and h's own included, |m| + |h| ≤ max(|a|, |b|)·(1 + u)), and each sum adds deg more. So every
/// computed quantity is within 30·u·M of its exact value, M := Σ_j |c_j|·(|m| + |h|)^j,
/// for degree ≤ 4 and with M itself off by far less than its size, and d₀ − Σ|d_k| in
/// floats is within 60·u·M < 10⁻¹⁴·M of the exact Taylor bound. Taking 10⁻¹⁰·M off is
/// below it with a margin of 10⁴; a degree above 4, or a value out of the float range,
/// gives −∞ (no claim).
fn float_taylor_lower(c: &[f64], a: f64, b: f64) -> f64 {
    if c.len() > 5 || !(a.is_finite() && b.is_finite()) {
        return f64::NEG_INFINITY;
    }
    let m = (a + b) / 2.0;
    let h = (b - a) / 2.0;
    let reach = m.abs() + h.abs();
    let mut d = [0.0f64; 5];
    let mut magnitude = 0.0;
    for (j, &cj) in c.iter().enumerate() {
        magnitude += cj.abs() * reach.powi(j as i32);
        let mut binom = 1.0;
        for (k, dk) in d.iter_mut().enumerate().take(j + 1) {
            *dk += cj * binom * m.powi((j - k) as i32) * h.powi(k as i32);
            binom = binom * (j - k) as f64 / (k + 1) as f64;
        }
    }
    let lower = d[0] - d[1..].iter().map(|x| x.abs()).sum::<f64>() - 1e-10 * magnitude;
    if lower.is_finite() && magnitude.is_finite() {
        lower
    } else {
        f64::NEG_INFINITY
    }
}

/// A lower bound on p over [from, to]: its Taylor form about the centre (module docs).
fn taylor_lower(p: &Polynomial, from: &Exact, to: &Exact) -> Exact {
    let centre = (from + to) / Exact::from(2);
    let radius = (to - from) / Exact::from(2);
    let around = p.compose_affine(&centre, &radius);
    let mut coefficients = around.coefficients().iter();
    let d0 = coefficients.next().cloned().unwrap_or(Exact::ZERO);
    coefficients.fold(d0, |acc, d| acc - d.clone().abs())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::num::{exact_decimal, exact_float};
    use proptest::prelude::*;

    proptest! {
        /// The float prefilter never claims more than the exact Taylor bound it stands in
        /// for, on polynomials of a squared distance's size and degree.
        #[test]
        fn the_float_taylor_bound_is_below_the_exact_one(
            c in proptest::collection::vec(-200.0f64..200.0, 1..6),
            t0 in 0.0f64..50.0,
            width in 0.0f64..0.2,
        ) {
            let exact: Vec<Exact> = c.iter().map(|&x| exact_decimal(x)).collect();
            let p = Polynomial::new(exact.clone());
            let (from, to) = (exact_decimal(t0), exact_decimal(t0 + width));
            let floats: Vec<f64> = exact.iter().map(|x| x.to_f64().value()).collect();
            let f = float_taylor_lower(&floats, from.to_f64().value(), to.to_f64().value());
            if f.is_finite() {
                prop_assert!(exact_float(f) <= taylor_lower(&p, &from, &to));
            }
        }
    }
}
