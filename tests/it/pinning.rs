//! s* pinned (issue 15): a certificate's s* lies in its bracket — the proved lower bound and
//! the replayed witness's separation — no wider than the tolerance it declares; the witness
//! is a run of the piece and shift it names; unknown fields are refused anywhere; and
//! `check --require` turns a valid certificate of another verdict into exit 1.
//!
//! The red team's forgeries are rebuilt here from real certificates, re-signed as a forger
//! would, with the witness's piece set to one its run really realises, so that nothing but
//! the bracket can reject them.

use safereach::analysis::analyse;
use safereach::core::model::Problem;
use safereach::core::num::{Exact, exact_float};
use safereach::core::scene::Scene;
use safereach::core::simulate;
use safereach::proof::certificate::{Certificate, check};
use safereach::proof::certificate_file::CertificateFile;
use safereach::proof::scene_certificate::{SceneCertificate, Trigger};
use safereach::proof::scene_search::search_scene;
use safereach::proof::schedule::{Decomposition, Piece};
use safereach::proof::separation::SEPARATION_TOLERANCE;
use safereach::proof::verdict::{Verdict, Witness, aim};
use safereach::proof::witness_schedule::replay_realises;
use serde_json::Value;

use crate::common::cli::{safereach, stdout};
use crate::common::forgery::resign;
use crate::common::paths::{fixture, load_problem, problem_file};
use crate::common::tmp;

fn certificate(problem: &Problem) -> Certificate {
    Certificate::from_analysis(&analyse(problem).expect("analysis"))
}

/// s* of a problem by the exact run search, an engine independent of the analyser.
fn exact_s_star(problem: &Problem) -> Exact {
    let search = search_scene(&Scene::from_problem(problem)).expect("the search finishes");
    search.min_separation().expect("a finite s*").to_exact()
}

/// A piece of `problem` (and shift) that the run of `w`'s speeds realises, as a forger
/// would pick it: the piece whose brake step, shifted, is the run's.
fn piece_realised_by(problem: &Problem, w: &Witness) -> (Piece, usize) {
    let dec = Decomposition::new(problem);
    let plain = simulate::replay(
        &dec.params,
        &w.obstacle_speeds.to_vec(),
        w.obstacle_speeds.len(),
        false,
    );
    let (t, _) = plain.run.outcome.brake.expect("the run brakes");
    dec.pieces
        .iter()
        .filter(|p| p.brake <= t && (p.merged || p.brake == t))
        .map(|p| (*p, t - p.brake))
        .find(|(p, shift)| {
            let replay = simulate::replay_reacting_at(
                &dec.params,
                &w.obstacle_speeds.to_vec(),
                aim(p, *shift, None),
                w.obstacle_speeds.len(),
                false,
            );
            replay_realises(&dec.params, &replay, p, *shift).is_ok()
        })
        .expect("some piece of the problem is realised by the run")
}

/// `cert` with the witness of `other` (a run of another problem whose speeds are allowed in
/// this one), its piece fixed to one the run realises here, and s* stated as the witness's
/// separation; re-signed.
fn with_foreign_witness(cert: &Certificate, other: &Certificate) -> Certificate {
    let mut forged = cert.clone();
    let mut w = other.witness.clone().expect("a witness");
    (w.piece, w.shift) = piece_realised_by(&cert.problem, &w);
    forged.min_separation = w.separation;
    forged.witness = Some(w);
    resign(&mut forged);
    forged
}

#[test]
fn honest_brackets_hold_the_exact_s_star_within_the_tolerance() {
    for (name, sets) in [
        ("seed.toml", &[][..]),
        ("fast-obstacle.toml", &[][..]),
        (
            "fast-obstacle.toml",
            &["environment.obstacle_speed=0.25"][..],
        ),
    ] {
        let problem = load_problem(name, sets);
        let cert = certificate(&problem);
        check(&cert).expect("the honest certificate checks");
        let (lb, s, r) = (
            cert.lower_bound.unwrap(),
            cert.min_separation.unwrap(),
            cert.witness.as_ref().and_then(|w| w.separation).unwrap(),
        );
        let truth = exact_s_star(&problem);
        assert!(
            exact_float(lb) <= truth && truth <= exact_float(r.next_up()),
            "{name}"
        );
        assert!(lb <= s && s <= r, "{name}: {lb} <= {s} <= {r}");
        assert!(r - lb <= SEPARATION_TOLERANCE, "{name}: bracket {lb}..{r}");
        assert_eq!(cert.separation_tolerance, SEPARATION_TOLERANCE);
    }
}

/// The red team's two forgeries: the seed's certificate with a static obstacle's run as its
/// witness and s* = 0.98 (true 0.33), and the fast obstacle's with the run of a 0.25 m/s
/// obstacle and s* = −0.09 (true −1.56). Both used to be accepted.
#[test]
fn the_red_team_s_star_forgeries_are_rejected() {
    let seed = load_problem("seed.toml", &[]);
    let fast = load_problem("fast-obstacle.toml", &[]);
    let cases = [
        (
            "seed, a static obstacle's witness",
            certificate(&seed),
            certificate(&load_problem(
                "seed.toml",
                &["environment.obstacle_speed=0"],
            )),
            0.98,
            exact_s_star(&seed),
        ),
        (
            "fast obstacle, a 0.25 m/s obstacle's witness",
            certificate(&fast),
            certificate(&load_problem(
                "fast-obstacle.toml",
                &["environment.obstacle_speed=0.25"],
            )),
            -0.09,
            exact_s_star(&fast),
        ),
    ];
    for (what, cert, other, claimed, truth) in cases {
        let forged = with_foreign_witness(&cert, &other);
        let stated = forged.min_separation.unwrap();
        assert!((stated - claimed).abs() < 1e-5, "{what}: claims {stated}");
        assert!(
            exact_float(stated) - truth.clone() > exact_float(0.3),
            "{what}"
        );
        assert_eq!(forged.verdict, cert.verdict);
        let err = check(&forged).expect_err(what);
        assert!(err.0.contains("bracket"), "{what}: {err}");
        // Declaring the bracket's width as the tolerance does not help a decided verdict.
        let mut wide = forged.clone();
        wide.separation_tolerance = 2.0;
        resign(&mut wide);
        assert!(
            check(&wide).is_err(),
            "{what}: a widened tolerance accepted"
        );
    }
}

/// The same forgeries through the binary: `check` exits 1 and names the bracket.
#[test]
fn check_names_the_bracket_of_a_forged_s_star() {
    let dir = tmp();
    let fast = load_problem("fast-obstacle.toml", &[]);
    let other = load_problem("fast-obstacle.toml", &["environment.obstacle_speed=0.25"]);
    let forged = with_foreign_witness(&certificate(&fast), &certificate(&other));
    let path = dir.path().join("forged.json");
    std::fs::write(&path, serde_json::to_string_pretty(&forged).unwrap()).unwrap();
    let out = safereach(dir.path())
        .args(["check", "forged.json"])
        .assert()
        .code(1)
        .get_output()
        .clone();
    let text = stdout(&out);
    assert!(
        text.contains("INVALID") && text.contains("bracket"),
        "{text}"
    );
}

#[test]
fn witness_piece_and_shift_edits_are_rejected() {
    let cert = certificate(&load_problem("seed.toml", &[]));
    let w = cert.witness.as_ref().unwrap();
    assert!(
        w.piece.merged && w.shift > 1,
        "the seed's worst case is a shifted merged piece"
    );
    type WitnessEdit = fn(&mut Witness);
    let edits: [(&str, WitnessEdit); 5] = [
        ("shift + 1", |w| w.shift += 1),
        ("shift - 1", |w| w.shift -= 1),
        ("piece.brake + 1", |w| w.piece.brake += 1),
        ("piece.brake + 1, shift - 1", |w| {
            w.piece.brake += 1;
            w.shift -= 1;
        }),
        ("piece not merged", |w| w.piece.merged = false),
    ];
    for (what, edit) in edits {
        let mut forged = cert.clone();
        edit(forged.witness.as_mut().unwrap());
        resign(&mut forged);
        let err = check(&forged).expect_err(what);
        assert!(
            err.0.contains("piece") || err.0.contains("shift"),
            "{what}: {err}"
        );
    }
}

fn scene_fixture(name: &str) -> SceneCertificate {
    serde_json::from_str(&std::fs::read_to_string(fixture(name)).unwrap()).unwrap()
}

fn resign_scene(c: &mut SceneCertificate) {
    c.digest = c.compute_digest();
}

#[test]
fn scene_certificate_forgeries_of_s_star_and_the_witness_are_rejected() {
    type SceneEdit = fn(&mut SceneCertificate) -> Option<()>;
    let edits: [(&str, SceneEdit); 7] = [
        ("s* above the witness", |c| {
            c.min_separation = Some(c.witness.as_ref()?.separation? + 1e-3);
            Some(())
        }),
        ("s* below the bound", |c| {
            c.min_separation = Some(c.lower_bound? - 1e-3);
            Some(())
        }),
        ("tolerance widened", |c| {
            c.separation_tolerance = 1.0;
            Some(())
        }),
        ("witness piece a step later", |c| {
            c.witness.as_mut()?.piece.brake += 1;
            Some(())
        }),
        ("witness piece a step earlier", |c| {
            let p = &mut c.witness.as_mut()?.piece;
            p.brake = p.brake.checked_sub(1)?;
            Some(())
        }),
        ("a trigger named where there is none, or dropped", |c| {
            let w = c.witness.as_mut()?;
            w.trigger = match w.trigger {
                None => Some(Trigger::Goal),
                Some(_) => None,
            };
            Some(())
        }),
        ("witness obstacle's lane renamed", |c| {
            c.witness.as_mut()?.lane += 1;
            Some(())
        }),
    ];
    for name in [
        "scene-destination.cert.json",
        "scene-short-sensing.cert.json",
    ] {
        let honest = scene_fixture(name);
        CertificateFile::Scene(Box::new(honest.clone()))
            .check()
            .expect("the fixture checks");
        for (what, edit) in edits {
            let mut forged = honest.clone();
            if edit(&mut forged).is_none() {
                continue;
            }
            resign_scene(&mut forged);
            let result = CertificateFile::Scene(Box::new(forged)).check();
            assert!(result.is_err(), "{name}: {what}: accepted");
        }
    }
}

#[test]
fn search_certificates_pin_s_star_too() {
    let scene = Scene::load(&problem_file("lane-change-refused.toml")).unwrap();
    let cert = match safereach::analysis::scene_answer::SceneAnswer::of(&scene)
        .unwrap()
        .certificate()
    {
        CertificateFile::Search(c) => *c,
        _ => panic!("a lane-change scene gets a search certificate"),
    };
    assert_eq!(cert.verdict, Verdict::Refuted);
    let honest = CertificateFile::Search(Box::new(cert.clone()));
    honest.check().expect("the honest certificate checks");
    let mut wide = cert.clone();
    wide.separation_tolerance = 1.0;
    wide.digest = wide.compute_digest();
    let err = CertificateFile::Search(Box::new(wide)).check().unwrap_err();
    assert!(err.0.contains("separation_tolerance"), "{err}");
}

/// Inserts `"unexpected": 1` into the object at `path` (keys and indices) of `json`.
fn with_unknown_field(json: &Value, path: &[&str]) -> Value {
    let mut out = json.clone();
    let mut at = &mut out;
    for step in path {
        at = match step.parse::<usize>() {
            Ok(i) => &mut at[i],
            Err(_) => &mut at[*step],
        };
    }
    at.as_object_mut()
        .unwrap_or_else(|| panic!("{path:?} is not an object"))
        .insert("unexpected".into(), Value::from(1));
    out
}

#[test]
fn unknown_fields_are_refused_anywhere_in_a_certificate() {
    let search = {
        let scene = Scene::load(&problem_file("lane-change-saves.toml")).unwrap();
        safereach::analysis::scene_answer::SceneAnswer::of_with_steps(&scene)
            .unwrap()
            .certificate()
            .to_json()
    };
    let read = |name: &str| std::fs::read_to_string(fixture(name)).unwrap();
    let cases: [(&str, String, &[&[&str]]); 4] = [
        (
            "seed",
            read("seed.cert.json"),
            &[
                &[],
                &["witness"],
                &["witness", "piece"],
                &["witness", "steps", "0"],
                &["witness", "obstacle_speeds", "0"],
                &["witness", "robot_modes", "0"],
                &["proofs", "0"],
                &["proofs", "0", "piece"],
                &["premises", "0"],
                &["problem", "robot"],
            ],
        ),
        (
            "scene (destination)",
            read("scene-destination.cert.json"),
            &[
                &[],
                &["witness"],
                &["witness", "piece"],
                &["obstacles", "0"],
                &["obstacles", "0", "bystanders", "0"],
                &["scene"],
                &["scene", "obstacles", "0"],
            ],
        ),
        (
            "scene (short sensing)",
            read("scene-short-sensing.cert.json"),
            &[&["witness", "steps", "3"], &["scene", "robot"]],
        ),
        (
            "search",
            search,
            &[
                &[],
                &["witness"],
                &["witness", "steps", "0"],
                &["witness", "lane_changes", "0"],
                &["obstacles", "0"],
                &["scene", "lane_change"],
            ],
        ),
    ];
    for (name, text, paths) in cases {
        let json: Value = serde_json::from_str(&text).unwrap();
        CertificateFile::from_json(&text).expect("the honest file reads");
        for path in paths {
            let edited = with_unknown_field(&json, path).to_string();
            let err = CertificateFile::from_json(&edited)
                .err()
                .unwrap_or_else(|| panic!("{name}: an unknown field at {path:?} was accepted"));
            assert!(
                err.to_string().contains("unknown field"),
                "{name} {path:?}: {err}"
            );
        }
    }
}

#[test]
fn check_require_exits_1_for_another_verdict() {
    let dir = tmp();
    let seed = fixture("seed.cert.json");
    let fast = fixture("fast-obstacle.cert.json");
    let run = |cert: &std::path::Path, require: &str, code: i32| {
        let out = safereach(dir.path())
            .arg("check")
            .arg(cert)
            .args(["--require", require])
            .assert()
            .code(code)
            .get_output()
            .clone();
        stdout(&out)
    };
    assert!(run(&seed, "certified", 0).contains("valid; verdict certified"));
    let text = run(&fast, "certified", 1);
    assert!(
        text.contains("valid, but its verdict is refuted, not the required certified"),
        "{text}"
    );
    assert!(run(&fast, "refuted", 0).contains("valid; verdict refuted"));
    // An invalid certificate stays invalid whatever is required.
    let mut forged: Certificate =
        serde_json::from_str(&std::fs::read_to_string(&seed).unwrap()).unwrap();
    forged.min_separation = Some(0.5);
    resign(&mut forged);
    let path = dir.path().join("forged.json");
    std::fs::write(&path, serde_json::to_string(&forged).unwrap()).unwrap();
    assert!(run(&path, "certified", 1).contains("INVALID"));
    // A verdict that does not exist is bad input.
    safereach(dir.path())
        .arg("check")
        .arg(&seed)
        .args(["--require", "safe"])
        .assert()
        .code(2);
}

/// A certificate of the earlier format is named as such, not as a missing field.
#[test]
fn an_earlier_format_is_named() {
    let mut json: Value =
        serde_json::from_str(&std::fs::read_to_string(fixture("seed.cert.json")).unwrap()).unwrap();
    json["format"] = Value::from("safereach-certificate/1");
    json.as_object_mut().unwrap().remove("separation_tolerance");
    let err = CertificateFile::from_json(&json.to_string()).unwrap_err();
    assert!(err.to_string().contains("earlier safereach"), "{err}");
}
