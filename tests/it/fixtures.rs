//! The committed fixtures (tests/fixtures/) against the current code: each is written again
//! by the binary; a certificate's verdict must be what the analyser answers now for the
//! problem it names, and `check` must accept it; a trace must be byte for byte what
//! `simulate` writes now. The lean tests read these files without the solver; this keeps
//! them from going stale silently. With `SAFEREACH_BLESS_FIXTURES=1` the fixtures are
//! rewritten instead (review the diff).

use safereach::proof::certificate::{Certificate, check};
use safereach::proof::verdict::Verdict;

use crate::common::cli::safereach;
use crate::common::fixtures::{BLESS, FIXTURES, Fixture, Kind};
use crate::common::paths::{fixture, load_problem, problem_file};
use crate::common::tmp;
use safereach::core::scene::Scene;
use safereach::proof::scene_certificate::SceneCertificate;
use safereach::proof::scene_check::check_scene;

/// The exit codes of the command that writes a fixture of `kind`.
fn exit_codes(kind: &Kind) -> &'static [i32] {
    match kind {
        Kind::Certificate(Verdict::Certified) => &[0],
        Kind::Certificate(Verdict::Refuted) => &[1],
        Kind::Certificate(Verdict::Inconclusive) => &[3],
        Kind::SceneCertificate(Verdict::Certified) => &[0],
        Kind::SceneCertificate(Verdict::Refuted) => &[1],
        Kind::SceneCertificate(Verdict::Inconclusive) => &[3],
        // 1: some run collided.
        Kind::Trace { .. } => &[0, 1],
    }
}

/// Holds the committed certificate `f` to `fresh`, the one written now.
fn same_certificate(f: &Fixture, verdict: Verdict, fresh: &str) {
    let fresh: Certificate = serde_json::from_str(fresh).expect("a certificate");
    let committed = f.certificate();
    assert_eq!(fresh.verdict, verdict, "{}: the analyser's verdict", f.file);
    assert_eq!(
        committed.verdict, fresh.verdict,
        "{}: stale (see {BLESS})",
        f.file
    );
    assert_eq!(
        committed.problem,
        load_problem(f.problem, f.sets),
        "{}: answers another problem than it names (see {BLESS})",
        f.file
    );
    let report = check(&committed).unwrap_or_else(|e| panic!("{}: rejected: {e}", f.file));
    assert_eq!(report.verdict, verdict, "{}", f.file);
}

/// Holds the committed scene certificate `f` to `fresh`, the one written now.
fn same_scene_certificate(f: &Fixture, verdict: Verdict, fresh: &str) {
    let fresh: SceneCertificate = serde_json::from_str(fresh).expect("a scene certificate");
    let committed = f.scene_certificate();
    assert_eq!(fresh.verdict, verdict, "{}: the analyser's verdict", f.file);
    assert_eq!(
        committed.verdict, fresh.verdict,
        "{}: stale (see {BLESS})",
        f.file
    );
    assert_eq!(
        committed.scene,
        Scene::load(&problem_file(f.problem)).expect("loads"),
        "{}: answers another scene than it names (see {BLESS})",
        f.file
    );
    let report = check_scene(&committed).unwrap_or_else(|e| panic!("{}: rejected: {e}", f.file));
    assert_eq!(report.verdict, verdict, "{}", f.file);
}

#[test]
fn fixtures_are_what_the_current_code_writes() {
    let dir = tmp();
    let bless = std::env::var(BLESS).is_ok_and(|v| v == "1");
    for f in FIXTURES {
        let out = safereach(dir.path()).args(f.args()).output().expect("runs");
        let code = out.status.code().expect("exited");
        assert!(
            exit_codes(&f.kind).contains(&code),
            "{:?}: exit {code}\n{}",
            f.args(),
            String::from_utf8_lossy(&out.stderr)
        );
        let written = dir.path().join(f.file);
        if bless {
            std::fs::copy(&written, fixture(f.file)).expect("fixture written");
        }
        let fresh = std::fs::read_to_string(&written).expect("written");
        match f.kind {
            Kind::Certificate(verdict) => same_certificate(f, verdict, &fresh),
            Kind::SceneCertificate(verdict) => same_scene_certificate(f, verdict, &fresh),
            Kind::Trace { .. } => assert!(
                fresh == f.text(),
                "tests/fixtures/{} differs from what simulate writes now (see {BLESS})",
                f.file
            ),
        }
    }
}
