//! `safereach simulate`: random obstacle behaviours (Monte Carlo), or the replay of a
//! certificate's witness, on the same discrete-time semantics the analyser reasons about.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use safereach::analysis;
use safereach::core::budget::{Budget, Work};
use safereach::core::model::Problem;
use safereach::core::num::Exact;
use safereach::core::output::trace_for_path;
use safereach::core::rational::Rational;
use safereach::core::show::{up, value};
use safereach::core::simulate;
use safereach::proof::certificate::Certificate;
use safereach::proof::certificate_file::CertificateFile;
use serde_json::Value;

use super::exit::Exit;
use super::input::{self, Input, Unreadable};
use super::output::{Output, write_file};
use super::scene_simulate;

/// Arguments of `safereach simulate`, as typed.
#[derive(clap::Args)]
pub struct SimulateArgs {
    /// Problem or scene file (TOML). With --replay it may be left out (the certificate's own
    /// problem is replayed); given, it must be the certificate's problem.
    #[arg(required_unless_present = "replay")]
    problem: Option<PathBuf>,
    /// Override a key (repeatable; not with --replay, which replays the certificate's problem
    /// as it was certified).
    #[arg(long = "set", value_name = "KEY=VALUE", conflicts_with = "replay")]
    sets: Vec<String>,
    /// Number of random runs.
    #[arg(long, default_value_t = 1000, conflicts_with = "replay")]
    pub(super) runs: usize,
    /// Budget: the most control periods the runs may simulate in all, counted as runs times
    /// each run's horizon (default 2,000,000,000, about a minute).
    #[arg(long, value_name = "N", conflicts_with = "replay")]
    pub(super) max_periods: Option<u64>,
    /// Seed of the first run (run i uses seed + i).
    #[arg(long, default_value_t = 0, conflicts_with = "replay")]
    pub(super) seed: u64,
    /// Replay this certificate's witness instead of random runs: the certificate is checked
    /// first (one that fails `check` is refused), and its own problem is replayed.
    #[arg(long, value_name = "CERT")]
    pub(super) replay: Option<PathBuf>,
    /// Write the replayed run (or the random run that came closest): CSV, or JSON Lines for .jsonl.
    #[arg(long, value_name = "FILE")]
    pub(super) trace: Option<PathBuf>,
    /// With --replay of a planar certificate: draw the witness seen from above into this
    /// SVG file.
    #[arg(long, value_name = "FILE.svg", requires = "replay")]
    pub(super) plot: Option<PathBuf>,
    /// Print JSON.
    #[arg(long)]
    pub(super) json: bool,
}

/// Runs `safereach simulate`: exit 0 no collision, 1 a collision.
pub fn run(args: SimulateArgs, out: &mut Output) -> Result<Exit> {
    if let Some(path) = &args.replay {
        return replay_certificate(path, &args, out);
    }
    let path = args
        .problem
        .as_deref()
        .context("a problem file is needed (or --replay CERT)")?;
    if args.runs == 0 {
        anyhow::bail!("--runs must be at least 1");
    }
    let input = input::problem_or_scene(path, &args.sets)?;
    let horizon = match &input {
        Input::Problem(p) => simulate::horizon(&analysis::params_f64(&p.params::<Exact>())),
        Input::Scene(s) => safereach::core::scene::simulate::horizon(&s.params::<f64>()),
        Input::Planar(planar) => {
            if args.trace.is_some() {
                anyhow::bail!("--trace: not written for planar problems yet (issue 36)");
            }
            return super::planar_simulate::random(
                planar, path, args.runs, args.seed, args.json, out,
            );
        }
    };
    let budget = Budget::new(Work::SimulatedPeriods, args.max_periods);
    simulate::runs_within(&budget, args.runs, horizon)
        .with_context(|| format!("{}: --runs {}", path.display(), args.runs))?;
    match input {
        Input::Problem(p) => random(
            &p,
            args.runs,
            args.seed,
            args.trace.as_deref(),
            args.json,
            out,
        ),
        Input::Scene(scene) => scene_simulate::random(&scene, &args, out),
        Input::Planar(_) => unreachable!("planar problems are simulated above"),
    }
}

/// `--replay`: the certificate is read and checked (a certificate that fails `check` is
/// refused: its witness proves nothing), the problem argument, if given, must be the
/// certificate's, and the witness is replayed on the certificate's own problem.
fn replay_certificate(path: &Path, args: &SimulateArgs, out: &mut Output) -> Result<Exit> {
    let cert = input::any_certificate(path, Unreadable::Reading)?;
    if let Err(e) = cert.check() {
        anyhow::bail!(
            "{}: the certificate fails check ({e}); only a valid certificate's witness is \
             replayed",
            path.display()
        );
    }
    if let Some(problem) = &args.problem {
        same_problem(problem, path, &cert)?;
    }
    let trace = args.trace.as_deref();
    match (&cert, &args.plot) {
        (CertificateFile::Planar(c), Some(file)) => {
            super::planar_plot::plot_witness(c, &path.display().to_string(), file)?;
        }
        (_, Some(_)) => anyhow::bail!(
            "--plot draws a planar certificate's witness from above; {} is not one",
            path.display()
        ),
        _ => {}
    }
    match &cert {
        CertificateFile::Single(c) => replay(&c.problem, path, c, trace, args.json, out),
        CertificateFile::Scene(c) => scene_simulate::replay(&c.scene, path, &cert, args, out),
        CertificateFile::Search(c) => scene_simulate::replay(&c.scene, path, &cert, args, out),
        CertificateFile::Planar(c) => {
            super::planar_simulate::replay(c, path, trace, args.json, out)
        }
    }
}

/// Refuses a problem file that is not the certificate's problem, naming the first key
/// that differs.
fn same_problem(problem: &Path, cert_path: &Path, cert: &CertificateFile) -> Result<()> {
    let given = match input::problem_or_scene(problem, &[])? {
        Input::Problem(p) => serde_json::to_value(&p)?,
        Input::Scene(s) => serde_json::to_value(&s)?,
        Input::Planar(p) => {
            return super::planar_simulate::same_problem(&p, problem, cert_path, cert);
        }
    };
    let certified = match cert {
        CertificateFile::Single(c) => serde_json::to_value(&c.problem)?,
        CertificateFile::Scene(c) => serde_json::to_value(&c.scene)?,
        CertificateFile::Search(c) => serde_json::to_value(&c.scene)?,
        CertificateFile::Planar(_) => anyhow::bail!(
            "{}: not the problem of {} (a planar certificate); leave the problem out to \
             replay the certificate's own",
            problem.display(),
            cert_path.display()
        ),
    };
    if let Some((key, here, there)) = first_difference(&given, &certified, String::new()) {
        anyhow::bail!(
            "{}: not the problem of {} ({key} is {here} in the file, {there} in the \
             certificate); leave the problem out to replay the certificate's own",
            problem.display(),
            cert_path.display()
        );
    }
    Ok(())
}

/// The first dotted key at which two JSON values differ, with both values as text ("absent"
/// for a key only one has).
fn first_difference(a: &Value, b: &Value, at: String) -> Option<(String, String, String)> {
    let key = |k: &str| {
        if at.is_empty() {
            k.to_string()
        } else {
            format!("{at}.{k}")
        }
    };
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
            keys.into_iter().find_map(|k| match (x.get(k), y.get(k)) {
                (Some(p), Some(q)) => first_difference(p, q, key(k)),
                (p, q) => {
                    let show = |v: Option<&Value>| v.map_or("absent".into(), Value::to_string);
                    Some((key(k), show(p), show(q)))
                }
            })
        }
        _ if a == b => None,
        _ => Some((
            if at.is_empty() {
                "the problem".into()
            } else {
                at
            },
            a.to_string(),
            b.to_string(),
        )),
    }
}

/// Replays the certificate's witness: the obstacle's speeds, period by period.
fn replay(
    problem: &Problem,
    cert_path: &Path,
    cert: &Certificate,
    trace: Option<&Path>,
    json: bool,
    out: &mut Output,
) -> Result<Exit> {
    let exact = problem.params::<Exact>();
    let witness = cert.witness.as_ref().with_context(|| {
        format!(
            "{}: the certificate has no witness to replay",
            cert_path.display()
        )
    })?;
    // Period by period only for a trace to write; else the replay leaps (same run).
    let replay = simulate::replay_segments(
        &exact,
        witness.obstacle_speeds.segments(),
        None,
        witness.aim(),
        witness.obstacle_speeds.len(),
        false,
        trace.is_some(),
    );
    if let Some(path) = trace {
        let rows = replay.trace();
        write_file(path, trace_for_path(path, &rows, "0").as_bytes())?;
    }
    let sep = replay.rest_gap().map(|g| g.to_f64().value());
    if json {
        writeln!(
            out,
            "{}",
            serde_json::json!({"replay": cert_path, "collided": replay.collided(), "separation": sep, "steps": replay.run.trace_rows()})
        )?;
    } else {
        writeln!(
            out,
            "replayed {}: {} periods, {}, separation at rest {}",
            cert_path.display(),
            replay.periods(),
            if replay.collided() {
                "COLLISION"
            } else {
                "no collision"
            },
            sep.map(|s| format!("{} m", value(s)))
                .unwrap_or_else(|| "- (never stopped)".into())
        )?;
    }
    Ok(Exit::fail_if(replay.collided()))
}

/// `runs` random runs; the trace written is the run that came closest.
fn random(
    problem: &Problem,
    runs: usize,
    seed: u64,
    trace: Option<&Path>,
    json: bool,
    out: &mut Output,
) -> Result<Exit> {
    // Exact numbers: every guard decides as a replay does (see analysis::monte_carlo).
    let exact = problem.params::<Rational>();
    let mc = analysis::monte_carlo(&exact, runs, seed);
    if let Some(path) = trace {
        let max = simulate::horizon(&analysis::params_f64(&problem.params::<Exact>()));
        let run = analysis::monte_carlo_run(&exact, seed, mc.closest_run, max, false);
        let rows = simulate::trace(&exact, &run);
        write_file(path, trace_for_path(path, &rows, "0").as_bytes())?;
    }
    if json {
        writeln!(out, "{}", serde_json::to_string(&mc)?)?;
    } else {
        // The least separation seen is an upper bound on s*: shown rounded up.
        writeln!(
            out,
            "{}: {} runs (seed {}), {} collisions, minimum separation seen {} m (run {})",
            problem.name,
            mc.runs,
            mc.seed,
            mc.collisions,
            up(mc.min_separation, 6),
            mc.closest_run
        )?;
    }
    Ok(Exit::fail_if(mc.collisions > 0))
}
