//! The premises a verdict is proved under, as one typed list shared by the certificate that
//! states them and the runtime monitor that checks them (DESIGN.md §3).
//!
//! A certificate says "passively safe, *provided that* obstacles move at most at W, the robot
//! brakes at least at b, …". Each of those provisos is a [`PremiseKind`]: it knows its name,
//! unit and wording, and where its bound comes from in a [`Problem`]. A [`Premise`] is a kind
//! with its bound. Adding a premise is one variant here (the compiler then asks for its name,
//! wording, unit and bound) plus its check in the monitor.
//!
//! On the wire a premise is the object `{"name", "description", "bound", "unit"}`, in that
//! order, exactly as certificates have always written it, so old certificates read and verify
//! unchanged (their digest covers this text). Reading is strict: a premise whose name this
//! build does not know, or whose wording or unit differs from the kind's, is an error naming
//! it, never silently skipped.

use std::fmt;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::core::model::Problem;

/// Which premise: one of the provisos a verdict is proved under.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PremiseKind {
    /// Every obstacle's speed towards the robot is at most W (m/s).
    ObstacleSpeed,
    /// The robot decelerates while braking by at least b (m/s²).
    BrakingDeceleration,
    /// The controller runs at least once every dt (s).
    ControlPeriod,
    /// Observations lag behind by at most L control periods.
    Latency,
    /// An obstacle is first seen at a gap of at least ρ (m).
    FirstDetectionGap,
    /// Observed gap and speed are off by at most σ (m).
    ObservationNoise,
    /// Observed obstacle speeds are off by at most σ_w (m/s). Listed only when positive, so
    /// that certificates of noise-free problems read and write as they always have.
    SpeedNoise,
}

impl PremiseKind {
    /// Every premise, in the order certificates list them.
    pub const ALL: [PremiseKind; 7] = [
        PremiseKind::ObstacleSpeed,
        PremiseKind::BrakingDeceleration,
        PremiseKind::ControlPeriod,
        PremiseKind::Latency,
        PremiseKind::FirstDetectionGap,
        PremiseKind::ObservationNoise,
        PremiseKind::SpeedNoise,
    ];

    /// How many premises there are: the size of every per-premise table.
    pub const COUNT: usize = PremiseKind::ALL.len();

    /// Its position in [`PremiseKind::ALL`]: the index into per-premise tables.
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The stable name (`obstacle_speed`, …) used in certificates and monitor output.
    pub const fn name(self) -> &'static str {
        match self {
            PremiseKind::ObstacleSpeed => "obstacle_speed",
            PremiseKind::BrakingDeceleration => "braking_deceleration",
            PremiseKind::ControlPeriod => "control_period",
            PremiseKind::Latency => "latency",
            PremiseKind::FirstDetectionGap => "first_detection_gap",
            PremiseKind::ObservationNoise => "observation_noise",
            PremiseKind::SpeedNoise => "speed_noise",
        }
    }

    /// The premise in words, to be followed by its bound and unit.
    pub const fn description(self) -> &'static str {
        match self {
            PremiseKind::ObstacleSpeed => "every obstacle's speed towards the robot is at most",
            PremiseKind::BrakingDeceleration => "the robot decelerates while braking by at least",
            PremiseKind::ControlPeriod => "the controller runs at least once every",
            PremiseKind::Latency => "observations lag behind by at most",
            PremiseKind::FirstDetectionGap => "an obstacle is first seen at a gap of at least",
            PremiseKind::ObservationNoise => "observed gap and speed are off by at most",
            PremiseKind::SpeedNoise => "observed obstacle speeds are off by at most",
        }
    }

    /// The unit of its bound, as certificates write it.
    pub const fn unit(self) -> &'static str {
        match self {
            PremiseKind::ObstacleSpeed | PremiseKind::SpeedNoise => "m/s",
            PremiseKind::BrakingDeceleration => "m/s^2",
            PremiseKind::ControlPeriod => "s",
            PremiseKind::Latency => "control periods",
            PremiseKind::FirstDetectionGap | PremiseKind::ObservationNoise => "m",
        }
    }

    /// Its bound in `problem`.
    pub fn bound_in(self, problem: &Problem) -> f64 {
        let r = &problem.robot;
        match self {
            PremiseKind::ObstacleSpeed => problem.environment.obstacle_speed,
            // What the plant guarantees: the analysis braked at b_min.
            PremiseKind::BrakingDeceleration => r.plant_braking(),
            PremiseKind::ControlPeriod => r.control_period,
            PremiseKind::Latency => f64::from(r.latency),
            // The reaction radius, or the initial gap when that is smaller: the model's
            // obstacle starts there, inside the area, and then that is what the proof covers.
            PremiseKind::FirstDetectionGap => problem.first_detection_gap().unwrap_or_else(|| {
                problem
                    .controller
                    .reaction_radius
                    .min(problem.environment.initial_gap.min())
            }),
            // σ_g: the gap noise the analysis covered (0: exact observations).
            PremiseKind::ObservationNoise => problem.gap_noise(),
            // σ_w: the speed noise the analysis covered.
            PremiseKind::SpeedNoise => problem.speed_noise(),
        }
    }

    /// The premise named `name`.
    pub fn from_name(name: &str) -> Option<PremiseKind> {
        PremiseKind::ALL.into_iter().find(|k| k.name() == name)
    }
}

impl fmt::Display for PremiseKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

impl PartialEq<str> for PremiseKind {
    fn eq(&self, name: &str) -> bool {
        self.name() == name
    }
}

impl PartialEq<&str> for PremiseKind {
    fn eq(&self, name: &&str) -> bool {
        self.name() == *name
    }
}

/// A premise of a verdict: its kind and bound (wording and unit come with the kind).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Premise {
    /// Which premise; written as its name (it compares equal to the name as a string).
    pub name: PremiseKind,
    /// The bound, in [`Premise::unit`].
    pub bound: f64,
}

impl Premise {
    /// The premise of kind `name` with its bound in `problem`.
    pub fn of(name: PremiseKind, problem: &Problem) -> Premise {
        Premise {
            name,
            bound: name.bound_in(problem),
        }
    }

    /// Its kind.
    pub fn kind(&self) -> PremiseKind {
        self.name
    }

    /// The premise in words, to be followed by the bound and unit.
    pub fn description(&self) -> &'static str {
        self.name.description()
    }

    /// The bound's unit.
    pub fn unit(&self) -> &'static str {
        self.name.unit()
    }
}

/// The premises of a problem's verdict, in [`PremiseKind::ALL`] order (DESIGN.md §3).
/// `speed_noise` is listed only when its bound is positive: a certificate without it means
/// σ_w = 0, and the certificates of noise-free problems stay byte for byte as they were.
pub fn premises(problem: &Problem) -> Vec<Premise> {
    PremiseKind::ALL
        .into_iter()
        .map(|kind| Premise::of(kind, problem))
        .filter(|p| p.name != PremiseKind::SpeedNoise || p.bound > 0.0)
        .collect()
}

/// The observation noise a list of premises allows: σ_g (m, `observation_noise`) and σ_w
/// (m/s, `speed_noise`), each 0 when the list does not state it (the first of each kind
/// counts, as for every premise).
pub fn noise(premises: &[Premise]) -> Noise {
    let first = |kind: PremiseKind| {
        premises
            .iter()
            .find(|p| p.name == kind)
            .map_or(0.0, |p| p.bound)
    };
    Noise {
        gap: first(PremiseKind::ObservationNoise),
        speed: first(PremiseKind::SpeedNoise),
    }
}

/// How far observations may be off, as a certificate's premises state it (see [`noise`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Noise {
    /// σ_g: an observed gap (or position) is within ±σ_g of the true one (m).
    pub gap: f64,
    /// σ_w: an observed obstacle speed is within ±σ_w of the true one (m/s).
    pub speed: f64,
}

/// A premise as written: the field order here is the order in certificates.
#[derive(Serialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
struct Written<'a> {
    name: &'a str,
    description: &'a str,
    bound: f64,
    unit: &'a str,
}

/// A premise as read, before its name is known to be one of ours.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Read {
    name: String,
    description: String,
    bound: f64,
    unit: String,
}

impl Serialize for Premise {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        Written {
            name: self.name.name(),
            description: self.name.description(),
            bound: self.bound,
            unit: self.name.unit(),
        }
        .serialize(s)
    }
}

#[cfg(feature = "schema")]
impl schemars::JsonSchema for Premise {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "Premise".into()
    }

    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        let names: Vec<&str> = PremiseKind::ALL.iter().map(|k| k.name()).collect();
        schemars::json_schema!({
            "description": "A premise the certificate's answer rests on: an assumption about the robot or its environment that the runtime monitor checks.",
            "type": "object",
            "properties": {
                "name": { "type": "string", "enum": names },
                "description": { "type": "string", "description": "What the premise says, in words." },
                "bound": { "type": "number", "description": "The premise's bound, in `unit`." },
                "unit": { "type": "string" },
            },
            "required": ["name", "description", "bound", "unit"],
            "additionalProperties": false,
        })
    }
}

impl<'de> Deserialize<'de> for Premise {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Premise, D::Error> {
        let read = Read::deserialize(d)?;
        Premise::try_from(read).map_err(serde::de::Error::custom)
    }
}

impl TryFrom<Read> for Premise {
    type Error = String;

    fn try_from(read: Read) -> Result<Premise, String> {
        let Some(kind) = PremiseKind::from_name(&read.name) else {
            return Err(format!(
                "certificate premise '{}' is not known to this monitor",
                read.name
            ));
        };
        let differs = |what: &str, found: &str, known: &str| {
            format!(
                "certificate premise '{}' has {what} {found:?}, but this build knows it as {known:?}",
                read.name
            )
        };
        if read.description != kind.description() {
            return Err(differs(
                "description",
                &read.description,
                kind.description(),
            ));
        }
        if read.unit != kind.unit() {
            return Err(differs("unit", &read.unit, kind.unit()));
        }
        Ok(Premise {
            name: kind,
            bound: read.bound,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn written_as_before() {
        let p = Premise {
            name: PremiseKind::ObstacleSpeed,
            bound: 0.15,
        };
        assert_eq!(
            serde_json::to_string(&p).unwrap(),
            r#"{"name":"obstacle_speed","description":"every obstacle's speed towards the robot is at most","bound":0.15,"unit":"m/s"}"#
        );
        let back: Premise = serde_json::from_str(&serde_json::to_string(&p).unwrap()).unwrap();
        assert_eq!(back, p);
        assert!(p.name == "obstacle_speed");
    }

    #[test]
    fn every_kind_round_trips() {
        for (i, kind) in PremiseKind::ALL.into_iter().enumerate() {
            assert_eq!(kind.index(), i);
            assert_eq!(PremiseKind::from_name(kind.name()), Some(kind));
            let p = Premise {
                name: kind,
                bound: 1.5,
            };
            let text = serde_json::to_string(&p).unwrap();
            assert_eq!(serde_json::from_str::<Premise>(&text).unwrap(), p);
        }
    }

    #[test]
    fn speed_noise_is_listed_only_when_positive_and_read_as_zero_when_absent() {
        let seed = include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/problems/seed.toml"));
        let problem = Problem::from_toml_str(seed, "seed.toml").unwrap();
        let listed = premises(&problem);
        assert!(listed.iter().all(|p| p.name != PremiseKind::SpeedNoise));
        assert_eq!(listed.len(), PremiseKind::COUNT - 1);
        assert_eq!(noise(&listed), Noise::default());
        let with = [
            Premise {
                name: PremiseKind::ObservationNoise,
                bound: 0.02,
            },
            Premise {
                name: PremiseKind::SpeedNoise,
                bound: 0.01,
            },
        ];
        assert_eq!(
            noise(&with),
            Noise {
                gap: 0.02,
                speed: 0.01
            }
        );
    }

    #[test]
    fn unknown_or_altered_premises_are_errors() {
        let unknown = r#"{"name":"wind_speed","description":"x","bound":1.0,"unit":"m/s"}"#;
        let e = serde_json::from_str::<Premise>(unknown).unwrap_err();
        assert!(
            e.to_string()
                .contains("certificate premise 'wind_speed' is not known to this monitor"),
            "{e}"
        );
        let unit = r#"{"name":"latency","description":"observations lag behind by at most","bound":1.0,"unit":"s"}"#;
        let e = serde_json::from_str::<Premise>(unit).unwrap_err();
        assert!(e.to_string().contains("premise 'latency' has unit"), "{e}");
        let wording =
            r#"{"name":"latency","description":"lag","bound":1.0,"unit":"control periods"}"#;
        let e = serde_json::from_str::<Premise>(wording).unwrap_err();
        assert!(e.to_string().contains("has description"), "{e}");
    }
}
