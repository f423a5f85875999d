//! What a robot embeds, tested as it is built there: without the solver
//! (`cargo test --release --no-default-features --test lean`). Nothing here can write a
//! certificate, so the tests read the committed fixtures (tests/fixtures/, written by the
//! binary and kept current by `it::fixtures`) and hold the exact check and the runtime
//! monitor to them:
//!
//! - `check` accepts each fixture and re-derives its verdict and bound;
//! - tampered copies (a number edited and the old digest left, or re-signed forgeries: a
//!   changed multiplier, bound or problem key, a dropped proof, …) are rejected;
//! - the monitor holds on a trace within the certificate's premises, flags a faster obstacle
//!   at the first sample that shows it, under the right premise, and refuses certificates
//!   that are not valid and certified.

#[allow(dead_code)] // the scaffolding of tests/it; this binary uses the solver-free part
#[path = "../it/common/mod.rs"]
mod common;

use safereach::core::num::f64_at_most;
use safereach::monitor::trace::Format;
use safereach::monitor::{Check, Event, Monitor, MonitorError, Verdict as Monitored};
use safereach::proof::certificate::{Certificate, check};
use safereach::proof::scene_certificate::SceneCertificate;
use safereach::proof::scene_check::check_scene;
use safereach::proof::verdict::Verdict;

use common::fixtures::{FIXTURES, Fixture, Kind};
use common::forgery::{self, Edit, bound_proof, resign, unsigned_edits_named_as_such};
use common::monitoring::text_events;

/// The certified fixture the traces are monitored against (the seed, W = 0.15 m/s).
const SEED: &Fixture = &FIXTURES[0];
/// A run of the seed itself: within [`SEED`]'s premises (JSON Lines).
const HELD_TRACE: &Fixture = &FIXTURES[3];
/// A run of the seed with obstacles up to 0.25 m/s: faster than [`SEED`] allows (CSV).
const FAST_TRACE: &Fixture = &FIXTURES[4];

/// The certificate fixtures, each with the verdict it was written with.
fn certificates() -> impl Iterator<Item = (&'static Fixture, Verdict)> {
    FIXTURES.iter().filter_map(|f| match f.kind {
        Kind::Certificate(verdict) => Some((f, verdict)),
        Kind::SceneCertificate(_) | Kind::Trace { .. } => None,
    })
}

/// The scene certificate fixtures, each with the verdict it was written with.
fn scene_certificates() -> impl Iterator<Item = (&'static Fixture, Verdict)> {
    FIXTURES.iter().filter_map(|f| match f.kind {
        Kind::SceneCertificate(verdict) => Some((f, verdict)),
        _ => None,
    })
}

/// An edit of a scene certificate.
type SceneEdit = fn(&mut SceneCertificate);

/// Scene certificates check without the solver; edits without a new digest are named as
/// such; re-signed edits of an obstacle, its lane or a proof are rejected.
#[test]
fn scene_certificates_check_and_reject_tampering_without_the_solver() {
    let mut seen = 0;
    for (f, verdict) in scene_certificates() {
        seen += 1;
        let cert = f.scene_certificate();
        let report = check_scene(&cert).unwrap_or_else(|e| panic!("{}: rejected: {e}", f.file));
        assert_eq!(report.verdict, verdict, "{}", f.file);
        assert_eq!(report.pieces, cert.pieces(), "{}", f.file);
        let witness = cert.witness.as_ref().expect("a witness");
        assert_eq!(witness.collides, verdict == Verdict::Refuted, "{}", f.file);
        let mut unsigned = cert.clone();
        unsigned.scene.obstacles[0].max_speed += 0.01;
        let err = check_scene(&unsigned).expect_err("an edit");
        assert!(err.0.contains("digest"), "{}: {err}", f.file);
        let reseal = |mut c: SceneCertificate| {
            c.digest = c.compute_digest();
            c
        };
        let edits: [(&str, SceneEdit); 4] = [
            ("obstacle faster", |c| {
                c.scene.obstacles[0].max_speed += 0.05
            }),
            ("obstacle nearer", |c| {
                c.scene.obstacles[0].position =
                    safereach::core::scene::Position::At(c.scene.obstacles[0].position.min() - 1.0)
            }),
            ("obstacle moved to another lane", |c| {
                c.scene.lanes = vec![0, 1];
                c.scene.obstacles[0].lane = 1;
            }),
            ("a proof's bound raised", |c| {
                let o = &mut c.obstacles[0];
                if let Some(p) = o
                    .own
                    .iter_mut()
                    .chain(o.bystanders.iter_mut())
                    .find(|p| p.bound.is_some())
                {
                    *p.bound.as_mut().unwrap() += 1e-6;
                }
            }),
        ];
        for (what, edit) in edits {
            let mut forged = cert.clone();
            edit(&mut forged);
            let err = check_scene(&reseal(forged)).expect_err(what);
            assert!(!err.0.contains("digest"), "{}: {what}: {err}", f.file);
        }
    }
    assert_eq!(seen, 2, "the scene certificate fixtures");
}

fn seed() -> Certificate {
    let cert = SEED.certificate();
    assert_eq!(cert.verdict, Verdict::Certified, "{}", SEED.file);
    cert
}

// ------------------------------------------------------------------------------------------
// check
// ------------------------------------------------------------------------------------------

#[test]
fn check_accepts_each_fixture_and_rederives_its_verdict() {
    for (f, verdict) in certificates() {
        let cert = f.certificate();
        assert_eq!(cert.verdict, verdict, "{}", f.file);
        let report = check(&cert).unwrap_or_else(|e| panic!("{}: rejected: {e}", f.file));
        assert_eq!(report.verdict, verdict, "{}", f.file);
        assert_eq!(report.pieces, cert.proofs.len(), "{}", f.file);
        assert_eq!(
            report.lower_bound.as_ref().map(f64_at_most),
            cert.lower_bound,
            "{}",
            f.file
        );
        // Each fixture has a witness: a collision exactly when refuted.
        let witness = cert.witness.as_ref().expect("a witness");
        assert_eq!(witness.collides, verdict == Verdict::Refuted, "{}", f.file);
        // Written and read again, it is the same certificate with the same digest.
        let text = serde_json::to_string(&cert).expect("serialises");
        let back: Certificate = serde_json::from_str(&text).expect("parses");
        assert_eq!(back, cert, "{}", f.file);
        assert_eq!(back.compute_digest(), cert.digest, "{}", f.file);
    }
}

#[test]
fn edits_of_a_fixture_without_a_new_digest_are_named_as_such() {
    for (f, _) in certificates() {
        let applied = unsigned_edits_named_as_such(f.file, &f.certificate());
        assert!(applied >= 6, "{}: only {applied} edits applied", f.file);
    }
}

/// Every forgery of the catalogue, re-signed. `it::certificate` skips edits of the problem
/// whose claims the analyser finds still true; without the analyser none is skipped: the
/// fixtures' problems are such that no edit of the catalogue leaves their claims true.
#[test]
fn re_signed_forgeries_of_a_fixture_are_rejected() {
    for (f, _) in certificates() {
        let cert = f.certificate();
        let applied =
            forgery::forgeries_rejected(f.file, &cert, |_| false).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            applied >= 15,
            "{}: only {applied} forgeries applied",
            f.file
        );
    }
}

/// Tampering of each kind, re-signed as a forger would, on the seed's certificate: each is
/// rejected for what it changed.
#[test]
fn each_kind_of_tampering_is_rejected_for_its_reason() {
    let cases: [(&str, Edit, &str); 7] = [
        (
            "a multiplier changed",
            |c| {
                let i = bound_proof(c)?;
                let z = &mut c.proofs[i].multipliers;
                let j = (0..z.len()).max_by(|&a, &b| z[a].total_cmp(&z[b]))?;
                z[j] *= 2.0;
                Some(())
            },
            "multipliers prove",
        ),
        (
            "a proof's bound raised",
            |c| {
                let i = bound_proof(c)?;
                *c.proofs[i].bound.as_mut()? += 1e-6;
                Some(())
            },
            "stated bound",
        ),
        (
            "the lower bound raised",
            |c| {
                *c.lower_bound.as_mut()? += 1e-3;
                Some(())
            },
            "stated lower bound",
        ),
        (
            "a proof dropped",
            |c| {
                c.proofs.pop()?;
                Some(())
            },
            "pieces",
        ),
        // Above V_a the wrong-assumption guard adds a piece.
        (
            "W raised above V_a",
            |c| {
                c.problem.environment.obstacle_speed = 0.3;
                Some(())
            },
            "pieces",
        ),
        // A slower obstacle: the robot brakes later, another piece.
        (
            "W lowered",
            |c| {
                c.problem.environment.obstacle_speed = 0.1;
                Some(())
            },
            "proof 0 is for",
        ),
        (
            "braking weakened",
            |c| {
                c.problem.robot.braking = 0.04;
                Some(())
            },
            "multipliers prove",
        ),
    ];
    let cert = seed();
    for (what, edit, reason) in cases {
        let mut forged = cert.clone();
        edit(&mut forged).expect("applies");
        resign(&mut forged);
        let err = check(&forged).expect_err(what);
        assert!(err.0.contains(reason), "{what}: {err}");
        assert!(
            !err.0.contains("digest"),
            "{what}: blamed on the digest: {err}"
        );
    }
}

// ------------------------------------------------------------------------------------------
// The monitor
// ------------------------------------------------------------------------------------------

/// The monitor of the seed's certificate.
fn seed_monitor() -> Monitor {
    Monitor::new(&seed()).expect("the seed's certificate is monitorable")
}

/// A CSV trace's rows: `t` and `obstacle_v` as written, read without the trace reader.
fn t_and_speed(csv: &str) -> Vec<(f64, f64)> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).expect(name);
    let (t, v) = (col("t"), col("obstacle_v"));
    lines
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            (cells[t].parse().unwrap(), cells[v].parse().unwrap())
        })
        .collect()
}

#[test]
fn a_trace_within_the_premises_holds() {
    let w = seed().problem.environment.obstacle_speed;
    let text = HELD_TRACE.text();
    let speeds: Vec<f64> = text
        .lines()
        .map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).expect("JSON Lines");
            v["obstacle_v"].as_f64().expect("obstacle_v")
        })
        .collect();
    let fastest = speeds.iter().copied().fold(0.0, f64::max);
    assert!(
        fastest <= w && fastest > 0.9 * w,
        "fastest {fastest}: not a clean test case"
    );
    let mut m = seed_monitor();
    let events = text_events(&mut m, &text, None);
    assert!(events.is_empty(), "{:?}", events.first());
    assert_eq!(m.verdict(), Monitored::Held);
    assert_eq!(m.samples(), speeds.len() as u64);
}

/// Feeds the fast trace (`text`) to the seed's monitor; asserts the first event is an
/// `obstacle_speed` violation at the first sample faster than W; returns every event.
fn first_fast_sample_flagged(text: &str, estimated: bool) -> Vec<Event> {
    let w = seed().problem.environment.obstacle_speed;
    let rows = t_and_speed(&FAST_TRACE.text());
    let k = rows
        .iter()
        .position(|&(_, v)| v > w)
        .expect("a sample faster than W");
    let (t, v) = rows[k];
    assert!(v > w + 1e-6, "{v} too close to {w}: not a clean test case");
    let mut m = seed_monitor();
    let events = text_events(&mut m, text, Some(Format::Csv));
    let first = events.first().expect("flagged");
    assert_eq!(first.check, Check::ObstacleSpeed, "{first:?}");
    assert_eq!(first.sample, k as u64);
    assert_eq!(first.t, Some(t));
    assert_eq!(first.obstacle_id, Some(0));
    assert_eq!(first.bound, Some(w));
    let observed = first.observed.expect("an observed speed");
    if estimated {
        assert!(
            (observed - v).abs() < 1e-9,
            "estimated {observed}, true {v}"
        );
    } else {
        assert_eq!(observed, v);
    }
    assert_eq!(m.first_violation(), Some(first));
    assert_eq!(m.verdict(), Monitored::Violated);
    assert!(
        events.iter().all(|e| e.check == Check::ObstacleSpeed),
        "{events:?}"
    );
    events
}

#[test]
fn an_obstacle_faster_than_certified_is_flagged_at_the_first_sample_that_shows_it() {
    let text = FAST_TRACE.text();
    let events = first_fast_sample_flagged(&text, false);
    // Every sample faster than W is reported, and nothing else.
    let w = seed().problem.environment.obstacle_speed;
    let rows = t_and_speed(&text);
    let fast: Vec<u64> = (0..rows.len())
        .filter(|&k| rows[k].1 > w)
        .map(|k| k as u64)
        .collect();
    let reported: Vec<u64> = events.iter().map(|e| e.sample).collect();
    assert_eq!(reported, fast);
}

#[test]
fn without_obstacle_v_the_estimated_speed_flags_the_same_sample() {
    let text = FAST_TRACE.text();
    assert!(text.starts_with("t,") && text.lines().next().unwrap().ends_with(",obstacle_v"));
    let positions: String = text
        .lines()
        .map(|l| l.rsplit_once(',').unwrap().0.to_string() + "\n")
        .collect();
    first_fast_sample_flagged(&positions, true);
}

#[test]
fn only_valid_certified_certificates_are_monitored() {
    for (f, verdict) in certificates() {
        let cert = f.certificate();
        match (verdict, Monitor::new(&cert)) {
            (Verdict::Certified, Ok(_)) => {}
            (v, Err(MonitorError::NotCertified(stated))) if v != Verdict::Certified => {
                assert_eq!(stated, v, "{}", f.file);
            }
            (_, other) => panic!("{}: {other:?}", f.file),
        }
    }
    // A faster obstacle claimed safe: edited (old digest), then re-signed.
    let mut forged = seed();
    forged.problem.environment.obstacle_speed = 0.3;
    assert!(matches!(
        Monitor::new(&forged),
        Err(MonitorError::Invalid(_))
    ));
    resign(&mut forged);
    assert!(matches!(
        Monitor::new(&forged),
        Err(MonitorError::Invalid(_))
    ));
}

/// The layers import downward only (core <- proof <- analysis <- cluster; monitor and
/// crosscheck over core and proof; cli over all): no `crate::` path in a layer names a layer above it.
/// The lean build already proves that nothing below `analysis` needs the solver; this
/// catches an upward import between layers that build together (core naming the monitor).
#[test]
fn layers_import_downward_only() {
    let forbidden: &[(&str, &[&str])] = &[
        (
            "core",
            &[
                "proof",
                "analysis",
                "cluster",
                "monitor",
                "crosscheck",
                "cli",
            ],
        ),
        (
            "proof",
            &["analysis", "cluster", "monitor", "crosscheck", "cli"],
        ),
        ("monitor", &["analysis", "cluster", "crosscheck", "cli"]),
        ("crosscheck", &["analysis", "cluster", "monitor", "cli"]),
        ("analysis", &["cluster", "monitor", "crosscheck", "cli"]),
        ("cluster", &["monitor", "crosscheck", "cli"]),
    ];
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut offences = Vec::new();
    for (layer, above) in forbidden {
        let mut stack = vec![src.join(layer)];
        while let Some(dir) = stack.pop() {
            for entry in std::fs::read_dir(&dir).expect("layer folder").flatten() {
                let path = entry.path();
                if path.is_dir() {
                    stack.push(path);
                    continue;
                }
                let text = std::fs::read_to_string(&path).expect("source file");
                for (n, line) in text.lines().enumerate() {
                    let code = line.split("//").next().unwrap_or("");
                    for upper in *above {
                        if code.contains(&format!("crate::{upper}")) {
                            offences.push(format!("{}:{}: {}", path.display(), n + 1, line.trim()));
                        }
                    }
                }
            }
        }
    }
    assert!(
        offences.is_empty(),
        "upward imports:\n{}",
        offences.join("\n")
    );
    assert!(
        src.join("core/semantics/mod.rs").exists(),
        "the walk looked at the real tree"
    );
}

/// The run search needs no solver: the embedded build decides a lane-change scene itself,
/// checks the certificate, and monitors against it.
#[test]
fn lane_change_scenes_are_decided_checked_and_monitored_without_the_solver() {
    use safereach::core::scene::Scene;
    use safereach::proof::search_certificate::certify_by_search;
    use safereach::proof::search_check::check_search;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/seed-lanes.toml");
    let scene = Scene::load(&path).expect("the shipped scene loads");
    let cert = certify_by_search(&scene).expect("searched");
    assert_eq!(cert.verdict, Verdict::Certified);
    assert_eq!(cert.min_separation_exact.as_deref(), Some("12/25"));
    let report = check_search(&cert).expect("checks");
    assert_eq!(report.verdict, Verdict::Certified);
    let mut forged = cert.clone();
    forged.scene.obstacles[1].position = safereach::core::scene::Position::At(7.0);
    forged.digest = forged.compute_digest();
    assert!(
        check_search(&forged).is_err(),
        "a moved parked car changes the answer"
    );
    Monitor::for_search(&cert).expect("a monitor for a certified search certificate");
}
