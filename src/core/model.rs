//! Problem files: the robot, its controller and the environment, in SI units.
//!
//! A [`Problem`] is what a user writes in TOML; [`Params`] is the same problem as numbers of
//! a chosen [`Scalar`] type, after validation. Exact parameters are the decimals the file
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

use std::borrow::Cow;
use std::fmt;
use std::ops::Range;
use std::path::Path;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use toml::Spanned;
use toml::de::{DeTable, DeValue, ValueDeserializer};

use crate::core::num::Scalar;

/// A verification problem: one robot, its controller, one oncoming obstacle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
}

/// The robot's dynamics and timing.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Robot {
    /// Top speed v_max (m/s), > 0.
    pub max_speed: f64,
    /// Acceleration a while speeding up (m/s²), > 0.
    pub acceleration: f64,
    /// Guaranteed deceleration b when braking (m/s²), > 0.
    pub braking: f64,
    /// Control period dt (s), > 0.
    pub control_period: f64,
    /// Observation latency L in whole control periods, ≥ 0.
    pub latency: u32,
    /// A collision is any instant with the robot moving and gap ≤ clearance (m), ≥ 0.
    pub clearance: f64,
}

/// The controller's braking rule.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
#[serde(deny_unknown_fields)]
pub struct Environment {
    /// W: the real bound on the obstacle's speed (m/s), ≥ 0; 0 is a static obstacle.
    pub obstacle_speed: f64,
    /// Gap between robot and obstacle at t = 0 (m), > clearance.
    pub initial_gap: f64,
}

/// A problem's numbers in a chosen number type.
#[allow(non_snake_case)]
#[derive(Clone, Debug, PartialEq)]
pub struct Params<N> {
    /// v_max
    pub v_max: N,
    /// a
    pub a: N,
    /// b
    pub b: N,
    /// dt
    pub dt: N,
    /// L (control periods)
    pub L: usize,
    /// clearance
    pub clearance: N,
    /// V_a
    pub V_a: N,
    /// ρ
    pub rho: N,
    /// danger rule
    pub rule: DangerRule,
    /// buffer
    pub buffer: N,
    /// whether the wrong-assumption guard is on
    pub wrong_assumption_brake: bool,
    /// W
    pub W: N,
    /// initial gap
    pub g0: N,
    /// Products every control period uses, computed once from the numbers above.
    pub k: StepConstants<N>,
}

/// Products of a problem's numbers that the step function uses every control period:
/// computing them once takes a third of the exact arithmetic out of each step.
#[derive(Clone, Debug, PartialEq)]
pub struct StepConstants<N> {
    /// 1/2
    pub half: N,
    /// v_max·dt
    pub v_max_dt: N,
    /// a·dt
    pub a_dt: N,
    /// a·dt²/2
    pub half_a_dt2: N,
    /// b·dt
    pub b_dt: N,
    /// b·dt²/2
    pub half_b_dt2: N,
}

impl<N: Scalar> StepConstants<N> {
    /// The constants of v_max, a, b and dt.
    pub fn of(v_max: &N, a: &N, b: &N, dt: &N) -> Self {
        let half = N::int(1) / N::int(2);
        let dt2 = dt.clone() * dt.clone();
        StepConstants {
            v_max_dt: v_max.clone() * dt.clone(),
            a_dt: a.clone() * dt.clone(),
            half_a_dt2: half.clone() * a.clone() * dt2.clone(),
            b_dt: b.clone() * dt.clone(),
            half_b_dt2: half.clone() * b.clone() * dt2,
            half,
        }
    }
}

impl Problem {
    /// The problem's numbers as `N` (exact decimals for rationals).
    pub fn params<N: Scalar>(&self) -> Params<N> {
        let r = &self.robot;
        let c = &self.controller;
        let e = &self.environment;
        let (v_max, a, b, dt) = (
            N::decimal(r.max_speed),
            N::decimal(r.acceleration),
            N::decimal(r.braking),
            N::decimal(r.control_period),
        );
        Params {
            k: StepConstants::of(&v_max, &a, &b, &dt),
            v_max,
            a,
            b,
            dt,
            L: r.latency as usize,
            clearance: N::decimal(r.clearance),
            V_a: N::decimal(c.assumed_obstacle_speed),
            rho: N::decimal(c.reaction_radius),
            rule: c.danger_rule,
            buffer: N::decimal(c.buffer),
            wrong_assumption_brake: c.wrong_assumption_brake,
            W: N::decimal(e.obstacle_speed),
            g0: N::decimal(e.initial_gap),
        }
    }
}

impl<N: Scalar> StepConstants<N> {
    pub(crate) fn map<M>(&self, f: &impl Fn(&N) -> M) -> StepConstants<M> {
        StepConstants {
            half: f(&self.half),
            v_max_dt: f(&self.v_max_dt),
            a_dt: f(&self.a_dt),
            half_a_dt2: f(&self.half_a_dt2),
            b_dt: f(&self.b_dt),
            half_b_dt2: f(&self.half_b_dt2),
        }
    }
}

impl<N: Scalar> Params<N> {
    /// The same problem in another number type, converting every number with `f`.
    pub fn map<M>(&self, f: impl Fn(&N) -> M) -> Params<M> {
        Params {
            v_max: f(&self.v_max),
            a: f(&self.a),
            b: f(&self.b),
            dt: f(&self.dt),
            L: self.L,
            clearance: f(&self.clearance),
            V_a: f(&self.V_a),
            rho: f(&self.rho),
            rule: self.rule,
            buffer: f(&self.buffer),
            wrong_assumption_brake: self.wrong_assumption_brake,
            W: f(&self.W),
            g0: f(&self.g0),
            k: self.k.map(&f),
        }
    }

    /// Whether the wrong-assumption guard can ever fire: it is on and the environment can
    /// move faster than the controller assumes (W > V_a).
    pub fn wrong_assumption_active(&self) -> bool {
        self.wrong_assumption_brake && self.W > self.V_a
    }
}

// ---------------------------------------------------------------------------------------------
// Reading, validating and writing problems
// ---------------------------------------------------------------------------------------------

/// Largest magnitude accepted for any number in a problem.
const MAX_MAGNITUDE: f64 = 1e9;
/// Largest latency accepted, in control periods.
const MAX_LATENCY: u32 = 1000;
/// Most control periods a problem may need: to cover the initial gap at top speed, to reach
/// top speed, or to stop from it.
const MAX_PERIODS: f64 = 1e6;

/// The type a key's value must have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
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
enum Bound {
    /// No bound of its own.
    Free,
    /// > 0.
    Positive,
    /// ≥ 0.
    NonNegative,
}

/// One key of a problem file.
struct KeySpec {
    /// Dotted key, e.g. `robot.braking`.
    key: &'static str,
    /// The type of its value.
    kind: Kind,
    /// Its unit, shown in messages.
    unit: &'static str,
    /// Its own bound (cross-key conditions are checked separately).
    bound: Bound,
}

const fn spec(key: &'static str, kind: Kind, unit: &'static str, bound: Bound) -> KeySpec {
    KeySpec {
        key,
        kind,
        unit,
        bound,
    }
}

/// Every key of a problem file, in file order. A unit test keeps this in step with the
/// serde types.
const KEYS: &[KeySpec] = &[
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
const TABLES: &[&str] = &["robot", "controller", "environment"];

fn key_spec(key: &str) -> Option<&'static KeySpec> {
    KEYS.iter().find(|s| s.key == key)
}

/// Where a value sits in a problem file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    /// 1-based line.
    pub line: usize,
    /// 1-based column, in characters.
    pub column: usize,
    /// The whole source line (without its line break).
    pub source_line: String,
    /// How many characters of the line the value covers (at least 1).
    pub width: usize,
}

impl Location {
    /// The location of the byte range `span` of `text`, if it lies inside `text`.
    fn of_span(text: &str, span: Range<usize>) -> Option<Location> {
        let before = text.get(..span.start)?;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let line_end = text[span.start..]
            .find('\n')
            .map_or(text.len(), |i| span.start + i);
        let source_line = text[line_start..line_end]
            .trim_end_matches('\r')
            .to_string();
        let width = text
            .get(span.start..span.end.min(line_end))
            .map_or(1, |s| s.chars().count().max(1));
        Some(Location {
            line: before.matches('\n').count() + 1,
            column: text[line_start..span.start].chars().count() + 1,
            source_line,
            width,
        })
    }
}

/// Renders `location` as a rustc-style pointer under the one-line message.
fn show_location(origin: &str, location: &Option<Box<Location>>) -> String {
    let Some(l) = location else {
        return String::new();
    };
    let gutter = " ".repeat(l.line.to_string().len());
    format!(
        "\n{gutter}--> {origin}:{}:{}\n{gutter} |\n{} | {}\n{gutter} | {}{}",
        l.line,
        l.column,
        l.line,
        l.source_line,
        " ".repeat(l.column - 1),
        "^".repeat(l.width),
    )
}

/// Renders the known keys of an unknown `--set` key's table.
fn show_known(known: &[String]) -> String {
    known.join(", ")
}

/// Why a problem could not be read or is not a valid problem.
///
/// Every variant names its origin: the file's path, the text's origin given to
/// [`Problem::from_toml_str`], or the offending `--set key=value`. The first line of the
/// message is self-contained; some messages add a pointer into the file below it.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ProblemError {
    /// The file could not be read (missing, unreadable, not UTF-8).
    #[error("{origin}: cannot read the problem file")]
    Read {
        /// The path.
        origin: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The text is not TOML, or not shaped like a problem (an unknown, missing or mistyped
    /// key). The message is the toml crate's, with line, column and a snippet when it has them.
    #[error("{origin}: {message}")]
    Parse {
        /// The file (or other origin of the text).
        origin: String,
        /// The dotted key the error is at, when known (e.g. `robot.braking` for a missing key).
        key: Option<String>,
        /// 1-based line of the error, when known.
        line: Option<usize>,
        /// The toml crate's message.
        message: String,
    },
    /// A value of the right type that is not allowed: non-finite, out of range, or violating a
    /// condition of the model.
    #[error("{origin}: {key} = {value}: {reason}{}", show_location(.origin, .location))]
    Invalid {
        /// The file, or the `--set key=value` the value came from.
        origin: String,
        /// The dotted key.
        key: String,
        /// The value as read.
        value: String,
        /// Why it is rejected.
        reason: String,
        /// Where the value sits in the file, when it comes from one.
        location: Option<Box<Location>>,
    },
    /// A `--set` key that no problem has.
    #[error("{origin}: unknown key `{key}`; known keys{}: {}",
        .table.as_ref().map(|t| format!(" of [{t}]")).unwrap_or_default(), show_known(.known))]
    UnknownKey {
        /// The `--set key=value`.
        origin: String,
        /// The key as given.
        key: String,
        /// The table the key was looked up in (`None`: the top level).
        table: Option<String>,
        /// The keys that table does have.
        known: Vec<String>,
    },
    /// A `--set` that is not `dotted.key=value`, or that sets a whole table.
    #[error("{origin}: {reason}")]
    BadOverride {
        /// The `--set` argument.
        origin: String,
        /// The key, if one could be read.
        key: Option<String>,
        /// What is wrong with it.
        reason: String,
    },
}

impl ProblemError {
    /// Where the error comes from: a path, an origin given to [`Problem::from_toml_str`],
    /// or `--set key=value`.
    pub fn origin(&self) -> &str {
        match self {
            ProblemError::Read { origin, .. }
            | ProblemError::Parse { origin, .. }
            | ProblemError::Invalid { origin, .. }
            | ProblemError::UnknownKey { origin, .. }
            | ProblemError::BadOverride { origin, .. } => origin,
        }
    }

    /// The dotted key the error is about, when known.
    pub fn key(&self) -> Option<&str> {
        match self {
            ProblemError::Read { .. } => None,
            ProblemError::Parse { key, .. } | ProblemError::BadOverride { key, .. } => {
                key.as_deref()
            }
            ProblemError::Invalid { key, .. } | ProblemError::UnknownKey { key, .. } => Some(key),
        }
    }

    /// The 1-based line in the file, when known.
    pub fn line(&self) -> Option<usize> {
        match self {
            ProblemError::Parse { line, .. } => *line,
            ProblemError::Invalid { location, .. } => location.as_ref().map(|l| l.line),
            _ => None,
        }
    }
}

/// A rule of the model a problem breaks.
struct Violation {
    key: &'static str,
    value: String,
    reason: String,
}

/// A number as shown in messages: plain when moderate, in exponent form when huge or tiny.
fn show_number(x: f64) -> String {
    let a = x.abs();
    if a.is_finite() && a != 0.0 && !(1e-6..1e9).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// A large count of control periods as shown in messages.
fn show_count(x: f64) -> String {
    if x < 1e15 {
        format!("{x:.0}")
    } else {
        format!("{x:.3e}")
    }
}

fn with_unit(text: String, unit: &str) -> String {
    if unit.is_empty() {
        text
    } else {
        format!("{text} ({unit})")
    }
}

/// One `--set dotted.key=value`, parsed and type-checked.
struct Override<'s> {
    /// `--set dotted.key=value`, the origin of its errors.
    origin: String,
    /// The key's description.
    spec: &'static KeySpec,
    /// The value to put in the document.
    value: Spanned<DeValue<'s>>,
}

impl<'s> Override<'s> {
    fn parse(set: &'s str) -> Result<Override<'s>, ProblemError> {
        let origin = format!("--set {set}");
        let Some((key, text)) = set.split_once('=') else {
            return Err(ProblemError::BadOverride {
                origin,
                key: None,
                reason: "expected dotted.key=value, e.g. environment.obstacle_speed=0.25".into(),
            });
        };
        let (key, text) = (key.trim(), text.trim());
        let Some(spec) = key_spec(key) else {
            return Err(unknown_key(origin, key));
        };
        // Strings may be given bare (`danger_rule=kinematic`, `name=foo`).
        let value =
            if matches!(spec.kind, Kind::Text | Kind::Rule) && !text.starts_with(['"', '\'']) {
                Spanned::new(0..text.len(), DeValue::String(Cow::Borrowed(text)))
            } else {
                DeValue::parse(text).map_err(|e| ProblemError::Invalid {
                    origin: origin.clone(),
                    key: key.to_string(),
                    value: text.to_string(),
                    reason: format!("not a TOML value: {}", e.message().trim_end()),
                    location: None,
                })?
            };
        type_check(spec.kind, value.clone()).map_err(|e| ProblemError::Invalid {
            origin: origin.clone(),
            key: key.to_string(),
            value: text.to_string(),
            reason: e.message().trim_end().to_string(),
            location: None,
        })?;
        Ok(Override {
            origin,
            spec,
            value,
        })
    }

    /// Puts the value into the document, creating its table if the document lacks it.
    fn apply(self, root: &mut DeTable<'s>) {
        let key = |k: &'s str| Spanned::new(0..0, Cow::Borrowed(k));
        match self.spec.key.split_once('.') {
            None => {
                root.insert(key(self.spec.key), self.value);
            }
            Some((table, field)) => match root.get_mut(table) {
                Some(v) => {
                    // A `table` that is not a table is the file's error; leave it to surface.
                    if let DeValue::Table(t) = v.get_mut() {
                        t.insert(key(field), self.value);
                    }
                }
                None => {
                    let mut t = DeTable::new();
                    t.insert(key(field), self.value);
                    root.insert(key(table), Spanned::new(0..0, DeValue::Table(t)));
                }
            },
        }
    }
}

/// Whether `value` deserialises as a value of `kind`, with serde's message if not.
fn type_check(kind: Kind, value: Spanned<DeValue<'_>>) -> Result<(), toml::de::Error> {
    fn check<T: DeserializeOwned>(value: Spanned<DeValue<'_>>) -> Result<(), toml::de::Error> {
        T::deserialize(ValueDeserializer::from(value)).map(drop)
    }
    match kind {
        Kind::Text => check::<String>(value),
        Kind::Number => check::<f64>(value),
        Kind::Count => check::<u32>(value),
        Kind::Rule => check::<DangerRule>(value),
        Kind::Flag => check::<bool>(value),
    }
}

/// The error for a `--set` of a key no problem has (or of a whole table).
fn unknown_key(origin: String, key: &str) -> ProblemError {
    if TABLES.contains(&key) {
        let keys: Vec<&str> = KEYS
            .iter()
            .map(|s| s.key)
            .filter(|k| k.starts_with(&format!("{key}.")))
            .collect();
        return ProblemError::BadOverride {
            origin,
            key: Some(key.to_string()),
            reason: format!(
                "`{key}` is a table; set one of its keys: {}",
                keys.join(", ")
            ),
        };
    }
    let (table, known) = match key.split_once('.') {
        Some((table, _)) if TABLES.contains(&table) => (
            Some(table.to_string()),
            KEYS.iter()
                .filter_map(|s| s.key.strip_prefix(&format!("{table}.")[..]))
                .map(str::to_string)
                .collect(),
        ),
        _ => (
            None,
            KEYS.iter()
                .filter(|s| !s.key.contains('.'))
                .map(|s| s.key.to_string())
                .chain(TABLES.iter().map(|t| format!("{t}.*")))
                .collect(),
        ),
    };
    ProblemError::UnknownKey {
        origin,
        key: key.to_string(),
        table,
        known,
    }
}

/// The span of the value at dotted `key` in `doc`.
fn value_span(doc: &DeTable<'_>, key: &str) -> Option<Range<usize>> {
    let mut table = doc;
    let mut parts = key.split('.').peekable();
    while let Some(part) = parts.next() {
        let value = table.get(part)?;
        if parts.peek().is_none() {
            return Some(value.span());
        }
        match value.get_ref() {
            DeValue::Table(t) => table = t,
            _ => return None,
        }
    }
    None
}

/// The dotted key whose key or value covers byte `pos` of the document, innermost first.
fn key_at(table: &DeTable<'_>, pos: usize, prefix: &str) -> Option<String> {
    for (k, v) in table.iter() {
        let path = if prefix.is_empty() {
            k.get_ref().to_string()
        } else {
            format!("{prefix}.{}", k.get_ref())
        };
        if let DeValue::Table(t) = v.get_ref()
            && let Some(inner) = key_at(t, pos, &path)
        {
            return Some(inner);
        }
        if k.span().contains(&pos) || v.span().contains(&pos) {
            return Some(path);
        }
    }
    None
}

/// A toml error as a [`ProblemError::Parse`], with the key it is at when `doc` can tell.
fn parse_error(
    origin: &str,
    text: &str,
    doc: Option<&DeTable<'_>>,
    error: toml::de::Error,
) -> ProblemError {
    let span = error.span();
    let line = span
        .clone()
        .and_then(|s| Location::of_span(text, s))
        .map(|l| l.line);
    let mut key = match (doc, span) {
        (Some(doc), Some(span)) => key_at(doc, span.start, ""),
        _ => None,
    };
    if let Some(missing) = error
        .message()
        .strip_prefix("missing field `")
        .and_then(|m| m.split('`').next())
    {
        key = Some(match key {
            Some(table) if TABLES.contains(&table.as_str()) => format!("{table}.{missing}"),
            _ => missing.to_string(),
        });
    }
    ProblemError::Parse {
        origin: origin.to_string(),
        key,
        line,
        message: error.to_string().trim_end().to_string(),
    }
}

impl Problem {
    /// Every key a problem file has, dotted (`robot.braking`), in file order.
    pub fn known_keys() -> impl Iterator<Item = &'static str> {
        KEYS.iter().map(|s| s.key)
    }

    /// Reads and validates a problem from TOML `text`; `origin` (usually the path) names the
    /// text in errors.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Problem, ProblemError> {
        Self::from_toml_str_with_overrides(text, origin, &[])
    }

    /// Reads and validates the problem file at `path`.
    pub fn load(path: &Path) -> Result<Problem, ProblemError> {
        Self::load_with_overrides(path, &[])
    }

    /// Reads the problem file at `path`, applies `sets` (each `dotted.key=value`, the value a
    /// TOML value; strings may be bare: `controller.danger_rule=kinematic`) in order, then
    /// validates the result. Errors in an override name the override as their origin.
    pub fn load_with_overrides(path: &Path, sets: &[String]) -> Result<Problem, ProblemError> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| ProblemError::Read {
            origin: origin.clone(),
            source,
        })?;
        Self::from_toml_str_with_overrides(&text, &origin, sets)
    }

    /// [`Problem::from_toml_str`] with `--set` overrides, as [`Problem::load_with_overrides`].
    pub fn from_toml_str_with_overrides(
        text: &str,
        origin: &str,
        sets: &[String],
    ) -> Result<Problem, ProblemError> {
        let overrides = sets
            .iter()
            .map(|s| Override::parse(s))
            .collect::<Result<Vec<_>, _>>()?;
        let doc = DeTable::parse(text).map_err(|e| parse_error(origin, text, None, e))?;
        let mut root = doc.clone();
        let overridden: Vec<(&'static str, String)> = overrides
            .iter()
            .map(|o| (o.spec.key, o.origin.clone()))
            .collect();
        for o in overrides {
            o.apply(root.get_mut());
        }
        let problem =
            Problem::deserialize(toml::de::Deserializer::from(root)).map_err(|mut e| {
                e.set_input(Some(text));
                parse_error(origin, text, Some(doc.get_ref()), e)
            })?;
        if let Some(v) = problem.violation() {
            let from_set = overridden.iter().rev().find(|(k, _)| *k == v.key);
            return Err(match from_set {
                Some((_, set)) => ProblemError::Invalid {
                    origin: set.clone(),
                    key: v.key.to_string(),
                    value: v.value,
                    reason: v.reason,
                    location: None,
                },
                None => ProblemError::Invalid {
                    origin: origin.to_string(),
                    key: v.key.to_string(),
                    value: v.value,
                    reason: v.reason,
                    location: value_span(doc.get_ref(), v.key)
                        .and_then(|s| Location::of_span(text, s))
                        .map(Box::new),
                },
            });
        }
        Ok(problem)
    }

    /// Checks the problem against the model's conditions (finite, in range, positive where
    /// required, a gap larger than the clearance, a horizon of at most a million control
    /// periods); `origin` names the problem in the error.
    pub fn validate(&self, origin: &str) -> Result<(), ProblemError> {
        match self.violation() {
            None => Ok(()),
            Some(v) => Err(ProblemError::Invalid {
                origin: origin.to_string(),
                key: v.key.to_string(),
                value: v.value,
                reason: v.reason,
                location: None,
            }),
        }
    }

    /// The problem as a TOML document that reads back as an equal problem.
    pub fn to_toml_string(&self) -> String {
        toml::to_string(self).expect("a problem always serialises to TOML")
    }

    /// The problem's numbers with their dotted keys, in file order.
    fn numbers(&self) -> [(&'static str, f64); 10] {
        let (r, c, e) = (&self.robot, &self.controller, &self.environment);
        [
            ("robot.max_speed", r.max_speed),
            ("robot.acceleration", r.acceleration),
            ("robot.braking", r.braking),
            ("robot.control_period", r.control_period),
            ("robot.clearance", r.clearance),
            (
                "controller.assumed_obstacle_speed",
                c.assumed_obstacle_speed,
            ),
            ("controller.reaction_radius", c.reaction_radius),
            ("controller.buffer", c.buffer),
            ("environment.obstacle_speed", e.obstacle_speed),
            ("environment.initial_gap", e.initial_gap),
        ]
    }

    /// The first rule of the model the problem breaks, in file order.
    fn violation(&self) -> Option<Violation> {
        if self.name.trim().is_empty() {
            return Some(Violation {
                key: "name",
                value: format!("{:?}", self.name),
                reason: "must not be empty".into(),
            });
        }
        let numbers = self.numbers();
        for spec in KEYS {
            if spec.kind == Kind::Count {
                let latency = self.robot.latency;
                if latency > MAX_LATENCY {
                    return Some(Violation {
                        key: spec.key,
                        value: latency.to_string(),
                        reason: with_unit(format!("must be <= {MAX_LATENCY}"), spec.unit),
                    });
                }
                continue;
            }
            let Some(&(_, x)) = numbers.iter().find(|(k, _)| *k == spec.key) else {
                continue;
            };
            let reason = if !x.is_finite() {
                Some("must be a finite number".to_string())
            } else if x.abs() > MAX_MAGNITUDE {
                Some(format!("out of range: magnitude above {MAX_MAGNITUDE:e}"))
            } else {
                match spec.bound {
                    Bound::Positive if x <= 0.0 => Some("must be > 0".to_string()),
                    Bound::NonNegative if x < 0.0 => Some("must be >= 0".to_string()),
                    _ => None,
                }
            };
            if let Some(reason) = reason {
                return Some(Violation {
                    key: spec.key,
                    value: show_number(x),
                    reason: with_unit(reason, spec.unit),
                });
            }
        }
        let (r, e) = (&self.robot, &self.environment);
        if e.initial_gap <= r.clearance {
            return Some(Violation {
                key: "environment.initial_gap",
                value: show_number(e.initial_gap),
                reason: format!(
                    "must be > robot.clearance = {} (m): the robot would start in collision",
                    show_number(r.clearance)
                ),
            });
        }
        let horizons = [
            (
                "environment.initial_gap",
                e.initial_gap,
                e.initial_gap / (r.max_speed * r.control_period),
                "initial_gap / (max_speed * control_period)",
                "to cover the initial gap at top speed",
            ),
            (
                "robot.acceleration",
                r.acceleration,
                r.max_speed / (r.acceleration * r.control_period),
                "max_speed / (acceleration * control_period)",
                "to reach top speed",
            ),
            (
                "robot.braking",
                r.braking,
                r.max_speed / (r.braking * r.control_period),
                "max_speed / (braking * control_period)",
                "to stop from top speed",
            ),
        ];
        for (key, x, periods, formula, what) in horizons {
            if periods > MAX_PERIODS {
                return Some(Violation {
                    key,
                    value: show_number(x),
                    reason: format!(
                        "absurd horizon: {formula} = {} control periods {what}; the analysis \
                         would need more than a million control periods",
                        show_count(periods)
                    ),
                });
            }
        }
        None
    }
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
                initial_gap: 10.0,
            },
        }
    }

    #[test]
    fn key_table_matches_the_serde_types() {
        let table: toml::Table = toml::from_str(&seed().to_toml_string()).unwrap();
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
        let mut numbers: Vec<&str> = seed().numbers().iter().map(|(k, _)| *k).collect();
        let mut number_keys: Vec<&str> = KEYS
            .iter()
            .filter(|s| s.kind == Kind::Number)
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
