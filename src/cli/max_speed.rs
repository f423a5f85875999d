//! `safereach max-speed`: the largest obstacle speed bound that is still certified for the
//! problem's reaction radius — where certification ends along W.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result};
use safereach::core::budget::{Budget, Work};

use safereach::analysis::radius;
use safereach::core::scene::Scene;

use super::boundary::{answer, certificate_text, region_at};
use super::exit::Exit;
use super::input::{self, Input};
use super::output::{Output, write_file};

/// Arguments of `safereach max-speed`.
#[derive(clap::Args)]
pub struct MaxSpeedArgs {
    /// Problem file (TOML).
    problem: PathBuf,
    /// Override a key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Print JSON.
    #[arg(long)]
    json: bool,
    /// Write the certificate just below the largest certified speed to this file.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Also prove a region statement: certified for every W ≤ the largest certified speed
    /// at every ρ ≥ the problem's (one region map; exit 3 when it is not established).
    #[arg(long)]
    region: bool,
    /// With `--region`: write the statement's region map to this file.
    #[arg(long, value_name = "FILE", requires = "region")]
    region_out: Option<PathBuf>,
    /// Budget: the most control periods the search may analyse in all, each analysis
    /// counting its problem's horizon (default 20,000,000).
    #[arg(long, value_name = "N")]
    max_periods: Option<u64>,
    /// In a scene: the obstacle (by name) whose bound is searched; default every moving
    /// obstacle's, together.
    #[arg(long, value_name = "NAME")]
    obstacle: Option<String>,
}

/// Runs `safereach max-speed`: exit 0 when some speed is certified, 1 otherwise.
pub fn run(args: MaxSpeedArgs, out: &mut Output) -> Result<Exit> {
    let problem = match input::problem_or_scene(&args.problem, &args.sets)? {
        Input::Problem(p) => p,
        Input::Scene(_) if args.region => anyhow::bail!(super::radius::NO_SCENE_REGION),
        Input::Scene(scene) => return scene_max_speed(&scene, &args, out),
        Input::Planar(_) if args.region => anyhow::bail!(super::radius::NO_PLANAR_REGION),
        Input::Planar(_) => {
            return super::planar_boundary::max_speed(
                &args.problem,
                &args.sets,
                args.obstacle.as_deref(),
                args.out.as_deref(),
                args.json,
                out,
            );
        }
    };
    if args.obstacle.is_some() {
        anyhow::bail!("--obstacle names an obstacle of a scene; this is a problem file");
    }
    let b = radius::max_speed_within(
        &problem,
        Budget::new(Work::AnalysedPeriods, args.max_periods),
    )
    .context("max-speed search failed")?;
    if let (Some(path), Some(a)) = (&args.out, &b.certified) {
        write_file(path, certificate_text(a)?.as_bytes())?;
    }
    let region = args.region.then(|| region_at(&b)).flatten();
    if let (Some(path), Some((_, Some(map)))) = (&args.region_out, &region) {
        write_file(path, (serde_json::to_string(map)? + "\n").as_bytes())?;
    }
    let holds = region.as_ref().is_none_or(|(s, _)| s.holds());
    if args.json {
        let a = answer(&problem, &b).with_region(region.map(|(s, _)| s));
        writeln!(out, "{}", serde_json::to_string_pretty(&a)?)?;
    } else {
        writeln!(out, "{}", b.describe(&problem))?;
        if let Some((statement, _)) = &region {
            writeln!(out, "  region: {}", statement.text())?;
        }
    }
    Ok(super::radius::region_exit(b.value.is_some(), holds))
}

/// `max-speed` on a scene: the largest bound of every moving obstacle (or the named one)
/// that is still certified.
fn scene_max_speed(scene: &Scene, args: &MaxSpeedArgs, out: &mut Output) -> Result<Exit> {
    let target = match &args.obstacle {
        Some(name) => Some(
            scene
                .obstacles
                .iter()
                .position(|o| &o.name == name)
                .with_context(|| format!("--obstacle {name}: the scene has no such obstacle"))?,
        ),
        None => None,
    };
    let budget = Budget::new(Work::AnalysedPeriods, args.max_periods);
    let m = safereach::analysis::scene_radius::scene_max_speed_within(scene, target, budget)
        .map_err(|e| anyhow::anyhow!("{}: {e}", scene.name))?;
    if let (Some(path), Some(_)) = (&args.out, m.value) {
        let text = m.at.certificate().to_json();
        write_file(path, text.as_bytes())?;
    }
    let who = match &args.obstacle {
        Some(name) => format!("\"{name}\""),
        None => "every moving obstacle".into(),
    };
    if args.json {
        writeln!(
            out,
            "{}",
            serde_json::json!({"obstacle": args.obstacle, "max_speed": m.value, "unbounded": m.unbounded})
        )?;
    } else {
        writeln!(
            out,
            "rho = {} m, {who}: {}",
            scene.controller.reaction_radius,
            m.describe()
        )?;
    }
    Ok(Exit::fail_if(m.value.is_none()))
}
