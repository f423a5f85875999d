//! What commands read: problem and scene files with `--set` overrides, and certificates. One
//! loader each, so every command names the file (and the key, and the reason) the same way
//! when the input is bad, and exits 2.

use std::path::Path;

use anyhow::{Context, Result};

use safereach::core::model::Problem;
use safereach::core::planar::PlanarProblem;
use safereach::core::scene::Scene;
use safereach::core::text_file;
use safereach::proof::certificate_file::CertificateFile;

/// A file read as what it states: a single-obstacle problem (`[environment]`, read with all
/// of today's checks, so it keeps today's answers and certificates), a scene, or a planar
/// problem (`[plane]`).
pub enum Input {
    /// A single-obstacle problem file.
    Problem(Problem),
    /// A scene file (or a problem file whose overrides make it a scene, e.g. `robot.goal`).
    Scene(Scene),
    /// A planar problem file (docs/semantics.md §13): certify, simulate, radius,
    /// max-speed, region, sweep and monitor answer it; explore and export-uppaal say they
    /// do not yet (issue 36).
    Planar(PlanarProblem),
}

/// The error of a command that does not analyse planar problems yet, for the file `path`.
pub fn planar_unsupported(path: &Path, command: &str) -> anyhow::Error {
    anyhow::anyhow!(
        "{}: planar problems are not supported by `safereach {command}` yet (issue 36)",
        path.display()
    )
}

/// Reads `path` with `sets` as a problem if it is one (a problem with a range of initial
/// gaps is read as the scene it is: one obstacle in lane 0), else as a scene (a scene file, or a
/// problem file whose overrides add scene keys). When neither reads, the error is the scene
/// reader's for a file in scene form (`[scene]` or `[[obstacle]]`), else the problem
/// reader's, so problem files keep today's messages.
pub fn problem_or_scene(path: &Path, sets: &[String]) -> Result<Input> {
    Ok(match problem_with_range_or_scene(path, sets)? {
        // A range of initial gaps is answered by the scene engines: the exact run search
        // covers every start (see `AnalysisError::GapRange`).
        Input::Problem(p) if p.environment.initial_gap.is_range() => {
            Input::Scene(Scene::from_problem(&p))
        }
        input => input,
    })
}

/// As [`problem_or_scene`], but a problem with a range of initial gaps stays a problem
/// (the explorer takes a finite set of starts in it). A file with a top-level `[plane]`
/// table is a planar problem, and only the planar reader's errors are reported for it.
pub fn problem_with_range_or_scene(path: &Path, sets: &[String]) -> Result<Input> {
    if planar_form(path) {
        return Ok(Input::Planar(PlanarProblem::load_with_overrides(
            path, sets,
        )?));
    }
    let problem_error = match Problem::load_with_overrides(path, sets) {
        Ok(p) => return Ok(Input::Problem(p)),
        Err(e) => e,
    };
    match Scene::load_with_overrides(path, sets) {
        Ok(s) => Ok(Input::Scene(s)),
        Err(e) if scene_form(path) => Err(e.into()),
        Err(_) => Err(problem_error.into()),
    }
}

/// Whether the file at `path` is a planar problem file (a `plane` table at its top level).
fn planar_form(path: &Path) -> bool {
    text_file::read_text(path, text_file::MAX_PROBLEM_BYTES)
        .is_ok_and(|text| PlanarProblem::is_planar(&text))
}

/// Whether the file at `path` has a `scene` or `obstacle` table at its top level.
fn scene_form(path: &Path) -> bool {
    text_file::read_text(path, text_file::MAX_PROBLEM_BYTES)
        .ok()
        .and_then(|text| text.parse::<toml::Table>().ok())
        .is_some_and(|t| t.contains_key("scene") || t.contains_key("obstacle"))
}

/// Reads a certificate file of either kind (JSON, as `certify --out` writes it), not
/// checked.
pub fn any_certificate(path: &Path, unreadable: Unreadable) -> Result<CertificateFile> {
    let text = certificate_text(path, unreadable)?;
    CertificateFile::from_json(&text)
        .with_context(|| format!("{}: not a safereach certificate", path.display()))
}

/// The text of a certificate or region map file (not parsed).
pub fn certificate_text(path: &Path, unreadable: Unreadable) -> Result<String> {
    text_file::read_text(path, text_file::MAX_CERTIFICATE_BYTES).with_context(|| match unreadable {
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
