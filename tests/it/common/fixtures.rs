//! The committed fixtures in `tests/fixtures/`: certificates and traces written by the
//! `safereach` binary. The lean tests (`tests/lean`, built without the solver) read them;
//! `it::fixtures` regenerates each with the current code and holds the committed copy to it,
//! so a fixture cannot go stale silently. After a deliberate change (of the certificate
//! format, say), rewrite them with
//! `SAFEREACH_BLESS_FIXTURES=1 cargo test --release --test it fixtures::` and review the diff.

use safereach::proof::certificate::Certificate;
use safereach::proof::scene_certificate::SceneCertificate;
use safereach::proof::verdict::Verdict;

use super::paths::{fixture, problem_file};

/// Set to `1` to rewrite the fixtures from the current code instead of comparing.
pub const BLESS: &str = "SAFEREACH_BLESS_FIXTURES";

/// A fixture: what `safereach <command> problems/<problem> --set <sets>… <args>` writes
/// into `file`.
pub struct Fixture {
    pub file: &'static str,
    pub problem: &'static str,
    pub sets: &'static [&'static str],
    pub kind: Kind,
    /// `certify --steps`: the witness keeps its per-period rows (the seed's and the short
    /// sensing scene's do, so the tests check both forms and the monitor tests replay rows).
    pub steps: bool,
}

/// What a fixture is, and so the command that writes it.
pub enum Kind {
    /// `certify … --out <file>`, which gives this verdict.
    Certificate(Verdict),
    /// `certify <scene> --out <file>`: a scene certificate with this verdict.
    SceneCertificate(Verdict),
    /// `simulate … --runs <runs> --trace <file>`: the random run that came closest.
    Trace { runs: u32 },
}

/// The seed (certified), an obstacle three times faster than assumed (refuted: the witness
/// collides), the seed at the boundary of its safe radius (inconclusive: the witness is a
/// closest approach, the proved bound is not above the clearance); a run of the seed itself
/// (W = 0.15 m/s, JSON Lines) and one with obstacles up to 0.25 m/s (CSV); two scene
/// certificates: a destination reached first (certified) and a short sensing range
/// (refuted).
pub const FIXTURES: &[Fixture] = &[
    Fixture {
        file: "seed.cert.json",
        problem: "seed.toml",
        sets: &[],
        kind: Kind::Certificate(Verdict::Certified),
        steps: true,
    },
    Fixture {
        file: "fast-obstacle.cert.json",
        problem: "fast-obstacle.toml",
        sets: &[],
        kind: Kind::Certificate(Verdict::Refuted),
        steps: false,
    },
    Fixture {
        file: "boundary.cert.json",
        problem: "seed.toml",
        sets: &[
            "controller.danger_rule=area",
            "robot.latency=0",
            "controller.reaction_radius=1.035",
        ],
        kind: Kind::Certificate(Verdict::Inconclusive),
        steps: false,
    },
    Fixture {
        file: "seed.run.jsonl",
        problem: "seed.toml",
        sets: &[],
        kind: Kind::Trace { runs: 200 },
        steps: false,
    },
    Fixture {
        file: "seed-w0.25.run.csv",
        problem: "seed.toml",
        sets: &["environment.obstacle_speed=0.25"],
        kind: Kind::Trace { runs: 200 },
        steps: false,
    },
    Fixture {
        file: "scene-destination.cert.json",
        problem: "scene-destination.toml",
        sets: &[],
        kind: Kind::SceneCertificate(Verdict::Certified),
        steps: false,
    },
    Fixture {
        file: "scene-short-sensing.cert.json",
        problem: "scene-short-sensing.toml",
        sets: &[],
        kind: Kind::SceneCertificate(Verdict::Refuted),
        steps: true,
    },
];

impl Fixture {
    /// The arguments of `safereach` that write this fixture into the working directory.
    pub fn args(&self) -> Vec<String> {
        let (command, tail) = match self.kind {
            Kind::Certificate(_) | Kind::SceneCertificate(_) => {
                ("certify", vec!["--out".into(), self.file.into()])
            }
            Kind::Trace { runs } => (
                "simulate",
                vec![
                    "--runs".into(),
                    runs.to_string(),
                    "--trace".into(),
                    self.file.into(),
                ],
            ),
        };
        let mut args = vec![
            command.into(),
            problem_file(self.problem).display().to_string(),
        ];
        for set in self.sets {
            args.extend(["--set".into(), set.to_string()]);
        }
        args.extend(tail);
        if self.steps {
            args.push("--steps".into());
        }
        args
    }

    /// The fixture, parsed as a certificate.
    pub fn certificate(&self) -> Certificate {
        serde_json::from_str(&self.text()).unwrap_or_else(|e| {
            panic!(
                "tests/fixtures/{} is not a certificate ({e}); regenerate it (see {BLESS})",
                self.file
            )
        })
    }

    /// The fixture, parsed as a scene certificate.
    pub fn scene_certificate(&self) -> SceneCertificate {
        serde_json::from_str(&self.text()).unwrap_or_else(|e| {
            panic!(
                "tests/fixtures/{} is not a scene certificate ({e}); regenerate it (see {BLESS})",
                self.file
            )
        })
    }

    /// The fixture as text.
    pub fn text(&self) -> String {
        let path = fixture(self.file);
        std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    }
}
