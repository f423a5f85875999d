//! What commands read: problem and scene files with `--set` overrides, and certificates. One
//! loader each, so every command names the file (and the key, and the reason) the same way
//! when the input is bad, and exits 2.

use std::path::Path;

use anyhow::{Context, Result};

use safereach::core::model::Problem;
use safereach::core::scene::Scene;
use safereach::proof::certificate::Certificate;

/// Reads the problem file at `path` and applies `sets` (`dotted.key=value`, in order). The
/// error names the file, or the override, the key and the reason.
pub fn problem(path: &Path, sets: &[String]) -> Result<Problem> {
    Ok(Problem::load_with_overrides(path, sets)?)
}

/// Reads the scene file at `path` (or a problem file, as its one-obstacle scene) and applies
/// `sets` (`dotted.key=value`, in order; an obstacle's keys as `obstacle.<index>.<key>`). The
/// error names the file, or the override, the key (an obstacle's by index and name) and the
/// reason.
pub fn scene(path: &Path, sets: &[String]) -> Result<Scene> {
    Ok(Scene::load_with_overrides(path, sets)?)
}

/// What a command that takes either reads: a single-obstacle problem, or a scene.
pub enum ProblemOrScene {
    /// A problem file (with `[environment]`), read by [`problem`].
    Problem(Problem),
    /// Any other scene file, read by [`scene`].
    Scene(Scene),
}

/// Reads `path` as a single-obstacle problem when it reads as one ([`problem`], so old files
/// give exactly what they gave), else as a scene ([`scene`]). When neither reads, the error
/// is the problem reader's for a file in the problem form (with `[environment]`; or not
/// readable, or not TOML at all: the messages are the same then) and the scene reader's
/// otherwise.
pub fn problem_or_scene(path: &Path, sets: &[String]) -> Result<ProblemOrScene> {
    let problem_error = match problem(path, sets) {
        Ok(p) => return Ok(ProblemOrScene::Problem(p)),
        Err(e) => e,
    };
    match scene(path, sets) {
        Ok(s) => Ok(ProblemOrScene::Scene(s)),
        Err(_) if problem_form(path) => Err(problem_error),
        Err(scene_error) => Err(scene_error),
    }
}

/// Whether the file at `path` is in the problem form: it has `[environment]`, or it cannot
/// be read as a TOML table at all.
fn problem_form(path: &Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|text| text.parse::<toml::Table>().ok())
        .is_none_or(|table| table.contains_key("environment"))
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
    let text = std::fs::read_to_string(path).with_context(|| match unreadable {
        Unreadable::Reading => format!("reading {}", path.display()),
        Unreadable::CannotRead => format!("{}: cannot read the certificate", path.display()),
    })?;
    serde_json::from_str(&text)
        .with_context(|| format!("{}: not a safereach certificate", path.display()))
}
