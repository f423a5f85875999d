//! Exit codes: what every `safereach` command's status means, in one place.
//!
//! A command answers a question, and its status is the answer, so scripts can branch on it
//! without parsing the output. Commands return an [`Exit`]; only [`Exit`]'s conversion to
//! [`ExitCode`] knows the numbers.
//!
//! | command         | 0 ([`Exit::Pass`])            | 1 ([`Exit::Fail`])                      | 3 ([`Exit::Inconclusive`]) |
//! |-----------------|-------------------------------|-----------------------------------------|----------------------------|
//! | `certify`       | certified                     | refuted                                 | inconclusive               |
//! | `check`         | the certificate is valid      | invalid, or not of the `--require`d verdict |                        |
//! | `simulate`      | no collision                  | a collision (random runs or the replay) |                            |
//! | `radius`        | every speed has a safe radius | some speed has none                     |                            |
//! | `max-speed`     | some speed is certified       | none is                                 |                            |
//! | `sweep`         | results written               |                                         |                            |
//! | `report`        | reports written               |                                         |                            |
//! | `monitor`       | every premise held            | a premise was violated                  |                            |
//! | `explore`       | safe                          | a collision                             | state budget reached       |
//! | `export-uppaal` | model and query written       |                                         |                            |
//!
//! Every command: 2 ([`Exit::Error`]) for bad input (a problem, grid, certificate or trace
//! that cannot be read or is not valid; an unusable certificate for `monitor`; bad
//! arguments, which clap reports itself with the same status), an I/O error or an internal
//! error, with the reason on stderr; 141 ([`Exit::ClosedPipe`]) when the reader of stdout
//! went away (`safereach explore … --json | head -1`): the command stops quietly, as a
//! program killed by SIGPIPE would (status 128 + 13).

use std::process::ExitCode;

use safereach::analysis::Verdict;
use safereach::crosscheck::explore::ExploreVerdict;
use safereach::monitor::Verdict as MonitorVerdict;

/// How a command ended (see the module docs for what each means per command).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Exit {
    /// The answer is yes: certified, valid, held, no collision, safe, written.
    Pass = 0,
    /// The answer is no: refuted, invalid, violated, a collision, no radius or speed.
    Fail = 1,
    /// Bad input, an I/O error or an internal error; the reason is on stderr.
    Error = 2,
    /// No answer either way (an inconclusive certificate, a state budget reached).
    Inconclusive = 3,
    /// Standard output was closed by its reader; nothing more is printed.
    ClosedPipe = 141,
}

impl Exit {
    /// [`Exit::Fail`] when `failed`, else [`Exit::Pass`].
    pub fn fail_if(failed: bool) -> Exit {
        if failed { Exit::Fail } else { Exit::Pass }
    }

    /// The status for a command that failed with `error`: [`Exit::ClosedPipe`] when it
    /// stopped because stdout was closed, else [`Exit::Error`].
    pub fn of_error(error: &anyhow::Error) -> Exit {
        let closed = error.chain().any(|cause| {
            cause
                .downcast_ref::<std::io::Error>()
                .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
        });
        if closed {
            Exit::ClosedPipe
        } else {
            Exit::Error
        }
    }
}

impl From<Exit> for ExitCode {
    fn from(exit: Exit) -> ExitCode {
        ExitCode::from(exit as u8)
    }
}

/// `certify`'s status for its verdict.
impl From<Verdict> for Exit {
    fn from(verdict: Verdict) -> Exit {
        match verdict {
            Verdict::Certified => Exit::Pass,
            Verdict::Refuted => Exit::Fail,
            Verdict::Inconclusive => Exit::Inconclusive,
        }
    }
}

/// `explore`'s status for its verdict.
impl From<ExploreVerdict> for Exit {
    fn from(verdict: ExploreVerdict) -> Exit {
        match verdict {
            ExploreVerdict::Safe => Exit::Pass,
            ExploreVerdict::Collision => Exit::Fail,
            ExploreVerdict::Inconclusive => Exit::Inconclusive,
        }
    }
}

/// `monitor`'s status for its verdict.
impl From<MonitorVerdict> for Exit {
    fn from(verdict: MonitorVerdict) -> Exit {
        match verdict {
            MonitorVerdict::Held => Exit::Pass,
            MonitorVerdict::Violated => Exit::Fail,
        }
    }
}
