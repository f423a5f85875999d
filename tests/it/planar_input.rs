//! Planar problem files (docs/semantics.md §13.10): every shipped one reads; the seed
//! embedded in the plane reads as exactly the numbers the planar engines are tested with
//! (tests/it/common/line_in_plane.rs, built by hand); every broken file is a
//! [`ProblemError`] naming the origin, the key and the reason; the CLI exits 2 naming the
//! file and the key, and says which commands do not take planar problems yet; `init
//! --planar` writes a template that reads back.

use std::path::{Path, PathBuf};

use safereach::core::model::{Problem, ProblemError};
use safereach::core::num::Exact;
use safereach::core::planar::{DangerZone, PlanarProblem, Start};
use safereach::core::plane::point::Point;
use safereach::core::template;

use crate::common::cli::{bad_input_exits_2, safereach};
use crate::common::line_in_plane::{decimal, embed};
use crate::common::paths::{root, seed_file};
use crate::common::{edit, tmp};

/// A valid planar problem; the cases below break it one edit at a time. Line numbers
/// matter: a case points at one.
const BASE: &str = r#"name = "base"

[plane]

[robot]
max_speed = 1.0
acceleration = 0.5
braking = 1.0
control_period = 0.1
latency = 1
clearance = 0.0
radius = 0.3
path = [[0, 0], [10, 0], [14, 4]]

[controller]
assumed_obstacle_speed = 1.4
reaction_radius = 3.0
danger_rule = "kinematic"
buffer = 0.2
wrong_assumption_brake = true

[sensing]
range = 8.0

[[obstacle]]
name = "walker"
radius = 0.3
start = [6.0, -4.0]
max_speed = 1.4
region = [[5, -5], [7, -5], [7, 5], [5, 5]]

[[obstacle]]
name = "car"
start_min = [20.0, -30.0]
start_max = [21.0, -20.0]
max_speed = 10
direction = [0, 1]
"#;

/// The shipped planar problems.
fn shipped() -> Vec<PathBuf> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(root().join("problems/planar"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    paths.sort();
    paths
}

fn point(x: f64, y: f64) -> Point {
    Point::new(decimal(x), decimal(y))
}

#[test]
fn every_shipped_planar_problem_reads_as_what_it_says() {
    let names: Vec<String> = shipped()
        .iter()
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        [
            "crossing-car",
            "nav2-stop-polygon",
            "overtaking",
            "pedestrian-crossing",
            "seed-in-plane"
        ]
    );
    for path in shipped() {
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(PlanarProblem::is_planar(&text), "{}", path.display());
        let problem = PlanarProblem::load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(problem.name, path.file_stem().unwrap().to_string_lossy());
        let params = problem.params();
        // A few hundred control periods at most: a path that ends driven at top speed,
        // plus stopping from it (the seed keeps the seed's horizon).
        let m = &params.motion;
        if params.path_ends {
            let drive = params.path.length() / (&m.v_max * &m.dt);
            let stop = &m.v_max / (&m.b_min * &m.dt);
            let periods = (drive + stop).to_f64().value();
            assert!(periods <= 400.0, "{}: {periods} periods", path.display());
        }
        // A 1-D reader refuses it, so it can never be analysed as a line problem by mistake.
        assert!(Problem::load(&path).is_err(), "{}", path.display());
    }
    let load = |name: &str| {
        PlanarProblem::load(&root().join(format!("problems/planar/{name}.toml")))
            .unwrap()
            .params()
    };
    let car = load("crossing-car");
    let unit = car.obstacles[0].direction.as_ref().unwrap().unit().clone();
    assert_eq!(unit, point(0.0, 1.0), "an axis direction is exact");
    assert!(car.path_ends && car.sensing.view_cos_half.is_none());
    let nav2 = load("nav2-stop-polygon");
    let DangerZone::Polygon(zone) = &nav2.zone else {
        panic!("the Nav2 file has a polygon zone");
    };
    assert!(zone.contains(&point(1.2, 0.0)) && !zone.contains(&point(1.3, 0.0)));
    // 120° and 360° are angles whose half has a rational cosine: exact, not rounded.
    let crossing = load("pedestrian-crossing");
    assert_eq!(crossing.sensing.view_cos_half, Some(decimal(0.5)));
    assert_eq!(crossing.sensing.first_detection, Some(decimal(2.0)));
    assert_eq!(
        load("overtaking").sensing.view_cos_half,
        Some(decimal(-1.0))
    );
}

#[test]
fn the_seed_in_the_plane_is_the_embedded_seed_field_by_field() {
    let file = PlanarProblem::load(&root().join("problems/planar/seed-in-plane.toml"))
        .unwrap()
        .params();
    let seed = Problem::load(&seed_file()).unwrap();
    let by_hand = embed(&seed);
    assert_eq!(file.motion, by_hand.motion);
    assert_eq!(file.robot_radius, by_hand.robot_radius);
    assert_eq!(file.path, by_hand.path);
    assert_eq!(file.path.drift(), &Exact::ZERO);
    assert_eq!(file.path_ends, by_hand.path_ends);
    assert_eq!(file.zone, by_hand.zone);
    assert_eq!(file.sensing, by_hand.sensing);
    assert_eq!(file.obstacles, by_hand.obstacles);
    assert_eq!(file, by_hand);
}

#[test]
fn the_base_reads_with_every_number_exact() {
    let p = PlanarProblem::from_toml_str(BASE, "base.toml").unwrap();
    let params = p.params();
    assert!(params.path_ends, "a given path stops at its end by default");
    // Segment lengths 10 and 4·√2: the second is irrational, so the analysed path drifts,
    // by at most about its length times the chord tolerance (10⁻⁹).
    let drift = params.path.drift().to_f64().value();
    assert!(drift > 0.0 && drift < 2e-8, "{drift}");
    let heading = params.path.segments()[1].direction.unit();
    let (x, y) = heading.to_f64();
    assert!((x - y).abs() < 2e-9 && x > 0.0, "({x}, {y})");
    assert_eq!(heading.norm_squared(), Exact::ONE);
    let car = &params.obstacles[1];
    assert_eq!(
        car.start,
        Start::Box {
            min: point(20.0, -30.0),
            max: point(21.0, -20.0)
        }
    );
    assert_eq!(car.radius, Exact::ZERO, "radius defaults to 0");
    // The line's obstacle numbers in `motion` are the fastest obstacle's.
    assert_eq!(params.motion.W, decimal(10.0));

    // "continue" keeps the path but not its end; --set reaches every planar key.
    let sets = [
        "robot.path_end=continue",
        "obstacle.1.max_speed=12",
        "sensing.field_of_view=90",
        "plane.direction_tolerance=1e-6",
    ]
    .map(String::from);
    let p = PlanarProblem::from_toml_str_with_overrides(BASE, "base.toml", &sets).unwrap();
    let params = p.params();
    assert!(!params.path_ends);
    assert_eq!(params.obstacles[1].max_speed, decimal(12.0));
    // cos 45° = √2/2 is irrational: rounded up (a narrower view), and by very little.
    let c = params.sensing.view_cos_half.unwrap();
    assert!(c > Exact::ZERO && &c * &c * Exact::from(2) > Exact::ONE);
    assert!(c.to_f64().value() - std::f64::consts::FRAC_1_SQRT_2 < 1e-11);
    // A coarser tolerance gives a coarser direction, still within it.
    let heading = params.path.segments()[1].direction.unit().to_f64();
    let chord = (heading.0 - std::f64::consts::FRAC_1_SQRT_2)
        .hypot(heading.1 - std::f64::consts::FRAC_1_SQRT_2);
    assert!(chord <= 1e-6, "{chord}");
}

/// Reads `text` and returns the error, which must name `origin`.
fn error(text: &str, sets: &[&str]) -> ProblemError {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    match PlanarProblem::from_toml_str_with_overrides(text, "bad.toml", &sets) {
        Ok(_) => panic!("accepted:\n{text}\nwith {sets:?}"),
        Err(e) => e,
    }
}

/// Broken files, one a line: what is broken | the text of BASE it replaces | by what | the
/// key named (`W.` for the walker's, `C.` for the car's) | a part of the reason.
const BROKEN: &[&str] = &[
    "unknown key | radius = 0.3\npath | colour = 1\npath | robot.colour | unknown key",
    "unknown obstacle key | max_speed = 10\n | max_speed = 10\nlane = 0\n | C.lane | unknown key",
    "an [environment] | [plane]\n | [plane]\n[environment]\n | environment | [[obstacle]]",
    "NaN | max_speed = 1.4\nregion | max_speed = nan\nregion | W.max_speed | finite",
    "infinite radius | radius = 0.3\npath | radius = inf\npath | robot.radius | finite",
    "negative robot radius | radius = 0.3\npath | radius = -0.1\npath | robot.radius | >= 0",
    "negative obstacle radius | radius = 0.3\nstart | radius = -1\nstart | W.radius | >= 0",
    "negative speed | max_speed = 10\n | max_speed = -10\n | C.max_speed | >= 0",
    "negative noise | range = 8.0\n | range = 8.0\nvelocity_noise = -0.1\n | sensing.velocity_noise | >= 0",
    "the 1-D rule on braking | braking = 1.0\n | braking = 1.0\nbraking_min = 2.0\n | robot.braking_min | must be <= robot.braking",
    "a 1-D key's own range | reaction_radius = 3.0 | reaction_radius = 0 | controller.reaction_radius | must be > 0",
    "self-crossing path | [[0, 0], [10, 0], [14, 4]] | [[0, 0], [10, 0], [10, 5], [5, 5], [5, -5]] | robot.path | segments 0 and 3 cross or touch",
    "zero-length segment | [10, 0], [14, 4]] | [10, 0], [10, 0], [14, 4]] | robot.path | has length 0",
    "path not from the origin | [[0, 0], [10, 0] | [[1, 0], [10, 0] | robot.path | [0, 0]",
    "a path that is not a list of points | path = [[0, 0], [10, 0], [14, 4]] | path = 5 | robot.path | expected a list of points",
    "non-convex region | [[5, -5], [7, -5], [7, 5], [5, 5]] | [[5, -5], [7, -5], [6, 0], [7, 5], [5, 5]] | W.region | not convex",
    "degenerate stop polygon | wrong_assumption_brake = true\n | wrong_assumption_brake = true\ndanger_zone = \"polygon\"\nstop_polygon = [[0, 0], [1, 0], [2, 0]]\n | controller.stop_polygon | on the line through its neighbours",
    "a stop polygon without the polygon zone | wrong_assumption_brake = true\n | wrong_assumption_brake = true\nstop_polygon = [[0, -1], [1, -1], [1, 1]]\n | controller.stop_polygon | danger_zone",
    "the polygon zone without its polygon | wrong_assumption_brake = true\n | wrong_assumption_brake = true\ndanger_zone = \"polygon\"\n | controller.stop_polygon | missing",
    "an unknown zone | wrong_assumption_brake = true\n | wrong_assumption_brake = true\ndanger_zone = \"square\"\n | controller.danger_zone | \"disc\", \"polygon\"",
    "duplicate names | name = \"car\" | name = \"walker\" | obstacle[1] (\"walker\").name | same name",
    "start outside the region | start = [6.0, -4.0] | start = [8.0, -4.0] | W.start | outside the obstacle's region",
    "start in collision | start_min = [20.0, -30.0]\nstart_max = [21.0, -20.0] | start_min = [0.2, -30.0]\nstart_max = [21.0, 0.1] | C.start_min | starts in collision",
    "a start box the wrong way round | start_max = [21.0, -20.0] | start_max = [19.0, -20.0] | C.start_min | start_min <= start_max",
    "start and a box | max_speed = 10\n | max_speed = 10\nstart = [1, 1]\n | C.start | not both",
    "zero direction | direction = [0, 1] | direction = [0, 0] | C.direction | nonzero",
    "field of view too wide | range = 8.0\n | range = 8.0\nfield_of_view = 400\n | sensing.field_of_view | (0, 360]",
    "field of view zero | range = 8.0\n | range = 8.0\nfield_of_view = 0\n | sensing.field_of_view | must be > 0",
    "a start closer than the first detection | range = 8.0\n | range = 8.0\nfirst_detection = 7.0\n | W.start | vacuously",
    "a direction tolerance above 1 | [plane]\n | [plane]\ndirection_tolerance = 2\n | plane.direction_tolerance | must be <= 1",
];

#[test]
fn every_broken_planar_file_names_its_key_and_reason() {
    let obstacle = |key: &str| {
        key.replacen("W.", "obstacle[0] (\"walker\").", 1).replacen(
            "C.",
            "obstacle[1] (\"car\").",
            1,
        )
    };
    for row in BROKEN {
        let [what, from, to, key, reason] = row.split(" | ").collect::<Vec<_>>()[..] else {
            panic!("five fields: {row}");
        };
        let key = obstacle(key);
        let text = edit(BASE, &[(from, to)]);
        let e = error(&text, &[]);
        assert_eq!(e.origin(), "bad.toml", "{what}: {e}");
        assert_eq!(e.key(), Some(key.as_str()), "{what}: {e}");
        let message = e.to_string();
        assert!(message.contains(reason), "{what}: {message}");
        assert!(!message.contains("invalid type"), "{what}: {message}");
    }
    let none = BASE.split("[[obstacle]]").next().unwrap();
    let e = error(none, &[]);
    assert_eq!(e.key(), Some("obstacle"), "{e}");
    assert!(e.to_string().contains("at least one"), "{e}");
}

#[test]
fn a_broken_value_is_pointed_at_and_an_override_is_named() {
    // The walker's max_speed sits on line 29.
    let text = edit(
        BASE,
        &[("max_speed = 1.4\nregion", "max_speed = -1.4\nregion")],
    );
    let e = error(&text, &[]);
    assert_eq!(e.line(), Some(29), "{e}");
    let e = error(BASE, &["obstacle.0.radius=-1"]);
    assert_eq!(e.origin(), "--set obstacle.0.radius=-1");
    assert_eq!(e.key(), Some("obstacle[0] (\"walker\").radius"));
    let e = error(BASE, &["robot.path=[[1,0],[0,5]]"]);
    assert_eq!(e.origin(), "--set robot.path=[[1,0],[0,5]]");
    assert_eq!(e.key(), Some("robot.path"));
    let e = error(BASE, &["robot.goal=3"]);
    assert_eq!(e.key(), Some("robot.goal"), "{e}");
    assert!(
        e.to_string()
            .contains("radius, path, path_tolerance, path_end"),
        "the known keys are listed: {e}"
    );
    let e = error(BASE, &["obstacle.2.radius=1"]);
    assert!(e.to_string().contains("there is no obstacle 2"), "{e}");
    // A line problem is not a planar one: the planar reader says what marks one.
    let line = std::fs::read_to_string(seed_file()).unwrap();
    let e = error(&line, &[]);
    assert_eq!(e.key(), Some("environment"), "{e}");
    let e = error(
        &line.replace("[environment]\n", "[plane]\n[[obstacle]]\n"),
        &[],
    );
    assert_eq!(
        e.key(),
        Some("obstacle[0] (\"obstacle-0\").obstacle_speed"),
        "{e}"
    );
}

#[test]
fn the_cli_exits_2_naming_the_file_and_key_and_what_is_not_supported_yet() {
    let dir = tmp();
    let d = dir.path();
    let bad = edit(BASE, &[("direction = [0, 1]", "direction = [0, 0]")]);
    std::fs::write(d.join("bad.toml"), bad).unwrap();
    let named = "bad.toml: obstacle[1] (\"car\").direction = [0, 0]: must be nonzero";
    bad_input_exits_2(d, "certify", Path::new("bad.toml"), &[(vec![], named)]);
    std::fs::write(d.join("good.toml"), BASE).unwrap();
    let good = Path::new("good.toml");
    for command in ["export-uppaal", "explore"] {
        let says = format!(
            "good.toml: planar problems are not supported by `safereach {command}` yet (issue 36)"
        );
        bad_input_exits_2(d, command, good, &[(vec![], says.as_str())]);
    }
    let set = "--set robot.radius=-1: robot.radius = -1: must be >= 0";
    bad_input_exits_2(
        d,
        "certify",
        good,
        &[(vec!["--set", "robot.radius=-1"], set)],
    );
}

#[test]
fn init_planar_writes_a_template_that_reads_back() {
    let dir = tmp();
    let d = dir.path();
    safereach(d).args(["init", "--planar"]).assert().code(0);
    let written = std::fs::read_to_string(d.join("planar.toml")).unwrap();
    assert_eq!(written, template::PLANAR);
    let read = PlanarProblem::load(&d.join("planar.toml")).unwrap();
    assert_eq!(
        read,
        PlanarProblem::from_toml_str(template::PLANAR, "t").unwrap()
    );
    assert_eq!(read.obstacles.len(), 1);
    safereach(d)
        .args(["init", "--planar", "mine.toml"])
        .assert()
        .code(0);
    assert!(PlanarProblem::load(&d.join("mine.toml")).is_ok());
    // It exists now: not overwritten by accident.
    safereach(d).args(["init", "--planar"]).assert().code(2);
    safereach(d)
        .args(["init", "--planar", "--scene"])
        .assert()
        .code(2);
}

/// What `stated_table` writes back reads as the problem its overrides state: every shipped
/// planar problem, with a controller key and an obstacle's key overridden.
#[test]
fn the_stated_table_reads_back_as_the_problem_with_its_overrides() {
    let dir = root().join("problems/planar");
    let sets = [
        "controller.reaction_radius=2.5".to_string(),
        "obstacle.0.max_speed=0.75".to_string(),
    ];
    for entry in std::fs::read_dir(&dir).expect("shipped") {
        let path = entry.expect("entry").path();
        let text = std::fs::read_to_string(&path).expect("readable");
        let origin = path.display().to_string();
        let with = PlanarProblem::from_toml_str_with_overrides(&text, &origin, &sets)
            .expect("the overrides are valid");
        let table = PlanarProblem::stated_table(&text, &origin, &sets).expect("applies");
        let again = PlanarProblem::from_toml_str(&toml::to_string(&table).expect("TOML"), &origin)
            .expect("the stated table reads");
        assert_eq!(again, with, "{origin}");
        assert_eq!(with.obstacles[0].max_speed, 0.75);
    }
}
