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

use safereach::analysis::planar::{PlanarBoundary, PlanarProbe, Safer, planar_boundary};
use safereach::core::planar::PlanarProblem;
use safereach::core::show::{down, up, value};
use safereach::core::text_file;

use super::exit::Exit;
use super::output::{Output, create_dir, write_file};
use super::planar_certify::explain;

/// Radii and speeds are searched to this (m, m/s).
const RESOLUTION: f64 = 1e-3;

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

/// The `obstacle.N.max_speed` keys of the moving obstacles `name` selects (all: None).
fn speed_keys(problem: &PlanarProblem, name: Option<&str>, flag: &str) -> Result<Vec<String>> {
    if let Some(n) = name
        && !problem.obstacles.iter().any(|o| o.name == n)
    {
        anyhow::bail!("--obstacle {n}: the problem has no such obstacle");
    }
    let keys: Vec<String> = problem
        .obstacles
        .iter()
        .enumerate()
        .filter(|(_, o)| name.map_or(o.max_speed > 0.0, |n| o.name == n))
        .map(|(i, _)| format!("obstacle.{i}.max_speed"))
        .collect();
    anyhow::ensure!(
        !keys.is_empty(),
        "{flag}: the problem has no moving obstacle"
    );
    Ok(keys)
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

/// One search, shown as it goes.
fn search(
    text: &str,
    path: &Path,
    sets: &[String],
    keys: &[String],
    interval: (f64, f64),
    safer: Safer,
    what: &str,
) -> Result<PlanarBoundary> {
    let bar = progress(what);
    let found = planar_boundary(
        text,
        &path.display().to_string(),
        sets,
        keys,
        interval,
        RESOLUTION,
        safer,
        |p| bar.set_message(format!("{} at {}", p.verdict.as_str(), value(p.value))),
    )
    .map_err(|e| explain(path, e));
    bar.finish_and_clear();
    found
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
    let hi = base
        .sensing
        .range
        .unwrap_or(4.0 * base.controller.reaction_radius);
    let key = vec!["controller.reaction_radius".to_string()];
    let speeds: Vec<Option<f64>> = if speeds.is_empty() {
        vec![None]
    } else {
        speeds.iter().map(|&w| Some(w)).collect()
    };
    let mut reports = Vec::new();
    let mut all = true;
    for w in &speeds {
        let mut probe_sets = sets.to_vec();
        if let Some(w) = w {
            let keys = speed_keys(&base, obstacle, "--speeds")?;
            probe_sets.extend(keys.iter().map(|k| format!("{k}={w}")));
        }
        let b = search(
            &text,
            path,
            &probe_sets,
            &key,
            (RESOLUTION, hi),
            Safer::Larger,
            "planar radius",
        )?;
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
    let keys = speed_keys(&base, obstacle, "max-speed")?;
    let w = base
        .obstacles
        .iter()
        .filter(|o| obstacle.is_none_or(|n| o.name == n))
        .map(|o| o.max_speed)
        .fold(0.0, f64::max);
    let hi = if w > 0.0 { 4.0 * w } else { 10.0 };
    let b = search(
        &text,
        path,
        sets,
        &keys,
        (0.0, hi),
        Safer::Smaller,
        "planar max-speed",
    )?;
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
