//! `safereach check`: re-verifies a certificate in exact arithmetic, without the solver, so
//! a verdict can be trusted without trusting the analyser that produced it.

use std::io::Write;
use std::path::PathBuf;

use anyhow::Result;
use safereach::proof::certificate_file::CertificateFile;

use super::exit::Exit;
use super::input::{self, Unreadable};
use super::output::Output;

/// Arguments of `safereach check`.
#[derive(clap::Args)]
pub struct CheckArgs {
    /// Certificate file (JSON).
    certificate: PathBuf,
}

/// Runs `safereach check`: exit 0 valid, 1 invalid.
pub fn run(args: CheckArgs, out: &mut Output) -> Result<Exit> {
    let path = &args.certificate;
    if let Ok(text) = std::fs::read_to_string(path)
        && super::region::is_map(&text)
    {
        return super::region::check_file(path, &text, out);
    }
    let cert = input::any_certificate(path, Unreadable::Reading)?;
    match cert.check() {
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
