//! `safereach simulate` on a scene: random behaviours of every obstacle (Monte Carlo), or
//! the replay of a scene certificate's witness, through the scene's step function.

use safereach::proof::exact_speed_runs::exact_speeds_from_segments;
use std::io::Write;

use anyhow::{Context, Result};

use safereach::analysis::{SpeedPattern, scene_monte_carlo, scene_monte_carlo_run};
use safereach::core::num::Exact;
use safereach::core::output::scene_trace_for_path;
use safereach::core::rational::Rational;
use safereach::core::scene::{Scene, simulate};
use safereach::core::show::{up, value};
use safereach::proof::certificate_file::CertificateFile;
use safereach::proof::search_certificate::{exact_from_text, witness_starts};

use super::exit::Exit;
use super::output::{Output, write_file};
use super::simulate::SimulateArgs;

/// Replays a scene certificate's witness (checked by the caller) on its scene: every
/// obstacle's speeds, period by period.
pub fn replay(
    scene: &Scene,
    path: &std::path::Path,
    cert: &CertificateFile,
    args: &SimulateArgs,
    out: &mut Output,
) -> Result<Exit> {
    let no_witness = || {
        format!(
            "{}: the certificate has no witness to replay",
            path.display()
        )
    };
    let params = scene.params::<Exact>();
    let (speeds, starts, obstacle) = match cert {
        CertificateFile::Single(_) => anyhow::bail!(
            "{}: a single-obstacle certificate, not a scene's",
            path.display(),
        ),
        CertificateFile::Planar(_) => {
            anyhow::bail!("{}: a planar certificate, not a scene's", path.display(),)
        }
        CertificateFile::Scene(cert) => {
            let w = cert.witness.as_ref().with_context(no_witness)?;
            let starts: Vec<Exact> = params
                .obstacles
                .iter()
                .map(|o| o.start_min.clone())
                .collect();
            (
                Speeds::Floats(w.obstacle_speeds.iter().map(|s| s.to_vec()).collect()),
                starts,
                w.obstacle,
            )
        }
        CertificateFile::Search(cert) => {
            let w = cert.witness.as_ref().with_context(no_witness)?;
            let exact = |t: &String| {
                exact_from_text(t)
                    .with_context(|| format!("{}: {t:?} is not an exact number", path.display()))
            };
            let starts = w
                .starts
                .iter()
                .map(|s| s.as_ref().map(exact).transpose())
                .collect::<Result<Vec<_>>>()?;
            if starts.len() != scene.obstacles.len() {
                anyhow::bail!(
                    "{}: the witness has starts for {} obstacles, the scene has {}",
                    path.display(),
                    starts.len(),
                    scene.obstacles.len()
                );
            }
            let speeds = w
                .obstacle_speeds
                .iter()
                .map(|segments| {
                    exact_speeds_from_segments(segments, exact_from_text)
                        .map_err(|e| anyhow::anyhow!("{}: witness speeds: {e}", path.display()))
                })
                .collect::<Result<Vec<_>>>()?;
            (
                Speeds::Exact(speeds),
                witness_starts(scene, &starts),
                w.obstacle,
            )
        }
    };
    if speeds.len() != scene.obstacles.len() {
        anyhow::bail!(
            "{}: the witness has speeds for {} obstacles, the scene has {}",
            path.display(),
            speeds.len(),
            scene.obstacles.len()
        );
    }
    let periods = speeds.periods();
    let replay = match &speeds {
        Speeds::Floats(f) => simulate::replay(&params, f, &starts, periods, false),
        Speeds::Exact(e) => simulate::replay_exact_speeds(&params, e, &starts, periods, false),
    };
    let rows = replay.trace();
    if let Some(trace) = &args.trace {
        write_file(trace, scene_trace_for_path(trace, &rows).as_bytes())?;
    }
    let seps = replay.separations();
    let worst = &scene.obstacles[obstacle].name;
    let sep = seps[obstacle].as_ref().map(|g| g.to_f64().value());
    if args.json {
        writeln!(
            out,
            "{}",
            serde_json::json!({"replay": path, "collided": replay.collided(), "obstacle": worst, "separation": sep, "steps": rows.len()})
        )?;
    } else {
        writeln!(
            out,
            "replayed {}: {} periods, {}, separation of \"{worst}\" {}",
            path.display(),
            replay.periods(),
            if replay.collided() {
                "COLLISION"
            } else {
                "no collision"
            },
            sep.map(|s| format!("{} m", value(s)))
                .unwrap_or_else(|| "- (never in its lane while moving)".into())
        )?;
    }
    Ok(Exit::fail_if(replay.collided()))
}

/// Random runs; the trace written is the run that came closest.
pub fn random(scene: &Scene, args: &SimulateArgs, out: &mut Output) -> Result<Exit> {
    // Exact numbers: every guard decides as a replay does (see analysis::scene_monte_carlo).
    let params = scene.params::<Rational>();
    let patterns = SpeedPattern::ALL;
    let mc = scene_monte_carlo(&params, args.runs, args.seed, &patterns);
    if let Some(trace) = &args.trace {
        let run = scene_monte_carlo_run(
            &params,
            args.seed,
            mc.closest_run,
            &patterns,
            simulate::horizon(&scene.params::<f64>()),
            false,
        );
        let rows = simulate::trace(&params, &run);
        write_file(trace, scene_trace_for_path(trace, &rows).as_bytes())?;
    }
    if args.json {
        writeln!(out, "{}", serde_json::to_string(&mc)?)?;
    } else {
        let closest = match (&mc.min_separation, &mc.closest_obstacle) {
            (Some(s), Some(o)) => format!("{} m to \"{o}\" (run {})", up(*s, 6), mc.closest_run),
            _ => "- (no obstacle shared a lane with the moving robot)".into(),
        };
        writeln!(
            out,
            "{}: {} runs (seed {}), {} collisions, minimum separation seen {closest}",
            scene.name, mc.runs, mc.seed, mc.collisions
        )?;
    }
    Ok(Exit::fail_if(mc.collisions > 0))
}

/// A witness's speeds: floats (scene certificates) or exact numbers (search certificates).
enum Speeds {
    Floats(Vec<Vec<f64>>),
    Exact(Vec<Vec<Exact>>),
}

impl Speeds {
    fn len(&self) -> usize {
        match self {
            Speeds::Floats(f) => f.len(),
            Speeds::Exact(e) => e.len(),
        }
    }

    fn periods(&self) -> usize {
        match self {
            Speeds::Floats(f) => f.iter().map(Vec::len).max().unwrap_or(0),
            Speeds::Exact(e) => e.iter().map(Vec::len).max().unwrap_or(0),
        }
    }
}
