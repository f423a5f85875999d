//! Certificates: `check` accepts every certificate the analyser writes, for every verdict,
//! and rejects every tampered one — an edit left with the old digest is named as such, and a
//! forgery that recomputes the digest is caught by the exact re-verification.

use proptest::prelude::*;
use proptest::test_runner::{Config as ProptestConfig, RngSeed};
use safereach::analysis::{Verdict, analyse};
use safereach::core::model::{Controller, DangerRule, Environment, Problem, Robot};
use safereach::core::num::f64_at_most;
use safereach::proof::certificate::{Certificate, check, premises};
use safereach::proof::program::ProofKind;
use safereach::proof::schedule::Decomposition;

// ---------------------------------------------------------------------------------------------
// Problems built in code
// ---------------------------------------------------------------------------------------------

/// The numbers of a problem, in the order a problem file lists them.
#[derive(Clone, Copy, Debug)]
struct Spec {
    v_max: f64,
    a: f64,
    b: f64,
    dt: f64,
    latency: u32,
    clearance: f64,
    v_a: f64,
    rho: f64,
    rule: DangerRule,
    buffer: f64,
    wab: bool,
    w: f64,
    g0: f64,
}

impl Spec {
    /// The seed paper's scenario with a robot of our choosing.
    fn seed() -> Spec {
        Spec {
            v_max: 0.8,
            a: 0.4,
            b: 0.5,
            dt: 0.1,
            latency: 1,
            clearance: 0.0,
            v_a: 0.2,
            rho: 1.4,
            rule: DangerRule::Paper,
            buffer: 0.1,
            wab: true,
            w: 0.15,
            g0: 10.0,
        }
    }

    fn problem(&self) -> Problem {
        let p = Problem {
            name: "test".into(),
            robot: Robot {
                max_speed: self.v_max,
                acceleration: self.a,
                braking: self.b,
                control_period: self.dt,
                latency: self.latency,
                clearance: self.clearance,
            },
            controller: Controller {
                assumed_obstacle_speed: self.v_a,
                reaction_radius: self.rho,
                danger_rule: self.rule,
                buffer: self.buffer,
                wrong_assumption_brake: self.wab,
            },
            environment: Environment {
                obstacle_speed: self.w,
                initial_gap: self.g0,
            },
        };
        p.validate("test problem").expect("test problems are valid");
        p
    }
}

/// A number with two decimals in [lo, hi] hundredths.
fn cents(lo: u32, hi: u32) -> impl Strategy<Value = f64> {
    (lo..=hi).prop_map(|i| f64::from(i) / 100.0)
}

/// Problems over every danger rule, latencies 0..=3, the guard on and off, W below and above
/// V_a, short and long initial gaps.
fn any_spec() -> impl Strategy<Value = Spec> {
    let robot = (
        cents(20, 200),
        cents(20, 200),
        cents(20, 300),
        cents(5, 20),
        0u32..=3,
        cents(0, 20),
    );
    let controller = (
        cents(0, 50),
        cents(10, 300),
        prop_oneof![
            Just(DangerRule::Paper),
            Just(DangerRule::Kinematic),
            Just(DangerRule::Area),
        ],
        cents(0, 30),
        any::<bool>(),
    );
    let environment = (cents(0, 100), prop_oneof![cents(30, 300), cents(500, 3000)]);
    (robot, controller, environment).prop_map(
        |((v_max, a, b, dt, latency, clearance), (v_a, rho, rule, buffer, wab), (w, g0))| Spec {
            v_max,
            a,
            b,
            dt,
            latency,
            clearance,
            v_a,
            rho,
            rule,
            buffer,
            wab,
            w,
            g0,
        },
    )
}

/// `cases` cases from a fixed seed (reproducible in CI); `PROPTEST_RNG_SEED=n` explores others.
fn config(cases: u32) -> ProptestConfig {
    let mut config = ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    };
    if config.rng_seed == RngSeed::Random {
        config.rng_seed = RngSeed::Fixed(0x5afe_4ead);
    }
    config
}

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
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/problems");
    let seed = Problem::load(std::path::Path::new(&format!("{dir}/seed.toml"))).expect("loads");
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
    fn check_accepts_every_certificate_the_analyser_writes(spec in any_spec()) {
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

/// An edit to a certificate; `None` when it does not apply to this certificate.
type Edit = fn(&mut Certificate) -> Option<()>;

/// Index of the first proof with a bound (not an infeasibility proof).
fn bound_proof(cert: &Certificate) -> Option<usize> {
    cert.proofs
        .iter()
        .position(|p| p.kind == Some(ProofKind::Bound))
}

/// Whether proof `i`'s multipliers now prove another bound than the one stated. (Any
/// multipliers ≥ 0 prove *some* bound; at an exact tie a changed multiplier can prove the
/// same one, and then the edit forges nothing.)
fn proves_another_bound(c: &Certificate, i: usize) -> bool {
    let proof = &c.proofs[i];
    let program = Decomposition::new(&c.problem).program(&proof.piece);
    program
        .bound(&proof.multipliers, true)
        .map(|b| f64_at_most(&b))
        != proof.bound
}

/// Changes one witness speed to another in [0, W].
fn change_witness_speed(c: &mut Certificate) -> Option<()> {
    let w_max = c.problem.environment.obstacle_speed;
    if w_max == 0.0 {
        return None;
    }
    let w = c.witness.as_mut()?;
    let k = w.obstacle_speeds.len().checked_sub(3)?;
    let s = &mut w.obstacle_speeds[k];
    *s = if *s > w_max / 2.0 { 0.0 } else { w_max };
    Some(())
}

/// Edits of numbers (and one of structure) that any honest tool would have to re-sign.
const NUMBER_EDITS: &[(&str, Edit)] = &[
    ("obstacle speed W", |c| {
        c.problem.environment.obstacle_speed += 0.01;
        Some(())
    }),
    ("reaction radius", |c| {
        c.problem.controller.reaction_radius += 0.01;
        Some(())
    }),
    ("a multiplier", |c| {
        let i = bound_proof(c)?;
        let z = &mut c.proofs[i].multipliers[0];
        *z = *z * 2.0 + 1.0;
        Some(())
    }),
    ("the lower bound", |c| {
        let lb = c.lower_bound.as_mut()?;
        *lb += 1e-3;
        Some(())
    }),
    ("min_separation", |c| {
        let s = c.min_separation.as_mut()?;
        *s += 1e-3;
        Some(())
    }),
    ("a witness speed", change_witness_speed),
    ("the verdict", |c| {
        c.verdict = match c.verdict {
            Verdict::Certified => Verdict::Refuted,
            _ => Verdict::Certified,
        };
        Some(())
    }),
    ("a dropped proof", |c| {
        c.proofs.pop()?;
        Some(())
    }),
];

#[test]
fn edits_without_a_new_digest_are_named_as_such() {
    for (name, cert) in [("certified", certified()), ("refuted", refuted())] {
        let mut applied = 0;
        for (what, edit) in NUMBER_EDITS {
            let mut forged = cert.clone();
            if edit(&mut forged).is_none() {
                continue;
            }
            applied += 1;
            assert!(forged != cert, "{what}: no edit");
            let err = check(&forged).expect_err(&format!("{name}: edited {what}, accepted"));
            assert!(
                err.0.contains("digest"),
                "{name}: edited {what}: the message does not name the digest: {err}"
            );
        }
        assert!(applied >= 6, "{name}: only {applied} edits applied");
    }
}

/// Rewrites the derived fields of a forged certificate as a forger would (premises and
/// clearance from the edited problem, the piece count) and signs it again.
fn resign(c: &mut Certificate) {
    c.premises = premises(&c.problem);
    c.clearance = c.problem.robot.clearance;
    c.pieces = c.proofs.len();
    c.digest = c.compute_digest();
}

/// Forgeries: each edit is re-signed with a correct digest (and consistent premises), so
/// only the exact re-verification can reject it. Edits of the problem come first (see
/// [`PROBLEM_EDITS`]).
const FORGERIES: &[(&str, Edit)] = &[
    ("W raised", |c| {
        c.problem.environment.obstacle_speed += 0.05;
        Some(())
    }),
    ("W lowered", |c| {
        let w = &mut c.problem.environment.obstacle_speed;
        if *w < 0.02 {
            return None;
        }
        *w -= 0.01;
        Some(())
    }),
    ("reaction radius raised", |c| {
        c.problem.controller.reaction_radius += 0.1;
        Some(())
    }),
    ("reaction radius lowered", |c| {
        c.problem.controller.reaction_radius -= 0.1;
        Some(())
    }),
    ("initial gap raised", |c| {
        c.problem.environment.initial_gap += 1.0;
        Some(())
    }),
    ("latency raised", |c| {
        c.problem.robot.latency += 1;
        Some(())
    }),
    ("latency lowered", |c| {
        c.problem.robot.latency = c.problem.robot.latency.checked_sub(1)?;
        Some(())
    }),
    ("clearance raised above s* of a certified problem", |c| {
        if c.verdict != Verdict::Certified {
            return None;
        }
        c.problem.robot.clearance = c.min_separation? + 0.05;
        Some(())
    }),
    // ---- end of problem edits ----
    ("last proof dropped", |c| {
        c.proofs.pop()?;
        Some(())
    }),
    ("first proof dropped", |c| {
        if c.proofs.is_empty() {
            return None;
        }
        c.proofs.remove(0);
        Some(())
    }),
    ("proofs reordered", |c| {
        if c.proofs.len() < 2 {
            return None;
        }
        c.proofs.swap(0, 1);
        Some(())
    }),
    ("proofs reversed", |c| {
        if c.proofs.len() < 2 {
            return None;
        }
        c.proofs.reverse();
        Some(())
    }),
    ("a bound proof's stated bound raised", |c| {
        let i = bound_proof(c)?;
        let b = c.proofs[i].bound.as_mut()?;
        *b += 1e-6;
        Some(())
    }),
    ("a bound proof's stated bound lowered", |c| {
        let i = bound_proof(c)?;
        let b = c.proofs[i].bound.as_mut()?;
        *b -= 1.0;
        Some(())
    }),
    ("a bound proof turned into an infeasibility proof", |c| {
        let i = bound_proof(c)?;
        c.proofs[i].kind = Some(ProofKind::Infeasible);
        Some(())
    }),
    ("a proof removed from a fully proved certificate", |c| {
        c.lower_bound?;
        let i = bound_proof(c)?;
        c.proofs[i].kind = None;
        c.proofs[i].multipliers.clear();
        c.proofs[i].bound = None;
        Some(())
    }),
    ("the largest multiplier of a bound proof doubled", |c| {
        let i = bound_proof(c)?;
        let z = &mut c.proofs[i].multipliers;
        let j = (0..z.len()).max_by(|&a, &b| z[a].total_cmp(&z[b]))?;
        z[j] *= 2.0;
        proves_another_bound(c, i).then_some(())
    }),
    ("a zero multiplier of a bound proof set to 1", |c| {
        let i = bound_proof(c)?;
        let z = c.proofs[i].multipliers.iter_mut().find(|z| **z == 0.0)?;
        *z = 1.0;
        proves_another_bound(c, i).then_some(())
    }),
    ("a multiplier dropped", |c| {
        let i = bound_proof(c)?;
        c.proofs[i].multipliers.pop()?;
        Some(())
    }),
    ("lower bound raised", |c| {
        let lb = c.lower_bound.as_mut()?;
        *lb += 1e-3;
        Some(())
    }),
    ("lower bound invented", |c| {
        if c.lower_bound.is_some() {
            return None;
        }
        c.lower_bound = Some(1.0);
        Some(())
    }),
    ("refuted -> certified", |c| {
        if c.verdict != Verdict::Refuted {
            return None;
        }
        c.verdict = Verdict::Certified;
        Some(())
    }),
    ("refuted -> inconclusive", |c| {
        if c.verdict != Verdict::Refuted {
            return None;
        }
        c.verdict = Verdict::Inconclusive;
        Some(())
    }),
    ("certified -> inconclusive", |c| {
        if c.verdict != Verdict::Certified {
            return None;
        }
        c.verdict = Verdict::Inconclusive;
        Some(())
    }),
    ("certified -> refuted", |c| {
        if c.verdict != Verdict::Certified {
            return None;
        }
        c.verdict = Verdict::Refuted;
        Some(())
    }),
    ("a witness speed changed", change_witness_speed),
    ("a witness speed above W", |c| {
        let w_max = c.problem.environment.obstacle_speed;
        let w = c.witness.as_mut()?;
        *w.obstacle_speeds.first_mut()? = w_max * 1.5 + 0.01;
        Some(())
    }),
    ("witness speeds cut short", |c| {
        let w = c.witness.as_mut()?;
        w.obstacle_speeds.pop()?;
        Some(())
    }),
    ("the witness's collision flag flipped", |c| {
        let w = c.witness.as_mut()?;
        w.collides = !w.collides;
        Some(())
    }),
    ("the witness removed from a refutation", |c| {
        if c.verdict != Verdict::Refuted {
            return None;
        }
        c.witness.take()?;
        Some(())
    }),
    ("min_separation moved", |c| {
        let s = c.min_separation.as_mut()?;
        *s += 1e-3;
        Some(())
    }),
    ("never_stops claimed against a witness", |c| {
        if c.never_stops || c.witness.is_none() {
            return None;
        }
        c.never_stops = true;
        c.min_separation = None;
        Some(())
    }),
];

/// How many of [`FORGERIES`] edit the problem.
const PROBLEM_EDITS: usize = 8;

/// Whether the claims of a certificate whose problem was edited are still true of the edited
/// problem (same verdict and lower bound as its honest certificate): then the old proofs may
/// well prove it, and accepting them is no mistake. (A robot that never moves, for one, is
/// safe whatever the obstacle's speed.)
fn claims_still_true(forged: &Certificate) -> bool {
    let honest = Certificate::from_analysis(&analyse(&forged.problem).expect("analysis"));
    honest.verdict == forged.verdict && honest.lower_bound == forged.lower_bound
}

/// Checks every applicable forgery of `cert`; returns how many applied, or the first one
/// `check` accepted.
fn forgeries_rejected(name: &str, cert: &Certificate) -> Result<usize, String> {
    check(cert).map_err(|e| format!("{name}: the honest certificate is rejected: {e}"))?;
    let mut applied = 0;
    for (i, (what, edit)) in FORGERIES.iter().enumerate() {
        let mut forged = cert.clone();
        if edit(&mut forged).is_none() {
            continue;
        }
        resign(&mut forged);
        if i < PROBLEM_EDITS
            && forged.problem.validate("forged").is_ok()
            && claims_still_true(&forged)
        {
            continue;
        }
        applied += 1;
        if forged == *cert {
            return Err(format!("{name}: {what}: no edit"));
        }
        match check(&forged) {
            Ok(report) => {
                return Err(format!(
                    "{name}: forgery accepted: {what} (report {report:?})"
                ));
            }
            Err(e) if e.0.contains("digest") => {
                return Err(format!(
                    "{name}: {what}: a re-signed forgery is blamed on the digest: {e}"
                ));
            }
            Err(_) => {}
        }
    }
    Ok(applied)
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
    fn forgeries_of_random_certificates_are_rejected(spec in any_spec()) {
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
