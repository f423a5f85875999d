//! Reading scene files strictly: the TOML document is parsed once, the `--set` overrides are
//! put into it, its shape is checked (known keys, one of the two forms), and each part is
//! read by the reader that knows it — a file with `[environment]` by the problem reader,
//! with all of a problem's checks, then the scene's settings on top.

use std::path::Path;

use serde::Deserialize;
use toml::de::DeTable;

use crate::core::model::document::parse_error;
use crate::core::model::overrides::PathStep;
use crate::core::model::read::{
    check_key_types, parse_overrides, problem_from_document, read_file,
};
use crate::core::model::{Controller, ProblemError, Robot, Sensing};
use crate::core::scene::Scene;
use crate::core::scene::fields::{Extras, lanes, obstacles, take_extras};
use crate::core::scene::keys::resolve;
use crate::core::scene::origin::Source;
use crate::core::scene::shape::{Form, check};

/// What a scene file has besides its scene keys and obstacles.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Head {
    name: String,
    robot: Robot,
    controller: Controller,
    #[serde(default)]
    sensing: Option<Sensing>,
}

impl Scene {
    /// Reads and validates a scene (or a single-obstacle problem, as its scene) from TOML
    /// `text`; `origin` (usually the path) names the text in errors.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Scene, ProblemError> {
        Self::from_toml_str_with_overrides(text, origin, &[])
    }

    /// Reads and validates the scene file (or problem file) at `path`.
    pub fn load(path: &Path) -> Result<Scene, ProblemError> {
        Self::load_with_overrides(path, &[])
    }

    /// Reads the scene file at `path`, applies `sets` in order, then validates the result.
    /// Each set is `dotted.key=value` with a TOML value (strings may be bare): a problem's
    /// keys, the scene's (`robot.goal=30`, `controller.lane_change=true`,
    /// `scene.lanes=[0,1]`) and an obstacle's, by its 0-based index
    /// (`obstacle.1.max_speed=0.2`). Errors in an override name the override as their origin.
    pub fn load_with_overrides(path: &Path, sets: &[String]) -> Result<Scene, ProblemError> {
        let (text, origin) = read_file(path)?;
        Self::from_toml_str_with_overrides(&text, &origin, sets)
    }

    /// [`Scene::from_toml_str`] with `--set` overrides, as [`Scene::load_with_overrides`].
    pub fn from_toml_str_with_overrides(
        text: &str,
        origin: &str,
        sets: &[String],
    ) -> Result<Scene, ProblemError> {
        let (overrides, sets) = parse_overrides(sets, resolve)?;
        let doc = DeTable::parse(text).map_err(|e| parse_error(origin, text, None, e))?;
        let doc = doc.get_ref();
        let source = Source {
            text,
            origin,
            doc,
            sets: &sets,
        };
        let mut root = doc.clone();
        for o in overrides {
            if doc.contains_key("environment")
                && o.target.path.first() == Some(&PathStep::Key("obstacle"))
            {
                return Err(ProblemError::BadOverride {
                    origin: o.origin.clone(),
                    key: Some(o.target.dotted.clone()),
                    reason: "the file is a single-obstacle problem ([environment]), with no \
                             [[obstacle]]: set environment.obstacle_speed or \
                             environment.initial_gap instead"
                        .into(),
                });
            }
            o.apply(&mut root)?;
        }
        let form = check(&source, &root)?;
        let extras = take_extras(&source, &mut root)?;
        let mut scene = match form {
            Form::Problem => {
                let problem = problem_from_document(text, origin, doc, root, &sets)?;
                Scene::from_problem(&problem)
            }
            Form::Scene => read_scene(&source, root)?,
        };
        let Extras {
            goal,
            sensing_range,
            lane_change,
        } = extras;
        scene.goal = goal;
        scene.sensing_range = sensing_range;
        scene.lane_change = lane_change;
        scene.lanes.sort_unstable();
        if let Some(v) = scene.violation() {
            return Err(source.invalid(v.key, scene.show_key(v.key), v.value, v.reason));
        }
        Ok(scene)
    }
}

/// The scene in `root`, a scene-form document without the scene's keys in `[robot]` and
/// `[controller]` (not yet validated; lanes in the file's order).
fn read_scene(source: &Source<'_>, mut root: DeTable<'_>) -> Result<Scene, ProblemError> {
    check_key_types(source.text, source.origin, source.doc)?;
    let obstacle = root.remove("obstacle");
    let scene = root.remove("scene");
    let head = Head::deserialize(toml::de::Deserializer::from(toml::Spanned::new(0..0, root)))
        .map_err(|mut e| {
            e.set_input(Some(source.text));
            parse_error(source.origin, source.text, Some(source.doc), e)
        })?;
    let lanes = lanes(source, scene.as_ref())?;
    let obstacles = match &obstacle {
        Some(value) => obstacles(source, value)?,
        None => Vec::new(),
    };
    Ok(Scene {
        name: head.name,
        robot: head.robot,
        controller: head.controller,
        goal: None,
        sensing_range: None,
        lane_change: None,
        sensing: head.sensing,
        lanes,
        obstacles,
    })
}
