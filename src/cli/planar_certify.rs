//! `safereach certify` on a planar problem: the verdict, the bracket on s*, the witness and
//! the certificate (docs/semantics.md §13). The lower end is proved from the SOC duals in
//! exact rationals; the upper end is a behaviour's exact replay; the certificate is checked
//! by `proof::planar::check` before anything is printed, as `check` would.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Result;

use safereach::analysis::planar::{
    BoundOptions, LowerBoundError, PlanarVerdict, ProblemText, certify_planar, planar_certificate,
};
use safereach::core::planar::PlanarProblem;
use safereach::core::show::{down, up, value};
use safereach::core::text_file;
use safereach::proof::certificate_file::CertificateFile;
use safereach::proof::planar::certificate::PlanarCertificate;
use safereach::proof::planar::domain::DomainError;

use super::exit::Exit;
use super::output::{Output, write_file};

/// The bracket the planar s* is refined to where the relaxation allows (issue 36: 1e-6).
const TOLERANCE: f64 = 1e-6;

/// Certifies the planar problem read from `path` with the overrides `sets`.
pub fn run(
    path: &Path,
    sets: &[String],
    out_path: &Option<PathBuf>,
    json: bool,
    out: &mut Output,
) -> Result<Exit> {
    // The certificate stores the text it was read from, so `check` reads the same problem.
    let text = text_file::read_text(path, text_file::MAX_PROBLEM_BYTES)
        .map_err(|e| anyhow::anyhow!("reading {}: {e}", path.display()))?;
    let problem =
        PlanarProblem::from_toml_str_with_overrides(&text, &path.display().to_string(), sets)?;
    let params = problem.params();
    let tolerance = safereach::core::num::exact_decimal(TOLERANCE);
    let options = BoundOptions::default();
    let answer = certify_planar(&params, &options, &tolerance).map_err(|e| explain(path, e))?;
    let stored = ProblemText {
        toml: &text,
        overrides: sets,
    };
    let cert = planar_certificate(
        &stored,
        &problem.name,
        &params,
        &answer,
        &options,
        TOLERANCE,
    );
    let cert = CertificateFile::Planar(Box::new(cert));
    // Never print a verdict the exact checker would not accept.
    cert.check()
        .map_err(|e| anyhow::anyhow!("internal error: the certificate does not verify: {e}"))?;
    let text = cert.to_json();
    if let Some(p) = out_path {
        write_file(p, text.as_bytes())?;
    }
    let CertificateFile::Planar(c) = &cert else {
        unreachable!("built above")
    };
    if json {
        write!(out, "{text}")?;
    } else {
        write!(out, "{}", summary(c))?;
    }
    Ok(match answer.verdict {
        PlanarVerdict::Certified => Exit::Pass,
        PlanarVerdict::Refuted => Exit::Fail,
        PlanarVerdict::Inconclusive => Exit::Inconclusive,
    })
}

fn explain(path: &Path, e: LowerBoundError) -> anyhow::Error {
    let why = match e {
        LowerBoundError::Domain(DomainError::Unsupported(key)) => {
            format!("{key} is not analysed by the planar engine yet (issue 36)")
        }
        LowerBoundError::Domain(DomainError::Unbounded) => "the path has no end and an \
            obstacle can keep up with the robot without a bounded region: no finite horizon \
            (give the robot a path that ends, or the obstacle a region)"
            .to_string(),
    };
    anyhow::anyhow!("{}: {why}", path.display())
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
