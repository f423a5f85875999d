//! What commands read: problem and scene files with `--set` overrides, and certificates. One
//! loader each, so every command names the file (and the key, and the reason) the same way
//! when the input is bad, and exits 2.

use std::path::Path;

use anyhow::{Context, Result};

use safereach::core::model::Problem;
use safereach::core::scene::Scene;
use safereach::proof::certificate::Certificate;
use safereach::proof::certificate_file::CertificateFile;

/// Reads the problem file at `path` and applies `sets` (`dotted.key=value`, in order). The
/// error names the file, or the override, the key and the reason.
pub fn problem(path: &Path, sets: &[String]) -> Result<Problem> {
    Ok(Problem::load_with_overrides(path, sets)?)
}

/// Reads the scene file at `path` (or a problem file, as its one-obstacle scene) and applies
/// `sets` (`dotted.key=value`, in order; an obstacle's keys as `obstacle.<index>.<key>`). The
/// error names the file, or the override, the key (an obstacle's by index and name) and the
/// reason.
// No subcommand reads scenes yet; they move over one by one.
#[allow(dead_code)]
pub fn scene(path: &Path, sets: &[String]) -> Result<Scene> {
    Ok(Scene::load_with_overrides(path, sets)?)
}

/// Reads a certificate file of either kind (JSON, as `certify --out` writes it), not
/// checked.
pub fn any_certificate(path: &Path, unreadable: Unreadable) -> Result<CertificateFile> {
    let text = read_certificate(path, unreadable)?;
    CertificateFile::from_json(&text)
        .with_context(|| format!("{}: not a safereach certificate", path.display()))
}

fn read_certificate(path: &Path, unreadable: Unreadable) -> Result<String> {
    std::fs::read_to_string(path).with_context(|| match unreadable {
        Unreadable::Reading => format!("reading {}", path.display()),
        Unreadable::CannotRead => format!("{}: cannot read the certificate", path.display()),
    })
}

/// How an unreadable certificate file is named in the error. `check` and
/// `simulate --replay` have always said `reading FILE: <reason>`, `monitor`
/// `FILE: cannot read the certificate: <reason>`; the two are kept so that every command's
/// messages stay as they were.
#[derive(Clone, Copy)]
pub enum Unreadable {
    /// `reading FILE: <reason>`.
    Reading,
    /// `FILE: cannot read the certificate: <reason>`.
    CannotRead,
}

/// Reads and parses the certificate at `path` (JSON, as `certify --out` writes it). It is
/// not checked here: that is `check`'s job, or the caller's.
pub fn certificate(path: &Path, unreadable: Unreadable) -> Result<Certificate> {
    let text = read_certificate(path, unreadable)?;
    serde_json::from_str(&text)
        .with_context(|| format!("{}: not a safereach certificate", path.display()))
}
