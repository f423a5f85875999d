//! Certificates: `check` accepts every certificate the analyser writes, for every verdict,
//! and rejects every tampered one — an edit left with the old digest is named as such, and a
//! forgery that recomputes the digest is caught by the exact re-verification.

use proptest::prelude::*;
use safereach::analysis::{Verdict, analyse};
use safereach::core::model::{DangerRule, Problem};
use safereach::proof::certificate::{Certificate, check};

use crate::common::forgery::{
    self, Edit, FORGERIES, PROBLEM_EDITS, resign, unsigned_edits_named_as_such,
};
use crate::common::paths::seed_file;
use crate::common::spec::{Spec, any_spec_uniform_w, config};

fn certificate(spec: &Spec) -> Certificate {
    let a = analyse(&spec.problem()).expect("analysis");
    Certificate::from_analysis(&a)
}

/// A certified problem (the seed scenario).
fn certified() -> Certificate {
    let cert = certificate(&Spec::seed());
    assert_eq!(cert.verdict, Verdict::Certified);
    cert
}

/// A refuted problem whose robot brakes too late (an obstacle faster than assumed, no
/// wrong-assumption guard).
fn refuted() -> Certificate {
    let cert = certificate(&Spec {
        w: 0.6,
        wab: false,
        ..Spec::seed()
    });
    assert_eq!(cert.verdict, Verdict::Refuted);
    assert!(cert.witness.is_some());
    cert
}

/// A refuted problem whose robot may never brake: the obstacle jumps over a tiny area.
fn never_stops() -> Certificate {
    let cert = certificate(&Spec {
        rule: DangerRule::Area,
        rho: 0.05,
        ..Spec::seed()
    });
    assert_eq!(cert.verdict, Verdict::Refuted);
    assert!(cert.never_stops, "{:?}", cert.min_separation);
    cert
}

/// The problem files shipped with the crate load and their certificates check.
#[test]
fn shipped_problem_certificates_check() {
    let seed = Problem::load(&seed_file()).expect("loads");
    let cert = Certificate::from_analysis(&analyse(&seed).expect("analysis"));
    assert_eq!(cert.verdict, Verdict::Certified);
    check(&cert).expect("the seed's certificate checks");
}

// ---------------------------------------------------------------------------------------------
// check accepts what the analyser writes
// ---------------------------------------------------------------------------------------------

fn accepted(spec: &Spec) -> Result<(), TestCaseError> {
    let a = analyse(&spec.problem()).expect("analysis");
    let cert = Certificate::from_analysis(&a);
    let report = check(&cert);
    prop_assert!(report.is_ok(), "{:?} rejected: {:?}", spec, report);
    let report = report.unwrap();
    prop_assert_eq!(report.verdict, a.verdict, "{:?}", spec);
    prop_assert_eq!(&report.lower_bound, &a.lower_bound, "{:?}", spec);
    prop_assert_eq!(report.pieces, a.outcomes.len(), "{:?}", spec);
    // The file round-trips.
    let text = serde_json::to_string(&cert).expect("serialises");
    let back: Certificate = serde_json::from_str(&text).expect("parses");
    prop_assert_eq!(&back, &cert, "{:?}", spec);
    prop_assert!(check(&back).is_ok(), "{:?}", spec);
    Ok(())
}

proptest! {
    #![proptest_config(config(64))]

    #[test]
    fn check_accepts_every_certificate_the_analyser_writes(spec in any_spec_uniform_w()) {
        accepted(&spec)?;
    }
}

#[test]
fn check_accepts_every_verdict() {
    let seed = Spec::seed();
    let cases = [
        seed,
        Spec { w: 0.0, ..seed },
        Spec {
            w: 0.6,
            wab: false,
            ..seed
        },
        Spec { w: 0.6, ..seed },
        Spec {
            rule: DangerRule::Area,
            rho: 0.05,
            ..seed
        },
        Spec {
            rule: DangerRule::Kinematic,
            latency: 3,
            ..seed
        },
        // The robot is still accelerating, and stops mid-step.
        Spec { g0: 0.9, ..seed },
        // The obstacle starts inside the area: with latency 0 the robot never moves.
        Spec {
            g0: 1.0,
            latency: 0,
            rule: DangerRule::Area,
            ..seed
        },
    ];
    let mut verdicts = Vec::new();
    for spec in cases {
        accepted(&spec).unwrap_or_else(|e| panic!("{e}"));
        verdicts.push(certificate(&spec).verdict);
    }
    assert!(verdicts.contains(&Verdict::Certified));
    assert!(verdicts.contains(&Verdict::Refuted));
}

#[test]
fn json_round_trip_keeps_the_certificate() {
    for cert in [certified(), refuted(), never_stops()] {
        for text in [
            serde_json::to_string(&cert).unwrap(),
            serde_json::to_string_pretty(&cert).unwrap(),
        ] {
            let back: Certificate = serde_json::from_str(&text).expect("parses");
            assert_eq!(back, cert);
            assert_eq!(back.compute_digest(), cert.digest);
            check(&back).expect("still checks");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Tampering
// ---------------------------------------------------------------------------------------------

#[test]
fn edits_without_a_new_digest_are_named_as_such() {
    for (name, cert) in [("certified", certified()), ("refuted", refuted())] {
        let applied = unsigned_edits_named_as_such(name, &cert);
        assert!(applied >= 6, "{name}: only {applied} edits applied");
    }
}

/// Whether the claims of a certificate whose problem was edited are still true of the edited
/// problem (same verdict and lower bound as its honest certificate): then the old proofs may
/// well prove it, and accepting them is no mistake. (A robot that never moves, for one, is
/// safe whatever the obstacle's speed.)
fn claims_still_true(forged: &Certificate) -> bool {
    let honest = Certificate::from_analysis(&analyse(&forged.problem).expect("analysis"));
    honest.verdict == forged.verdict && honest.lower_bound == forged.lower_bound
}

/// Checks every applicable forgery of `cert` (see [`forgery::forgeries_rejected`]).
fn forgeries_rejected(name: &str, cert: &Certificate) -> Result<usize, String> {
    forgery::forgeries_rejected(name, cert, claims_still_true)
}

#[test]
fn re_signed_forgeries_are_rejected() {
    assert_eq!(
        FORGERIES[PROBLEM_EDITS - 1].0,
        "clearance raised above s* of a certified problem"
    );
    let run = |name: &str, cert: &Certificate| {
        forgeries_rejected(name, cert).unwrap_or_else(|e| panic!("{e}"))
    };
    let c = run("certified", &certified());
    let r = run("refuted", &refuted());
    let n = run("never stops", &never_stops());
    assert!(c >= 20 && r >= 20 && n >= 12, "applied: {c}, {r}, {n}");
}

#[test]
fn a_certificate_of_another_problem_is_rejected() {
    let seed = Spec::seed();
    let mut cert = certified();
    let other = Spec {
        w: 0.6,
        wab: false,
        ..seed
    };
    cert.problem = other.problem();
    resign(&mut cert);
    assert!(check(&cert).is_err());
    // The same pieces (only W differs and W stays below V_a), other bounds.
    let mut cert = certified();
    cert.problem = Spec { w: 0.1, ..seed }.problem();
    resign(&mut cert);
    assert!(check(&cert).is_err());
}

proptest! {
    #![proptest_config(config(24))]

    /// Forgeries of certificates of random problems, every verdict.
    #[test]
    fn forgeries_of_random_certificates_are_rejected(spec in any_spec_uniform_w()) {
        let cert = certificate(&spec);
        let result = forgeries_rejected(&format!("{spec:?}"), &cert);
        prop_assert!(result.is_ok(), "{}", result.unwrap_err());
    }
}

/// A certificate without a witness still states s* (`min_separation`) and `never_stops`;
/// `check` must not accept those claims unverified. Four re-signed forgeries: the seed's
/// certificate with its witness removed and s* inflated, or `never_stops` claimed; and the
/// certificate of a robot that never moves (it sees the obstacle in its area before it
/// starts, so every piece is infeasible and there is no witness) with an invented s* or
/// `never_stops`.
/// (Regression: `check` used to verify these claims only through the witness.)
#[test]
fn claims_without_a_witness_are_rejected() {
    let never_moves = certificate(&Spec {
        rule: DangerRule::Area,
        latency: 0,
        g0: 1.0,
        ..Spec::seed()
    });
    assert!(never_moves.witness.is_none() && never_moves.min_separation.is_none());
    check(&never_moves).expect("the honest certificate checks");
    let forgeries: [(&str, Certificate, Edit); 4] = [
        ("seed: witness removed, s* inflated", certified(), |c| {
            c.witness = None;
            c.min_separation = Some(100.0);
            Some(())
        }),
        (
            "seed: witness removed, never_stops claimed",
            certified(),
            |c| {
                c.witness = None;
                c.min_separation = None;
                c.never_stops = true;
                Some(())
            },
        ),
        ("robot never moves: s* invented", never_moves.clone(), |c| {
            c.min_separation = Some(-1.0);
            Some(())
        }),
        ("robot never moves: never_stops claimed", never_moves, |c| {
            c.never_stops = true;
            Some(())
        }),
    ];
    let mut accepted = Vec::new();
    for (what, mut forged, edit) in forgeries {
        edit(&mut forged).expect("applies");
        resign(&mut forged);
        if let Ok(report) = check(&forged) {
            accepted.push(format!("{what} (checked as {})", report.verdict.as_str()));
        }
    }
    assert!(accepted.is_empty(), "forgeries accepted: {accepted:#?}");
}
