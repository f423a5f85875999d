//! The keys a problem file has: their types, units and bounds, and the limits every number
//! must respect. One table serves reading, overrides, validation and messages.

/// Largest magnitude accepted for any number in a problem.
pub(super) const MAX_MAGNITUDE: f64 = 1e9;
/// Largest latency accepted, in control periods.
pub(super) const MAX_LATENCY: u32 = 1000;
/// Most control periods a problem may need: to cover the initial gap at top speed, to reach
/// top speed, or to stop from it.
pub(super) const MAX_PERIODS: f64 = 1e6;

/// The type a key's value must have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
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
}

/// The lower bound a number must respect.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Bound {
    /// No bound of its own.
    Free,
    /// > 0.
    Positive,
    /// ≥ 0.
    NonNegative,
}

/// One key of a problem file.
pub(super) struct KeySpec {
    /// Dotted key, e.g. `robot.braking`.
    pub(super) key: &'static str,
    /// The type of its value.
    pub(super) kind: Kind,
    /// Its unit, shown in messages.
    pub(super) unit: &'static str,
    /// Its own bound (cross-key conditions are checked separately).
    pub(super) bound: Bound,
}

pub(super) const fn spec(
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
pub(super) const KEYS: &[KeySpec] = &[
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
    spec("environment.initial_gap", Kind::Number, "m", Bound::Free),
];

/// The tables of a problem file.
pub(super) const TABLES: &[&str] = &["robot", "controller", "environment"];

pub(super) fn key_spec(key: &str) -> Option<&'static KeySpec> {
    KEYS.iter().find(|s| s.key == key)
}
