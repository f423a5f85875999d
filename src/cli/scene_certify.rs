//! `safereach certify` on a scene: the verdict, the worst case named by obstacle and lane,
//! s* per obstacle, and the scene certificate (checked exactly before anything is printed).

use std::io::Write;
use std::path::PathBuf;

use anyhow::Result;

use safereach::analysis::scene_answer::SceneAnswer;
use safereach::analysis::scene_worst::SceneWorstCase;
use safereach::core::scene::Scene;
use safereach::core::semantics::Mode;
use safereach::proof::certificate_file::CertificateFile;
use safereach::proof::scene_certificate::SceneCertificate;

use safereach::core::show::{down, up, value};

use super::certify::{lower_bound_text, premises_text, s_star_text};
use super::exit::Exit;
use super::output::{Output, write_file};
use super::search_summary::search_summary;

/// Analyses a scene, writes its certificate and prints the answer; the exit code is the
/// verdict's (0 certified, 1 refuted, 3 inconclusive). Scenes with lane changes or position
/// ranges are decided by the exact run search and get a search certificate.
pub fn run(
    scene: &Scene,
    out_path: &Option<PathBuf>,
    json: bool,
    steps: bool,
    out: &mut Output,
) -> Result<Exit> {
    let answer = match steps {
        true => SceneAnswer::of_with_steps(scene),
        false => SceneAnswer::of(scene),
    }
    .map_err(|e| anyhow::anyhow!("{}: {e}", scene.name))?;
    let cert = answer.certificate();
    cert.check()
        .map_err(|e| anyhow::anyhow!("internal error: the certificate does not verify: {e}"))?;
    let text = cert.to_json();
    if let Some(path) = out_path {
        write_file(path, text.as_bytes())?;
    }
    if json {
        write!(out, "{text}")?;
    } else {
        match &cert {
            CertificateFile::Scene(c) => write!(out, "{}", summary(c, brake_time(&answer)))?,
            CertificateFile::Search(c) => write!(out, "{}", search_summary(c))?,
            CertificateFile::Single(_) | CertificateFile::Planar(_) => {
                unreachable!("a scene's answer is a scene certificate")
            }
        }
    }
    Ok(cert.verdict().into())
}

/// When the schedule analyser's witness brakes (s), from its exact replay: the
/// certificate keeps the rows only with `--steps`.
fn brake_time(answer: &SceneAnswer) -> Option<f64> {
    let SceneAnswer::Schedule(a, _) = answer else {
        return None;
    };
    let w = a.witness.as_ref()?;
    w.steps
        .iter()
        .find(|r| r.row.robot_mode == Mode::Brake)
        .map(|r| r.row.t)
}

/// The human-readable answer (numbers as [`super::certify`] shows them), with when the
/// witness's robot brakes (s).
fn summary(cert: &SceneCertificate, brake_at: Option<f64>) -> String {
    let scene = &cert.scene;
    let mut s = format!("{}: {}\n", scene.name, cert.verdict.as_str());
    let witness_sep = cert.witness.as_ref().and_then(|w| w.separation);
    let sep = if cert.min_separation.is_none() && !cert.never_stops && cert.obstacles.is_empty() {
        "+inf (no obstacle shares the robot's lane)".to_string()
    } else {
        s_star_text(
            cert.min_separation,
            cert.never_stops,
            cert.lower_bound,
            witness_sep,
            "-inf (an obstacle can pass the robot while it never brakes)",
        )
    };
    s += &format!("  worst-case minimum separation s* = {sep}\n");
    s += &lower_bound_text(cert.lower_bound, cert.clearance);
    if let Some(w) = &cert.witness {
        let worst = SceneWorstCase::from_witness(scene, w);
        let brake = brake_at
            .map(|t| format!(", robot brakes at t = {} s", value(t)))
            .unwrap_or_default();
        s += &format!(
            "  {}: {}{brake}; {}\n",
            if cert.min_separation.is_some() {
                "worst case"
            } else {
                "behaviour found"
            },
            worst.describe(),
            match (w.collides, w.separation) {
                (true, _) => "collides".to_string(),
                (false, Some(r)) => format!("gap at rest {} m", up(r, 9)),
                (false, None) => "never at rest in its lane".to_string(),
            }
        );
    }
    s += "  per obstacle of the robot's lane (others are out of reach):\n";
    for o in &cert.obstacles {
        let bound = o
            .lower_bound
            .map_or("none proved".to_string(), |x| format!("{} m", down(x, 9)));
        s += &format!(
            "    {:<16} separation >= {:<16} pieces {} own + {} bystander\n",
            format!("\"{}\"", o.name),
            bound,
            o.own.len(),
            o.bystanders.len()
        );
    }
    s += &format!(
        "  pieces: {} ({} linear programs solved)\n",
        cert.pieces(),
        cert.programs_solved
    );
    s += &premises_text(&cert.premises);
    s
}
