//! The keys a problem file has: their types, units and bounds, and the limits every number
//! must respect. One table serves reading, overrides, validation and messages; scene files
//! describe their own keys with the same [`KeySpec`]s (`core::scene::keys`).

use serde::de::DeserializeOwned;
use toml::Spanned;
use toml::de::{DeValue, ValueDeserializer};

use crate::core::model::DangerRule;

/// Largest magnitude accepted for any number in a problem.
pub(crate) const MAX_MAGNITUDE: f64 = 1e9;
/// Largest latency accepted, in control periods.
pub(crate) const MAX_LATENCY: u32 = 1000;
/// Most control periods a problem may need: to cover the initial gap at top speed, to reach
/// top speed, or to stop from it. It bounds whatever walks periods — the analyser's programs
/// (a variable per period), per-period speed lists, simulations, explorers, scene replays and
/// searches; the single-obstacle witness replay leaps over quiescent stretches and does not
/// need it (docs/certificates.md §6).
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
    /// A point of the plane: `[x, y]` (planar problems).
    Point,
    /// A list of points: `[[x, y], ...]` (a path or a polygon).
    Points,
}

impl Kind {
    /// What a value of this kind is, in the user's words.
    pub(crate) fn expected(self) -> &'static str {
        match self {
            Kind::Text => "text",
            Kind::Number => "a number",
            Kind::Count => "a whole number >= 0",
            Kind::Rule => "one of paper, kinematic, area",
            Kind::Flag => "true or false",
            Kind::Lane => "a lane (a whole number)",
            Kind::Lanes => "a list of lanes (whole numbers), e.g. [0, 1]",
            Kind::Position => "a number or a range [min, max]",
            Kind::Point => "a point [x, y]",
            Kind::Points => "a list of points [[x, y], ...]",
        }
    }

    /// Whether `value` reads as a value of this kind; if not, the reason in the user's words
    /// ("expected a number, got the text \"fast\"").
    pub(crate) fn check(self, value: Spanned<DeValue<'_>>) -> Result<(), String> {
        fn reads<T: DeserializeOwned>(value: &Spanned<DeValue<'_>>) -> bool {
            T::deserialize(ValueDeserializer::from(value.clone())).is_ok()
        }
        let ok = match self {
            Kind::Text => reads::<String>(&value),
            Kind::Number => reads::<f64>(&value),
            Kind::Count => reads::<u32>(&value),
            Kind::Rule => reads::<DangerRule>(&value),
            Kind::Flag => reads::<bool>(&value),
            Kind::Lane => reads::<i32>(&value),
            Kind::Lanes => reads::<Vec<i32>>(&value),
            Kind::Position => reads::<crate::core::model::Position>(&value),
            Kind::Point => reads::<[f64; 2]>(&value),
            Kind::Points => reads::<Vec<[f64; 2]>>(&value),
        };
        if ok {
            return Ok(());
        }
        let got = match (self, value.get_ref()) {
            (Kind::Position, DeValue::Array(items)) if items.len() != 2 => {
                format!("a list of {} values", items.len())
            }
            (Kind::Position | Kind::Lanes, DeValue::Array(items)) => {
                let fits = |x: &DeValue<'_>| match x {
                    DeValue::Integer(_) => true,
                    DeValue::Float(_) => self == Kind::Position,
                    _ => false,
                };
                match items.iter().find(|x| !fits(x.get_ref())) {
                    Some(x) => format!("a list with {} in it", shown(x.get_ref())),
                    None => format!("{} (out of range)", shown(value.get_ref())),
                }
            }
            (Kind::Count | Kind::Lane, DeValue::Integer(_)) => {
                format!("{} (out of range)", shown(value.get_ref()))
            }
            (_, v) => shown(v),
        };
        Err(format!("expected {}, got {got}", self.expected()))
    }
}

/// A TOML value in the user's words: `1.5`, the text "fast", a list, a table.
pub(crate) fn shown(value: &DeValue<'_>) -> String {
    match value {
        DeValue::String(s) => format!("the text {s:?}"),
        DeValue::Integer(i) => i.to_string(),
        DeValue::Float(f) => f.to_string(),
        DeValue::Boolean(b) => b.to_string(),
        DeValue::Datetime(d) => format!("the date {d}"),
        DeValue::Array(items) => format!("a list of {} values", items.len()),
        DeValue::Table(_) => "a table".to_string(),
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

impl KeySpec {
    /// [`Kind::check`] with the key's unit: "expected a number in m/s, got the text
    /// \"fast\"".
    pub(crate) fn check(&self, value: Spanned<DeValue<'_>>) -> Result<(), String> {
        self.kind.check(value).map_err(|reason| {
            if self.unit.is_empty() {
                return reason;
            }
            let what = self.kind.expected();
            let of = if self.kind == Kind::Count { "of" } else { "in" };
            reason.replacen(what, &format!("{what} {of} {}", self.unit), 1)
        })
    }
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
            ("\"near\"", "got the text \"near\""),
            ("true", "got true"),
            ("[1]", "got a list of 1 values"),
            ("[1, 2, 3]", "got a list of 3 values"),
            ("[1, \"x\"]", "got a list with the text \"x\" in it"),
            ("{ min = 1 }", "got a table"),
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
