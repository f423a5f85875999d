//! `safereach certify` on a planar problem: the verdict, the bracket on s*, the witness and
//! the certificate (docs/semantics.md §13). The lower end is proved from the SOC duals in
//! exact rationals; the upper end is a behaviour's exact replay; the certificate is checked
//! by `proof::planar::check` before anything is printed (`certify_text`), as `check` would.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Result;

use safereach::analysis::planar::{BoundaryError, PlanarVerdict, certify_text};
use safereach::core::show::{down, up, value};
use safereach::core::text_file;
use safereach::proof::planar::certificate::PlanarCertificate;

use super::exit::Exit;
use super::output::{Output, write_file};

/// Certifies the planar problem read from `path` with the overrides `sets`.
pub fn run(
    path: &Path,
    sets: &[String],
    (out_path, plot): (&Option<PathBuf>, &Option<PathBuf>),
    json: bool,
    out: &mut Output,
) -> Result<Exit> {
    // The certificate stores the text it was read from, so `check` reads the same problem.
    let text = text_file::read_text(path, text_file::MAX_PROBLEM_BYTES)
        .map_err(|e| anyhow::anyhow!("reading {}: {e}", path.display()))?;
    let (verdict, cert) =
        certify_text(&text, &path.display().to_string(), sets).map_err(|e| explain(path, e))?;
    let text = serde_json::to_string_pretty(&cert)? + "\n";
    if let Some(p) = out_path {
        write_file(p, text.as_bytes())?;
    }
    if let Some(file) = plot {
        super::planar_plot::plot_witness(&cert, &path.display().to_string(), file)?;
    }
    if json {
        write!(out, "{text}")?;
    } else {
        write!(out, "{}", summary(&cert))?;
    }
    Ok(exit(verdict))
}

/// certify's exit code for a planar verdict: 0 certified, 1 refuted, 3 inconclusive.
pub(super) fn exit(verdict: PlanarVerdict) -> Exit {
    match verdict {
        PlanarVerdict::Certified => Exit::Pass,
        PlanarVerdict::Refuted => Exit::Fail,
        PlanarVerdict::Inconclusive => Exit::Inconclusive,
    }
}

/// A planar analysis error in the user's terms: a problem error as the reader names it
/// (exit 2), anything else after the file's name.
pub(super) fn explain(path: &Path, e: BoundaryError) -> anyhow::Error {
    match e {
        BoundaryError::Problem(p) => p.into(),
        other => anyhow::anyhow!("{}: {other}", path.display()),
    }
}

fn summary(r: &PlanarCertificate) -> String {
    let mut s = format!("{}: {} (planar)\n", r.problem, r.verdict.as_str());
    let lower = down(r.lower_bound, 9);
    s += &match r.upper_bound {
        Some(u) => format!(
            "  worst-case minimum separation s* in [{lower}, {}] m (Euclidean, between the \
             discs, instants inside steps included)\n",
            up(u, 9)
        ),
        None => format!("  worst-case minimum separation s* >= {lower} m (no witness)\n"),
    };
    s += &format!(
        "  proved: s* >= {lower} m from {} second-order cone programs, each bound \
         recomputed from its duals in exact rationals; clearance {} m\n",
        r.programs,
        value(r.clearance)
    );
    s += &format!(
        "  certificate: {} leaves, re-verified without the solver (safereach check)\n",
        r.leaves()
    );
    if r.budget_exhausted {
        s += "  note: the refinement budget ran out; the bound is sound but may be loose\n";
    }
    if r.unsolved_leaves > 0 {
        s += &format!(
            "  note: {} leaves the solver could not bound were given the floor -(r_R + r_i)\n",
            r.unsolved_leaves
        );
    }
    if let Some(w) = &r.witness {
        let brake = match (&w.brake_step, &w.guard) {
            (Some(k), Some(g)) => format!("brakes at step {k} ({g})"),
            _ => "never brakes".to_string(),
        };
        s += &format!(
            "  witness: {} closest at t = {} s; the robot {brake}{}\n",
            w.obstacle,
            value(w.closest_at),
            w.rest
                .map(|t| format!(", rests at t = {} s", value(t)))
                .unwrap_or_default()
        );
    }
    if r.verdict == safereach::proof::verdict::Verdict::Inconclusive {
        s += "  the clearance lies inside the bracket: the relaxation (reductions.md §11) \
              cannot decide it\n";
    }
    s
}
