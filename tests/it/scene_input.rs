//! Scene files: reading (inline text and files), defaults, the single-obstacle form, `--set`
//! overrides of scene and obstacle keys, round trips, and every broken scene as a typed
//! [`ProblemError`] naming the origin, the key (an obstacle's by index and name) and the
//! reason, with the line where the file has one.

use std::path::PathBuf;

use safereach::core::model::{Problem, ProblemError};
use safereach::core::scene::{LaneChange, Obstacle, Position, Scene};

use crate::common::paths::{root, seed_file};
use crate::common::{edit, tmp};

/// A valid scene using every key; the cases below break it one edit at a time. Line numbers
/// matter: the cases point at them.
const BASE: &str = r#"name = "lanes"

[robot]
max_speed = 0.8
acceleration = 0.4
braking = 0.5
control_period = 0.1
latency = 1
clearance = 0.0
goal = 30.0
sensing_range = 3.0

[controller]
assumed_obstacle_speed = 0.2
reaction_radius = 1.4
danger_rule = "paper"
buffer = 0.1
wrong_assumption_brake = true
lane_change = true
lane_change_periods = 10
lane_change_rear_gap = 0.5

[scene]
lanes = [1, 0, -1]

[[obstacle]]
name = "oncoming"
lane = 0
position = 10.0
max_speed = 0.15

[[obstacle]]
name = "parked"
lane = 1
position = [4.0, 5.0]
max_speed = 0.0
static = true

[[obstacle]]
lane = -1
position = 6
max_speed = 0.1
"#;

/// The seed problem's text (the single-obstacle form), for the old-form cases.
const OLD: &str = r#"name = "old"

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

fn sets(sets: &[&str]) -> Vec<String> {
    sets.iter().map(|s| s.to_string()).collect()
}

/// The robot and controller BASE and OLD share, from the problem reader.
fn old_problem() -> Problem {
    Problem::from_toml_str(OLD, "old.toml").unwrap()
}

/// BASE, written out independently of the reader.
fn base_scene() -> Scene {
    let p = old_problem();
    Scene {
        name: "lanes".into(),
        robot: p.robot,
        controller: p.controller,
        goal: Some(30.0),
        sensing_range: Some(3.0),
        lane_change: Some(LaneChange {
            periods: 10,
            rear_gap: 0.5,
        }),
        sensing: None,
        lanes: vec![-1, 0, 1],
        obstacles: vec![
            Obstacle {
                name: "oncoming".into(),
                lane: 0,
                position: Position::At(10.0),
                max_speed: 0.15,
                is_static: false,
            },
            Obstacle {
                name: "parked".into(),
                lane: 1,
                position: Position::Range(4.0, 5.0),
                max_speed: 0.0,
                is_static: true,
            },
            Obstacle {
                name: "obstacle-2".into(),
                lane: -1,
                position: Position::At(6.0),
                max_speed: 0.1,
                is_static: false,
            },
        ],
    }
}

#[test]
fn the_base_scene_reads_as_written_with_lanes_sorted_and_defaults() {
    assert_eq!(
        Scene::from_toml_str(BASE, "base.toml").unwrap(),
        base_scene()
    );
}

#[test]
fn optional_keys_take_their_defaults() {
    let text = edit(
        BASE,
        &[
            ("goal = 30.0\n", ""),
            ("sensing_range = 3.0\n", ""),
            ("lane_change = true\n", ""),
            ("lane_change_periods = 10\n", ""),
            ("lane_change_rear_gap = 0.5\n", ""),
            ("[scene]\nlanes = [1, 0, -1]\n", ""),
            ("name = \"oncoming\"\n", ""),
            ("lane = 1\n", "lane = 0\n"),
            ("lane = -1\n", "lane = 0\n"),
            ("static = true\n", ""),
        ],
    );
    let s = Scene::from_toml_str(&text, "defaults.toml").unwrap();
    assert_eq!(s.goal, None);
    assert_eq!(s.sensing_range, None);
    assert_eq!(s.lane_change, None);
    assert_eq!(s.lanes, vec![0]);
    let names: Vec<&str> = s.obstacles.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["obstacle-0", "parked", "obstacle-2"]);
    assert!(s.obstacles.iter().all(|o| !o.is_static));

    // `[scene]` without `lanes` is lane 0 alone too.
    let with_table = edit(&text, &[("[[obstacle]]", "[scene]\n\n[[obstacle]]")]);
    assert_eq!(Scene::from_toml_str(&with_table, "x.toml").unwrap(), s);
}

#[test]
fn obstacles_must_be_tables() {
    let text = edit(
        BASE,
        &[("name = \"lanes\"\n", "name = \"lanes\"\nobstacle = 3\n")],
    );
    let text = &text[..text.find("[[obstacle]]").unwrap()];
    let err = Scene::from_toml_str(text, "bad.toml").unwrap_err();
    assert_eq!(err.key(), Some("obstacle"));
    assert!(
        err.to_string()
            .starts_with("bad.toml: obstacle: must be [[obstacle]] tables, not an integer"),
        "{err}"
    );
    assert_eq!(err.line(), Some(2));
    let text = text.replace("obstacle = 3", "obstacle = [1]");
    let err = Scene::from_toml_str(&text, "bad.toml").unwrap_err();
    assert_eq!(err.key(), Some("obstacle[0]"));
    assert!(
        err.to_string()
            .contains("must be a table ([[obstacle]]), not an integer"),
        "{err}"
    );
}

#[test]
fn lane_change_settings_without_lane_change_are_checked_and_ignored() {
    let off = edit(BASE, &[("lane_change = true", "lane_change = false")]);
    let s = Scene::from_toml_str(&off, "off.toml").unwrap();
    assert_eq!(s.lane_change, None);
    let absent = edit(BASE, &[("lane_change = true\n", "")]);
    assert_eq!(Scene::from_toml_str(&absent, "x.toml").unwrap(), s);
    // Still checked: a value out of range is an error even when switched off.
    let bad = edit(
        &off,
        &[("lane_change_periods = 10", "lane_change_periods = 0")],
    );
    let err = Scene::from_toml_str(&bad, "bad.toml").unwrap_err();
    assert_eq!(err.key(), Some("controller.lane_change_periods"));
    assert!(err.to_string().contains("must be >= 1"), "{err}");
    assert_eq!(err.line(), Some(20));
    let bad = edit(&off, &[("rear_gap = 0.5", "rear_gap = \"far\"")]);
    let err = Scene::from_toml_str(&bad, "bad.toml").unwrap_err();
    assert_eq!(err.key(), Some("controller.lane_change_rear_gap"));
}

/// A broken scene text and what its error must say.
struct Case {
    what: &'static str,
    /// Edits to the base text (BASE, or OLD where `old`).
    edits: &'static [(&'static str, &'static str)],
    /// Substrings the error's message must contain.
    expect: &'static [&'static str],
    /// The key the error must name, if any.
    key: Option<&'static str>,
    /// The 1-based line the error must point at, if any.
    line: Option<usize>,
}

const CASES: &[Case] = &[
    Case {
        what: "lane not in lanes",
        edits: &[("lane = -1\n", "lane = 2\n")],
        expect: &[
            "bad.toml: obstacle[2] (\"obstacle-2\").lane = 2: not a lane of the scene: scene.lanes = [-1, 0, 1]",
            "bad.toml:40:8",
        ],
        key: Some("obstacle[2] (\"obstacle-2\").lane"),
        line: Some(40),
    },
    Case {
        what: "lanes without lane 0",
        edits: &[("lanes = [1, 0, -1]", "lanes = [1, -1]")],
        expect: &["bad.toml: scene.lanes = [-1, 1]: must contain lane 0"],
        key: Some("scene.lanes"),
        line: Some(24),
    },
    Case {
        what: "lanes with a repeat",
        edits: &[("lanes = [1, 0, -1]", "lanes = [1, 0, -1, 1]")],
        expect: &["bad.toml: scene.lanes = [-1, 0, 1, 1]: lane 1 is listed twice"],
        key: Some("scene.lanes"),
        line: Some(24),
    },
    Case {
        what: "empty lanes",
        edits: &[("lanes = [1, 0, -1]", "lanes = []")],
        expect: &["scene.lanes = []: must contain lane 0"],
        key: Some("scene.lanes"),
        line: Some(24),
    },
    Case {
        what: "a lane out of range",
        edits: &[("lanes = [1, 0, -1]", "lanes = [1, 0, -1, 2000000]")],
        expect: &["scene.lanes = [-1, 0, 1, 2000000]: lane 2000000 is out of range"],
        key: Some("scene.lanes"),
        line: Some(24),
    },
    Case {
        what: "lanes not integers",
        edits: &[("lanes = [1, 0, -1]", "lanes = [1, 0, 0.5]")],
        expect: &[
            "bad.toml: scene.lanes = [1, 0, 0.5]: expected a list of lanes (whole numbers), e.g. [0, 1], got a list with 0.5 in it",
        ],
        key: Some("scene.lanes"),
        line: Some(24),
    },
    Case {
        what: "static with max_speed > 0",
        edits: &[("max_speed = 0.0", "max_speed = 0.2")],
        expect: &[
            "bad.toml: obstacle[1] (\"parked\").max_speed = 0.2: a static obstacle must have max_speed = 0",
        ],
        key: Some("obstacle[1] (\"parked\").max_speed"),
        line: Some(36),
    },
    Case {
        what: "duplicate names",
        edits: &[("name = \"parked\"", "name = \"oncoming\"")],
        expect: &[
            "bad.toml: obstacle[1] (\"oncoming\").name = \"oncoming\": obstacle[0] has the same name",
            "must be unique",
        ],
        key: Some("obstacle[1] (\"oncoming\").name"),
        line: Some(33),
    },
    Case {
        what: "a name equal to another's default",
        edits: &[("name = \"oncoming\"", "name = \"obstacle-2\"")],
        expect: &[
            "obstacle[2] (\"obstacle-2\").name = \"obstacle-2\": obstacle[0] has the same name",
        ],
        key: Some("obstacle[2] (\"obstacle-2\").name"),
        // The name is a default: the error points at the obstacle's header.
        line: Some(39),
    },
    Case {
        what: "an empty name",
        edits: &[("name = \"parked\"", "name = \" \"")],
        expect: &["obstacle[1] (\" \").name = \" \": must not be empty"],
        key: Some("obstacle[1] (\" \").name"),
        line: Some(33),
    },
    Case {
        what: "sensing range below the reaction radius",
        edits: &[("sensing_range = 3.0", "sensing_range = 1.0")],
        expect: &[
            "bad.toml: robot.sensing_range = 1: must be >= controller.reaction_radius = 1.4 (m)",
        ],
        key: Some("robot.sensing_range"),
        line: Some(11),
    },
    Case {
        what: "a lane change with one lane",
        edits: &[
            ("lanes = [1, 0, -1]", "lanes = [0]"),
            ("lane = 1\n", "lane = 0\n"),
            ("lane = -1\n", "lane = 0\n"),
        ],
        expect: &["bad.toml: controller.lane_change = true: a lane change with one lane"],
        key: Some("controller.lane_change"),
        line: Some(19),
    },
    Case {
        what: "a lane change with no lane next to lane 0",
        edits: &[
            ("lanes = [1, 0, -1]", "lanes = [0, 2]"),
            ("lane = 1\n", "lane = 2\n"),
            ("lane = -1\n", "lane = 0\n"),
        ],
        expect: &["controller.lane_change = true: no lane to change into: scene.lanes = [0, 2]"],
        key: Some("controller.lane_change"),
        line: Some(19),
    },
    Case {
        what: "missing lane_change_periods",
        edits: &[("lane_change_periods = 10\n", "")],
        expect: &[
            "bad.toml: controller.lane_change_periods: missing: required when controller.lane_change = true",
        ],
        key: Some("controller.lane_change_periods"),
        line: Some(19),
    },
    Case {
        what: "missing lane_change_rear_gap",
        edits: &[("lane_change_rear_gap = 0.5\n", "")],
        expect: &["bad.toml: controller.lane_change_rear_gap: missing: required when"],
        key: Some("controller.lane_change_rear_gap"),
        line: Some(19),
    },
    Case {
        what: "zero lane-change periods",
        edits: &[("lane_change_periods = 10", "lane_change_periods = 0")],
        expect: &["controller.lane_change_periods = 0: must be >= 1 (control periods)"],
        key: Some("controller.lane_change_periods"),
        line: Some(20),
    },
    Case {
        what: "fractional lane-change periods",
        edits: &[("lane_change_periods = 10", "lane_change_periods = 2.5")],
        expect: &[
            "controller.lane_change_periods = 2.5: expected a whole number >= 0 of control periods, got 2.5",
        ],
        key: Some("controller.lane_change_periods"),
        line: Some(20),
    },
    Case {
        what: "negative rear gap",
        edits: &[("lane_change_rear_gap = 0.5", "lane_change_rear_gap = -0.5")],
        expect: &["controller.lane_change_rear_gap = -0.5: must be >= 0 (m)"],
        key: Some("controller.lane_change_rear_gap"),
        line: Some(21),
    },
    Case {
        what: "lane_change not a boolean",
        edits: &[("lane_change = true", "lane_change = \"yes\"")],
        expect: &["controller.lane_change = \"yes\": expected true or false, got the text \"yes\""],
        key: Some("controller.lane_change"),
        line: Some(19),
    },
    Case {
        what: "range with min > max",
        edits: &[("position = [4.0, 5.0]", "position = [5.0, 4.0]")],
        expect: &[
            "bad.toml: obstacle[1] (\"parked\").position = [5, 4]: a range [min, max] needs min <= max",
        ],
        key: Some("obstacle[1] (\"parked\").position"),
        line: Some(35),
    },
    Case {
        what: "position at the clearance",
        edits: &[("position = 6\n", "position = 0\n")],
        expect: &[
            "bad.toml: obstacle[2] (\"obstacle-2\").position = 0: must be > robot.clearance = 0 (m)",
        ],
        key: Some("obstacle[2] (\"obstacle-2\").position"),
        line: Some(41),
    },
    Case {
        what: "range reaching the clearance",
        edits: &[
            ("clearance = 0.0", "clearance = 0.5"),
            ("position = [4.0, 5.0]", "position = [0.5, 5.0]"),
        ],
        expect: &[
            "obstacle[1] (\"parked\").position = [0.5, 5]: its min must be > robot.clearance = 0.5 (m)",
        ],
        key: Some("obstacle[1] (\"parked\").position"),
        line: Some(35),
    },
    Case {
        what: "unknown key in an obstacle",
        edits: &[(
            "name = \"parked\"\n",
            "name = \"parked\"\ncolour = \"red\"\n",
        )],
        expect: &[
            "bad.toml: obstacle[1] (\"parked\").colour: unknown key; an obstacle has name, lane, position, max_speed, static",
        ],
        key: Some("obstacle[1] (\"parked\").colour"),
        line: Some(34),
    },
    Case {
        what: "missing key in an obstacle",
        edits: &[("max_speed = 0.1\n", "")],
        expect: &[
            "bad.toml: obstacle[2] (\"obstacle-2\").max_speed: missing: every obstacle needs",
        ],
        key: Some("obstacle[2] (\"obstacle-2\").max_speed"),
        line: Some(39),
    },
    Case {
        what: "lane not an integer",
        edits: &[("lane = 1\n", "lane = 1.5\n")],
        expect: &["obstacle[1] (\"parked\").lane = 1.5: expected a lane (a whole number), got 1.5"],
        key: Some("obstacle[1] (\"parked\").lane"),
        line: Some(34),
    },
    Case {
        what: "max_speed a string",
        edits: &[("max_speed = 0.15", "max_speed = \"fast\"")],
        expect: &[
            "obstacle[0] (\"oncoming\").max_speed = \"fast\": expected a number in m/s, got the text \"fast\"",
        ],
        key: Some("obstacle[0] (\"oncoming\").max_speed"),
        line: Some(30),
    },
    Case {
        what: "position a string",
        edits: &[("position = 10.0", "position = \"near\"")],
        expect: &[
            "obstacle[0] (\"oncoming\").position = \"near\": expected a number or a range [min, max] in m, got the text \"near\"",
        ],
        key: Some("obstacle[0] (\"oncoming\").position"),
        line: Some(29),
    },
    Case {
        what: "position with three numbers",
        edits: &[("position = [4.0, 5.0]", "position = [4.0, 5.0, 6.0]")],
        expect: &[
            "obstacle[1] (\"parked\").position = [4.0, 5.0, 6.0]: expected a number or a range [min, max] in m, got a list of 3 values",
        ],
        key: Some("obstacle[1] (\"parked\").position"),
        line: Some(35),
    },
    Case {
        what: "static not a boolean",
        edits: &[("static = true", "static = 1")],
        expect: &["obstacle[1] (\"parked\").static = 1: expected true or false, got 1"],
        key: Some("obstacle[1] (\"parked\").static"),
        line: Some(37),
    },
    Case {
        what: "name not a string",
        edits: &[("name = \"parked\"", "name = 5")],
        expect: &["obstacle[1] (\"obstacle-1\").name = 5: expected text, got 5"],
        key: Some("obstacle[1] (\"obstacle-1\").name"),
        line: Some(33),
    },
    Case {
        what: "negative obstacle speed",
        edits: &[("max_speed = 0.15", "max_speed = -0.15")],
        expect: &["obstacle[0] (\"oncoming\").max_speed = -0.15: must be >= 0 (m/s)"],
        key: Some("obstacle[0] (\"oncoming\").max_speed"),
        line: Some(30),
    },
    Case {
        what: "NaN obstacle speed",
        edits: &[("max_speed = 0.15", "max_speed = nan")],
        expect: &["obstacle[0] (\"oncoming\").max_speed = NaN: must be a finite number (m/s)"],
        key: Some("obstacle[0] (\"oncoming\").max_speed"),
        line: Some(30),
    },
    Case {
        what: "infinite position",
        edits: &[("position = 10.0", "position = inf")],
        expect: &["obstacle[0] (\"oncoming\").position = inf: must be a finite number (m)"],
        key: Some("obstacle[0] (\"oncoming\").position"),
        line: Some(29),
    },
    Case {
        what: "range to infinity",
        edits: &[("position = [4.0, 5.0]", "position = [4.0, inf]")],
        expect: &["obstacle[1] (\"parked\").position = [4, inf]: must be a finite number (m)"],
        key: Some("obstacle[1] (\"parked\").position"),
        line: Some(35),
    },
    Case {
        what: "NaN goal",
        edits: &[("goal = 30.0", "goal = nan")],
        expect: &["bad.toml: robot.goal = NaN: must be a finite number (m)"],
        key: Some("robot.goal"),
        line: Some(10),
    },
    Case {
        what: "infinite sensing range",
        edits: &[("sensing_range = 3.0", "sensing_range = inf")],
        expect: &["robot.sensing_range = inf: must be a finite number (m)"],
        key: Some("robot.sensing_range"),
        line: Some(11),
    },
    Case {
        what: "NaN rear gap",
        edits: &[("lane_change_rear_gap = 0.5", "lane_change_rear_gap = nan")],
        expect: &["controller.lane_change_rear_gap = NaN: must be a finite number (m)"],
        key: Some("controller.lane_change_rear_gap"),
        line: Some(21),
    },
    Case {
        what: "zero goal",
        edits: &[("goal = 30.0", "goal = 0")],
        expect: &["bad.toml: robot.goal = 0: must be > 0 (m)"],
        key: Some("robot.goal"),
        line: Some(10),
    },
    Case {
        what: "negative goal",
        edits: &[("goal = 30.0", "goal = -5.0")],
        expect: &["bad.toml: robot.goal = -5: must be > 0 (m)"],
        key: Some("robot.goal"),
        line: Some(10),
    },
    Case {
        what: "goal a string",
        edits: &[("goal = 30.0", "goal = \"far\"")],
        expect: &["robot.goal = \"far\": expected a number in m, got the text \"far\""],
        key: Some("robot.goal"),
        line: Some(10),
    },
    Case {
        what: "goal beyond the horizon",
        edits: &[("goal = 30.0", "goal = 200000")],
        expect: &[
            "robot.goal = 200000: absurd horizon",
            "to reach the goal at top speed",
        ],
        key: Some("robot.goal"),
        line: Some(10),
    },
    Case {
        what: "an obstacle beyond the horizon",
        edits: &[("position = [4.0, 5.0]", "position = [4.0, 200000]")],
        expect: &[
            "obstacle[1] (\"parked\").position = [4, 200000]: absurd horizon",
            "more than a million control periods",
        ],
        key: Some("obstacle[1] (\"parked\").position"),
        line: Some(35),
    },
    Case {
        what: "robot keys keep the problem's rules",
        edits: &[("braking = 0.5", "braking = -0.5")],
        expect: &[
            "bad.toml: robot.braking = -0.5: must be > 0 (m/s^2)",
            "bad.toml:6:11",
        ],
        key: Some("robot.braking"),
        line: Some(6),
    },
    Case {
        what: "missing robot key",
        edits: &[("braking = 0.5\n", "")],
        expect: &["bad.toml: ", "missing field `braking`"],
        key: Some("robot.braking"),
        line: None,
    },
    Case {
        what: "unknown key in [robot]",
        edits: &[("braking = 0.5\n", "braking = 0.5\nwheel_radius = 0.1\n")],
        expect: &[
            "bad.toml: robot.wheel_radius: unknown key; [robot] has max_speed",
            "goal, sensing_range",
        ],
        key: Some("robot.wheel_radius"),
        line: Some(7),
    },
    Case {
        what: "unknown key in [scene]",
        edits: &[("lanes = [1, 0, -1]\n", "lanes = [1, 0, -1]\nwidth = 3\n")],
        expect: &["bad.toml: scene.width: unknown key; [scene] has lanes"],
        key: Some("scene.width"),
        line: Some(25),
    },
    Case {
        what: "unknown top-level key",
        edits: &[("name = \"lanes\"\n", "name = \"lanes\"\ncolour = 1\n")],
        expect: &["bad.toml: colour: unknown key; a scene file has name, [robot]"],
        key: Some("colour"),
        line: Some(2),
    },
    Case {
        what: "environment beside obstacles",
        edits: &[(
            "[scene]",
            "[environment]\nobstacle_speed = 0.15\ninitial_gap = 10.0\n\n[scene]",
        )],
        expect: &[
            "bad.toml: environment: a file is either a single-obstacle problem ([environment]) or a scene",
            "not both",
        ],
        key: Some("environment"),
        line: Some(23),
    },
    Case {
        what: "scene without obstacles",
        edits: &[(
            "[[obstacle]]\nname = \"oncoming\"\nlane = 0\nposition = 10.0\nmax_speed = 0.15\n\n\
             [[obstacle]]\nname = \"parked\"\nlane = 1\nposition = [4.0, 5.0]\nmax_speed = 0.0\n\
             static = true\n\n[[obstacle]]\nlane = -1\nposition = 6\nmax_speed = 0.1\n",
            "",
        )],
        expect: &["bad.toml: obstacle: a scene needs at least one [[obstacle]]"],
        key: Some("obstacle"),
        line: None,
    },
    Case {
        what: "TOML syntax error",
        edits: &[("max_speed = 0.15", "max_speed = 0.1.5")],
        expect: &["bad.toml: TOML parse error at line 30"],
        key: None,
        line: Some(30),
    },
];

/// Checks `err` against `case`, recording what does not match in `failures`.
fn check_case(case: &Case, origin: &str, err: &ProblemError, failures: &mut Vec<String>) {
    let message = err.to_string();
    for want in case.expect {
        if !message.contains(want) {
            failures.push(format!("{}: message lacks {want:?}:\n{message}", case.what));
        }
    }
    if err.origin() != origin {
        failures.push(format!("{}: origin {:?}", case.what, err.origin()));
    }
    if let Some(key) = case.key
        && err.key() != Some(key)
    {
        failures.push(format!("{}: key {:?}, want {key:?}", case.what, err.key()));
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

#[test]
fn broken_scenes_are_rejected_with_their_reason() {
    let mut failures = Vec::new();
    for case in CASES {
        match Scene::from_toml_str(&edit(BASE, case.edits), "bad.toml") {
            Ok(_) => failures.push(format!("{}: accepted", case.what)),
            Err(err) => check_case(case, "bad.toml", &err, &mut failures),
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n\n"));
}

#[test]
fn broken_scene_files_name_their_path() {
    let dir = tmp();
    let path = dir.path().join("bad.toml");
    let origin = path.display().to_string();
    let mut failures = Vec::new();
    for case in CASES {
        std::fs::write(&path, edit(BASE, case.edits)).unwrap();
        match Scene::load(&path) {
            Ok(_) => failures.push(format!("{}: accepted", case.what)),
            Err(err) => {
                let case = Case {
                    expect: &[],
                    ..*case
                };
                check_case(&case, &origin, &err, &mut failures);
                if !err.to_string().starts_with(&format!("{origin}: ")) {
                    failures.push(format!("{}: {err}", case.what));
                }
            }
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n\n"));
}

#[test]
fn validate_names_an_obstacle_by_index_and_name() {
    let mut s = base_scene();
    s.validate("s").unwrap();
    s.obstacles[1].max_speed = 0.2;
    let err = s.validate("scenes/x.toml").unwrap_err();
    assert_eq!(
        err.to_string(),
        "scenes/x.toml: obstacle[1] (\"parked\").max_speed = 0.2: a static obstacle must have \
         max_speed = 0"
    );
    assert_eq!(err.line(), None);
}

// ---- The single-obstacle form ----

#[test]
fn an_old_file_is_the_scene_of_its_problem() {
    let scene = Scene::from_toml_str(OLD, "old.toml").unwrap();
    assert_eq!(scene, Scene::from_problem(&old_problem()));
    assert_eq!(scene.as_problem(), Some(old_problem()));
}

#[test]
fn an_old_file_may_carry_the_scene_settings() {
    let text = edit(
        OLD,
        &[
            (
                "clearance = 0.0\n",
                "clearance = 0.0\ngoal = 30\nsensing_range = 2\n",
            ),
            (
                "wrong_assumption_brake = true\n",
                "wrong_assumption_brake = true\nlane_change = false\nlane_change_periods = 3\n",
            ),
        ],
    );
    let scene = Scene::from_toml_str(&text, "old.toml").unwrap();
    let want = Scene {
        goal: Some(30.0),
        sensing_range: Some(2.0),
        ..Scene::from_problem(&old_problem())
    };
    assert_eq!(scene, want);
    // The problem reader does not know them.
    assert!(Problem::from_toml_str(&text, "old.toml").is_err());

    // A lane change needs a second lane, which the single-obstacle form cannot have.
    let text = edit(
        OLD,
        &[(
            "wrong_assumption_brake = true\n",
            "wrong_assumption_brake = true\nlane_change = true\nlane_change_periods = 3\nlane_change_rear_gap = 0.5\n",
        )],
    );
    let err = Scene::from_toml_str(&text, "old.toml").unwrap_err();
    assert!(
        err.to_string()
            .starts_with("old.toml: controller.lane_change = true: a lane change with one lane"),
        "{err}"
    );
    assert_eq!(err.line(), Some(17));
    // And the scene rules hold there too.
    let text = edit(
        OLD,
        &[("clearance = 0.0\n", "clearance = 0.0\ngoal = -1\n")],
    );
    let err = Scene::from_toml_str(&text, "old.toml").unwrap_err();
    assert!(
        err.to_string()
            .starts_with("old.toml: robot.goal = -1: must be > 0 (m)"),
        "{err}"
    );
    assert_eq!(err.line(), Some(10));
}

#[test]
fn an_old_file_fails_the_problem_checks_with_the_problem_messages() {
    let edits: &[&[(&str, &str)]] = &[
        &[("braking = 0.5", "braking = -0.5")],
        &[("obstacle_speed = 0.15", "obstacle_speed = nan")],
        &[("clearance = 0.0", "clearance = 12")],
        &[("initial_gap = 10.0", "initial_gap = 200000")],
        &[("latency = 1", "latency = 1.5")],
        &[("latency = 1", "latency = 5000")],
        &[("danger_rule = \"paper\"", "danger_rule = \"fast\"")],
        &[("name = \"old\"", "name = \"\"")],
        &[("braking = 0.5\n", "")],
        &[("initial_gap = 10.0\n", "")],
        &[("braking = 0.5", "braking = 0.5.1")],
    ];
    for edits in edits {
        let text = edit(OLD, edits);
        let want = Problem::from_toml_str(&text, "old.toml").unwrap_err();
        let got = Scene::from_toml_str(&text, "old.toml").unwrap_err();
        assert_eq!(got.to_string(), want.to_string(), "{edits:?}");
        assert_eq!(got.key(), want.key(), "{edits:?}");
        assert_eq!(got.line(), want.line(), "{edits:?}");
    }
}

/// Problem files shipped in problems/ (grid files, `*-grid.toml`, are sweeps).
fn shipped_files() -> Vec<PathBuf> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(root().join("problems"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .filter(|p| !p.to_string_lossy().ends_with("-grid.toml"))
        .collect();
    paths.sort();
    paths
}

#[test]
fn every_shipped_file_reads_as_a_scene() {
    let paths = shipped_files();
    assert!(paths.contains(&seed_file()));
    for path in &paths {
        let scene = Scene::load(path).unwrap_or_else(|e| panic!("{e}"));
        scene.validate(&path.display().to_string()).unwrap();
        // Files in the single-obstacle form read as their problem's scene.
        if let Ok(problem) = Problem::load(path) {
            assert_eq!(scene, Scene::from_problem(&problem), "{}", path.display());
        }
        let text = scene.to_toml_string();
        assert_eq!(
            Scene::from_toml_str(&text, "round-trip").unwrap(),
            scene,
            "{text}"
        );
    }
}

// ---- Round trips ----

#[test]
fn scenes_round_trip() {
    let base = base_scene();
    let text = base.to_toml_string();
    assert_eq!(Scene::from_toml_str(&text, "rt").unwrap(), base, "{text}");

    let mut s = base_scene();
    s.goal = None;
    s.sensing_range = None;
    s.lane_change = None;
    s.lanes = vec![-3, 0, 7];
    s.obstacles[1].lane = 7;
    s.obstacles[2].lane = -3;
    s.obstacles[0].position = Position::Range(7.25, 7.25);
    s.obstacles[2].max_speed = 1e-7;
    let text = s.to_toml_string();
    assert_eq!(Scene::from_toml_str(&text, "rt").unwrap(), s, "{text}");

    let old = Scene::from_problem(&old_problem());
    let text = old.to_toml_string();
    assert!(!text.contains("[environment]"), "{text}");
    assert_eq!(Scene::from_toml_str(&text, "rt").unwrap(), old, "{text}");
}

// ---- Overrides ----

#[test]
fn overrides_set_scene_and_obstacle_keys() {
    let s = Scene::from_toml_str_with_overrides(
        BASE,
        "base.toml",
        &sets(&[
            "obstacle.0.max_speed=0.25",
            "obstacle.0.position=[8, 12.5]",
            "obstacle.0.name=front",
            "obstacle.2.lane=1",
            "obstacle.2.static=true",
            "obstacle.2.max_speed=0",
            "scene.lanes=[1, 0]",
            "robot.goal=50",
            "robot.sensing_range = 2",
            "controller.lane_change_periods=4",
            "controller.lane_change_rear_gap=0",
        ]),
    )
    .unwrap();
    let mut want = base_scene();
    want.obstacles[0] = Obstacle {
        name: "front".into(),
        lane: 0,
        position: Position::Range(8.0, 12.5),
        max_speed: 0.25,
        is_static: false,
    };
    want.obstacles[2] = Obstacle {
        lane: 1,
        is_static: true,
        max_speed: 0.0,
        ..want.obstacles[2].clone()
    };
    want.lanes = vec![0, 1];
    want.goal = Some(50.0);
    want.sensing_range = Some(2.0);
    want.lane_change = Some(LaneChange {
        periods: 4,
        rear_gap: 0.0,
    });
    assert_eq!(s, want);

    let off = Scene::from_toml_str_with_overrides(
        BASE,
        "base.toml",
        &sets(&["controller.lane_change=false"]),
    )
    .unwrap();
    assert_eq!(off.lane_change, None);

    // The last override of a key wins; no overrides: the file as it is.
    let s = Scene::from_toml_str_with_overrides(
        BASE,
        "base.toml",
        &sets(&["obstacle.1.lane=-1", "obstacle.1.lane=0"]),
    )
    .unwrap();
    assert_eq!(s.obstacles[1].lane, 0);
    assert_eq!(
        Scene::from_toml_str_with_overrides(BASE, "base.toml", &[]).unwrap(),
        base_scene()
    );

    // On a single-obstacle file: its keys and the scene settings.
    let s = Scene::from_toml_str_with_overrides(
        OLD,
        "old.toml",
        &sets(&["environment.obstacle_speed=0.3", "robot.goal=12"]),
    )
    .unwrap();
    assert_eq!(s.obstacles[0].max_speed, 0.3);
    assert_eq!(s.goal, Some(12.0));
}

/// A base text, overrides that break it, substrings the error must contain, its key.
type SetCase = (
    &'static str,
    &'static [&'static str],
    &'static [&'static str],
    Option<&'static str>,
);

#[test]
fn bad_overrides_name_the_flag() {
    let cases: &[SetCase] = &[
        (
            BASE,
            &["obstacle.1.max_speed=0.2"],
            &[
                "--set obstacle.1.max_speed=0.2: obstacle[1] (\"parked\").max_speed = 0.2: a static obstacle must have max_speed = 0",
            ],
            Some("obstacle[1] (\"parked\").max_speed"),
        ),
        (
            BASE,
            &["obstacle.3.lane=0"],
            &[
                "--set obstacle.3.lane=0: there is no obstacle 3: the file has 3 [[obstacle]] tables, indices 0 to 2",
            ],
            Some("obstacle.3.lane"),
        ),
        (
            BASE,
            &["obstacle.0.lane=5"],
            &[
                "--set obstacle.0.lane=5: obstacle[0] (\"oncoming\").lane = 5: not a lane of the scene",
            ],
            Some("obstacle[0] (\"oncoming\").lane"),
        ),
        (
            BASE,
            &["obstacle.0.lane=1.5"],
            &[
                "--set obstacle.0.lane=1.5: obstacle.0.lane = 1.5: expected a lane (a whole number), got 1.5",
            ],
            Some("obstacle.0.lane"),
        ),
        (
            BASE,
            &["obstacle.0.position=[1, 2, 3]"],
            &[
                "--set obstacle.0.position=[1, 2, 3]: ",
                "got a list of 3 values",
            ],
            Some("obstacle.0.position"),
        ),
        (
            BASE,
            &["obstacle.0.position=[12, 8]"],
            &[
                "--set obstacle.0.position=[12, 8]: obstacle[0] (\"oncoming\").position = [12, 8]: a range [min, max] needs min <= max",
            ],
            Some("obstacle[0] (\"oncoming\").position"),
        ),
        (
            BASE,
            &["obstacle.0.colour=red"],
            &[
                "--set obstacle.0.colour=red: unknown key `obstacle.0.colour`; known keys of [[obstacle]]: name, lane, position, max_speed, static",
            ],
            Some("obstacle.0.colour"),
        ),
        (
            BASE,
            &["obstacle.first.lane=0"],
            &["--set obstacle.first.lane=0: `first` is not an obstacle index"],
            Some("obstacle.first.lane"),
        ),
        (
            BASE,
            &["obstacle.0=1"],
            &["--set obstacle.0=1: set one key of one obstacle: obstacle.<index>.<key>"],
            Some("obstacle.0"),
        ),
        (
            BASE,
            &["scene=1"],
            &["--set scene=1: `scene` is a table; set one of its keys: scene.lanes"],
            Some("scene"),
        ),
        (
            BASE,
            &["scene.lanes=[0, 0]"],
            &["--set scene.lanes=[0, 0]: scene.lanes = [0, 0]: lane 0 is listed twice"],
            Some("scene.lanes"),
        ),
        (
            BASE,
            &["scene.lanes=[0, 0.5]"],
            &[
                "--set scene.lanes=[0, 0.5]: scene.lanes = [0, 0.5]: expected a list of lanes (whole numbers), e.g. [0, 1], got a list with 0.5 in it",
            ],
            Some("scene.lanes"),
        ),
        (
            BASE,
            &["robot.goal=-1"],
            &["--set robot.goal=-1: robot.goal = -1: must be > 0 (m)"],
            Some("robot.goal"),
        ),
        (
            BASE,
            &["robot.sensing_range=1"],
            &[
                "--set robot.sensing_range=1: robot.sensing_range = 1: must be >= controller.reaction_radius",
            ],
            Some("robot.sensing_range"),
        ),
        (
            BASE,
            &["robot.goals=1"],
            &[
                "--set robot.goals=1: unknown key `robot.goals`; known keys of [robot]: ",
                "goal, sensing_range",
            ],
            Some("robot.goals"),
        ),
        (
            BASE,
            &["controller.lane_change=yes"],
            &[
                "--set controller.lane_change=yes: controller.lane_change = yes: expected true or false, got `yes`",
            ],
            Some("controller.lane_change"),
        ),
        (
            BASE,
            &["environment.obstacle_speed=0.1"],
            &[
                "--set environment.obstacle_speed=0.1: environment: ",
                "not both",
            ],
            Some("environment"),
        ),
        (
            OLD,
            &["scene.lanes=[0, 1]"],
            &["--set scene.lanes=[0, 1]: environment: ", "not both"],
            Some("environment"),
        ),
        (
            OLD,
            &["obstacle.0.max_speed=0.1"],
            &[
                "--set obstacle.0.max_speed=0.1: the file is a single-obstacle problem",
                "environment.obstacle_speed",
            ],
            Some("obstacle.0.max_speed"),
        ),
        (
            OLD,
            &[
                "controller.lane_change=true",
                "controller.lane_change_periods=2",
                "controller.lane_change_rear_gap=0",
            ],
            &[
                "--set controller.lane_change=true: controller.lane_change = true: a lane change with one lane",
            ],
            Some("controller.lane_change"),
        ),
        (
            OLD,
            &["controller.lane_change=true"],
            &["--set controller.lane_change=true: controller.lane_change_periods: missing"],
            Some("controller.lane_change_periods"),
        ),
        (
            OLD,
            &["robot.braking=-1"],
            &["--set robot.braking=-1: robot.braking = -1: must be > 0 (m/s^2)"],
            Some("robot.braking"),
        ),
    ];
    let mut failures = Vec::new();
    for (text, set, expect, key) in cases {
        let err = match Scene::from_toml_str_with_overrides(text, "f.toml", &sets(set)) {
            Ok(_) => {
                failures.push(format!("{set:?}: accepted"));
                continue;
            }
            Err(e) => e,
        };
        let message = err.to_string();
        for want in *expect {
            if !message.contains(want) {
                failures.push(format!("{set:?}: message lacks {want:?}:\n{message}"));
            }
        }
        if !err.origin().starts_with("--set ") {
            failures.push(format!("{set:?}: origin {:?}", err.origin()));
        }
        if key.is_some() && err.key() != *key {
            failures.push(format!("{set:?}: key {:?}, want {key:?}", err.key()));
        }
        if err.line().is_some() {
            failures.push(format!("{set:?}: a line {:?} for a flag", err.line()));
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n\n"));
}

#[test]
fn a_duplicate_name_is_blamed_on_the_later_obstacle() {
    // Whichever of the two names an override set, the error points at the later one and
    // names the earlier.
    let err =
        Scene::from_toml_str_with_overrides(BASE, "f.toml", &sets(&["obstacle.0.name=parked"]))
            .unwrap_err();
    assert!(
        err.to_string().starts_with(
            "f.toml: obstacle[1] (\"parked\").name = \"parked\": obstacle[0] has the same name"
        ),
        "{err}"
    );
    assert_eq!(err.line(), Some(33));
    let err =
        Scene::from_toml_str_with_overrides(BASE, "f.toml", &sets(&["obstacle.2.name=parked"]))
            .unwrap_err();
    assert!(
        err.to_string().starts_with(
            "--set obstacle.2.name=parked: obstacle[2] (\"parked\").name = \"parked\": \
             obstacle[1] has the same name"
        ),
        "{err}"
    );
}

#[test]
fn errors_in_a_scene_file_name_the_file_even_with_overrides() {
    let dir = tmp();
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, edit(BASE, &[("max_speed = 0.0", "max_speed = 0.2")])).unwrap();
    let err = Scene::load_with_overrides(&path, &sets(&["robot.goal=40"])).unwrap_err();
    assert!(
        err.to_string().starts_with(&format!(
            "{}: obstacle[1] (\"parked\").max_speed = 0.2: a static obstacle",
            path.display()
        )),
        "{err}"
    );
    assert_eq!(err.line(), Some(36));
    // An override fixes the file's error.
    let s = Scene::load_with_overrides(&path, &sets(&["obstacle.1.static=false"])).unwrap();
    assert!(!s.obstacles[1].is_static);
    assert_eq!(s.obstacles[1].max_speed, 0.2);
    // A scene file that is missing is a read error.
    let err = Scene::load(&dir.path().join("none.toml")).unwrap_err();
    assert!(matches!(err, ProblemError::Read { .. }), "{err:?}");
    // Old files through the file loader too.
    assert_eq!(
        Scene::load_with_overrides(&seed_file(), &sets(&["robot.goal=5"]))
            .unwrap()
            .goal,
        Some(5.0)
    );
}
