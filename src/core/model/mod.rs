//! Problem files: the robot, its controller and the environment, in SI units.
//!
//! A [`Problem`] is what a user writes in TOML; [`Params`] is the same problem as numbers of
//! a chosen [`Scalar`](crate::core::num::Scalar) type, after validation. Exact parameters are the decimals the file
//! states (see [`crate::core::num::exact_decimal`]), so `0.1` s is one tenth of a second.
//!
//! # Reading problems
//!
//! [`Problem::load`], [`Problem::load_with_overrides`] and [`Problem::from_toml_str`] read a
//! problem strictly: a TOML syntax error, an unknown or missing key, a value of the wrong type
//! (a float for `robot.latency`, a string that is not a danger rule), a non-finite or
//! out-of-range number are all a [`ProblemError`] naming the file, the key and the reason,
//! with the line where the file has one. An integer is accepted where a float is expected
//! (`initial_gap = 10`).
//!
//! Overrides (`--set dotted.key=value`) are applied to the parsed document before it is
//! deserialised, so they pass the same checks; an error in an override names the override
//! (`--set robot.braking=-1: robot.braking = -1: must be > 0 (m/s^2)`).

pub(crate) mod document;
pub(crate) mod error;
pub(crate) mod keys;
pub(crate) mod overrides;
mod params;
mod position;
pub(crate) mod read;
pub(crate) mod validate;

use std::fmt;

use serde::{Deserialize, Serialize};

pub use error::{Location, ProblemError};
pub use params::{Params, StepConstants};
pub use position::Position;

/// A verification problem: one robot, its controller, one oncoming obstacle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct Problem {
    /// Short name shown in reports.
    pub name: String,
    /// The robot's dynamics and timing.
    pub robot: Robot,
    /// The controller's braking rule.
    pub controller: Controller,
    /// What the environment really does.
    pub environment: Environment,
    /// How far observations may be off (optional table; None: exact observations).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensing: Option<Sensing>,
}

/// How far the robot's observations may be off from the truth (DESIGN.md §1.2). The errors
/// are the environment's choice, per observation, adversarially.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct Sensing {
    /// σ_g: every observed gap is within ±σ_g of the true one (m), ≥ 0; None: 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap_noise: Option<f64>,
    /// σ_w: every observed obstacle speed is within ±σ_w of the true one (m/s), ≥ 0;
    /// None: 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed_noise: Option<f64>,
    /// d_det: an obstacle may stay hidden until its first observation shows a true gap of
    /// at least d_det (m), > 0, which may lie inside ρ; None: visible from the start.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub first_detection_gap: Option<f64>,
}

impl Problem {
    /// σ_g: the gap noise bound (0 unless the problem says otherwise).
    pub fn gap_noise(&self) -> f64 {
        self.sensing
            .as_ref()
            .and_then(|s| s.gap_noise)
            .unwrap_or(0.0)
    }

    /// d_det: the least true gap at which a hidden obstacle is first seen (None: no
    /// obstacle is hidden).
    pub fn first_detection_gap(&self) -> Option<f64> {
        self.sensing.as_ref().and_then(|s| s.first_detection_gap)
    }

    /// σ_w: the speed noise bound (0 unless the problem says otherwise).
    pub fn speed_noise(&self) -> f64 {
        self.sensing
            .as_ref()
            .and_then(|s| s.speed_noise)
            .unwrap_or(0.0)
    }
}

/// The robot's dynamics and timing.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct Robot {
    /// Top speed v_max (m/s), > 0.
    pub max_speed: f64,
    /// Acceleration a while speeding up (m/s²), > 0.
    pub acceleration: f64,
    /// Deceleration b the controller computes with when braking (m/s²), > 0.
    pub braking: f64,
    /// Control period dt (s), > 0.
    pub control_period: f64,
    /// Observation latency L in whole control periods, ≥ 0.
    pub latency: u32,
    /// A collision is any instant with the robot moving and gap ≤ clearance (m), ≥ 0.
    pub clearance: f64,
    /// b_min: the deceleration the plant guarantees while braking (m/s²), in (0, b];
    /// None: b. The plant may brake at any rate in [b_min, b]; the controller's danger
    /// distance keeps b.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub braking_min: Option<f64>,
    /// v0: the robot's speed at t = 0 (m/s), in [0, v_max]; None: 0 (at rest). At v_max it
    /// starts in Drive, else in Accelerate.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial_speed: Option<f64>,
}

impl Robot {
    /// b_min: the plant's guaranteed deceleration (b unless the problem says less).
    pub fn plant_braking(&self) -> f64 {
        self.braking_min.unwrap_or(self.braking)
    }

    /// v0: the robot's speed at t = 0 (0 unless the problem says otherwise).
    pub fn start_speed(&self) -> f64 {
        self.initial_speed.unwrap_or(0.0)
    }
}

/// The controller's braking rule.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct Controller {
    /// V_a: the obstacle speed bound the controller believes (m/s), ≥ 0.
    pub assumed_obstacle_speed: f64,
    /// ρ: the robot reacts to obstacles whose observed gap is in (0, ρ] (m), > 0.
    pub reaction_radius: f64,
    /// Which collision-danger distance the controller uses.
    pub danger_rule: DangerRule,
    /// Extra distance added to the danger distance (m), ≥ 0.
    pub buffer: f64,
    /// Brake when an obstacle in the area is seen faster than V_a.
    pub wrong_assumption_brake: bool,
}

/// The collision-danger distance d_coll(v) the controller compares the observed gap with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "lowercase")]
pub enum DangerRule {
    /// The seed paper's formula: v·t_b + V_a·t_b + buffer with t_b = v/b.
    Paper,
    /// Kinematic stopping distance: v²/(2b) + V_a·v/b + buffer.
    Kinematic,
    /// Brake on entering the reaction area (d_coll = ∞).
    Area,
}

/// What the environment really does.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct Environment {
    /// W: the real bound on the obstacle's speed (m/s), ≥ 0; 0 is a static obstacle.
    pub obstacle_speed: f64,
    /// Gap between robot and obstacle at t = 0 (m), > clearance; or a range `[min, max]`
    /// whose every point the environment may choose.
    pub initial_gap: Position,
}

impl fmt::Display for DangerRule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            DangerRule::Paper => "paper",
            DangerRule::Kinematic => "kinematic",
            DangerRule::Area => "area",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::keys::{KEYS, Kind};
    use super::*;

    /// The seed problem, written out.
    fn seed() -> Problem {
        Problem {
            name: "seed".into(),
            robot: Robot {
                max_speed: 0.8,
                acceleration: 0.4,
                braking: 0.5,
                control_period: 0.1,
                latency: 1,
                clearance: 0.0,
                braking_min: None,
                initial_speed: None,
            },
            controller: Controller {
                assumed_obstacle_speed: 0.2,
                reaction_radius: 1.4,
                danger_rule: DangerRule::Paper,
                buffer: 0.1,
                wrong_assumption_brake: true,
            },
            environment: Environment {
                obstacle_speed: 0.15,
                initial_gap: Position::At(10.0),
            },
            sensing: None,
        }
    }

    #[test]
    fn key_table_matches_the_serde_types() {
        // Every optional key given, so that every key is written.
        let mut full = seed();
        full.robot.braking_min = Some(0.4);
        full.robot.initial_speed = Some(0.1);
        full.sensing = Some(Sensing {
            gap_noise: Some(0.01),
            speed_noise: Some(0.02),
            first_detection_gap: Some(0.8),
        });
        let table: toml::Table = toml::from_str(&full.to_toml_string()).unwrap();
        let mut keys = Vec::new();
        for (k, v) in &table {
            match v.as_table() {
                Some(t) => keys.extend(t.keys().map(|f| format!("{k}.{f}"))),
                None => keys.push(k.clone()),
            }
        }
        let mut known: Vec<String> = Problem::known_keys().map(str::to_string).collect();
        keys.sort();
        known.sort();
        assert_eq!(keys, known);
        let mut numbers: Vec<&str> = full.numbers().iter().map(|(k, _)| *k).collect();
        let mut number_keys: Vec<&str> = KEYS
            .iter()
            .filter(|s| matches!(s.kind, Kind::Number | Kind::Position))
            .map(|s| s.key)
            .collect();
        numbers.sort();
        number_keys.sort();
        assert_eq!(numbers, number_keys);
    }

    #[test]
    fn seed_is_valid_and_round_trips() {
        let p = seed();
        p.validate("seed").unwrap();
        assert_eq!(Problem::from_toml_str(&p.to_toml_string(), "x").unwrap(), p);
    }

    #[test]
    fn location_points_at_the_value() {
        let text = "a = 1\nb =  -0.5 # c\n";
        let l = Location::of_span(text, 11..15).unwrap();
        assert_eq!((l.line, l.column, l.width), (2, 6, 4));
        assert_eq!(l.source_line, "b =  -0.5 # c");
    }
}
