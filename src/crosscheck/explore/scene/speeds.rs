//! The scene explorer's actions per obstacle: each moving obstacle's own finite speed set
//! within [0, W_i] (by default {0, W_i}), read from `--speeds` exactly.

use std::fmt;

use super::super::speeds::parse_speed;
use super::super::{ExploreError, MAX_SPEEDS, SpeedSet, show_exact};
use crate::core::num::Exact;
use crate::core::scene::SceneParams;
use crate::core::scene::keys::obstacle_label;

/// One finite speed set per obstacle of a scene, in the scene's order: obstacle i picks,
/// every period, a speed from its own set ⊆ [0, W_i] (a static obstacle's set is {0}).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneSpeeds {
    sets: Vec<SpeedSet>,
}

impl SceneSpeeds {
    /// The default: {0, W_i} for every obstacle (the extremes; {0} when W_i = 0).
    pub fn extremes(params: &SceneParams<Exact>) -> SceneSpeeds {
        Self::with_levels(params, &[], "").expect("0 and W_i always lie within [0, W_i]")
    }

    /// `n` evenly spaced speeds from 0 to W_i for every obstacle: {0, W_i/(n−1), …, W_i}
    /// (n ≥ 2), as [`SpeedSet::evenly_spaced`] for one obstacle.
    pub fn evenly_spaced(
        params: &SceneParams<Exact>,
        n: usize,
    ) -> Result<SceneSpeeds, ExploreError> {
        let sets = params
            .obstacles
            .iter()
            .map(|o| SpeedSet::evenly_spaced(&o.max_speed, n))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(SceneSpeeds { sets })
    }

    /// {0, W_i} plus every one of `levels` that lies within [0, W_i], for every obstacle: a
    /// level above an obstacle's bound is left out of that obstacle's set. A negative level,
    /// or one above every obstacle's bound, is an error (`spec` names the flag's text).
    pub fn with_levels(
        params: &SceneParams<Exact>,
        levels: &[Exact],
        spec: &str,
    ) -> Result<SceneSpeeds, ExploreError> {
        let bad = |reason: String| ExploreError::Speeds {
            spec: spec.into(),
            reason,
        };
        let top = params
            .obstacles
            .iter()
            .map(|o| o.max_speed.clone())
            .max()
            .unwrap_or(Exact::ZERO);
        if let Some(level) = levels.iter().find(|l| **l < Exact::ZERO || **l > top) {
            return Err(bad(format!(
                "speed {} m/s is outside [0, {}] m/s, the largest obstacle bound (max_speed)",
                show_exact(level),
                show_exact(&top)
            )));
        }
        let sets = params
            .obstacles
            .iter()
            .map(|o| {
                let mut list = vec![Exact::ZERO, o.max_speed.clone()];
                list.extend(levels.iter().filter(|l| **l <= o.max_speed).cloned());
                SpeedSet::from_list(&o.max_speed, list, spec)
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(SceneSpeeds { sets })
    }

    /// Explicit sets, one per obstacle in the scene's order (each sorted and deduplicated
    /// here); every speed of obstacle i must lie within [0, W_i].
    pub fn from_sets(
        params: &SceneParams<Exact>,
        sets: Vec<Vec<Exact>>,
    ) -> Result<SceneSpeeds, ExploreError> {
        if sets.len() != params.obstacles.len() {
            return Err(ExploreError::Speeds {
                spec: format!("{} sets", sets.len()),
                reason: format!(
                    "one speed set per obstacle is needed ({} obstacles)",
                    params.obstacles.len()
                ),
            });
        }
        let sets = sets
            .into_iter()
            .enumerate()
            .map(|(i, list)| {
                let o = &params.obstacles[i];
                let label = obstacle_label(i, &o.name);
                if let Some(bad) = list.iter().find(|s| **s < Exact::ZERO || **s > o.max_speed) {
                    return Err(ExploreError::Speeds {
                        spec: label.clone(),
                        reason: format!(
                            "speed {} m/s is outside [0, W] = [0, {}] m/s ({label}.max_speed)",
                            show_exact(bad),
                            show_exact(&o.max_speed)
                        ),
                    });
                }
                SpeedSet::from_list(&o.max_speed, list, &label)
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(SceneSpeeds { sets })
    }

    /// Reads `--speeds` for a scene: a bare whole number N is N evenly spaced speeds from 0
    /// to W_i for every obstacle; anything else is a comma-separated list of extra levels
    /// in m/s (decimals read as the decimals they are, or fractions like `3/80`), added to
    /// every obstacle's {0, W_i} where they fit ([`SceneSpeeds::with_levels`]).
    pub fn parse(spec: &str, params: &SceneParams<Exact>) -> Result<SceneSpeeds, ExploreError> {
        let text = spec.trim();
        let bad = |reason: String| ExploreError::Speeds {
            spec: spec.to_string(),
            reason,
        };
        if !text.is_empty() && text.bytes().all(|b| b.is_ascii_digit()) {
            let n: usize = text
                .parse()
                .map_err(|_| bad(format!("count too large (at most {MAX_SPEEDS})")))?;
            return Self::evenly_spaced(params, n).map_err(|e| match e {
                ExploreError::Speeds { reason, .. } => bad(reason),
                other => other,
            });
        }
        let mut levels = Vec::new();
        for (i, item) in text.split(',').map(str::trim).enumerate() {
            // An empty element (`0,,0.15`) is a typo, not nothing: refused, not skipped.
            if item.is_empty() {
                return Err(bad(format!("element {} is empty", i + 1)));
            }
            levels.push(parse_speed(item).map_err(|reason| bad(format!("`{item}`: {reason}")))?);
        }
        if levels.is_empty() {
            return Err(bad("no speeds given".into()));
        }
        Self::with_levels(params, &levels, spec)
    }

    /// The sets, one per obstacle in the scene's order.
    pub fn sets(&self) -> &[SpeedSet] {
        &self.sets
    }

    /// Obstacle i's set.
    pub fn of(&self, i: usize) -> &SpeedSet {
        &self.sets[i]
    }
}

impl fmt::Display for SceneSpeeds {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let items: Vec<String> = self.sets.iter().map(ToString::to_string).collect();
        write!(f, "{}", items.join(", "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::scene::Scene;

    fn params() -> SceneParams<Exact> {
        let text = r#"
            name = "s"
            [robot]
            max_speed = 0.5
            acceleration = 0.5
            braking = 0.5
            control_period = 0.5
            latency = 0
            clearance = 0.0
            [controller]
            assumed_obstacle_speed = 0.2
            reaction_radius = 1.0
            danger_rule = "paper"
            buffer = 0.1
            wrong_assumption_brake = true
            [[obstacle]]
            lane = 0
            position = 3.0
            max_speed = 0.3
            [[obstacle]]
            lane = 0
            position = 4.0
            max_speed = 0.1
            [[obstacle]]
            lane = 0
            position = 2.0
            max_speed = 0.0
            static = true
        "#;
        Scene::from_toml_str(text, "test").unwrap().params()
    }

    fn q(n: i64, d: i64) -> Exact {
        Exact::from(n) / Exact::from(d)
    }

    #[test]
    fn the_default_is_zero_and_each_bound() {
        let s = SceneSpeeds::extremes(&params());
        assert_eq!(s.of(0).speeds(), [Exact::ZERO, q(3, 10)]);
        assert_eq!(s.of(1).speeds(), [Exact::ZERO, q(1, 10)]);
        assert_eq!(s.of(2).speeds(), [Exact::ZERO]);
    }

    #[test]
    fn levels_join_the_sets_they_fit() {
        let s = SceneSpeeds::parse("0.2, 1/20", &params()).unwrap();
        assert_eq!(s.of(0).speeds(), [Exact::ZERO, q(1, 20), q(1, 5), q(3, 10)]);
        assert_eq!(s.of(1).speeds(), [Exact::ZERO, q(1, 20), q(1, 10)]);
        assert_eq!(s.of(2).speeds(), [Exact::ZERO]);
        let n = SceneSpeeds::parse("4", &params()).unwrap();
        assert_eq!(n.of(0).speeds(), [Exact::ZERO, q(1, 10), q(1, 5), q(3, 10)]);
        assert_eq!(n.of(2).len(), 1);
    }

    #[test]
    fn bad_sets_are_refused_with_the_reason() {
        let p = params();
        let msg = |r: Result<SceneSpeeds, ExploreError>| r.unwrap_err().to_string();
        assert!(msg(SceneSpeeds::parse("0.5", &p)).contains("largest obstacle bound"));
        assert!(msg(SceneSpeeds::parse("-0.1", &p)).contains("outside"));
        assert!(msg(SceneSpeeds::parse("x", &p)).contains("not a number"));
        assert!(msg(SceneSpeeds::parse("1", &p)).contains("at least 2"));
        assert!(msg(SceneSpeeds::parse(",", &p)).contains("element 1 is empty"));
        assert!(msg(SceneSpeeds::parse("0.1,,0.2", &p)).contains("element 2 is empty"));
        let over = SceneSpeeds::from_sets(&p, vec![vec![q(1, 5)], vec![q(1, 5)], vec![]]);
        assert!(msg(over).contains("obstacle[1] (\"obstacle-1\").max_speed"));
        assert!(msg(SceneSpeeds::from_sets(&p, vec![])).contains("one speed set per obstacle"));
    }
}
