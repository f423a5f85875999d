//! Bad problem input: every broken problem text or `--set` override is a typed
//! [`ProblemError`] naming the origin, the key and the reason (the CLI turns it into exit 2).
//! Also: every shipped problem loads, and problems round-trip through TOML.

use std::path::PathBuf;

use proptest::prelude::*;
use safereach::core::model::{DangerRule, Position, Problem, ProblemError, Robot};

use crate::common::paths::{problem_file, root, seed_file};
use crate::common::spec::{Spec, any_rule};

/// A valid problem (the seed's numbers); the cases below break it one edit at a time.
const BASE: &str = r#"name = "base"

[robot]
max_speed = 0.8
acceleration = 0.4
braking = 0.5
control_period = 0.1
latency = 1
clearance = 0.0

[controller]
assumed_obstacle_speed = 0.2
reaction_radius = 1.4
danger_rule = "paper"
buffer = 0.1
wrong_assumption_brake = true

[environment]
obstacle_speed = 0.15
initial_gap = 10.0
"#;

/// A broken problem text and what its error must say.
struct Case {
    /// What is broken.
    what: &'static str,
    /// Edits to [`BASE`]: each `from` must occur in it and is replaced by `to`.
    edits: &'static [(&'static str, &'static str)],
    /// Substrings the error's message must contain.
    expect: &'static [&'static str],
    /// The dotted key the error must name, if any.
    key: Option<&'static str>,
    /// The 1-based line the error must point at, if any.
    line: Option<usize>,
}

const CASES: &[Case] = &[
    Case {
        what: "unknown top-level key",
        edits: &[("name = \"base\"", "name = \"base\"\ncolour = \"red\"")],
        expect: &["bad.toml: ", "unknown field `colour`", "line 2"],
        key: Some("colour"),
        line: Some(2),
    },
    Case {
        what: "unknown key in [robot]",
        edits: &[("braking = 0.5\n", "braking = 0.5\nwheel_radius = 0.1\n")],
        expect: &["bad.toml: ", "unknown field `wheel_radius`", "line 7"],
        key: Some("robot.wheel_radius"),
        line: Some(7),
    },
    Case {
        what: "missing key in [robot]",
        edits: &[("braking = 0.5\n", "")],
        expect: &["bad.toml: ", "missing field `braking`"],
        key: Some("robot.braking"),
        line: None,
    },
    Case {
        what: "missing top-level key",
        edits: &[("name = \"base\"\n", "")],
        expect: &["bad.toml: ", "missing field `name`"],
        key: Some("name"),
        line: None,
    },
    Case {
        what: "missing table",
        edits: &[(
            "[environment]\nobstacle_speed = 0.15\ninitial_gap = 10.0\n",
            "",
        )],
        expect: &["bad.toml: ", "missing field `environment`"],
        key: Some("environment"),
        line: None,
    },
    Case {
        what: "negative braking",
        edits: &[("braking = 0.5", "braking = -0.5")],
        expect: &[
            "bad.toml: robot.braking = -0.5: must be > 0 (m/s^2)",
            "bad.toml:6:11",
        ],
        key: Some("robot.braking"),
        line: Some(6),
    },
    Case {
        what: "zero control period",
        edits: &[("control_period = 0.1", "control_period = 0")],
        expect: &["bad.toml: robot.control_period = 0: must be > 0 (s)"],
        key: Some("robot.control_period"),
        line: Some(7),
    },
    Case {
        what: "nan",
        edits: &[("obstacle_speed = 0.15", "obstacle_speed = nan")],
        expect: &["bad.toml: environment.obstacle_speed = NaN: must be a finite number (m/s)"],
        key: Some("environment.obstacle_speed"),
        line: Some(19),
    },
    Case {
        what: "inf",
        edits: &[("initial_gap = 10.0", "initial_gap = +inf")],
        expect: &["bad.toml: environment.initial_gap = inf: must be a finite number (m)"],
        key: Some("environment.initial_gap"),
        line: Some(20),
    },
    Case {
        what: "negative inf",
        edits: &[("buffer = 0.1", "buffer = -inf")],
        expect: &["controller.buffer = -inf: must be a finite number (m)"],
        key: Some("controller.buffer"),
        line: Some(15),
    },
    Case {
        what: "out of range",
        edits: &[("reaction_radius = 1.4", "reaction_radius = 2e9")],
        expect: &["controller.reaction_radius = 2e9: out of range: magnitude above 1e9"],
        key: Some("controller.reaction_radius"),
        line: Some(13),
    },
    Case {
        what: "latency as float",
        edits: &[("latency = 1", "latency = 1.5")],
        expect: &[
            "bad.toml: robot.latency = 1.5: ",
            "expected a whole number >= 0 of control periods, got 1.5",
            "bad.toml:8:11",
        ],
        key: Some("robot.latency"),
        line: Some(8),
    },
    Case {
        what: "negative latency",
        edits: &[("latency = 1", "latency = -1")],
        expect: &[
            "bad.toml: robot.latency = -1: expected a whole number >= 0 of control periods, got -1",
        ],
        key: Some("robot.latency"),
        line: Some(8),
    },
    Case {
        what: "latency too large",
        edits: &[("latency = 1", "latency = 5000")],
        expect: &["bad.toml: robot.latency = 5000: must be <= 1000 (control periods)"],
        key: Some("robot.latency"),
        line: Some(8),
    },
    Case {
        what: "number as string",
        edits: &[("max_speed = 0.8", "max_speed = \"0.8\"")],
        expect: &[
            "bad.toml: robot.max_speed = \"0.8\": expected a number in m/s, got the text \"0.8\"",
        ],
        key: Some("robot.max_speed"),
        line: Some(4),
    },
    Case {
        what: "initial gap equal to the clearance",
        edits: &[
            ("clearance = 0.0", "clearance = 0.5"),
            ("initial_gap = 10.0", "initial_gap = 0.5"),
        ],
        expect: &["bad.toml: environment.initial_gap = 0.5: must be > robot.clearance = 0.5 (m)"],
        key: Some("environment.initial_gap"),
        line: Some(20),
    },
    Case {
        what: "initial gap below the clearance",
        edits: &[("clearance = 0.0", "clearance = 12")],
        expect: &["environment.initial_gap = 10: must be > robot.clearance = 12 (m)"],
        key: Some("environment.initial_gap"),
        line: Some(20),
    },
    Case {
        what: "negative clearance",
        edits: &[("clearance = 0.0", "clearance = -0.1")],
        expect: &["robot.clearance = -0.1: must be >= 0 (m)"],
        key: Some("robot.clearance"),
        line: Some(9),
    },
    Case {
        what: "absurd horizon",
        edits: &[("initial_gap = 10.0", "initial_gap = 200000")],
        expect: &[
            "environment.initial_gap = 200000: absurd horizon",
            "more than a million control periods",
        ],
        key: Some("environment.initial_gap"),
        line: Some(20),
    },
    Case {
        what: "braking too weak to stop within the horizon",
        edits: &[("braking = 0.5", "braking = 1e-7")],
        expect: &[
            "robot.braking = 1e-7: absurd horizon",
            "to stop from top speed",
        ],
        key: Some("robot.braking"),
        line: Some(6),
    },
    Case {
        what: "bad danger rule",
        edits: &[("danger_rule = \"paper\"", "danger_rule = \"fast\"")],
        expect: &[
            "bad.toml: controller.danger_rule = \"fast\": ",
            "expected one of paper, kinematic, area, got the text \"fast\"",
            "bad.toml:14:",
        ],
        key: Some("controller.danger_rule"),
        line: Some(14),
    },
    Case {
        what: "empty name",
        edits: &[("name = \"base\"", "name = \"  \"")],
        expect: &["bad.toml: name = \"  \": must not be empty"],
        key: Some("name"),
        line: Some(1),
    },
    Case {
        what: "TOML syntax error",
        edits: &[("braking = 0.5", "braking = 0.5.1")],
        expect: &["bad.toml: TOML parse error at line 6, column"],
        key: None,
        line: Some(6),
    },
    Case {
        what: "unclosed table header",
        edits: &[("[controller]", "[controller")],
        expect: &["bad.toml: TOML parse error at line 11"],
        key: None,
        line: Some(11),
    },
    Case {
        what: "duplicate key",
        edits: &[("buffer = 0.1\n", "buffer = 0.1\nbuffer = 0.2\n")],
        expect: &["bad.toml: TOML parse error at line 16", "duplicate key"],
        key: None,
        line: Some(16),
    },
];

fn edited(case: &Case) -> String {
    let mut text = BASE.to_string();
    for (from, to) in case.edits {
        assert!(
            text.contains(from),
            "{}: `{from}` not in the base text",
            case.what
        );
        text = text.replacen(from, to, 1);
    }
    text
}

#[test]
fn base_text_is_valid() {
    Problem::from_toml_str(BASE, "base.toml").unwrap();
}

#[test]
fn broken_problems_are_rejected_with_their_reason() {
    let mut failures = Vec::new();
    for case in CASES {
        let text = edited(case);
        let err = match Problem::from_toml_str(&text, "bad.toml") {
            Ok(_) => {
                failures.push(format!("{}: accepted", case.what));
                continue;
            }
            Err(e) => e,
        };
        let message = err.to_string();
        for want in case.expect {
            if !message.contains(want) {
                failures.push(format!("{}: message lacks {want:?}:\n{message}", case.what));
            }
        }
        if err.origin() != "bad.toml" {
            failures.push(format!("{}: origin {:?}", case.what, err.origin()));
        }
        if let Some(key) = case.key
            && err.key() != Some(key)
        {
            failures.push(format!(
                "{}: key {:?}, want {key:?}:\n{message}",
                case.what,
                err.key()
            ));
        }
        if let Some(line) = case.line
            && err.line() != Some(line)
        {
            failures.push(format!(
                "{}: line {:?}, want {line}:\n{message}",
                case.what,
                err.line()
            ));
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n\n"));
}

#[test]
fn integers_are_accepted_for_floats() {
    let text = BASE
        .replace("initial_gap = 10.0", "initial_gap = 10")
        .replace("clearance = 0.0", "clearance = 0")
        .replace("max_speed = 0.8", "max_speed = 1");
    let p = Problem::from_toml_str(&text, "ints.toml").unwrap();
    assert_eq!(p.environment.initial_gap, Position::At(10.0));
    assert_eq!(p.robot.clearance, 0.0);
    assert_eq!(p.robot.max_speed, 1.0);
}

#[test]
fn validate_names_origin_key_value_and_reason() {
    let mut p = Problem::from_toml_str(BASE, "base.toml").unwrap();
    p.robot.braking = -0.5;
    let err = p.validate("problems/x.toml").unwrap_err();
    assert_eq!(
        err.to_string(),
        "problems/x.toml: robot.braking = -0.5: must be > 0 (m/s^2)"
    );
    assert!(matches!(err, ProblemError::Invalid { .. }));
}

fn with_sets(sets: &[&str]) -> Result<Problem, ProblemError> {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    Problem::load_with_overrides(&seed_file(), &sets)
}

#[test]
fn overrides_apply_with_toml_types() {
    let seed = Problem::load(&seed_file()).unwrap();
    let p = with_sets(&[
        "environment.obstacle_speed=0.25",
        "controller.danger_rule=kinematic",
        "controller.wrong_assumption_brake=false",
        "robot.latency=2",
        "name=foo",
    ])
    .unwrap();
    assert_eq!(p.environment.obstacle_speed, 0.25);
    assert_eq!(p.controller.danger_rule, DangerRule::Kinematic);
    assert!(!p.controller.wrong_assumption_brake);
    assert_eq!(p.robot.latency, 2);
    assert_eq!(p.name, "foo");
    assert_eq!(
        p.robot,
        Robot {
            latency: 2,
            ..seed.robot.clone()
        }
    );

    // Quoted strings, integers for floats, spaces around `=`, the last override wins.
    let p = with_sets(&[
        "controller.danger_rule=\"area\"",
        "environment.obstacle_speed=1",
        "robot.braking = 0.75",
        "robot.braking=0.6",
    ])
    .unwrap();
    assert_eq!(p.controller.danger_rule, DangerRule::Area);
    assert_eq!(p.environment.obstacle_speed, 1.0);
    assert_eq!(p.robot.braking, 0.6);

    // No overrides: the file as it is.
    assert_eq!(with_sets(&[]).unwrap(), seed);
}

#[test]
fn bad_overrides_are_rejected_with_their_reason() {
    let cases: &[(&[&str], &[&str], Option<&str>)] = &[
        (
            &["robot.brakes=1"],
            &[
                "--set robot.brakes=1: unknown key `robot.brakes`",
                "known keys of [robot]",
                "braking",
            ],
            Some("robot.brakes"),
        ),
        (
            &["colour=red"],
            &["--set colour=red: unknown key `colour`", "name", "robot.*"],
            Some("colour"),
        ),
        (
            &["robot=1"],
            &["--set robot=1: `robot` is a table", "robot.braking"],
            Some("robot"),
        ),
        (
            &["robot.braking"],
            &["--set robot.braking: expected dotted.key=value"],
            None,
        ),
        (
            &["robot.latency=2.5"],
            &[
                "--set robot.latency=2.5: robot.latency = 2.5: expected a whole number >= 0 of control periods, got 2.5",
            ],
            Some("robot.latency"),
        ),
        (
            &["environment.obstacle_speed=fast"],
            &["--set environment.obstacle_speed=fast: environment.obstacle_speed = fast: "],
            Some("environment.obstacle_speed"),
        ),
        (
            &["environment.obstacle_speed=\"0.25\""],
            &[
                "--set environment.obstacle_speed=\"0.25\": environment.obstacle_speed = \"0.25\": expected a number in m/s, got the text \"0.25\"",
            ],
            Some("environment.obstacle_speed"),
        ),
        (
            &["controller.wrong_assumption_brake=yes"],
            &[
                "--set controller.wrong_assumption_brake=yes: controller.wrong_assumption_brake = yes: expected true or false, got `yes`",
            ],
            Some("controller.wrong_assumption_brake"),
        ),
        (
            &["controller.danger_rule=fast"],
            &[
                "--set controller.danger_rule=fast: controller.danger_rule = fast: expected one of paper, kinematic, area, got the text \"fast\"",
            ],
            Some("controller.danger_rule"),
        ),
        (
            &["robot.braking=-1"],
            &["--set robot.braking=-1: robot.braking = -1: must be > 0 (m/s^2)"],
            Some("robot.braking"),
        ),
        (
            &["environment.obstacle_speed=nan"],
            &[
                "--set environment.obstacle_speed=nan: environment.obstacle_speed = NaN: must be a finite number",
            ],
            Some("environment.obstacle_speed"),
        ),
        (
            &["robot.clearance=20"],
            &[": environment.initial_gap = 10: must be > robot.clearance = 20 (m)"],
            Some("environment.initial_gap"),
        ),
        (
            &["name="],
            &["--set name=: name = \"\": must not be empty"],
            Some("name"),
        ),
    ];
    let mut failures = Vec::new();
    for (sets, expect, key) in cases {
        let err = match with_sets(sets) {
            Ok(_) => {
                failures.push(format!("{sets:?}: accepted"));
                continue;
            }
            Err(e) => e,
        };
        let message = err.to_string();
        for want in *expect {
            if !message.contains(want) {
                failures.push(format!("{sets:?}: message lacks {want:?}:\n{message}"));
            }
        }
        if err.key() != *key {
            failures.push(format!("{sets:?}: key {:?}, want {key:?}", err.key()));
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n\n"));
}

#[test]
fn errors_in_the_file_name_the_file_even_with_overrides() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, BASE.replace("braking = 0.5", "braking = -0.5")).unwrap();
    let err = Problem::load_with_overrides(&path, &["robot.latency=0".to_string()]).unwrap_err();
    let message = err.to_string();
    assert!(
        message.starts_with(&format!(
            "{}: robot.braking = -0.5: must be > 0",
            path.display()
        )),
        "{message}"
    );
    assert_eq!(err.line(), Some(6));

    // An override fixes the file's error.
    let p = Problem::load_with_overrides(&path, &["robot.braking=0.5".to_string()]).unwrap();
    assert_eq!(p.robot.braking, 0.5);

    // An unknown key in the file is the file's error, whatever is overridden.
    std::fs::write(
        &path,
        BASE.replace("buffer = 0.1", "buffer = 0.1\nbufer = 0.2"),
    )
    .unwrap();
    let err =
        Problem::load_with_overrides(&path, &["controller.buffer=0".to_string()]).unwrap_err();
    let message = err.to_string();
    assert!(
        message.starts_with(&path.display().to_string()),
        "{message}"
    );
    assert!(
        message.contains("unknown field `bufer`") && message.contains("line 16"),
        "{message}"
    );
}

#[test]
fn a_missing_file_is_a_read_error() {
    let err = Problem::load(&problem_file("no-such-problem.toml")).unwrap_err();
    assert!(matches!(err, ProblemError::Read { .. }), "{err:?}");
    assert!(
        err.to_string()
            .contains("no-such-problem.toml: cannot read"),
        "{err}"
    );
}

/// Problem files shipped in problems/ (grid files, `*-grid.toml`, are sweeps, not problems).
fn shipped_problems() -> Vec<PathBuf> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(root().join("problems"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .filter(|p| !p.to_string_lossy().ends_with("-grid.toml"))
        // Scene files (tests/it/scene_input.rs reads them) have no [environment].
        .filter(|p| {
            std::fs::read_to_string(p)
                .unwrap()
                .contains("[environment]")
        })
        .collect();
    paths.sort();
    paths
}

#[test]
fn every_shipped_problem_loads_and_validates() {
    let paths = shipped_problems();
    for name in [
        "seed",
        "static-obstacle",
        "fast-obstacle",
        "zero-latency",
        "kinematic-rule",
        "area-rule",
    ] {
        assert!(
            paths.contains(&problem_file(&format!("{name}.toml"))),
            "{name}.toml missing"
        );
    }
    for path in &paths {
        let p = Problem::load(path).unwrap_or_else(|e| panic!("{e}"));
        p.validate(&path.display().to_string()).unwrap();
        assert_eq!(
            Some(p.name.as_str()),
            path.file_stem().and_then(|s| s.to_str()),
            "{}",
            path.display()
        );
    }
}

#[test]
fn shipped_problems_round_trip() {
    for path in shipped_problems() {
        let p = Problem::load(&path).unwrap();
        let text = p.to_toml_string();
        assert_eq!(
            Problem::from_toml_str(&text, "round-trip").unwrap(),
            p,
            "{text}"
        );
    }
}

/// Finite floats of every magnitude, including negative zero and subnormals.
fn any_float() -> impl Strategy<Value = f64> {
    prop::num::f64::NORMAL | prop::num::f64::SUBNORMAL | prop::num::f64::ZERO
}

prop_compose! {
    fn any_problem()(
        name in "[ -~]{0,12}",
        robot in (any_float(), any_float(), any_float(), any_float(), any::<u32>(), any_float()),
        controller in (any_float(), any_float(), any_rule(), any_float(), any::<bool>()),
        environment in (any_float(), any_float()),
    ) -> Problem {
        let (v_max, a, b, dt, latency, clearance) = robot;
        let (v_a, rho, rule, buffer, wab) = controller;
        let (w, g0) = environment;
        let spec = Spec {
            name: "", v_max, a, b, dt, latency, clearance, v_a, rho, rule, buffer, wab, w, g0,
        };
        Problem { name, ..spec.build() }
    }
}

proptest! {
    /// Serialising and parsing gives the same problem back, bit for bit, valid or not.
    #[test]
    fn any_problem_round_trips(p in any_problem()) {
        let text = p.to_toml_string();
        let back: Problem = toml::from_str(&text).unwrap();
        prop_assert_eq!(&back, &p);
        for (x, y) in [
            (back.robot.max_speed, p.robot.max_speed),
            (back.robot.clearance, p.robot.clearance),
            (
                back.environment.initial_gap.min(),
                p.environment.initial_gap.min(),
            ),
        ] {
            prop_assert_eq!(x.to_bits(), y.to_bits());
        }
        // Through the validating reader: the same verdict and, if valid, the same problem.
        match Problem::from_toml_str(&text, "round-trip") {
            Ok(q) => prop_assert_eq!(q, p),
            Err(e) => prop_assert!(p.validate("round-trip").is_err(), "{}", e),
        }
    }
}
