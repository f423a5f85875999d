//! `safereach certify`: the verdict for one problem, with the certificate that proves it.
//!
//! The certificate is checked in exact arithmetic before anything is printed, so the command
//! never reports a verdict the checker would not accept.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result};

use safereach::analysis;
use safereach::core::semantics::Mode;
use safereach::core::show::{down, up, value};
use safereach::core::simulate;
use safereach::proof::certificate::{self, Certificate, Premise};

use super::exit::Exit;
use super::input::{self, Input};
use super::output::{Output, write_file};
use super::scene_certify;

/// Arguments of `safereach certify`.
#[derive(clap::Args)]
pub struct CertifyArgs {
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
    pub(super) out: Option<PathBuf>,
    /// Also store the witness's state at every control period (`witness.steps`); without
    /// it the witness is its speed and mode segments, whose size does not grow with the
    /// horizon (a run search's witness keeps its exact speeds per period for now).
    #[arg(long)]
    steps: bool,
    /// For a planar problem: draw the worst case seen from above into this SVG file.
    #[arg(long, value_name = "FILE.svg")]
    plot: Option<PathBuf>,
}

/// Runs `safereach certify`: exit 0 certified, 1 refuted, 3 inconclusive.
pub fn run(args: CertifyArgs, out: &mut Output) -> Result<Exit> {
    let problem = match input::problem_or_scene(&args.problem, &args.sets)? {
        Input::Problem(p) => p,
        Input::Scene(scene) => {
            return scene_certify::run(&scene, &args.out, args.json, args.steps, out);
        }
        Input::Planar(_) => {
            // Read again from its text, which the certificate stores.
            return super::planar_certify::run(
                &args.problem,
                &args.sets,
                (&args.out, &args.plot),
                args.json,
                out,
            );
        }
    };
    if args.plot.is_some() {
        anyhow::bail!(
            "--plot draws a planar problem's worst case from above; {} is not a planar problem",
            args.problem.display()
        );
    }
    let analysis = analysis::analyse(&problem).context("analysis failed")?;
    let cert = if args.steps {
        Certificate::from_analysis_with_steps(&analysis)
    } else {
        Certificate::from_analysis(&analysis)
    };
    // Never print a verdict the exact checker would not accept.
    certificate::check(&cert)
        .map_err(|e| anyhow::anyhow!("internal error: the certificate does not verify: {e}"))?;
    let text = serde_json::to_string_pretty(&cert)? + "\n";
    if let Some(path) = &args.out {
        write_file(path, text.as_bytes())?;
    }
    if args.json {
        write!(out, "{text}")?;
    } else {
        write!(out, "{}", summary(&cert, witness_times(&analysis)))?;
    }
    Ok(cert.verdict.into())
}

/// When the witness's robot brakes and when its trace ends (s), as its rows show them.
#[derive(Clone, Copy, Default)]
struct WitnessTimes {
    brake: Option<f64>,
    end: Option<f64>,
}

/// The witness's [`WitnessTimes`], from its exact replay (without rows per period).
fn witness_times(analysis: &analysis::Analysis) -> WitnessTimes {
    let Some(w) = &analysis.witness else {
        return WitnessTimes::default();
    };
    let replay = simulate::replay_segments(
        &analysis.decomposition.params,
        w.obstacle_speeds.segments(),
        None,
        w.aim(),
        w.obstacle_speeds.len(),
        false,
        false,
    );
    let brake = replay.run.modes.iter().find(|m| m.mode == Mode::Brake);
    WitnessTimes {
        brake: brake.map(|m| replay.period_start(m.start)),
        end: replay.end_time(),
    }
}

/// The human-readable answer: verdict, worst case, bound and premises. Bounds are shown
/// rounded in their own direction, times and values without float noise
/// ([`safereach::core::show`]).
fn summary(cert: &Certificate, times: WitnessTimes) -> String {
    let mut s = format!("{}: {}\n", cert.problem.name, cert.verdict.as_str());
    let witness_sep = cert.witness.as_ref().and_then(|w| w.separation);
    s += &format!(
        "  worst-case minimum separation s* = {}\n",
        s_star_text(
            cert.min_separation,
            cert.never_stops,
            cert.lower_bound,
            witness_sep,
            "-inf (the robot can miss the obstacle entirely and never brake)",
        )
    );
    s += &lower_bound_text(cert.lower_bound, cert.clearance);
    if let Some(w) = &cert.witness {
        let end = match (times.end, w.separation) {
            (Some(l), Some(r)) => format!(", ends at t = {} s with gap {} m", value(l), up(r, 9)),
            (Some(l), None) => format!(", ends at t = {} s still moving", value(l)),
            (None, _) => String::new(),
        };
        s += &format!(
            "  {}: {}{}{end}\n",
            if cert.min_separation.is_some() {
                "worst case"
            } else {
                "behaviour found"
            },
            if w.collides {
                "collides"
            } else {
                "closest approach"
            },
            times
                .brake
                .map(|b| format!(", robot brakes at t = {} s", value(b)))
                .unwrap_or_default(),
        );
    }
    s += &format!(
        "  pieces: {} ({} linear programs solved)\n",
        cert.pieces, cert.programs_solved
    );
    s += &premises_text(&cert.premises);
    s
}

/// The s* line's value: s* with its bracket (the proved bound rounded down, the witness's
/// separation rounded up), −∞, or what is known when nothing pins s*.
pub(super) fn s_star_text(
    stated: Option<f64>,
    never_stops: bool,
    lower: Option<f64>,
    witness: Option<f64>,
    minus_infinity: &str,
) -> String {
    match (stated, never_stops, lower, witness) {
        (_, true, ..) => minus_infinity.to_string(),
        (Some(x), _, Some(b), Some(r)) => {
            format!("{x:.6} m (between {} and {} m)", down(b, 9), up(r, 9))
        }
        (Some(x), ..) => format!("{x:.6} m"),
        (None, _, Some(b), Some(r)) => format!(
            "not pinned: at least {} m (proved), at most {} m (the behaviour found)",
            down(b, 9),
            up(r, 9)
        ),
        (None, _, Some(b), None) => format!("at least {} m (proved)", down(b, 9)),
        (None, _, None, Some(r)) => format!(
            "not pinned: no bound is proved; the behaviour found reaches {} m",
            up(r, 9)
        ),
        (None, _, None, None) => "unknown (no worst case could be realised)".to_string(),
    }
}

/// The lower-bound line: the bound rounded down, against the clearance.
pub(super) fn lower_bound_text(lower: Option<f64>, clearance: f64) -> String {
    match lower {
        Some(lb) => format!(
            "  rigorous lower bound {} m vs clearance {} m\n",
            down(lb, 9),
            value(clearance)
        ),
        None => "  no finite lower bound proved\n".to_string(),
    }
}

/// The premises, one a line, each bound without float noise.
pub(super) fn premises_text(premises: &[Premise]) -> String {
    let mut s = "  premises:\n".to_string();
    for p in premises {
        s += &format!(
            "    {:<21} {} {} {}\n",
            p.name,
            p.description(),
            value(p.bound),
            p.unit()
        );
    }
    s
}
