//! The planar monitor's [`Summary`]: the line's premises and behaviour checks, as far as a
//! planar trace can show them, and the `plane` part: the planar checks and each certified
//! obstacle.

use serde::Serialize;

use super::PlanarMonitor;
use crate::monitor::check::PremiseCheck;
use crate::monitor::{
    BehaviourCheck, Check, CheckSummary, FailSafeSummary, PlaneCheck, PremiseSummary, Status,
    Summary,
};
use crate::proof::premise::PremiseKind;

/// What a planar certificate's monitor adds to the [`Summary`].
#[derive(Clone, Debug, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct PlaneSummary {
    /// The planar checks, in [`PlaneCheck::ALL`]'s order.
    pub checks: Vec<CheckSummary>,
    /// The certificate's obstacles, in its problem's order.
    pub obstacles: Vec<PlanarObstacleSummary>,
    /// Tracked objects seen whose id names no obstacle of the certificate.
    pub unmatched: u64,
}

/// One obstacle of the planar certificate in a [`PlaneSummary`].
#[derive(Clone, Debug, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct PlanarObstacleSummary {
    /// Its name: the trace obstacle id it is matched to.
    pub name: String,
    /// r_i (m).
    pub radius: f64,
    /// W_i (m/s).
    pub max_speed: f64,
    /// Some sample had its name as obstacle id.
    pub seen: bool,
    /// Violations by its samples.
    pub violations: u64,
}

/// Why a check cannot be monitored on a planar trace (None: it can).
fn not_monitored(m: &PlanarMonitor, check: Check) -> Option<&'static str> {
    let all_round = m.rule.all_round();
    match check {
        Check::Premise(PremiseKind::Latency) => {
            Some("planar traces carry no observation times (obstacle_t)")
        }
        Check::Premise(PremiseKind::ObservationNoise | PremiseKind::SpeedNoise) => {
            Some("observation errors need the true positions, which a trace does not carry")
        }
        Check::Premise(PremiseKind::BrakingDeceleration) if !m.carried_mode => {
            Some("no sample carried robot_mode, so braking cannot be recognised")
        }
        Check::Premise(PremiseKind::FirstDetectionGap) | Check::ObservationDropout
            if !all_round =>
        {
            Some("the field of view is limited: an obstacle may leave or enter it unseen")
        }
        Check::ControllerReaction if !m.carried_mode => {
            Some("no sample carried robot_mode, so braking cannot be recognised")
        }
        Check::ObservationInconsistent if !m.carried_velocity => {
            Some("no sample carried obstacle_vx, obstacle_vy")
        }
        _ => None,
    }
}

/// Why a check was never evaluated.
fn not_checked(check: Check) -> &'static str {
    match check {
        Check::Premise(PremiseKind::FirstDetectionGap) => {
            "no obstacle was first seen after the first instant"
        }
        Check::ObservationDropout => "no obstacle was seen where it had to stay in view",
        Check::ControllerReaction => "no observation called for a reaction",
        Check::Premise(k) => PremiseCheck::of(k).not_checked,
        Check::Behaviour(c) => c.row().not_checked,
        Check::Plane(c) => c.row().not_checked,
        _ => "no sample gave the opportunity",
    }
}

impl PlanarMonitor {
    /// How `check` fared.
    fn status(&self, check: Check) -> (Status, u64, u64, Option<String>) {
        let checks = self.checks(check);
        let violations = self.violations(check);
        let (status, reason) = if violations > 0 {
            (Status::Violated, None)
        } else if let Some(r) = not_monitored(self, check) {
            (Status::NotMonitored, Some(r.to_string()))
        } else if checks == 0 {
            (Status::NotChecked, Some(not_checked(check).to_string()))
        } else {
            (Status::Held, None)
        };
        (status, checks, violations, reason)
    }

    fn check_summary(&self, check: Check, bound: Option<f64>) -> CheckSummary {
        let (status, checks, violations, reason) = self.status(check);
        CheckSummary {
            check,
            status,
            bound,
            unit: match check {
                Check::RobotEnvelope => "m/s",
                _ => check.unit(),
            }
            .to_string(),
            checks,
            violations,
            reason,
            margin: self.margins[check.index()].seen(),
        }
    }

    /// The premise's bound, as the certificate's problem states it.
    fn premise_bound(&self, kind: PremiseKind) -> f64 {
        let r = &self.rule;
        match kind {
            PremiseKind::ObstacleSpeed => r.largest_speed(),
            PremiseKind::BrakingDeceleration => r.motion.b_min,
            PremiseKind::ControlPeriod => r.motion.dt,
            PremiseKind::Latency => r.motion.L as f64,
            PremiseKind::FirstDetectionGap => r.first_detection.unwrap_or(0.0),
            PremiseKind::ObservationNoise => r.position_noise,
            PremiseKind::SpeedNoise => r.velocity_noise,
        }
    }

    /// The summary so far.
    pub fn summary(&self) -> Summary {
        let premises = PremiseKind::ALL
            .into_iter()
            .filter(|&k| k != PremiseKind::SpeedNoise || self.rule.velocity_noise > 0.0)
            .map(|kind| {
                let check = Check::Premise(kind);
                let (status, checks, violations, reason) = self.status(check);
                PremiseSummary {
                    premise: check,
                    status,
                    bound: self.premise_bound(kind),
                    unit: check.unit().to_string(),
                    checks,
                    violations,
                    reason,
                    margin: self.margins[check.index()].seen(),
                }
            })
            .collect();
        let behaviour = BehaviourCheck::ALL
            .into_iter()
            .map(|c| {
                let bound = match c {
                    BehaviourCheck::Collision => Some(self.rule.motion.clearance),
                    BehaviourCheck::RobotEnvelope => Some(self.rule.motion.v_max),
                    _ => None,
                };
                self.check_summary(Check::Behaviour(c), bound)
            })
            .collect();
        let seen: Vec<bool> = (0..self.rule.obstacles.len())
            .map(|i| self.tracks.iter().any(|t| t.seen && t.certified == Some(i)))
            .collect();
        let unmatched = self
            .tracks
            .iter()
            .filter(|t| t.seen && t.certified.is_none())
            .count() as u64;
        let plane = PlaneSummary {
            checks: PlaneCheck::ALL
                .into_iter()
                .map(|c| {
                    let bound = match c {
                        PlaneCheck::RobotPath => Some(self.rule.drift),
                        _ => None,
                    };
                    self.check_summary(Check::Plane(c), bound)
                })
                .collect(),
            obstacles: self
                .rule
                .obstacles
                .iter()
                .zip(seen)
                .zip(&self.obstacle_violations)
                .map(|((o, seen), &violations)| PlanarObstacleSummary {
                    name: o.name.clone(),
                    radius: o.radius,
                    max_speed: o.max_speed,
                    seen,
                    violations,
                })
                .collect(),
            unmatched,
        };
        Summary {
            verdict: self.verdict(),
            samples: self.samples,
            instants: if self.robot.is_some() {
                self.instant + 1
            } else {
                0
            },
            obstacles: self.distinct_obstacles,
            violations: self.violations.iter().sum(),
            first_violation: self.first,
            premises,
            fail_safe: Check::FAIL_SAFE
                .into_iter()
                .map(|c| FailSafeSummary {
                    check: c,
                    violations: self.violations(c),
                })
                .collect(),
            behaviour,
            scene: None,
            plane: Some(plane),
        }
    }
}
