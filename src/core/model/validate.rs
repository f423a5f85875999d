//! The model's conditions on a problem's numbers: finite, in range, positive where
//! required, a gap above the clearance, a horizon of at most a million control periods.

use crate::core::model::error::{Violation, show_count, show_number, with_unit};
use crate::core::model::keys::{
    Bound, KEYS, KeySpec, Kind, MAX_LATENCY, MAX_MAGNITUDE, MAX_PERIODS,
};
use crate::core::model::{Controller, Problem, Robot};

impl Problem {
    /// The problem's numbers with their dotted keys, in file order.
    pub(super) fn numbers(&self) -> [(&'static str, f64); 10] {
        let env = &self.environment;
        let mut numbers = [("", 0.0); 10];
        numbers[..8].copy_from_slice(&robot_controller_numbers(&self.robot, &self.controller));
        numbers[8] = ("environment.obstacle_speed", env.obstacle_speed);
        numbers[9] = ("environment.initial_gap", env.initial_gap);
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
        let &(_, x) = numbers.iter().find(|(k, _)| *k == spec.key)?;
        number_violation(spec, x)
    }

    /// A robot that would start in collision.
    fn gap_violation(&self) -> Option<Violation> {
        let (r, e) = (&self.robot, &self.environment);
        (e.initial_gap <= r.clearance).then(|| Violation {
            key: "environment.initial_gap",
            value: show_number(e.initial_gap),
            reason: format!(
                "must be > robot.clearance = {} (m): the robot would start in collision",
                show_number(r.clearance)
            ),
        })
    }

    /// A horizon beyond what any engine should be asked to cover.
    fn horizon_violation(&self) -> Option<Violation> {
        let gap = self.environment.initial_gap;
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

/// The robot's and the controller's numbers with their dotted keys, in file order.
pub(crate) fn robot_controller_numbers(r: &Robot, c: &Controller) -> [(&'static str, f64); 8] {
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
    ]
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
        absurd(
            "robot.braking",
            r.braking,
            r.max_speed / (r.braking * r.control_period),
            "max_speed / (braking * control_period)",
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
