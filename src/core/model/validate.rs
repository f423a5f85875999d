//! The model's conditions on a problem's numbers: finite, in range, positive where
//! required, a gap above the clearance, a horizon of at most a million control periods.

use crate::core::model::error::{Violation, show_count, show_number, with_unit};
use crate::core::model::keys::{
    Bound, KEYS, KeySpec, Kind, MAX_LATENCY, MAX_MAGNITUDE, MAX_PERIODS,
};
use crate::core::model::{Controller, Position, Problem, Robot, Sensing};

impl Problem {
    /// The problem's numbers with their dotted keys, in file order (optional keys only
    /// when given; a range's ends both under its key).
    pub(super) fn numbers(&self) -> Vec<(&'static str, f64)> {
        let env = &self.environment;
        let mut numbers = robot_controller_numbers(&self.robot, &self.controller);
        numbers.push(("environment.obstacle_speed", env.obstacle_speed));
        numbers.push(("environment.initial_gap", env.initial_gap.min()));
        if env.initial_gap.is_range() {
            numbers.push(("environment.initial_gap", env.initial_gap.max()));
        }
        numbers.extend(sensing_numbers(self.sensing.as_ref()));
        numbers
    }

    /// The first rule of the model the problem breaks, in file order.
    pub(super) fn violation(&self) -> Option<Violation> {
        if self.name.trim().is_empty() {
            return Some(Violation {
                key: "name",
                value: format!("{:?}", self.name),
                reason: "must not be empty".into(),
            });
        }
        let numbers = self.numbers();
        KEYS.iter()
            .find_map(|spec| self.key_violation(spec, &numbers))
            .or_else(|| robot_violation(&self.robot))
            .or_else(|| self.gap_violation())
            .or_else(|| self.horizon_violation())
    }

    /// A number outside its own key's range (finite, magnitude, sign; latency's cap).
    fn key_violation(
        &self,
        spec: &'static KeySpec,
        numbers: &[(&'static str, f64)],
    ) -> Option<Violation> {
        if spec.kind == Kind::Count {
            return latency_violation(spec, self.robot.latency);
        }
        numbers
            .iter()
            .filter(|(k, _)| *k == spec.key)
            .find_map(|&(_, x)| number_violation(spec, x))
    }

    /// A range the wrong way round, or a robot that would start in collision.
    fn gap_violation(&self) -> Option<Violation> {
        let (r, e) = (&self.robot, &self.environment);
        let gap = e.initial_gap;
        if let Position::Range(lo, hi) = gap
            && lo > hi
        {
            return Some(Violation {
                key: "environment.initial_gap",
                value: show_range(&gap),
                reason: format!(
                    "a range [min, max] needs min <= max; here min {} > max {}",
                    show_number(lo),
                    show_number(hi)
                ),
            });
        }
        let which = if gap.is_range() {
            "its min must be"
        } else {
            "must be"
        };
        if gap.min() <= r.clearance {
            return Some(Violation {
                key: "environment.initial_gap",
                value: show_range(&gap),
                reason: format!(
                    "{which} > robot.clearance = {} (m): the robot would start in collision",
                    show_number(r.clearance)
                ),
            });
        }
        let d_det = self.sensing.as_ref().and_then(|s| s.first_detection_gap);
        d_det.filter(|&d| gap.min() < d).map(|d| Violation {
            key: "environment.initial_gap",
            value: show_range(&gap),
            reason: occluded_too_close(which, d),
        })
    }

    /// A horizon beyond what any engine should be asked to cover.
    fn horizon_violation(&self) -> Option<Violation> {
        let gap = self.environment.initial_gap.max();
        distance_horizon_violation(
            &self.robot,
            "environment.initial_gap",
            gap,
            "initial_gap / (max_speed * control_period)",
            "to cover the initial gap at top speed",
        )
        .or_else(|| motion_horizon_violation(&self.robot))
    }
}

/// A number or a range as a file writes it.
pub(crate) fn show_range(p: &Position) -> String {
    match *p {
        Position::At(x) => show_number(x),
        Position::Range(lo, hi) => format!("[{}, {}]", show_number(lo), show_number(hi)),
    }
}

/// The robot's keys that tie to another key: the plant's braking at most the controller's,
/// an initial speed at most the top speed.
pub(crate) fn robot_violation(r: &Robot) -> Option<Violation> {
    if let Some(b_min) = r.braking_min
        && b_min > r.braking
    {
        return Some(Violation {
            key: "robot.braking_min",
            value: show_number(b_min),
            reason: format!(
                "must be <= robot.braking = {} (m/s^2): the plant guarantees at least \
                 braking_min, the controller computes with braking",
                show_number(r.braking)
            ),
        });
    }
    if let Some(v0) = r.initial_speed
        && v0 > r.max_speed
    {
        return Some(Violation {
            key: "robot.initial_speed",
            value: show_number(v0),
            reason: format!(
                "must be <= robot.max_speed = {} (m/s)",
                show_number(r.max_speed)
            ),
        });
    }
    None
}

/// Why a start closer than d_det is refused: no observation of it could be its first
/// sighting, so the occlusion premise would rule the obstacle out and an answer would hold
/// vacuously.
pub(crate) fn occluded_too_close(which: &str, d_det: f64) -> String {
    format!(
        "{which} >= sensing.first_detection_gap = {} (m): an occluded obstacle is first seen at \
         a true gap of at least d_det, so one starting closer could never be seen and the \
         premise would rule it out (every answer would hold vacuously); start it at d_det or \
         beyond, or lower d_det",
        show_number(d_det)
    )
}

/// The robot's and the controller's numbers with their dotted keys, in file order (the
/// optional robot keys only when given).
/// The `[sensing]` numbers given, with their dotted keys, in file order.
pub(crate) fn sensing_numbers(sensing: Option<&Sensing>) -> Vec<(&'static str, f64)> {
    let Some(s) = sensing else {
        return Vec::new();
    };
    let optional = [
        ("sensing.gap_noise", s.gap_noise),
        ("sensing.speed_noise", s.speed_noise),
        ("sensing.first_detection_gap", s.first_detection_gap),
    ];
    optional
        .iter()
        .filter_map(|&(k, x)| Some((k, x?)))
        .collect()
}

pub(crate) fn robot_controller_numbers(r: &Robot, c: &Controller) -> Vec<(&'static str, f64)> {
    let optional = [
        ("robot.braking_min", r.braking_min),
        ("robot.initial_speed", r.initial_speed),
    ];
    let mut numbers = vec![
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
    ];
    numbers.extend(optional.iter().filter_map(|&(k, x)| Some((k, x?))));
    numbers
}

/// The robot's and the controller's rules as a problem checks them: each key's own range
/// in file order, the keys that tie together, and the motion's horizons (to reach top speed,
/// to stop from it). A planar problem's motion is checked by exactly these.
pub(crate) fn motion_violation(r: &Robot, c: &Controller) -> Option<Violation> {
    let numbers = robot_controller_numbers(r, c);
    KEYS.iter()
        .filter(|s| s.key.starts_with("robot.") || s.key.starts_with("controller."))
        .find_map(|spec| match spec.kind {
            Kind::Count => latency_violation(spec, r.latency),
            _ => numbers
                .iter()
                .filter(|(k, _)| *k == spec.key)
                .find_map(|&(_, x)| number_violation(spec, x)),
        })
        .or_else(|| robot_violation(r))
        .or_else(|| motion_horizon_violation(r))
}

/// `latency` above the cap [`MAX_LATENCY`] of `spec` (`robot.latency`).
pub(crate) fn latency_violation(spec: &'static KeySpec, latency: u32) -> Option<Violation> {
    (latency > MAX_LATENCY).then(|| Violation {
        key: spec.key,
        value: latency.to_string(),
        reason: with_unit(format!("must be <= {MAX_LATENCY}"), spec.unit),
    })
}

/// `x` outside the range of its key `spec`: not finite, too large, or of the wrong sign.
pub(crate) fn number_violation(spec: &'static KeySpec, x: f64) -> Option<Violation> {
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
    reason.map(|reason| Violation {
        key: spec.key,
        value: show_number(x),
        reason: with_unit(reason, spec.unit),
    })
}

/// A distance `x` (at `key`) the robot would need more than [`MAX_PERIODS`] control periods
/// to cover at top speed; `formula` shows the division in the message.
pub(crate) fn distance_horizon_violation(
    r: &Robot,
    key: &'static str,
    x: f64,
    formula: &str,
    what: &str,
) -> Option<Violation> {
    absurd(key, x, x / (r.max_speed * r.control_period), formula, what)
}

/// A robot that needs more than [`MAX_PERIODS`] control periods to reach top speed or to
/// stop from it.
pub(crate) fn motion_horizon_violation(r: &Robot) -> Option<Violation> {
    absurd(
        "robot.acceleration",
        r.acceleration,
        r.max_speed / (r.acceleration * r.control_period),
        "max_speed / (acceleration * control_period)",
        "to reach top speed",
    )
    .or_else(|| {
        let (key, b, formula) = match r.braking_min {
            Some(b_min) => (
                "robot.braking_min",
                b_min,
                "max_speed / (braking_min * control_period)",
            ),
            None => (
                "robot.braking",
                r.braking,
                "max_speed / (braking * control_period)",
            ),
        };
        absurd(
            key,
            b,
            r.max_speed / (b * r.control_period),
            formula,
            "to stop from top speed",
        )
    })
}

/// The violation of a horizon of `periods` above [`MAX_PERIODS`].
fn absurd(key: &'static str, x: f64, periods: f64, formula: &str, what: &str) -> Option<Violation> {
    (periods > MAX_PERIODS).then(|| Violation {
        key,
        value: show_number(x),
        reason: format!(
            "absurd horizon: {formula} = {} control periods {what}; the analysis \
             would need more than a million control periods",
            show_count(periods)
        ),
    })
}
