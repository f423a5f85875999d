//! Budgets: the most work a command does before it stops and says so.
//!
//! A command that could run for hours or fill the memory on legal input (a tiny control
//! period, a billion Monte Carlo runs, a grid of 10¹² cells, an exploration whose states are
//! large) is given a budget in the unit of its work. Every budget has a stated default and a
//! flag that raises it; work past it is refused before it starts, or stops when the running
//! count reaches it, with an [`OverBudget`] error that names the work, the limit and the flag
//! — never a hang, an abort or a silent wrap. Counts use checked arithmetic: a count that
//! overflows is over every budget. docs/budgets.md lists them all.

use std::fmt;
use std::sync::atomic::{AtomicU64, Ordering};

/// A kind of work that is budgeted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Work {
    /// Control periods simulated in floats: Monte Carlo runs times each run's horizon.
    SimulatedPeriods,
    /// Control periods analysed in exact arithmetic, summed over a search's analyses
    /// (`radius`, `max-speed`): each analysis counts its problem's horizon.
    AnalysedPeriods,
    /// Cells of a sweep grid.
    Cells,
    /// Bytes of memory an exploration's visited states may take.
    ExploreMemory,
    /// Boxes a region search decides.
    Boxes,
}

impl Work {
    /// The work's unit, plural.
    pub fn unit(self) -> &'static str {
        match self {
            Work::SimulatedPeriods => "simulated control periods",
            Work::AnalysedPeriods => "analysed control periods",
            Work::Cells => "cells",
            Work::ExploreMemory => "bytes of memory",
            Work::Boxes => "boxes",
        }
    }

    /// The command-line flag that sets the limit.
    pub fn flag(self) -> &'static str {
        match self {
            Work::SimulatedPeriods | Work::AnalysedPeriods => "--max-periods",
            Work::Cells => "--max-cells",
            Work::ExploreMemory => "--max-memory",
            Work::Boxes => "--max-boxes",
        }
    }

    /// The default limit: about a minute of work or 2 GiB of memory on a laptop core.
    pub fn default_limit(self) -> u64 {
        match self {
            // ~40 million float periods per second (the seed's Monte Carlo).
            Work::SimulatedPeriods => 2_000_000_000,
            // ~1,000,000 exact periods per second in a search's analyses, measured on the
            // area-rule problem at dt = 0.000113 s (495,580 periods per analysis: the whole
            // radius search, 7 analyses, in 6 s).
            Work::AnalysedPeriods => 20_000_000,
            // ~2,000–5,000 cells per second on two cores.
            Work::Cells => 1_000_000,
            Work::ExploreMemory => 2 << 30,
            // A box takes about 1–10 ms (the seed's map: 16,000 boxes in 1–3 s).
            Work::Boxes => 1_000_000,
        }
    }
}

/// A limit on one kind of work.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Budget {
    /// What is limited.
    pub work: Work,
    /// The most of it allowed.
    pub limit: u64,
}

impl Budget {
    /// The budget for `work` with its default limit.
    pub fn default_for(work: Work) -> Budget {
        Budget {
            work,
            limit: work.default_limit(),
        }
    }

    /// The budget for `work`: `limit` when given, else the default.
    pub fn new(work: Work, limit: Option<u64>) -> Budget {
        Budget {
            work,
            limit: limit.unwrap_or_else(|| work.default_limit()),
        }
    }

    /// `Ok` if `needed` (`None`: more than a count can hold) is within the limit; else the
    /// error, saying it is `asked` that needs it ("50,000 runs of 400 periods each").
    pub fn allow(&self, asked: impl Into<String>, needed: Option<u64>) -> Result<(), OverBudget> {
        match needed {
            Some(n) if n <= self.limit => Ok(()),
            _ => Err(OverBudget {
                asked: asked.into(),
                needed,
                budget: *self,
            }),
        }
    }
}

/// Work beyond a [`Budget`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OverBudget {
    /// What was asked, in the user's terms.
    pub asked: String,
    /// How much work it needs (`None`: more than a count can hold).
    pub needed: Option<u64>,
    /// The budget it exceeds.
    pub budget: Budget,
}

impl fmt::Display for OverBudget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let unit = self.budget.work.unit();
        match self.needed {
            Some(n) => write!(f, "{} needs {} {unit}", self.asked, grouped(n))?,
            None => write!(f, "{} needs more {unit} than can be counted", self.asked)?,
        }
        write!(
            f,
            ", more than the budget of {} ({} raises it)",
            grouped(self.budget.limit),
            self.budget.work.flag()
        )
    }
}

impl std::error::Error for OverBudget {}

/// A running count against a budget, shared by parallel workers.
#[derive(Debug)]
pub struct Meter {
    budget: Budget,
    used: AtomicU64,
}

impl Meter {
    /// A meter at zero.
    pub fn new(budget: Budget) -> Meter {
        Meter {
            budget,
            used: AtomicU64::new(0),
        }
    }

    /// Counts `amount` more for `what` (e.g. "analysis 12 of the search"), or the error if
    /// that would pass the budget (the count is then left as it was).
    pub fn charge(&self, what: impl FnOnce() -> String, amount: u64) -> Result<(), OverBudget> {
        let mut used = self.used.load(Ordering::Relaxed);
        loop {
            let next = used.checked_add(amount).filter(|&n| n <= self.budget.limit);
            let Some(next) = next else {
                return Err(OverBudget {
                    asked: what(),
                    needed: used.checked_add(amount),
                    budget: self.budget,
                });
            };
            match self
                .used
                .compare_exchange_weak(used, next, Ordering::Relaxed, Ordering::Relaxed)
            {
                Ok(_) => return Ok(()),
                Err(now) => used = now,
            }
        }
    }

    /// Counts one more `kind` of analysis (e.g. "scene analysis") of `horizon` periods for a
    /// search, or the error naming what the search had analysed so far.
    pub fn charge_analysis(&self, kind: &str, horizon: u64) -> Result<(), OverBudget> {
        let done = self.used();
        self.charge(
            || {
                format!(
                    "the search, after {} control periods analysed, one more {kind} of {} \
                     periods,",
                    grouped(done),
                    grouped(horizon)
                )
            },
            horizon,
        )
    }

    /// The work counted so far.
    pub fn used(&self) -> u64 {
        self.used.load(Ordering::Relaxed)
    }
}

/// `n` with thousands separated by commas.
pub fn grouped(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_budget_names_the_work_the_limit_and_the_flag() {
        let b = Budget::new(Work::SimulatedPeriods, Some(1000));
        assert!(b.allow("x", Some(1000)).is_ok());
        let e = b.allow("2 runs of 501 periods", Some(1002)).unwrap_err();
        assert_eq!(
            e.to_string(),
            "2 runs of 501 periods needs 1,002 simulated control periods, more than the \
             budget of 1,000 (--max-periods raises it)"
        );
        let e = b.allow("too many", None).unwrap_err();
        assert!(
            e.to_string()
                .contains("needs more simulated control periods than can be counted"),
            "{e}"
        );
    }

    #[test]
    fn a_meter_stops_at_its_limit_and_keeps_its_count() {
        let m = Meter::new(Budget::new(Work::AnalysedPeriods, Some(10)));
        assert!(m.charge(|| "a".into(), 6).is_ok());
        let e = m.charge(|| "b".into(), 5).unwrap_err();
        assert_eq!(e.needed, Some(11));
        assert_eq!(m.used(), 6);
        assert!(m.charge(|| "c".into(), 4).is_ok());
        assert!(
            m.charge(|| "d".into(), u64::MAX)
                .is_err_and(|e| e.needed.is_none())
        );
    }

    #[test]
    fn counts_are_grouped_by_thousands() {
        assert_eq!(grouped(0), "0");
        assert_eq!(grouped(999), "999");
        assert_eq!(grouped(1000), "1,000");
        assert_eq!(
            grouped(18_446_744_073_709_551_615),
            "18,446,744,073,709,551,615"
        );
    }
}
