//! The scene analyser against what is known independently: the single-obstacle analyser
//! (a scene that is one obstacle, or whose extra obstacles are out of reach), and the
//! closed form of a static obstacle alone.

use proptest::prelude::*;
use safereach::analysis::scene::analyse_scene;
use safereach::analysis::{Verdict, analyse};
use safereach::core::model::Problem;
use safereach::core::num::{Exact, Scalar};
use safereach::core::scene::{Obstacle, Position, Scene};
use safereach::core::semantics::{Mode, RobotState, danger_distance, robot_motion};

use crate::common::paths::load_problem;
use crate::common::spec::{any_spec, config};

fn obstacle(name: &str, lane: i32, x: f64, w: f64, is_static: bool) -> Obstacle {
    Obstacle {
        name: name.into(),
        lane,
        position: Position::At(x),
        max_speed: w,
        is_static,
    }
}

/// The single-obstacle answer: whether certified, exact lower bound and s*.
fn single(problem: &Problem) -> (bool, Option<Exact>, Option<f64>) {
    let a = analyse(problem).expect("analysed");
    (
        a.verdict == Verdict::Certified,
        a.lower_bound,
        a.min_separation,
    )
}

fn scene_answer(scene: &Scene) -> (bool, Option<Exact>, Option<f64>) {
    let a = analyse_scene(scene).expect("analysed");
    (
        a.verdict == Verdict::Certified,
        a.lower_bound,
        a.min_separation,
    )
}

/// Every shipped single-obstacle problem, read as a scene, gives its own answer exactly.
#[test]
fn shipped_problems_as_scenes_give_their_own_answers() {
    for name in [
        "seed",
        "fast-obstacle",
        "static-obstacle",
        "zero-latency",
        "area-rule",
        "kinematic-rule",
    ] {
        let problem = load_problem(&format!("{name}.toml"), &[]);
        let scene = Scene::from_problem(&problem);
        assert_eq!(scene_answer(&scene), single(&problem), "{name}");
    }
}

proptest! {
    #![proptest_config(config(24))]

    /// Obstacles in lanes the robot never enters (no lane changes) change nothing: the
    /// answer is exactly the single obstacle's.
    #[test]
    fn obstacles_in_other_lanes_are_out_of_reach(spec in any_spec(), x in 0.5f64..20.0, w in 0.0f64..1.0) {
        let problem = spec.problem();
        let mut scene = Scene::from_problem(&problem);
        scene.lanes = vec![-1, 0, 1];
        scene.obstacles.push(obstacle("left", -1, x, w, false));
        scene.obstacles.push(obstacle("right", 1, x * 0.5 + 0.2, 0.0, true));
        prop_assert_eq!(scene_answer(&scene), single(&problem));
    }
}
