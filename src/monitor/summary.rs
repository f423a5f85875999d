//! What the monitor saw, at the end of a trace or at any moment: counts, the first
//! violation, and how every premise fared ([`Status`]: held, violated, not checked, or not
//! monitored, with the reason).

use serde::{Deserialize, Serialize};

use super::check::PremiseCheck;
use super::{Check, Event, Monitor, Verdict};
use crate::proof::premise::PremiseKind;

/// How a premise fared.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
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

/// One premise in a [`Summary`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
}

/// One fail-safe check in a [`Summary`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FailSafeSummary {
    /// The check.
    pub check: Check,
    /// Times it was violated.
    pub violations: u64,
}

/// What the monitor saw, at the end of a trace (or at any moment).
#[derive(Clone, Debug, PartialEq, Serialize)]
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
            premises: PremiseKind::ALL
                .into_iter()
                .map(|kind| self.premise_summary(kind))
                .collect(),
            fail_safe,
        }
    }

    /// How premise `kind` fared.
    fn premise_summary(&self, kind: PremiseKind) -> PremiseSummary {
        let check = Check::Premise(kind);
        let row = PremiseCheck::of(kind);
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
        PremiseSummary {
            premise: check,
            status,
            bound: self.bounds.of(check).unwrap_or(0.0),
            unit: check.unit().to_string(),
            checks,
            violations,
            reason,
        }
    }
}
