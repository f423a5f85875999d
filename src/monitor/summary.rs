//! What the monitor saw, at the end of a trace or at any moment: counts, the first
//! violation, and how every premise fared ([`Status`]: held, violated, not checked, or not
//! monitored, with the reason); under a scene certificate also the scene checks and each of
//! the scene's obstacles ([`SceneSummary`]).

use serde::{Deserialize, Serialize};

use super::check::PremiseCheck;
use super::{BehaviourCheck, Check, Event, Monitor, SceneCheck, Verdict};
use crate::proof::premise::PremiseKind;

/// How a premise fared.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Checked at least once, never violated.
    Held,
    /// Violated at least once.
    Violated,
    /// Monitored, but no sample gave the opportunity (e.g. the robot never braked).
    NotChecked,
    /// Cannot be checked from these samples (see the reason).
    NotMonitored,
}

impl Status {
    /// The words used in output.
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Held => "held",
            Status::Violated => "violated",
            Status::NotChecked => "not checked",
            Status::NotMonitored => "not monitored",
        }
    }
}

/// The smallest slack a check had: how far the observed value stayed from breaking the
/// bound it is compared with (bound − observed for an upper bound, observed − bound for a
/// lower one, in the check's unit; negative where it was broken), and where.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct Margin {
    /// The slack.
    pub slack: f64,
    /// Time of the sample that had it (s).
    pub t: f64,
    /// Index of that sample (0-based count of samples fed to the monitor).
    pub sample: u64,
}

impl Margin {
    /// No slack seen yet.
    pub(crate) const NONE: Margin = Margin {
        slack: f64::INFINITY,
        t: f64::NAN,
        sample: 0,
    };

    /// The margin, once some evaluation had a slack.
    pub(crate) fn seen(self) -> Option<Margin> {
        self.slack.is_finite().then_some(self)
    }
}

/// One premise in a [`Summary`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct PremiseSummary {
    /// The premise.
    pub premise: Check,
    /// How it fared.
    pub status: Status,
    /// Its bound.
    pub bound: f64,
    /// The bound's unit.
    pub unit: String,
    /// Times it was evaluated.
    pub checks: u64,
    /// Times it was violated.
    pub violations: u64,
    /// Why it was not checked or not monitored.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// Its smallest slack, when it was evaluated on a value.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub margin: Option<Margin>,
}

/// One fail-safe check in a [`Summary`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct FailSafeSummary {
    /// The check.
    pub check: Check,
    /// Times it was violated.
    pub violations: u64,
}

/// What the monitor saw, at the end of a trace (or at any moment).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct Summary {
    /// The standing verdict.
    pub verdict: Verdict,
    /// Samples fed (malformed ones included).
    pub samples: u64,
    /// Distinct instants (values of `t`) among the accepted samples.
    pub instants: u64,
    /// Distinct obstacles among the accepted samples.
    pub obstacles: u64,
    /// Violations of all checks.
    pub violations: u64,
    /// The first violation.
    pub first_violation: Option<Event>,
    /// The certificate's premises, in its order.
    pub premises: Vec<PremiseSummary>,
    /// The fail-safe checks on the input.
    pub fail_safe: Vec<FailSafeSummary>,
    /// The checks of the model beyond its premises (observations, controller, collision).
    pub behaviour: Vec<CheckSummary>,
    /// Under a scene certificate: the scene checks and the scene's obstacles (absent for a
    /// single-obstacle certificate, whose summary is as it always was).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scene: Option<SceneSummary>,
    /// Under a planar certificate: the planar checks and the certificate's obstacles.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plane: Option<super::planar::PlaneSummary>,
}

/// What a scene certificate's monitor adds to the [`Summary`].
#[derive(Clone, Debug, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct SceneSummary {
    /// The scene checks, in [`SceneCheck::ALL`]'s order.
    pub checks: Vec<CheckSummary>,
    /// The scene's obstacles, in scene order.
    pub obstacles: Vec<CertifiedObstacleSummary>,
    /// Tracked objects seen whose id matches no obstacle of the scene (checked against the
    /// scene's largest moving bound, in any lane).
    pub unmatched: u64,
}

/// A scene check's summary: a [`CheckSummary`].
pub type SceneCheckSummary = CheckSummary;

/// One behaviour or scene check in a [`Summary`].
#[derive(Clone, Debug, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct CheckSummary {
    /// The check.
    pub check: Check,
    /// How it fared.
    pub status: Status,
    /// Its bound, where it has one fixed bound: 2σ_g/dt for `static_obstacle`, the clearance
    /// for `collision`, v_max for `robot_envelope`, ρ for `observation_dropout`
    /// (`obstacle_lane` compares each obstacle with its own lane; the others' bounds vary
    /// with the sample and are in their events).
    pub bound: Option<f64>,
    /// The bound's unit.
    pub unit: String,
    /// Times it was evaluated.
    pub checks: u64,
    /// Times it was violated.
    pub violations: u64,
    /// Why it was not checked or not monitored.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// Its smallest slack, when it was evaluated on a value (`robot_envelope`: the speed's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub margin: Option<Margin>,
}

/// One obstacle of the scene in a [`SceneSummary`]: what the certificate assumed of it and
/// whether the trace showed it.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct CertifiedObstacleSummary {
    /// Its name: the trace obstacle id it is matched to.
    pub name: String,
    /// Its certified lane.
    pub lane: i32,
    /// W_i (m/s).
    pub max_speed: f64,
    /// Static: it must not move.
    #[serde(rename = "static")]
    pub is_static: bool,
    /// Some sample had its name as obstacle id.
    pub seen: bool,
    /// Premise and scene-check violations by its samples.
    pub violations: u64,
}

impl Monitor {
    /// The summary so far: counts, the first violation and the status of every premise.
    pub fn summary(&self) -> Summary {
        let fail_safe = Check::FAIL_SAFE
            .into_iter()
            .map(|c| FailSafeSummary {
                check: c,
                violations: self.violations(c),
            })
            .collect();
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
            // `speed_noise` only where the certificate states it (σ_w > 0): certificates
            // without it, as every noise-free one, read as σ_w = 0 and summarise as before.
            premises: PremiseKind::ALL
                .into_iter()
                .filter(|&k| k != PremiseKind::SpeedNoise || self.bounds.speed_noise > 0.0)
                .map(|kind| self.premise_summary(kind))
                .collect(),
            fail_safe,
            behaviour: BehaviourCheck::ALL
                .into_iter()
                .map(|c| {
                    let bound = match c {
                        BehaviourCheck::Collision => Some(self.rule.clearance),
                        BehaviourCheck::RobotEnvelope => Some(self.rule.moving.v_max),
                        BehaviourCheck::ObservationDropout => Some(self.rule.moving.rho),
                        BehaviourCheck::ObservationInconsistent
                        | BehaviourCheck::ControllerReaction
                        | BehaviourCheck::RobotMotion => None,
                    };
                    self.check_summary(Check::Behaviour(c), c.row(), bound)
                })
                .collect(),
            scene: self.scene_summary(),
            plane: None,
        }
    }

    /// How a behaviour or scene check fared.
    fn check_summary(&self, check: Check, row: &PremiseCheck, bound: Option<f64>) -> CheckSummary {
        let (status, checks, violations, reason) = self.status(check, row);
        // robot_envelope's events carry their unit in the detail; its bound here is v_max.
        let unit = match check {
            Check::RobotEnvelope => "m/s",
            _ => row.unit,
        };
        CheckSummary {
            check,
            status,
            bound,
            unit: unit.to_string(),
            checks,
            violations,
            reason,
            margin: self.margin(check),
        }
    }

    /// The smallest slack `check` had so far, if it was evaluated on a value.
    pub fn margin(&self, check: Check) -> Option<Margin> {
        self.margins[check.index()].seen()
    }

    /// The scene checks and obstacles, under a scene certificate.
    fn scene_summary(&self) -> Option<SceneSummary> {
        let scene = self.scene.as_ref()?;
        let mut seen = vec![false; scene.obstacles.len()];
        let mut unmatched = 0;
        for track in self.obstacles.iter().filter(|t| t.seen) {
            match track.certified_index().and_then(|i| seen.get_mut(i)) {
                Some(s) => *s = true,
                None => unmatched += 1,
            }
        }
        let obstacles = scene
            .obstacles
            .iter()
            .zip(&scene.names)
            .zip(seen.into_iter().zip(&scene.violations))
            .map(
                |((o, name), (seen, &violations))| CertifiedObstacleSummary {
                    name: name.clone(),
                    lane: o.lane,
                    max_speed: o.max_speed,
                    is_static: o.is_static,
                    seen,
                    violations,
                },
            )
            .collect();
        let checks = SceneCheck::ALL
            .into_iter()
            .map(|c| {
                let bound = match c {
                    SceneCheck::StaticObstacle => {
                        Some(2.0 * self.bounds.observation_noise / self.bounds.control_period)
                    }
                    SceneCheck::ObstacleLane => None,
                };
                self.check_summary(Check::Scene(c), c.row(), bound)
            })
            .collect();
        Some(SceneSummary {
            checks,
            obstacles,
            unmatched,
        })
    }

    /// How `check` (whose row is `row`) fared: status, evaluations, violations, reason.
    fn status(&self, check: Check, row: &PremiseCheck) -> (Status, u64, u64, Option<String>) {
        let checks = self.checks(check);
        let violations = self.violations(check);
        let (status, reason) = if violations > 0 {
            (Status::Violated, None)
        } else if let Some(r) = (row.not_monitored)(self.carried) {
            (Status::NotMonitored, Some(r.to_string()))
        } else if checks == 0 {
            (Status::NotChecked, Some(row.not_checked.to_string()))
        } else {
            (Status::Held, None)
        };
        (status, checks, violations, reason)
    }

    /// How premise `kind` fared.
    fn premise_summary(&self, kind: PremiseKind) -> PremiseSummary {
        let check = Check::Premise(kind);
        let (status, checks, violations, reason) = self.status(check, PremiseCheck::of(kind));
        PremiseSummary {
            premise: check,
            status,
            bound: self.bounds.of(check).unwrap_or(0.0),
            unit: check.unit().to_string(),
            checks,
            violations,
            reason,
            margin: self.margin(check),
        }
    }
}
