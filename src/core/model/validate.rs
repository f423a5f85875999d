//! The model's conditions on a problem's numbers: finite, in range, positive where
//! required, a gap above the clearance, a horizon of at most a million control periods.

use crate::core::model::Problem;
use crate::core::model::error::{Violation, show_count, show_number, with_unit};
use crate::core::model::keys::{
    Bound, KEYS, KeySpec, Kind, MAX_LATENCY, MAX_MAGNITUDE, MAX_PERIODS,
};

impl Problem {
    /// The problem's numbers with their dotted keys, in file order.
    pub(super) fn numbers(&self) -> [(&'static str, f64); 10] {
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
    fn key_violation(&self, spec: &KeySpec, numbers: &[(&'static str, f64)]) -> Option<Violation> {
        if spec.kind == Kind::Count {
            let latency = self.robot.latency;
            return (latency > MAX_LATENCY).then(|| Violation {
                key: spec.key,
                value: latency.to_string(),
                reason: with_unit(format!("must be <= {MAX_LATENCY}"), spec.unit),
            });
        }
        let &(_, x) = numbers.iter().find(|(k, _)| *k == spec.key)?;
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
        let r = &self.robot;
        let e = &self.environment;
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
