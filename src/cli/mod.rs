//! The `safereach` command: a thin shell over the library.
//!
//! Exit codes: `certify` 0 certified, 1 refuted, 3 inconclusive; `check` 0 valid,
//! 1 invalid; `simulate` 0 no collision, 1 a collision; 2 always means bad input or an
//! internal error.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};

use safereach::analysis::{self, Verdict};
use safereach::core::model::Problem;
use safereach::core::output::{trace_for_path, write_atomic};
use safereach::core::simulate;
use safereach::proof::certificate::{self, Certificate};

/// `println!` that reports a failed write (a closed pipe) as an error instead of panicking.
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout(), $($arg)*)?
    }};
}

/// `print!` that reports a failed write as an error instead of panicking.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        write!(std::io::stdout(), $($arg)*)?
    }};
}

mod explore;
mod monitor;
mod radius;
mod sweep;

#[derive(Parser)]
#[command(
    name = "safereach",
    version,
    about = "Certify or refute passive safety of a mobile robot against oncoming obstacles"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Certify or refute passive safety for a problem file (exit 0 certified, 1 refuted, 3 inconclusive).
    Certify {
        /// Problem file (TOML).
        problem: PathBuf,
        /// Override a key, e.g. `environment.obstacle_speed=0.25` (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
        /// Print the certificate as JSON instead of a summary.
        #[arg(long)]
        json: bool,
        /// Write the certificate to this file (atomically).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Re-verify a certificate in exact arithmetic, without the solver (exit 0 valid, 1 invalid).
    Check {
        /// Certificate file (JSON).
        certificate: PathBuf,
    },
    /// Simulate random obstacle behaviours, or replay a certificate's witness.
    Simulate {
        /// Problem file (TOML).
        problem: PathBuf,
        /// Override a key (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
        /// Number of random runs.
        #[arg(long, default_value_t = 1000)]
        runs: usize,
        /// Seed of the first run (run i uses seed + i).
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Replay this certificate's witness instead of random runs.
        #[arg(long, value_name = "CERT")]
        replay: Option<PathBuf>,
        /// Write the replayed run (or the random run that came closest): CSV, or JSON Lines for .jsonl.
        #[arg(long, value_name = "FILE")]
        trace: Option<PathBuf>,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// The smallest certified reaction radius for the obstacle speed bound (exit 1 if none).
    Radius(radius::RadiusArgs),
    /// The largest certified obstacle speed bound for the reaction radius (exit 1 if none).
    MaxSpeed(radius::MaxSpeedArgs),
    /// Analyse a grid of problems in parallel (JSON Lines + CSV into --out).
    Sweep(sweep::SweepArgs),
    /// Regenerate reports (Markdown + SVG) from grids, or merge sweep shards into them.
    Report(sweep::ReportArgs),
    /// Check live traces against a certificate's premises (exit 0 held, 1 violated, 2 unusable certificate or I/O error).
    Monitor(monitor::MonitorArgs),
    /// Exhaustive breadth-first exploration of the finite model (obstacle speeds from a finite set).
    Explore(explore::ExploreArgs),
    /// Export the finite model as UPPAAL timed automata (XML) plus the safety query (.q).
    ExportUppaal(explore::ExportUppaalArgs),
}

/// Parses the command line and runs the subcommand.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(code) => code,
        // The reader went away (`safereach certify --json | head`): stop quietly, as a
        // program killed by SIGPIPE would (status 128 + 13).
        Err(e)
            if e.chain().any(|c| {
                c.downcast_ref::<std::io::Error>()
                    .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
            }) =>
        {
            ExitCode::from(141)
        }
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn run(cli: Cli) -> Result<ExitCode> {
    match cli.command {
        Command::Certify {
            problem,
            sets,
            json,
            out,
        } => certify(&problem, &sets, json, out.as_deref()),
        Command::Check { certificate } => check(&certificate),
        Command::Simulate {
            problem,
            sets,
            runs,
            seed,
            replay,
            trace,
            json,
        } => simulate_cmd(
            &problem,
            &sets,
            runs,
            seed,
            replay.as_deref(),
            trace.as_deref(),
            json,
        ),
        Command::Radius(args) => radius::run(args),
        Command::MaxSpeed(args) => radius::max_speed(args),
        Command::Sweep(args) => sweep::run(args),
        Command::Report(args) => sweep::report_cmd(args),
        Command::Monitor(args) => monitor::run(args),
        Command::Explore(args) => explore::run(args),
        Command::ExportUppaal(args) => explore::export_uppaal(args),
    }
}

fn load(problem: &Path, sets: &[String]) -> Result<Problem> {
    Ok(Problem::load_with_overrides(problem, sets)?)
}

fn certify(problem: &Path, sets: &[String], json: bool, out: Option<&Path>) -> Result<ExitCode> {
    let problem = load(problem, sets)?;
    let analysis = analysis::analyse(&problem).context("analysis failed")?;
    let cert = Certificate::from_analysis(&analysis);
    // Never print a verdict the exact checker would not accept.
    certificate::check(&cert)
        .map_err(|e| anyhow::anyhow!("internal error: the certificate does not verify: {e}"))?;
    let text = serde_json::to_string_pretty(&cert)? + "\n";
    if let Some(path) = out {
        write_atomic(path, text.as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
    }
    if json {
        out!("{text}");
    } else {
        out!("{}", summary(&cert));
    }
    Ok(ExitCode::from(match cert.verdict {
        Verdict::Certified => 0,
        Verdict::Refuted => 1,
        Verdict::Inconclusive => 3,
    }))
}

fn summary(cert: &Certificate) -> String {
    let mut s = format!("{}: {}\n", cert.problem.name, cert.verdict.as_str());
    let sep = match (cert.min_separation, cert.never_stops) {
        (_, true) => "-inf (the robot can miss the obstacle entirely and never brake)".to_string(),
        (Some(x), _) => format!("{x:.6} m"),
        (None, _) => "unknown (no worst case could be realised)".to_string(),
    };
    s += &format!("  worst-case minimum separation s* = {sep}\n");
    match cert.lower_bound {
        Some(lb) => {
            s += &format!(
                "  rigorous lower bound {lb:.9} m vs clearance {} m\n",
                cert.clearance
            )
        }
        None => s += "  no finite lower bound proved\n",
    }
    if let Some(w) = &cert.witness {
        let brake = w
            .steps
            .iter()
            .find(|r| r.robot_mode == safereach::core::semantics::Mode::Brake);
        let last = w.steps.last();
        s += &format!(
            "  worst case: {}{}{}\n",
            if w.collides {
                "collides"
            } else {
                "closest approach"
            },
            brake
                .map(|b| format!(", robot brakes at t = {:.3} s", b.t))
                .unwrap_or_default(),
            last.map(|l| format!(", ends at t = {:.3} s with gap {:.6} m", l.t, l.gap))
                .unwrap_or_default(),
        );
    }
    s += &format!(
        "  pieces: {} ({} linear programs solved)\n",
        cert.pieces, cert.programs_solved
    );
    s += "  premises:\n";
    for p in &cert.premises {
        s += &format!(
            "    {:<21} {} {} {}\n",
            p.name,
            p.description(),
            p.bound,
            p.unit()
        );
    }
    s
}

fn read_certificate(path: &Path) -> Result<Certificate> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    serde_json::from_str(&text)
        .with_context(|| format!("{}: not a safereach certificate", path.display()))
}

fn check(path: &Path) -> Result<ExitCode> {
    let cert = read_certificate(path)?;
    match certificate::check(&cert) {
        Ok(report) => {
            outln!(
                "{}: valid; verdict {} re-verified in exact arithmetic over {} pieces",
                path.display(),
                report.verdict.as_str(),
                report.pieces
            );
            Ok(ExitCode::SUCCESS)
        }
        Err(e) => {
            outln!("{}: INVALID: {e}", path.display());
            Ok(ExitCode::from(1))
        }
    }
}

fn simulate_cmd(
    problem: &Path,
    sets: &[String],
    runs: usize,
    seed: u64,
    replay: Option<&Path>,
    trace: Option<&Path>,
    json: bool,
) -> Result<ExitCode> {
    let problem = load(problem, sets)?;
    let exact = problem.params::<safereach::core::num::Exact>();
    let floats = analysis::params_f64(&exact);
    if let Some(cert_path) = replay {
        let cert = read_certificate(cert_path)?;
        let witness = cert.witness.as_ref().with_context(|| {
            format!(
                "{}: the certificate has no witness to replay",
                cert_path.display()
            )
        })?;
        let replay = simulate::replay(
            &exact,
            &witness.obstacle_speeds,
            witness.obstacle_speeds.len(),
            false,
        );
        let rows = replay.trace();
        if let Some(path) = trace {
            write_atomic(path, trace_for_path(path, &rows, "0").as_bytes())
                .with_context(|| format!("writing {}", path.display()))?;
        }
        let sep = replay.rest_gap().map(|g| g.to_f64().value());
        if json {
            outln!(
                "{}",
                serde_json::json!({"replay": cert_path, "collided": replay.collided(), "separation": sep, "steps": rows.len()})
            );
        } else {
            outln!(
                "replayed {}: {} periods, {}, separation at rest {}",
                cert_path.display(),
                replay.periods(),
                if replay.collided() {
                    "COLLISION"
                } else {
                    "no collision"
                },
                sep.map(|s| format!("{s:.9} m"))
                    .unwrap_or_else(|| "- (never stopped)".into())
            );
        }
        return Ok(ExitCode::from(u8::from(replay.collided())));
    }
    if runs == 0 {
        anyhow::bail!("--runs must be at least 1");
    }
    let mc = analysis::monte_carlo(&floats, runs, seed);
    if let Some(path) = trace {
        let max = simulate::horizon(&floats);
        let run = simulate::run(
            floats.clone(),
            analysis::random_speeds(floats.W, seed, mc.closest_run),
            max,
            false,
        );
        let rows = simulate::trace(&floats, &run);
        write_atomic(path, trace_for_path(path, &rows, "0").as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
    }
    if json {
        outln!("{}", serde_json::to_string(&mc)?);
    } else {
        outln!(
            "{}: {} runs (seed {}), {} collisions, minimum separation seen {:.6} m (run {})",
            problem.name,
            mc.runs,
            mc.seed,
            mc.collisions,
            mc.min_separation,
            mc.closest_run
        );
    }
    Ok(ExitCode::from(u8::from(mc.collisions > 0)))
}
