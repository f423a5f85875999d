//! Univariate polynomials over exact rationals, and the one question the planar replay asks
//! of them: does p(τ) fall to (or below) a threshold c somewhere on a closed interval
//! [a, b], and how low does it get? (docs/semantics.md §13.5; issue 36.)
//!
//! Within one control period the robot's and an obstacle's centres are polynomials in the
//! time τ since the period's start, so their squared separation D(τ) is a polynomial of
//! degree ≤ 4 with rational coefficients. A collision check must not sample τ nor round:
//! a forged witness could graze the threshold between samples, or touch it exactly. Every
//! answer here is decided in [`Exact`] arithmetic by *Sturm's theorem*:
//!
//! > Let q be square-free (no repeated roots) and q₀ = q, q₁ = q′, qᵢ₊₁ = −rem(qᵢ₋₁, qᵢ)
//! > until a remainder is 0 (the last qᵢ is then a nonzero constant). For a real x let
//! > V(x) be the number of sign changes in q₀(x), q₁(x), … with zeros dropped. Then for
//! > a < b the number of *distinct* real roots of q in the half-open interval (a, b] is
//! > V(a) − V(b).
//!
//! "Distinct" means a root is counted once whatever its multiplicity: (τ − 1)³ has one root.
//! A polynomial p that has repeated roots is first reduced to its square-free part
//! p / gcd(p, p′), which has the same roots, each simple. The half-open interval is what
//! the theorem gives when a or b is itself a root: V is right-continuous at a root of q
//! (just left of it q and q′ differ in sign, at and just right of it they do not, q being 0
//! at it and dropped), so a root at b is counted and a root at a is not. The decisions
//! ([`Polynomial::min_at_most`], [`Polynomial::min_below`]) and the bracket on the minimum
//! ([`Polynomial::minimum_on`]) are built on those counts and prove themselves in their
//! documentation.

use dashu_int::ops::Abs;

use std::ops::{Add, Mul, Neg, Sub};

use crate::core::num::Exact;

/// A polynomial c₀ + c₁τ + … + cₙτⁿ with exact rational coefficients.
///
/// The coefficients are stored from the constant term up and trimmed: the last one stored
/// is nonzero, and the zero polynomial stores none. So two polynomials are equal exactly when
/// they are the same function.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Polynomial {
    coefficients: Vec<Exact>,
}

/// An exact bracket on the minimum of a polynomial over a closed interval
/// ([`Polynomial::minimum_on`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MinimumBracket {
    /// Not above the minimum: p(τ) ≥ `lower` at every τ of the interval.
    pub lower: Exact,
    /// Not below the minimum, and attained: `upper` = p(`at`).
    pub upper: Exact,
    /// A point of the interval where p is `upper`, so within the asked width of the minimum.
    pub at: Exact,
}

impl Polynomial {
    /// The polynomial with these coefficients, constant term first (trailing zeros are
    /// dropped).
    pub fn new(mut coefficients: Vec<Exact>) -> Self {
        while coefficients.last().is_some_and(Exact::is_zero) {
            coefficients.pop();
        }
        Polynomial { coefficients }
    }

    /// The zero polynomial.
    pub fn zero() -> Self {
        Polynomial::new(Vec::new())
    }

    /// The constant polynomial c.
    pub fn constant(c: Exact) -> Self {
        Polynomial::new(vec![c])
    }

    /// The coefficients, constant term first, without trailing zeros (empty for zero).
    pub fn coefficients(&self) -> &[Exact] {
        &self.coefficients
    }

    /// Whether this is the zero polynomial.
    pub fn is_zero(&self) -> bool {
        self.coefficients.is_empty()
    }

    /// The degree; `None` for the zero polynomial (whose degree is −∞ by convention).
    pub fn degree(&self) -> Option<usize> {
        self.coefficients.len().checked_sub(1)
    }

    /// p(x), by Horner's rule.
    pub fn eval(&self, x: &Exact) -> Exact {
        self.coefficients
            .iter()
            .rev()
            .fold(Exact::ZERO, |acc, c| acc * x + c)
    }

    /// p′.
    pub fn derivative(&self) -> Self {
        Polynomial::new(
            self.coefficients
                .iter()
                .enumerate()
                .skip(1)
                .map(|(k, c)| c * Exact::from(k))
                .collect(),
        )
    }

    /// k·p.
    pub fn scale(&self, k: &Exact) -> Self {
        Polynomial::new(self.coefficients.iter().map(|c| c * k).collect())
    }

    /// The polynomial τ ↦ p(shift + scale·τ): p re-expressed around `shift` (its Taylor
    /// coefficients there, times powers of `scale`), by Horner's rule in polynomials.
    pub fn compose_affine(&self, shift: &Exact, scale: &Exact) -> Self {
        let inner = Polynomial::new(vec![shift.clone(), scale.clone()]);
        self.coefficients
            .iter()
            .rev()
            .fold(Polynomial::zero(), |acc, c| {
                &(&acc * &inner) + &Polynomial::constant(c.clone())
            })
    }

    /// Quotient and remainder of Euclidean division: p = q·divisor + r with r = 0 or
    /// deg r < deg divisor.
    ///
    /// # Panics
    /// If `divisor` is the zero polynomial.
    pub fn div_rem(&self, divisor: &Polynomial) -> (Polynomial, Polynomial) {
        let n = divisor.degree().expect("division by the zero polynomial");
        let lead = &divisor.coefficients[n];
        let mut rest = self.coefficients.clone();
        let mut quotient = vec![Exact::ZERO; rest.len().saturating_sub(n)];
        while rest.len() > n {
            let top = rest.len() - 1;
            let factor = &rest[top] / lead;
            for (k, d) in divisor.coefficients.iter().enumerate() {
                rest[top - n + k] -= &factor * d;
            }
            quotient[top - n] = factor;
            rest.pop(); // now exactly zero
        }
        (Polynomial::new(quotient), Polynomial::new(rest))
    }

    /// The remainder of Euclidean division ([`Polynomial::div_rem`]).
    ///
    /// # Panics
    /// If `divisor` is the zero polynomial.
    pub fn rem(&self, divisor: &Polynomial) -> Polynomial {
        self.div_rem(divisor).1
    }

    /// The same polynomial divided by its leading coefficient (zero stays zero).
    pub fn monic(&self) -> Polynomial {
        match self.coefficients.last() {
            Some(lead) => self.scale(&(Exact::ONE / lead)),
            None => Polynomial::zero(),
        }
    }

    /// The monic greatest common divisor (zero when both are zero), by Euclid's algorithm.
    pub fn gcd(&self, other: &Polynomial) -> Polynomial {
        let (mut a, mut b) = (self.monic(), other.monic());
        while !b.is_zero() {
            let r = a.rem(&b).monic();
            a = b;
            b = r;
        }
        a
    }

    /// p / gcd(p, p′): the same distinct roots, each simple (zero stays zero).
    pub fn square_free_part(&self) -> Polynomial {
        if self.is_zero() {
            return Polynomial::zero();
        }
        self.div_rem(&self.gcd(&self.derivative())).0
    }

    /// The Sturm sequence of p's square-free part q: q₀ = q, q₁ = q′, qᵢ₊₁ = −rem(qᵢ₋₁, qᵢ),
    /// up to the last nonzero term (a constant). Each term is divided by the absolute value
    /// of its leading coefficient, which changes no sign and keeps the numbers small. Empty
    /// for the zero polynomial.
    pub fn sturm_sequence(&self) -> Vec<Polynomial> {
        let positive = |p: Polynomial| match p.coefficients.last() {
            Some(lead) => {
                let magnitude = lead.clone().abs();
                p.scale(&(Exact::ONE / magnitude))
            }
            None => p,
        };
        let q = positive(self.square_free_part());
        if q.is_zero() {
            return Vec::new();
        }
        let mut sequence = vec![q.clone(), positive(q.derivative())];
        while !sequence[sequence.len() - 1].is_zero() {
            let n = sequence.len();
            let next = -&sequence[n - 2].rem(&sequence[n - 1]);
            sequence.push(positive(next));
        }
        sequence.pop(); // the zero remainder that ended it
        sequence
    }

    /// The number of distinct real roots in the half-open interval (a, b] (Sturm's theorem,
    /// in this module's documentation): a root at b is counted, one at a is not, a repeated
    /// root once. 0 when a ≥ b.
    ///
    /// # Panics
    /// If p is the zero polynomial (every point is a root).
    pub fn count_distinct_roots(&self, a: &Exact, b: &Exact) -> usize {
        RootCounter::new(self).count(a, b)
    }

    /// Isolating intervals for the distinct real roots in the closed interval [a, b], in
    /// increasing order: closed rational intervals [lo, hi] ⊆ [a, b], pairwise disjoint,
    /// each containing exactly one root and narrower than `width` (hi − lo < width). A root
    /// found exactly, such as one at a or b, is given as [r, r]; every other interval has
    /// ends that are not roots, so its root lies strictly inside. Empty when a > b.
    ///
    /// Bisection with Sturm counts: an interval holding several roots is split at its
    /// midpoint, one holding a single root is narrowed until both of its ends have moved
    /// inwards (so that neighbours cannot share an end) and it is narrow enough.
    ///
    /// # Panics
    /// If p is the zero polynomial, or if `width` ≤ 0.
    pub fn isolate_roots(&self, a: &Exact, b: &Exact, width: &Exact) -> Vec<(Exact, Exact)> {
        RootCounter::new(self).isolate(a, b, width)
    }

    /// Whether p(τ) ≤ c for some τ in [a, b] (false when a > b).
    ///
    /// Proof. Let f = p − c. If f(a) ≤ 0 or f(b) ≤ 0, yes. Otherwise f(a) > 0 and f(b) > 0
    /// (so f ≠ 0), and f ≤ 0 at some τ ∈ (a, b) exactly when f has a root in (a, b): a root
    /// is such a τ, and conversely f(a) > 0 ≥ f(τ) puts a root in (a, τ] by the intermediate
    /// value theorem. As b is not a root, that is a nonzero Sturm count on (a, b]. A root
    /// where p touches c from above (a double root of f) counts: p ≤ c holds there.
    pub fn min_at_most(&self, c: &Exact, a: &Exact, b: &Exact) -> bool {
        if a > b {
            return false;
        }
        let f = self - &Polynomial::constant(c.clone());
        if f.eval(a) <= Exact::ZERO || f.eval(b) <= Exact::ZERO {
            return true;
        }
        f.count_distinct_roots(a, b) > 0
    }

    /// Whether p(τ) < c for some τ in [a, b] (false when a > b). Unlike
    /// [`Polynomial::min_at_most`], a point where p touches c from above and turns back does
    /// not count.
    ///
    /// Proof. Let f = p − c. If f = 0, no; if f(a) < 0 or f(b) < 0, yes. Otherwise let
    /// a = z₀ < z₁ < … < z_m = b be a, b and the finitely many roots of f between them.
    /// f ≥ 0 at every zⱼ, and on each open gap (zⱼ, zⱼ₊₁) f has no root, hence (intermediate
    /// value theorem) one constant sign. So f < 0 somewhere exactly when it is negative at
    /// one rational point of some gap. Such points come from the isolating intervals of f's
    /// roots ([`Polynomial::isolate_roots`]), with [a, a] and [b, b] added at the ends: for
    /// consecutive intervals I ∋ zⱼ and J ∋ zⱼ₊₁ with I's end below J's start, the midpoint
    /// s of I's end and J's start has zⱼ ≤ end(I) < s < start(J) ≤ zⱼ₊₁, so it lies in the
    /// gap; and every gap has such a pair, the intervals being sorted and disjoint (only an
    /// added [a, a] or [b, b] may repeat a root's, and a repeat has no gap between). This
    /// decides a touching root (f ≥ 0 on both sides) from a crossing one exactly.
    pub fn min_below(&self, c: &Exact, a: &Exact, b: &Exact) -> bool {
        if a > b {
            return false;
        }
        let f = self - &Polynomial::constant(c.clone());
        if f.is_zero() {
            return false;
        }
        if f.eval(a) < Exact::ZERO || f.eval(b) < Exact::ZERO {
            return true;
        }
        let any_width = b - a + Exact::ONE;
        let mut marks = vec![(a.clone(), a.clone())];
        marks.extend(f.isolate_roots(a, b, &any_width));
        marks.push((b.clone(), b.clone()));
        marks.windows(2).any(|pair| {
            let (end, start) = (&pair[0].1, &pair[1].0);
            end < start && f.eval(&midpoint(end, start)) < Exact::ZERO
        })
    }

    /// An exact bracket [lower, upper] on m = min{p(τ) : τ ∈ [a, b]} with
    /// upper − lower < `width`, and a point `at` of [a, b] where p is `upper`.
    ///
    /// Proof. m is attained at a, at b, or at a root r of p′ inside (Fermat). Each such root
    /// lies in one isolating interval of p′ ([`Polynomial::isolate_roots`]) within [a, b].
    /// Over an interval with centre t and radius ρ, p(t + ρs) = Σ dₖsᵏ for s ∈ [−1, 1]
    /// ([`Polynomial::compose_affine`]), so p ≥ d₀ − Σₖ≥₁ |dₖ| there, and p(t) = d₀. So m is
    /// at least `lower`, the least of p(a), p(b) and those bounds, and at most `upper`, the
    /// least of p(a), p(b) and the values d₀ (each is p at a point of [a, b]). Each interval is
    /// narrowed (Sturm bisection of p′) until its gap Σₖ≥₁ |dₖ| is below `width`, which
    /// happens: as ρ → 0 every dₖ with k ≥ 1 carries a factor ρ. Then upper − lower < width:
    /// `lower` is an endpoint value (and `upper` ≤ it) or some interval's d₀ − gap with
    /// `upper` ≤ that d₀.
    ///
    /// # Panics
    /// If a > b or `width` ≤ 0.
    pub fn minimum_on(&self, a: &Exact, b: &Exact, width: &Exact) -> MinimumBracket {
        assert!(a <= b, "minimum_on an empty interval");
        assert!(*width > Exact::ZERO, "minimum_on to a width ≤ 0");
        let mut best = MinimumBracket {
            lower: self.eval(a),
            upper: self.eval(a),
            at: a.clone(),
        };
        let mut consider = |lower: Exact, upper: Exact, at: &Exact| {
            if lower < best.lower {
                best.lower = lower;
            }
            if upper < best.upper {
                best.upper = upper;
                best.at = at.clone();
            }
        };
        let at_b = self.eval(b);
        consider(at_b.clone(), at_b, b);
        let slope = self.derivative();
        if slope.is_zero() {
            return best;
        }
        let critical = RootCounter::new(&slope);
        let any_width = b - a + Exact::ONE;
        for (mut lo, mut hi) in critical.isolate(a, b, &any_width) {
            loop {
                if lo == hi {
                    let value = self.eval(&lo);
                    consider(value.clone(), value, &lo);
                    break;
                }
                let centre = midpoint(&lo, &hi);
                let radius = (&hi - &lo) / Exact::from(2);
                let around = self.compose_affine(&centre, &radius);
                let (d0, rest) = around
                    .coefficients
                    .split_first()
                    .map_or((Exact::ZERO, &[][..]), |(d0, rest)| (d0.clone(), rest));
                let gap = rest
                    .iter()
                    .fold(Exact::ZERO, |sum, d| sum + d.clone().abs());
                if gap < *width {
                    consider(&d0 - &gap, d0, &centre);
                    break;
                }
                let half = &radius;
                (lo, hi) = critical.refine(&lo, &hi, half);
            }
        }
        best
    }
}

/// (x + y) / 2.
fn midpoint(x: &Exact, y: &Exact) -> Exact {
    (x + y) / Exact::from(2)
}

/// A nonzero polynomial with its Sturm sequence, for the many counts one isolation makes.
struct RootCounter<'p> {
    poly: &'p Polynomial,
    sturm: Vec<Polynomial>,
}

impl<'p> RootCounter<'p> {
    /// # Panics
    /// If `poly` is zero: its roots cannot be counted.
    fn new(poly: &'p Polynomial) -> Self {
        assert!(
            !poly.is_zero(),
            "the roots of the zero polynomial are every point"
        );
        RootCounter {
            poly,
            sturm: poly.sturm_sequence(),
        }
    }

    /// V(x): sign changes along the Sturm sequence at x, zeros dropped.
    fn variations(&self, x: &Exact) -> usize {
        let signs = self
            .sturm
            .iter()
            .map(|q| q.eval(x))
            .filter(|v| !v.is_zero())
            .map(|v| v > Exact::ZERO);
        let mut changes = 0;
        let mut previous = None;
        for positive in signs {
            if previous.is_some_and(|p| p != positive) {
                changes += 1;
            }
            previous = Some(positive);
        }
        changes
    }

    /// Distinct roots in (lo, hi]; 0 when lo ≥ hi.
    fn count(&self, lo: &Exact, hi: &Exact) -> usize {
        if lo >= hi {
            return 0;
        }
        // V is non-increasing in x for a Sturm sequence, so this never underflows.
        self.variations(lo) - self.variations(hi)
    }

    /// Distinct roots in the open (lo, hi).
    fn count_open(&self, lo: &Exact, hi: &Exact) -> usize {
        let closed_at_hi = self.count(lo, hi);
        if lo < hi && self.is_root(hi) {
            closed_at_hi - 1
        } else {
            closed_at_hi
        }
    }

    fn is_root(&self, x: &Exact) -> bool {
        self.poly.eval(x).is_zero()
    }

    /// [`Polynomial::isolate_roots`].
    fn isolate(&self, a: &Exact, b: &Exact, width: &Exact) -> Vec<(Exact, Exact)> {
        assert!(*width > Exact::ZERO, "isolating roots to a width ≤ 0");
        let mut found = Vec::new();
        if a > b {
            return found;
        }
        if self.is_root(a) {
            found.push((a.clone(), a.clone()));
        }
        if a == b {
            return found;
        }
        self.split(a, b, self.count_open(a, b), width, &mut found);
        if self.is_root(b) {
            found.push((b.clone(), b.clone()));
        }
        found
    }

    /// Appends isolating intervals, in order, for the `roots` distinct roots in the open
    /// (lo, hi).
    fn split(
        &self,
        lo: &Exact,
        hi: &Exact,
        roots: usize,
        width: &Exact,
        found: &mut Vec<(Exact, Exact)>,
    ) {
        match roots {
            0 => {}
            1 => found.push(self.refine(lo, hi, width)),
            _ => {
                let mid = midpoint(lo, hi);
                if self.is_root(&mid) {
                    self.split(lo, &mid, self.count(lo, &mid) - 1, width, found);
                    found.push((mid.clone(), mid.clone()));
                } else {
                    self.split(lo, &mid, self.count(lo, &mid), width, found);
                }
                self.split(&mid, hi, self.count_open(&mid, hi), width, found);
            }
        }
    }

    /// For exactly one distinct root in the open (lo, hi) (whose ends may be roots): an
    /// interval inside it, narrower than `width`, that holds the root and either is [r, r]
    /// or has both ends moved strictly inwards, at points that are not roots.
    fn refine(&self, lo: &Exact, hi: &Exact, width: &Exact) -> (Exact, Exact) {
        let (mut lo, mut hi) = (lo.clone(), hi.clone());
        let (mut lo_moved, mut hi_moved) = (false, false);
        loop {
            if lo_moved && hi_moved && &hi - &lo < *width {
                return (lo, hi);
            }
            let mid = midpoint(&lo, &hi);
            if self.is_root(&mid) {
                return (mid.clone(), mid);
            }
            // mid is not a root, so (lo, mid] counts the open (lo, mid).
            if self.count(&lo, &mid) == 1 {
                hi = mid;
                hi_moved = true;
            } else {
                lo = mid;
                lo_moved = true;
            }
        }
    }
}

impl Add for &Polynomial {
    type Output = Polynomial;
    fn add(self, other: &Polynomial) -> Polynomial {
        let (long, short) = if self.coefficients.len() >= other.coefficients.len() {
            (self, other)
        } else {
            (other, self)
        };
        let mut sum = long.coefficients.clone();
        for (s, c) in sum.iter_mut().zip(&short.coefficients) {
            *s += c;
        }
        Polynomial::new(sum)
    }
}

impl Neg for &Polynomial {
    type Output = Polynomial;
    fn neg(self) -> Polynomial {
        Polynomial::new(self.coefficients.iter().map(|c| -c.clone()).collect())
    }
}

impl Sub for &Polynomial {
    type Output = Polynomial;
    fn sub(self, other: &Polynomial) -> Polynomial {
        self + &(-other)
    }
}

impl Mul for &Polynomial {
    type Output = Polynomial;
    fn mul(self, other: &Polynomial) -> Polynomial {
        if self.is_zero() || other.is_zero() {
            return Polynomial::zero();
        }
        let mut product = vec![Exact::ZERO; self.coefficients.len() + other.coefficients.len() - 1];
        for (i, x) in self.coefficients.iter().enumerate() {
            for (j, y) in other.coefficients.iter().enumerate() {
                product[i + j] += x * y;
            }
        }
        Polynomial::new(product)
    }
}
