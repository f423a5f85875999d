//! The keys a problem file has: their types, units and bounds, and the limits every number
//! must respect. One table serves reading, overrides, validation and messages; scene files
//! describe their own keys with the same [`KeySpec`]s (`core::scene::keys`).

use serde::de::DeserializeOwned;
use toml::Spanned;
use toml::de::{DeValue, ValueDeserializer};

use crate::core::model::DangerRule;
use crate::core::model::error::with_article;

/// Largest magnitude accepted for any number in a problem.
pub(crate) const MAX_MAGNITUDE: f64 = 1e9;
/// Largest latency accepted, in control periods.
pub(crate) const MAX_LATENCY: u32 = 1000;
/// Most control periods a problem may need: to cover the initial gap at top speed, to reach
/// top speed, or to stop from it.
pub(crate) const MAX_PERIODS: f64 = 1e6;

/// The type a key's value must have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// A string.
    Text,
    /// A finite number (an integer is accepted).
    Number,
    /// A whole number ≥ 0.
    Count,
    /// A [`DangerRule`] name.
    Rule,
    /// A boolean.
    Flag,
    /// A lane: a whole number (negative: to the right of lane 0).
    Lane,
    /// A list of lanes.
    Lanes,
    /// An initial position: a number, or a range `[min, max]`.
    Position,
}

impl Kind {
    /// Whether `value` reads as a value of this kind; the reason in serde's words if not.
    pub(crate) fn check(self, value: Spanned<DeValue<'_>>) -> Result<(), String> {
        fn check<T: DeserializeOwned>(value: Spanned<DeValue<'_>>) -> Result<(), String> {
            T::deserialize(ValueDeserializer::from(value))
                .map(drop)
                .map_err(|e| e.message().trim_end().to_string())
        }
        match self {
            Kind::Text => check::<String>(value),
            Kind::Number => check::<f64>(value),
            Kind::Count => check::<u32>(value),
            Kind::Rule => check::<DangerRule>(value),
            Kind::Flag => check::<bool>(value),
            Kind::Lane => check::<i32>(value),
            Kind::Lanes => check::<Vec<i32>>(value),
            Kind::Position => {
                const EXPECTED: &str = "expected a number or a range [min, max]";
                let number = |v: &DeValue<'_>| matches!(v, DeValue::Integer(_) | DeValue::Float(_));
                let found = match value.get_ref() {
                    DeValue::Array(items) if items.len() != 2 => {
                        Some(format!("an array of {} values", items.len()))
                    }
                    DeValue::Array(items) => items.iter().find(|x| !number(x.get_ref())).map(|x| {
                        format!(
                            "a range with {} in it",
                            with_article(x.get_ref().type_str())
                        )
                    }),
                    v if number(v) => None,
                    v => Some(with_article(v.type_str())),
                };
                match found {
                    Some(found) => Err(format!("invalid type: {found}, {EXPECTED}")),
                    // An integer too large for a float is still refused here.
                    None => check::<crate::core::model::Position>(value)
                        .map_err(|_| format!("not a number: {EXPECTED}")),
                }
            }
        }
    }
}

/// The lower bound a number must respect.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Bound {
    /// No bound of its own.
    Free,
    /// > 0.
    Positive,
    /// ≥ 0.
    NonNegative,
}

/// One key of a problem file.
#[derive(Debug)]
pub(crate) struct KeySpec {
    /// Dotted key, e.g. `robot.braking`.
    pub(crate) key: &'static str,
    /// The type of its value.
    pub(crate) kind: Kind,
    /// Its unit, shown in messages.
    pub(crate) unit: &'static str,
    /// Its own bound (cross-key conditions are checked separately).
    pub(crate) bound: Bound,
}

pub(crate) const fn spec(
    key: &'static str,
    kind: Kind,
    unit: &'static str,
    bound: Bound,
) -> KeySpec {
    KeySpec {
        key,
        kind,
        unit,
        bound,
    }
}

/// Every key of a problem file, in file order. A unit test keeps this in step with the
/// serde types.
pub(crate) const KEYS: &[KeySpec] = &[
    spec("name", Kind::Text, "", Bound::Free),
    spec("robot.max_speed", Kind::Number, "m/s", Bound::Positive),
    spec("robot.acceleration", Kind::Number, "m/s^2", Bound::Positive),
    spec("robot.braking", Kind::Number, "m/s^2", Bound::Positive),
    spec("robot.control_period", Kind::Number, "s", Bound::Positive),
    spec(
        "robot.latency",
        Kind::Count,
        "control periods",
        Bound::NonNegative,
    ),
    spec("robot.clearance", Kind::Number, "m", Bound::NonNegative),
    spec("robot.braking_min", Kind::Number, "m/s^2", Bound::Positive),
    spec(
        "robot.initial_speed",
        Kind::Number,
        "m/s",
        Bound::NonNegative,
    ),
    spec(
        "controller.assumed_obstacle_speed",
        Kind::Number,
        "m/s",
        Bound::NonNegative,
    ),
    spec(
        "controller.reaction_radius",
        Kind::Number,
        "m",
        Bound::Positive,
    ),
    spec("controller.danger_rule", Kind::Rule, "", Bound::Free),
    spec("controller.buffer", Kind::Number, "m", Bound::NonNegative),
    spec(
        "controller.wrong_assumption_brake",
        Kind::Flag,
        "",
        Bound::Free,
    ),
    spec(
        "environment.obstacle_speed",
        Kind::Number,
        "m/s",
        Bound::NonNegative,
    ),
    spec("environment.initial_gap", Kind::Position, "m", Bound::Free),
    spec("sensing.gap_noise", Kind::Number, "m", Bound::NonNegative),
    spec(
        "sensing.speed_noise",
        Kind::Number,
        "m/s",
        Bound::NonNegative,
    ),
    spec(
        "sensing.first_detection_gap",
        Kind::Number,
        "m",
        Bound::Positive,
    ),
];

/// The tables of a problem file.
pub(crate) const TABLES: &[&str] = &["robot", "controller", "environment", "sensing"];

pub(crate) fn key_spec(key: &str) -> Option<&'static KeySpec> {
    KEYS.iter().find(|s| s.key == key)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn position(text: &str) -> Result<(), String> {
        Kind::Position.check(DeValue::parse(text).unwrap())
    }

    #[test]
    fn a_position_is_a_number_or_two() {
        for ok in ["1", "2.5", "-3", "nan", "[1, 2]", "[1.5, 2]", "[2, 1]"] {
            assert_eq!(position(ok), Ok(()), "{ok}");
        }
        for (bad, found) in [
            ("\"near\"", "a string"),
            ("true", "a boolean"),
            ("[1]", "an array of 1 values"),
            ("[1, 2, 3]", "an array of 3 values"),
            ("[1, \"x\"]", "a range with a string in it"),
            ("{ min = 1 }", "a table"),
        ] {
            let err = position(bad).unwrap_err();
            assert!(err.contains(found), "{bad}: {err}");
        }
    }

    #[test]
    fn lanes_are_whole_numbers() {
        let lanes = |t| Kind::Lanes.check(DeValue::parse(t).unwrap());
        assert!(lanes("[-1, 0, 1]").is_ok());
        assert!(lanes("[0, 0.5]").is_err());
        assert!(lanes("0").is_err());
        assert!(
            Kind::Lane
                .check(DeValue::parse("3000000000").unwrap())
                .is_err()
        );
    }
}
