//! `safereach radius` and `max-speed` on a planar problem (docs/semantics.md §13): where
//! certification ends along the reaction radius or an obstacle speed bound, by bisection
//! with one planar `certify` per probe (`analysis::planar::planar_boundary`). The value
//! claimed is the certified probe's, whose certificate `check` re-verifies; the nearest
//! uncertified probe is named with its verdict.

use std::io::{IsTerminal, Write};
use std::path::Path;

use anyhow::Result;
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;

use safereach::analysis::planar::{
    KnobError, PlanarBoundary, PlanarProbe, RESOLUTION, max_speed_search, safe_radius_search,
};
use safereach::core::planar::PlanarProblem;
use safereach::core::show::{down, up, value};
use safereach::core::text_file;

use super::exit::Exit;
use super::output::{Output, create_dir, write_file};
use super::planar_certify::explain;

/// One search as `--json` prints it.
#[derive(Serialize)]
struct BoundaryReport {
    problem: String,
    /// `reaction_radius` or `max_speed`.
    parameter: &'static str,
    /// The keys set to each probe's value.
    keys: Vec<String>,
    /// The overrides every probe has (`--set`, `--speeds`).
    sets: Vec<String>,
    /// The claimed value: the certified probe's (null: none in the interval).
    value: Option<f64>,
    certified: Option<ProbeReport>,
    uncertified: Option<ProbeReport>,
    resolution: f64,
    probes: usize,
}

#[derive(Serialize)]
struct ProbeReport {
    value: f64,
    verdict: &'static str,
    lower_bound: f64,
    upper_bound: Option<f64>,
}

fn probe_report(p: &PlanarProbe) -> ProbeReport {
    ProbeReport {
        value: p.value,
        verdict: p.verdict.as_str(),
        lower_bound: p.certificate.lower_bound,
        upper_bound: p.certificate.upper_bound,
    }
}

/// The problem file's text and the problem it states with `sets`.
fn read(path: &Path, sets: &[String]) -> Result<(String, PlanarProblem)> {
    let text = text_file::read_text(path, text_file::MAX_PROBLEM_BYTES)
        .map_err(|e| anyhow::anyhow!("reading {}: {e}", path.display()))?;
    let problem =
        PlanarProblem::from_toml_str_with_overrides(&text, &path.display().to_string(), sets)?;
    Ok((text, problem))
}

fn progress(what: &str) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new_spinner();
    bar.set_style(
        ProgressStyle::with_template(&format!("{{elapsed_precise}} {what}: {{msg}}"))
            .expect("static template"),
    );
    bar
}

/// The error of a search, in the user's terms: a bad request or problem as itself, else
/// naming the file.
fn knob_error(path: &Path, e: KnobError) -> anyhow::Error {
    match e {
        KnobError::Input(why) => anyhow::anyhow!("{why}"),
        KnobError::Probe(e) => explain(path, e),
    }
}

/// What the spinner says after each probe.
fn shown(bar: &ProgressBar) -> impl FnMut(&PlanarProbe) + '_ {
    |p| bar.set_message(format!("{} at {}", p.verdict.as_str(), value(p.value)))
}

fn report(
    problem: &PlanarProblem,
    parameter: &'static str,
    sets: &[String],
    b: &PlanarBoundary,
) -> BoundaryReport {
    BoundaryReport {
        problem: problem.name.clone(),
        parameter,
        keys: b.keys.clone(),
        sets: sets.to_vec(),
        value: b.certified.as_ref().map(|p| p.value),
        certified: b.certified.as_ref().map(probe_report),
        uncertified: b.uncertified.as_ref().map(probe_report),
        resolution: RESOLUTION,
        probes: b.probes,
    }
}

fn describe(r: &BoundaryReport, name: &str, unit: &str) -> String {
    let bracket = |p: &ProbeReport| match p.upper_bound {
        Some(u) => format!("s* in [{}, {}] m", down(p.lower_bound, 9), up(u, 9)),
        None => format!("s* >= {} m", down(p.lower_bound, 9)),
    };
    let mut s = match &r.certified {
        Some(c) => format!(
            "{name} {} {unit} (certified, {}",
            value(c.value),
            bracket(c)
        ),
        None => format!("no certified {name} in the searched interval ("),
    };
    if let Some(u) = &r.uncertified {
        if r.certified.is_some() {
            s += "; ";
        }
        s += &format!(
            "at {} {unit}: {}, {}",
            value(u.value),
            u.verdict,
            bracket(u)
        );
    }
    s + &format!("; {} planar certifications)", r.probes)
}

/// `radius` on a planar problem: per speed bound, the smallest certified reaction radius in
/// [10⁻³ m, the sensing range] (4ρ without a range).
pub fn radius(
    path: &Path,
    sets: &[String],
    speeds: &[f64],
    obstacle: Option<&str>,
    certificates: Option<&Path>,
    json: bool,
    out: &mut Output,
) -> Result<Exit> {
    let (text, base) = read(path, sets)?;
    let origin = path.display().to_string();
    let speeds: Vec<Option<f64>> = if speeds.is_empty() {
        vec![None]
    } else {
        speeds.iter().map(|&w| Some(w)).collect()
    };
    let mut reports = Vec::new();
    let mut all = true;
    for w in &speeds {
        let bar = progress("planar radius");
        let found = safe_radius_search(
            &text,
            &origin,
            sets,
            &base,
            w.map(|w| (w, obstacle)),
            shown(&bar),
        );
        bar.finish_and_clear();
        let (probe_sets, b) = found.map_err(|e| knob_error(path, e))?;
        all &= b.certified.is_some();
        if let (Some(dir), Some(c)) = (certificates, &b.certified) {
            create_dir(dir)?;
            let label = w.map_or("file".to_string(), |w| w.to_string());
            let json = serde_json::to_string_pretty(&c.certificate)? + "\n";
            write_file(&dir.join(format!("radius-W{label}.json")), json.as_bytes())?;
        }
        let r = report(&base, "reaction_radius", &probe_sets, &b);
        if !json {
            let given = match w {
                Some(w) => format!("W = {} m/s", value(*w)),
                None => "the file's speed bounds".to_string(),
            };
            writeln!(
                out,
                "{} (planar), {given}: {}",
                base.name,
                describe(&r, "safe radius", "m")
            )?;
        }
        reports.push(r);
    }
    if json {
        let text = if reports.len() == 1 {
            serde_json::to_string_pretty(&reports[0])?
        } else {
            serde_json::to_string_pretty(&reports)?
        };
        writeln!(out, "{text}")?;
    }
    Ok(if all { Exit::Pass } else { Exit::Fail })
}

/// `max-speed` on a planar problem: the largest certified speed bound in [0, 4 W] (W the
/// largest of the searched obstacles' bounds; 10 m/s when all are 0), given to every moving
/// obstacle together or to the one `--obstacle` names.
pub fn max_speed(
    path: &Path,
    sets: &[String],
    obstacle: Option<&str>,
    out_file: Option<&Path>,
    json: bool,
    out: &mut Output,
) -> Result<Exit> {
    let (text, base) = read(path, sets)?;
    let bar = progress("planar max-speed");
    let found = max_speed_search(
        &text,
        &path.display().to_string(),
        sets,
        &base,
        obstacle,
        shown(&bar),
    );
    bar.finish_and_clear();
    let b = found.map_err(|e| knob_error(path, e))?;
    if let (Some(file), Some(c)) = (out_file, &b.certified) {
        let json = serde_json::to_string_pretty(&c.certificate)? + "\n";
        write_file(file, json.as_bytes())?;
    }
    let r = report(&base, "max_speed", sets, &b);
    if json {
        writeln!(out, "{}", serde_json::to_string_pretty(&r)?)?;
    } else {
        writeln!(
            out,
            "{} (planar), rho = {} m: {}",
            base.name,
            value(base.controller.reaction_radius),
            describe(&r, "max obstacle speed", "m/s")
        )?;
    }
    Ok(if b.certified.is_some() {
        Exit::Pass
    } else {
        Exit::Fail
    })
}
