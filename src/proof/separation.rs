//! s* as a bracket: what a certificate's proofs and its witness pin the worst-case minimum
//! separation to.
//!
//! The proofs give a lower bound B (every behaviour separates by at least B); the witness is
//! one real behaviour, replayed exactly, so its separation r is at least s*. Both are stated
//! rounded down to floats, so s* lies in [B, r] up to r's last bit. A certificate states s*
//! only inside that bracket, and declares how wide the bracket is allowed to be
//! (`separation_tolerance`): [`SEPARATION_TOLERANCE`], or, for an inconclusive verdict only,
//! the bracket's own width rounded up (the analyser may fail to realise the worst piece on a
//! guard's boundary, and then s* is only known to lie between B and the next worst
//! behaviour). A decided verdict whose bracket is wider states no s* at all. `check` holds
//! every certificate kind to this ([`check_stated`]), so a stated s* is never more than the
//! declared tolerance away from the truth.

use crate::core::num::{Exact, exact_float, f64_at_least};
use crate::proof::verdict::{REPLAY_TOLERANCE, Verdict};

/// The bracket width a certificate declares unless its verdict says why not (m): the
/// analyser accepts a witness only when it replays this close to its piece's optimum.
pub const SEPARATION_TOLERANCE: f64 = REPLAY_TOLERANCE;

/// The floats that bracket s*: the proved lower bound and the witness's separation, each as
/// the certificate states it (rounded down).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bracket {
    /// B: the proved lower bound on s*.
    pub lower: f64,
    /// r: the witness's replayed separation (s* ≤ r up to its last bit).
    pub upper: f64,
}

impl Bracket {
    /// The bracket of a certificate: none without a proved bound or a witness that stops.
    pub fn of(lower: Option<f64>, upper: Option<f64>) -> Option<Bracket> {
        Some(Bracket {
            lower: lower?,
            upper: upper?,
        })
    }

    /// r − B, exactly.
    pub fn width(&self) -> Exact {
        exact_float(self.upper) - exact_float(self.lower)
    }

    /// The tolerance a certificate of `verdict` with this bracket declares, or None when the
    /// verdict may not state s* with it (a decided verdict with a bracket wider than
    /// [`SEPARATION_TOLERANCE`]).
    pub fn tolerance_for(&self, verdict: Verdict) -> Option<f64> {
        let width = self.width();
        if width <= exact_float(SEPARATION_TOLERANCE) {
            Some(SEPARATION_TOLERANCE)
        } else if verdict == Verdict::Inconclusive {
            Some(f64_at_least(&width))
        } else {
            None
        }
    }
}

/// What a certificate states of s*: the analyser's estimate moved into the bracket, and the
/// tolerance it declares. No s* (and the default tolerance) when there is no estimate, no
/// bracket, or the verdict may not state one with it.
pub fn stated(
    verdict: Verdict,
    estimate: Option<f64>,
    bracket: Option<Bracket>,
) -> (Option<f64>, f64) {
    let pinned = estimate.zip(bracket).and_then(|(s, b)| {
        let tolerance = b.tolerance_for(verdict)?;
        (b.lower <= b.upper).then(|| (s.clamp(b.lower, b.upper), tolerance))
    });
    match pinned {
        Some((s, tolerance)) => (Some(s), tolerance),
        None => (None, SEPARATION_TOLERANCE),
    }
}

/// Checks a certificate's stated s* (`stated`) and declared tolerance against its bracket
/// (built from its verified lower bound and witness separation); the error says what is
/// wrong in the certificate's terms.
/// What a certificate states about its outcome, for [`settle`].
#[derive(Clone, Copy, Debug)]
pub struct Stated {
    /// The stated verdict.
    pub verdict: Verdict,
    /// The stated s* (`min_separation`).
    pub min_separation: Option<f64>,
    /// The declared bracket width (`separation_tolerance`).
    pub tolerance: f64,
    /// The stated lower bound.
    pub lower_bound: Option<f64>,
    /// The stated separation of the witness.
    pub witness_separation: Option<f64>,
}

/// The verdict the evidence gives — `certified` when the proofs put s* above the clearance,
/// `refuted` when the replayed witness collides, else `inconclusive` — held to the stated
/// one, and the stated s* held to its bracket ([`check_stated`]). Shared by every
/// certificate kind's check, so that all of them settle an outcome alike.
pub fn settle(certified: bool, collides: bool, stated: Stated) -> Result<Verdict, String> {
    let verdict = match (certified, collides) {
        (true, true) => return Err("the proofs certify, yet the witness collides".into()),
        (true, false) => Verdict::Certified,
        (false, true) => Verdict::Refuted,
        (false, false) => Verdict::Inconclusive,
    };
    if verdict != stated.verdict {
        return Err(format!(
            "stated verdict {} does not follow; the evidence gives {}",
            stated.verdict.as_str(),
            verdict.as_str()
        ));
    }
    check_stated(
        verdict,
        stated.min_separation,
        stated.tolerance,
        Bracket::of(stated.lower_bound, stated.witness_separation),
    )?;
    Ok(verdict)
}

/// The stated s* held to its bracket: inside it, and the bracket no wider than the declared
/// tolerance.
pub fn check_stated(
    verdict: Verdict,
    stated: Option<f64>,
    tolerance: f64,
    bracket: Option<Bracket>,
) -> Result<(), String> {
    if let Some(b) = bracket
        && b.upper < b.lower
    {
        return Err(format!(
            "the witness separates by {} m, below the proved lower bound {} m: the proofs and \
             the witness contradict each other",
            b.upper, b.lower
        ));
    }
    let Some(s) = stated else {
        if tolerance != SEPARATION_TOLERANCE {
            return Err(format!(
                "separation_tolerance is {tolerance}, but no s* is stated (it must be the \
                 default {SEPARATION_TOLERANCE})"
            ));
        }
        return Ok(());
    };
    let Some(b) = bracket else {
        return Err(
            "min_separation is stated, but nothing pins it: it needs both a proved lower bound \
             and a witness that comes to rest"
                .into(),
        );
    };
    // r is the witness's separation rounded down: s* may lie up to its last bit above it.
    if !(b.lower <= s && s <= b.upper.next_up()) {
        return Err(format!(
            "min_separation {s} m lies outside its bracket [{}, {}] m (the proved lower bound \
             and the witness's separation)",
            b.lower, b.upper
        ));
    }
    match b.tolerance_for(verdict) {
        None => Err(format!(
            "the s* bracket [{}, {}] m is wider than the {SEPARATION_TOLERANCE} m a {} \
             certificate pins s* to, so it may not state min_separation",
            b.lower,
            b.upper,
            verdict.as_str()
        )),
        Some(expected) if expected != tolerance => Err(format!(
            "separation_tolerance is {tolerance}, but the s* bracket [{}, {}] m of this {} \
             certificate needs {expected}",
            b.lower,
            b.upper,
            verdict.as_str()
        )),
        Some(_) => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bracket(lower: f64, upper: f64) -> Option<Bracket> {
        Some(Bracket { lower, upper })
    }

    #[test]
    fn a_narrow_bracket_pins_s_star_for_every_verdict() {
        for v in [Verdict::Certified, Verdict::Refuted, Verdict::Inconclusive] {
            let b = bracket(0.33 - 1e-9, 0.33 + 1e-7);
            assert_eq!(stated(v, Some(0.33), b), (Some(0.33), SEPARATION_TOLERANCE));
            assert!(check_stated(v, Some(0.33), SEPARATION_TOLERANCE, b).is_ok());
            // An estimate outside the bracket is moved to its nearer end.
            assert_eq!(stated(v, Some(0.4), b).0, Some(0.33 + 1e-7));
            assert!(check_stated(v, Some(0.34), SEPARATION_TOLERANCE, b).is_err());
            let above = (0.33 + 1e-7f64).next_up();
            assert!(check_stated(v, Some(above), SEPARATION_TOLERANCE, b).is_ok());
            assert!(check_stated(v, Some(above.next_up()), SEPARATION_TOLERANCE, b).is_err());
            assert!(check_stated(v, Some(0.32), SEPARATION_TOLERANCE, b).is_err());
            // Declaring a wider tolerance than the bracket needs is refused.
            assert!(check_stated(v, Some(0.33), 1e-3, b).is_err());
        }
    }

    #[test]
    fn a_wide_bracket_is_stated_only_by_an_inconclusive_certificate() {
        let b = bracket(0.0, 0.25);
        for v in [Verdict::Certified, Verdict::Refuted] {
            assert_eq!(stated(v, Some(0.1), b), (None, SEPARATION_TOLERANCE));
            assert!(check_stated(v, Some(0.1), SEPARATION_TOLERANCE, b).is_err());
            assert!(check_stated(v, Some(0.1), 0.25, b).is_err());
            assert!(check_stated(v, None, SEPARATION_TOLERANCE, b).is_ok());
        }
        let v = Verdict::Inconclusive;
        assert_eq!(stated(v, Some(0.1), b), (Some(0.1), 0.25));
        assert!(check_stated(v, Some(0.1), 0.25, b).is_ok());
        assert!(check_stated(v, Some(0.1), SEPARATION_TOLERANCE, b).is_err());
    }

    #[test]
    fn the_declared_width_never_understates_the_exact_one() {
        // 0.1 and 0.3 as floats are 0.1000000000000000055… and 0.299999999999999988…; their
        // float difference rounds to nearest, which may be below the exact one.
        let b = Bracket {
            lower: 0.1,
            upper: 0.3,
        };
        let t = b.tolerance_for(Verdict::Inconclusive).unwrap();
        assert!(exact_float(t) >= b.width());
        assert!(exact_float(t.next_down()) < b.width());
    }

    #[test]
    fn s_star_needs_a_bracket_and_a_consistent_one() {
        let v = Verdict::Certified;
        assert!(check_stated(v, Some(0.3), SEPARATION_TOLERANCE, None).is_err());
        assert!(check_stated(v, None, SEPARATION_TOLERANCE, None).is_ok());
        assert!(check_stated(v, None, 0.5, None).is_err());
        assert!(check_stated(v, None, SEPARATION_TOLERANCE, bracket(0.3, 0.2)).is_err());
    }
}
