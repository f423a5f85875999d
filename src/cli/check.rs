//! `safereach check`: re-verifies a certificate in exact arithmetic, without the solver, so
//! a verdict can be trusted without trusting the analyser that produced it.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result};
use safereach::proof::certificate_file::CertificateFile;
use safereach::proof::verdict::Verdict;

use super::exit::Exit;
use super::input::{self, Unreadable};
use super::output::Output;

/// Arguments of `safereach check`.
#[derive(clap::Args)]
pub struct CheckArgs {
    /// Certificate file (JSON).
    certificate: PathBuf,
    /// Also require this verdict: a valid certificate of another verdict exits 1 (for
    /// pipelines that must not go on unless, say, the problem is certified).
    #[arg(long, value_name = "VERDICT")]
    require: Option<RequiredVerdict>,
}

/// A verdict `--require` can ask for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(super) enum RequiredVerdict {
    /// Safe: a rigorous lower bound on s* above the clearance.
    Certified,
    /// Unsafe: a witness replayed exactly collides.
    Refuted,
    /// Neither.
    Inconclusive,
}

impl RequiredVerdict {
    pub(super) fn verdict(self) -> Verdict {
        match self {
            RequiredVerdict::Certified => Verdict::Certified,
            RequiredVerdict::Refuted => Verdict::Refuted,
            RequiredVerdict::Inconclusive => Verdict::Inconclusive,
        }
    }
}

/// Runs `safereach check`: exit 0 valid (and of the `--require`d verdict), 1 invalid or of
/// another verdict.
pub fn run(args: CheckArgs, out: &mut Output) -> Result<Exit> {
    let path = &args.certificate;
    let text = input::certificate_text(path, Unreadable::Reading)?;
    if safereach::proof::certificate_file::is_region_map(&text) {
        return super::region::check_file(path, &text, args.require.map(|r| r.verdict()), out);
    }
    let cert = CertificateFile::from_json(&text)
        .with_context(|| format!("{}: not a safereach certificate", path.display()))?;
    match cert.check() {
        Ok(report) if args.require.is_some_and(|r| r.verdict() != report.verdict) => {
            writeln!(
                out,
                "{}: valid, but its verdict is {}, not the required {}",
                path.display(),
                report.verdict.as_str(),
                args.require.map_or("", |r| r.verdict().as_str()),
            )?;
            Ok(Exit::Fail)
        }
        Ok(report) => {
            let over = match cert {
                CertificateFile::Search(_) => {
                    format!("by searching its {} runs again", report.pieces)
                }
                _ => format!("over {} pieces", report.pieces),
            };
            writeln!(
                out,
                "{}: valid; verdict {} re-verified in exact arithmetic {over}",
                path.display(),
                report.verdict.as_str(),
            )?;
            Ok(Exit::Pass)
        }
        Err(e) => {
            writeln!(out, "{}: INVALID: {e}", path.display())?;
            Ok(Exit::Fail)
        }
    }
}
