//! Commented templates a new problem starts from (`safereach init`): every key a file may
//! have, its unit, its bound and its default, with values that certify as written. The
//! texts are TOML files beside this one, so they read as what a user gets.

/// A single-obstacle problem: the seed robot, one obstacle in its lane, `[sensing]`
/// commented out. Certified as written.
pub const PROBLEM: &str = include_str!("problem.toml");

/// A scene: the seed's whole picture (an oncoming obstacle, parked ones in the lanes to
/// either side, lane changes on), the destination, sensing range and `[sensing]` commented
/// out. Certified as written.
pub const SCENE: &str = include_str!("scene.toml");

/// A planar problem (docs/semantics.md §13): a 0.3 m robot at 1 m/s on a 12 m path, one
/// pedestrian crossing ahead of it on a zebra crossing, range, field of view and occlusion
/// set, noise commented out. Reads as a planar problem ([`crate::core::planar`]).
pub const PLANAR: &str = include_str!("planar.toml");

/// `template` with every commented key line (`# key = value  # ...`) made a key line; with
/// `defaults_only`, only the lines marked `(default)`, which change nothing. The table
/// header `# [sensing]` is uncommented with them.
pub fn uncommented(template: &str, defaults_only: bool) -> String {
    let mut out = String::with_capacity(template.len());
    for line in template.lines() {
        let key_line = line
            .strip_prefix("# ")
            .filter(|rest| is_key_line(rest) && (!defaults_only || rest.ends_with("(default)")));
        let table = line.strip_prefix("# ").filter(|rest| *rest == "[sensing]");
        out.push_str(key_line.or(table).unwrap_or(line));
        out.push('\n');
    }
    out
}

/// Whether `line` is `key = value  # comment` for a bare TOML key (prose never has the
/// comment after a value).
fn is_key_line(line: &str) -> bool {
    line.split_once(" = ").is_some_and(|(key, rest)| {
        !key.is_empty()
            && key
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
            && rest.contains("  # ")
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::model::Problem;
    use crate::core::model::keys::{KEYS, KeySpec};
    use crate::core::scene::Scene;
    use crate::core::scene::keys::{OBSTACLE_KEYS, SCENE_KEYS};

    /// The line of `template` that sets `key` (commented or not) in table `table`.
    fn line_of<'t>(template: &'t str, table: &str, key: &str) -> Option<&'t str> {
        let mut current = "";
        for line in template.lines() {
            let bare = line.strip_prefix("# ").unwrap_or(line);
            if let Some(header) = bare.strip_prefix('[') {
                current = header.trim_matches(|c| c == '[' || c == ']');
            } else if current == table && bare.starts_with(&format!("{key} = ")) {
                return Some(line);
            }
        }
        None
    }

    /// Every key appears in its table, and its comment names its unit.
    fn states_every_key<'k>(
        template: &str,
        keys: impl IntoIterator<Item = (&'k str, &'k KeySpec)>,
    ) {
        for (table, spec) in keys {
            let key = spec.key.rsplit('.').next().unwrap();
            let table = if spec.key.contains('.') {
                spec.key.split('.').next().unwrap()
            } else {
                table
            };
            let line = line_of(template, table, key)
                .unwrap_or_else(|| panic!("the template has no line for {}", spec.key));
            let unit = spec.unit;
            let named = [",", ":"]
                .iter()
                .any(|end| line.contains(&format!("# {unit}{end}")));
            assert!(
                named || unit.is_empty(),
                "{}: the comment does not name its unit {:?}: {line}",
                spec.key,
                spec.unit
            );
        }
    }

    #[test]
    fn the_problem_template_states_every_key_with_its_unit() {
        let problem_keys = KEYS.iter().map(|s| ("", s));
        states_every_key(PROBLEM, problem_keys);
    }

    #[test]
    fn the_scene_template_states_every_key_with_its_unit() {
        let head = KEYS
            .iter()
            .filter(|s| !s.key.starts_with("environment."))
            .chain(SCENE_KEYS.iter().copied())
            .map(|s| ("", s));
        let obstacle = OBSTACLE_KEYS.iter().map(|s| ("obstacle", *s));
        states_every_key(SCENE, head.chain(obstacle));
    }

    #[test]
    fn the_templates_read_and_their_defaults_are_the_defaults() {
        let problem = Problem::from_toml_str(PROBLEM, "problem template").unwrap();
        let defaults = Problem::from_toml_str(&uncommented(PROBLEM, true), "defaults").unwrap();
        assert_eq!(problem.params::<f64>(), defaults.params::<f64>());
        Problem::from_toml_str(&uncommented(PROBLEM, false), "every key").unwrap();

        let scene = Scene::from_toml_str(SCENE, "scene template").unwrap();
        let defaults = Scene::from_toml_str(&uncommented(SCENE, true), "defaults").unwrap();
        assert_eq!(scene.params::<f64>(), defaults.params::<f64>());
        Scene::from_toml_str(&uncommented(SCENE, false), "every key").unwrap();
    }

    #[test]
    fn the_planar_template_states_every_key_and_reads() {
        use crate::core::planar::PlanarProblem;
        use crate::core::planar::keys::{OBSTACLE_KEYS, plain_keys};
        // start_min, start_max and stop_polygon are alternatives to keys the template sets
        // (a start point, the disc zone): its prose gives them, not a key line.
        let alternatives = ["start_min", "start_max", "controller.stop_polygon"];
        let head = plain_keys().into_iter().map(|s| ("", s));
        let obstacle = OBSTACLE_KEYS.iter().map(|s| ("obstacle", *s));
        let keys = head
            .chain(obstacle)
            .filter(|(_, s)| !alternatives.contains(&s.key));
        states_every_key(PLANAR, keys);
        for key in alternatives {
            let bare = key.rsplit('.').next().unwrap();
            assert!(PLANAR.contains(&format!("{bare} = [")), "{key}");
        }
        let planar = PlanarProblem::from_toml_str(PLANAR, "planar template").unwrap();
        let defaults = uncommented(PLANAR, true);
        let defaults = PlanarProblem::from_toml_str(&defaults, "defaults").unwrap();
        assert_eq!(planar.params(), defaults.params());
        assert_ne!(
            uncommented(PLANAR, true),
            PLANAR,
            "some default line is uncommented"
        );
    }

    #[test]
    fn uncommenting_writes_every_key_and_only_defaults_when_asked() {
        let all = uncommented(PROBLEM, false);
        let defaults = uncommented(PROBLEM, true);
        for key in [
            "braking_min",
            "initial_speed",
            "gap_noise",
            "first_detection_gap",
        ] {
            assert!(
                all.lines().any(|l| l.starts_with(&format!("{key} = "))),
                "{key}"
            );
        }
        assert!(defaults.lines().any(|l| l.starts_with("gap_noise = ")));
        assert!(
            !defaults
                .lines()
                .any(|l| l.starts_with("first_detection_gap = "))
        );
        assert_eq!(uncommented("# a prose line\n", false), "# a prose line\n");
    }
}
