//! `safereach explore`: exhaustive breadth-first exploration of the finite model, where the
//! obstacle picks its speed each period from a finite set — an independent check of
//! `certify` that needs no solver. With `--grid`, the exported UPPAAL network is explored on
//! its integer grid instead (what UPPAAL would answer for `export-uppaal`). A scene file
//! (anything that does not read as a single-obstacle problem) is explored as a scene, every
//! obstacle with its own speed set ([`super::explore_scene`]).
//!
//! Exit codes: 0 safe, 1 collision, 3 inconclusive (state budget reached), 2 bad input or an
//! internal error.

use safereach::core::show::value;
use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use safereach::core::budget::Work;
use serde_json::{Value, json};

use safereach::core::model::Problem;
use safereach::core::num::Exact;
use safereach::core::output::trace_csv;
use safereach::core::semantics::Mode;
use safereach::core::simulate::TraceRow;
use safereach::crosscheck::explore::scene::DEFAULT_SCENE_MAX_STATES;
use safereach::crosscheck::explore::{
    self, Exploration, ExploreVerdict, FiniteModel, Options, SpeedSet, show_exact,
};
use safereach::crosscheck::uppaal::{self, GridExploration};

use super::exit::Exit;
use super::explore_scene;
use super::input::{self, Input};
use super::output::{Output, write_file};

/// Arguments of `safereach explore`, as typed.
#[derive(clap::Args)]
pub struct ExploreArgs {
    /// Problem or scene file (TOML).
    problem: PathBuf,
    /// Override a key, e.g. `environment.obstacle_speed=0.25` or `obstacle.0.max_speed=0.2`
    /// (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Obstacle speeds per period: a count N (N evenly spaced speeds 0, W/(N-1), ..., W;
    /// default 5) or a comma-separated list in m/s (`0,0.05,0.15`; fractions like `3/80`
    /// too). For a scene, every obstacle i has its own set: a count N spaces N speeds over
    /// [0, W_i], a list adds its levels to {0, W_i} where they fit (default {0, W_i}).
    #[arg(long, value_name = "N|LIST")]
    speeds: Option<String>,
    /// Stop with `inconclusive` after this many distinct states (bounds memory; default
    /// 2000000 for a problem, 600000 for a scene: under 1 GB at small latencies; --max-memory
    /// lowers it for a scene's large states).
    #[arg(long, value_name = "N")]
    max_states: Option<usize>,
    /// Memory budget for the stored states, in MiB (default 2048): the state limit is lowered
    /// to what fits (1 KiB a problem's state; a scene's grows with the latency).
    #[arg(long, value_name = "MIB")]
    max_memory: Option<u64>,
    /// Initial gaps explored in a range `environment.initial_gap = [min, max]`: N evenly
    /// spaced starts, both ends included (default 5; N >= 2). The environment picks one,
    /// like a speed: the exploration covers exactly these. Single-obstacle problems only.
    #[arg(long, value_name = "N")]
    starts: Option<usize>,
    /// Print JSON (verdict, states, min_separation, path, ...).
    #[arg(long)]
    json: bool,
    /// Write the counterexample (or, when safe, the closest approach) as CSV in the
    /// simulator's trace format.
    #[arg(long, value_name = "FILE")]
    trace: Option<PathBuf>,
    /// Explore the exported UPPAAL network on its integer grid instead (what UPPAAL would
    /// answer for `export-uppaal` with the same --speeds).
    #[arg(long)]
    grid: bool,
}

/// `--speeds` for `problem`: a count or a list, within its obstacle speed bound W.
pub fn speed_set(problem: &Problem, speeds: &str) -> Result<SpeedSet> {
    let w: Exact = problem.params::<Exact>().W;
    Ok(SpeedSet::parse(speeds, &w)?)
}

/// The single-obstacle explorer's default `--speeds`.
const DEFAULT_SPEEDS: &str = "5";

/// Runs `safereach explore`: exit 0 safe, 1 collision, 3 inconclusive.
pub fn run(args: ExploreArgs, out: &mut Output) -> Result<Exit> {
    // The explorer takes a range of initial gaps as a finite set of starts; so does the
    // grid explorer, like the UPPAAL export (the same starts).
    let input = input::problem_with_range_or_scene(&args.problem, &args.sets)?;
    let problem = match input {
        Input::Problem(problem) => problem,
        Input::Planar(_) => return Err(input::planar_unsupported(&args.problem, "explore")),
        Input::Scene(scene) => {
            if args.starts.is_some() {
                anyhow::bail!(
                    "--starts applies to single-obstacle problems; a scene explores both ends \
                     of every obstacle's position range"
                );
            }
            let options = Options {
                max_states: args.max_states.unwrap_or(DEFAULT_SCENE_MAX_STATES),
                max_memory: memory(args.max_memory)?,
            };
            if args.grid {
                if args.trace.is_some() {
                    anyhow::bail!(
                        "--trace is not available with --grid (the grid explorer reports states, not traces)"
                    );
                }
                return explore_scene::run_grid(
                    &scene,
                    args.speeds.as_deref(),
                    &options,
                    args.json,
                    out,
                );
            }
            return explore_scene::run(
                &scene,
                args.speeds.as_deref(),
                &options,
                args.json,
                args.trace.as_deref(),
                out,
            );
        }
    };
    let speeds = speed_set(&problem, args.speeds.as_deref().unwrap_or(DEFAULT_SPEEDS))?;
    let options = Options {
        max_states: args.max_states.unwrap_or(explore::DEFAULT_MAX_STATES),
        max_memory: memory(args.max_memory)?,
    };
    if args.grid {
        if args.trace.is_some() {
            anyhow::bail!(
                "--trace is not available with --grid (the grid explorer reports states, not traces)"
            );
        }
        let starts = args.starts.unwrap_or(explore::DEFAULT_STARTS);
        return run_grid(&problem, speeds, starts, &options, args.json, out);
    }
    let model = FiniteModel::new(&problem, speeds)
        .with_starts(args.starts.unwrap_or(explore::DEFAULT_STARTS))?;
    let result = explore::explore_model(&model, &options)?;
    let witness = result.counterexample.as_ref().or(result.closest.as_ref());
    if let (Some(path), Some(w)) = (&args.trace, witness) {
        write_file(path, trace_csv(&w.trace, "0").as_bytes())?;
    }
    if args.json {
        writeln!(
            out,
            "{}",
            serde_json::to_string_pretty(&to_json(&problem, &result, &options))?
        )?;
    } else {
        write!(
            out,
            "{}",
            summary(&problem, &result, &options, args.trace.as_deref())
        )?;
    }
    Ok(result.verdict.into())
}

fn path_json(path: &explore::Path) -> Value {
    json!({
        "periods": path.periods(),
        "start": path.start.to_f64().value(),
        "start_exact": show_exact(&path.start),
        "first_seen_period": path.first_seen,
        "errors_let_guard_fire": path.reacts,
        "obstacle_speeds": path.speeds.iter().map(|s| s.to_f64().value()).collect::<Vec<_>>(),
        "obstacle_speeds_exact": path.speeds.iter().map(show_exact).collect::<Vec<_>>(),
        "collides": path.run.outcome.collided,
        "steps": path.trace,
    })
}

/// `--max-memory` in bytes (default: the explorer's memory budget).
fn memory(mib: Option<u64>) -> Result<u64> {
    match mib {
        None => Ok(Work::ExploreMemory.default_limit()),
        Some(0) => anyhow::bail!("--max-memory must be at least 1 (MiB)"),
        Some(m) => m
            .checked_mul(1 << 20)
            .context("--max-memory: more MiB than can be counted in bytes"),
    }
}

fn message(result: &Exploration, options: &Options) -> Option<String> {
    (!result.complete).then(|| {
        format!(
            "{}{}",
            if result.verdict == ExploreVerdict::Inconclusive {
                "inconclusive: "
            } else {
                "incomplete: "
            },
            explore::budget_reached(result.states, result.state_limit, options)
        )
    })
}

fn to_json(problem: &Problem, result: &Exploration, options: &Options) -> Value {
    json!({
        "problem": problem.name,
        "verdict": result.verdict.as_str(),
        "message": message(result, options),
        "complete": result.complete,
        "states": result.states,
        "transitions": result.transitions,
        "depth": result.depth,
        "speeds": result.speeds.speeds().iter().map(|s| s.to_f64().value()).collect::<Vec<_>>(),
        "speeds_exact": result.speeds.speeds().iter().map(show_exact).collect::<Vec<_>>(),
        "starts": result.starts.iter().map(|s| s.to_f64().value()).collect::<Vec<_>>(),
        "starts_exact": result.starts.iter().map(show_exact).collect::<Vec<_>>(),
        "property": "always: never moving with gap <= clearance",
        "min_separation": if result.never_stops { None } else { result.min_separation.as_ref().map(|s| s.to_f64().value()) },
        "min_separation_exact": if result.never_stops { None } else { result.min_separation.as_ref().map(show_exact) },
        "never_stops": result.never_stops,
        "clearance": problem.robot.clearance,
        "path": result.counterexample.as_ref().map(path_json),
        "closest": result.closest.as_ref().map(path_json),
    })
}

/// The obstacle's speeds along a path, run-length encoded: `0.15 x12, 0 x3`.
fn speeds_rle(speeds: &[Exact]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut i = 0;
    while i < speeds.len() {
        let mut j = i;
        while j < speeds.len() && speeds[j] == speeds[i] {
            j += 1;
        }
        parts.push(format!("{} x{}", show_exact(&speeds[i]), j - i));
        i = j;
    }
    parts.join(", ")
}

fn brake_time(rows: &[TraceRow]) -> Option<f64> {
    rows.iter()
        .find(|r| r.robot_mode == Mode::Brake)
        .map(|r| r.t)
}

fn summary(
    problem: &Problem,
    result: &Exploration,
    options: &Options,
    trace: Option<&Path>,
) -> String {
    let mut s = format!("{}: {}\n", problem.name, result.verdict.as_str());
    if let Some(m) = message(result, options) {
        s += &format!("  {m}\n");
    }
    s += &format!(
        "  obstacle speeds {} m/s ({} actions per state, fixed order)\n",
        result.speeds,
        result.speeds.len()
    );
    if result.starts.len() > 1 {
        let xs: Vec<String> = result.starts.iter().map(show_exact).collect();
        s += &format!(
            "  initial gaps {{{}}} m (one init state each)\n",
            xs.join(", ")
        );
    }
    s += &format!(
        "  states {} ({} transitions, longest path {} periods){}\n",
        result.states,
        result.transitions,
        result.depth,
        if result.complete { "" } else { " - partial" }
    );
    let over = if result.complete {
        "all"
    } else {
        "the explored"
    };
    let sep = if result.never_stops {
        "-inf (some behaviour never brakes)".to_string()
    } else {
        match &result.min_separation {
            Some(x) => format!("{} m", value(x.to_f64().value())),
            None => "none (no behaviour moves and comes to rest)".into(),
        }
    };
    s += &format!(
        "  minimum separation over {over} behaviours: {sep} (clearance {} m)\n",
        value(problem.robot.clearance)
    );
    if let Some(c) = &result.counterexample {
        let last = c.trace.last();
        s += &format!(
            "  counterexample (shortest path, {} periods){}{}\n",
            c.periods(),
            brake_time(&c.trace)
                .map(|t| format!(": robot brakes at t = {} s", value(t)))
                .unwrap_or_else(|| ": robot never brakes".into()),
            last.map(|r| format!(
                ", collides by t = {} s (gap {} m)",
                value(r.t),
                value(r.gap)
            ))
            .unwrap_or_default()
        );
        s += &format!(
            "    obstacle speeds per period: {}\n",
            speeds_rle(&c.speeds)
        );
        s += &choices(problem, result, c);
    } else if let Some(c) = &result.closest {
        s += &format!(
            "  closest approach ({} periods): obstacle speeds per period: {}\n",
            c.periods(),
            speeds_rle(&c.speeds)
        );
        s += &choices(problem, result, c);
    }
    if let Some(path) = trace {
        let what = if result.counterexample.is_some() {
            "counterexample"
        } else if result.closest.is_some() {
            "closest approach"
        } else {
            "nothing (no path to write)"
        };
        s += &format!("  trace: {what} written to {}\n", path.display());
    }
    s
}

/// The path's other choices, where the problem leaves any: its start in a range, when a
/// hidden obstacle was first seen, and (with noise) where an error let the guard fire.
fn choices(problem: &Problem, result: &Exploration, path: &explore::Path) -> String {
    let mut s = String::new();
    if result.starts.len() > 1 {
        s += &format!("    initial gap {} m\n", show_exact(&path.start));
    }
    let p = problem.params::<Exact>();
    if p.d_det.is_some() {
        s += &match path.first_seen {
            Some(k) => format!("    obstacle first seen at the start of period {k}\n"),
            None => "    obstacle hidden throughout\n".into(),
        };
    }
    if p.noisy() {
        let fire: Vec<String> = (0..path.periods())
            .filter(|&k| path.reacts[k])
            .map(|k| k.to_string())
            .collect();
        s += &format!(
            "    observation errors keep the guard quiet{}\n",
            if fire.is_empty() {
                String::new()
            } else {
                format!(" except in period {} (they let it fire)", fire.join(", "))
            }
        );
    }
    s
}

/// `explore --grid`: the UPPAAL network explored on its integer grid.
fn run_grid(
    problem: &Problem,
    speeds: SpeedSet,
    starts: usize,
    options: &Options,
    json: bool,
    out: &mut Output,
) -> Result<Exit> {
    let model = uppaal::export_with_starts(problem, &speeds, starts)?;
    let result: GridExploration = uppaal::explore_grid(&model, options)?;
    let sep = result.min_separation.as_ref().map(|g| g.to_f64().value());
    if json {
        let v = json!({
            "problem": problem.name,
            "grid": true,
            "verdict": result.verdict.as_str(),
            "complete": result.complete,
            "states": result.states,
            "min_separation": sep,
            "min_separation_grid": result.min_separation_grid,
            "scale_per_metre": model.grid.scale.to_string(),
            "collision_period": result.collision_period,
            "path": Value::Null,
        });
        writeln!(out, "{}", serde_json::to_string_pretty(&v)?)?;
        return Ok(result.verdict.into());
    }
    writeln!(
        out,
        "{}: {} (UPPAAL network on the integer grid, 1 unit = 1/{} m, 1 time unit = {} s)",
        problem.name,
        result.verdict.as_str(),
        model.grid.scale,
        problem.robot.control_period
    )?;
    writeln!(
        out,
        "  network states {}{}",
        result.states,
        if result.complete {
            ""
        } else {
            " - state budget reached"
        }
    )?;
    if let Some(k) = result.collision_period {
        writeln!(out, "  first collision in period {k} (shortest path)")?;
    }
    match (result.min_separation_grid, sep) {
        (Some(g), Some(m)) if result.verdict == ExploreVerdict::Safe => writeln!(
            out,
            "  minimum separation at rest: {g} units = {} m",
            value(m)
        )?,
        _ => {}
    }
    Ok(result.verdict.into())
}
