//! `safereach radius`: the smallest reaction radius that is still certified, per obstacle
//! speed bound — where certification ends along ρ.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result};

use safereach::analysis::radius;
use safereach::core::scene::Scene;

use super::boundary::{answer, certificate_text};
use super::exit::Exit;
use super::input::{self, Input};
use super::output::{Output, create_dir, write_file};

/// Arguments of `safereach radius`.
#[derive(clap::Args)]
pub struct RadiusArgs {
    /// Problem file (TOML).
    problem: PathBuf,
    /// Override a key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Obstacle speed bounds W to answer for (comma-separated; default: the problem's).
    #[arg(long, value_delimiter = ',')]
    speeds: Vec<f64>,
    /// Print JSON.
    #[arg(long)]
    json: bool,
    /// Write the certificate just above each safe radius into this directory.
    #[arg(long, value_name = "DIR")]
    certificates: Option<PathBuf>,
    /// In a scene: the obstacle (by name) whose bound `--speeds` sets; default every moving
    /// obstacle's.
    #[arg(long, value_name = "NAME")]
    obstacle: Option<String>,
}

/// Runs `safereach radius`: exit 0 when every speed has a safe radius, 1 otherwise.
pub fn run(args: RadiusArgs, out: &mut Output) -> Result<Exit> {
    let base = match input::problem_or_scene(&args.problem, &args.sets)? {
        Input::Problem(p) => p,
        Input::Scene(scene) => return scene_radius(&scene, &args, out),
    };
    if args.obstacle.is_some() {
        anyhow::bail!("--obstacle names an obstacle of a scene; this is a problem file");
    }
    let speeds = if args.speeds.is_empty() {
        vec![base.environment.obstacle_speed]
    } else {
        args.speeds.clone()
    };
    let mut answers = Vec::new();
    let mut all = true;
    for &w in &speeds {
        let mut sets = args.sets.clone();
        sets.push(format!("environment.obstacle_speed={w}"));
        let problem = input::problem(&args.problem, &sets)?;
        let b = radius::safe_radius(&problem).context("radius search failed")?;
        all &= b.value.is_some();
        if let (Some(dir), Some(a)) = (&args.certificates, &b.certified) {
            create_dir(dir)?;
            write_file(
                &dir.join(format!("radius-W{w}.json")),
                certificate_text(a)?.as_bytes(),
            )?;
        }
        if !args.json {
            writeln!(out, "{}", b.describe(&problem))?;
        }
        answers.push(answer(&problem, &b));
    }
    if args.json {
        if args.speeds.is_empty() {
            writeln!(out, "{}", serde_json::to_string_pretty(&answers[0])?)?;
        } else {
            writeln!(out, "{}", serde_json::to_string_pretty(&answers)?)?;
        }
    }
    Ok(Exit::fail_if(!all))
}

/// `radius` on a scene: per speed bound (given to every moving obstacle, or to the one
/// `--obstacle` names), the smallest certified reaction radius up to the sensing range.
fn scene_radius(scene: &Scene, args: &RadiusArgs, out: &mut Output) -> Result<Exit> {
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
    let moving = |i: usize| !scene.obstacles[i].is_static && target.is_none_or(|t| t == i);
    let speeds = if args.speeds.is_empty() {
        vec![None]
    } else {
        args.speeds.iter().map(|&w| Some(w)).collect()
    };
    let mut answers = Vec::new();
    let mut all = true;
    for w in speeds {
        let mut s = scene.clone();
        if let Some(w) = w {
            for i in (0..s.obstacles.len()).filter(|&i| moving(i)) {
                s.obstacles[i].max_speed = w;
            }
            s.validate(&format!("--speeds {w}"))?;
        }
        let r = safereach::analysis::scene_radius::scene_radius(&s)
            .map_err(|e| anyhow::anyhow!("{}: {e}", s.name))?;
        all &= r.value.is_some();
        let label = match (w, &args.obstacle) {
            (Some(w), Some(name)) => format!("W = {w} m/s for \"{name}\""),
            (Some(w), None) => format!("W = {w} m/s for every moving obstacle"),
            (None, _) => "the scene's bounds".to_string(),
        };
        if let (Some(dir), Some(_)) = (&args.certificates, r.value) {
            create_dir(dir)?;
            let text = r.at.certificate().to_json();
            let name = w.map_or("radius.json".to_string(), |w| format!("radius-W{w}.json"));
            write_file(&dir.join(name), text.as_bytes())?;
        }
        if args.json {
            answers.push(serde_json::json!({
                "speed": w, "obstacle": args.obstacle, "radius": r.value, "cap": r.cap,
                "verdict_at_cap": r.value.is_none().then(|| r.at.verdict().as_str()),
            }));
        } else {
            writeln!(out, "{label}: {}", r.describe())?;
        }
    }
    if args.json {
        writeln!(out, "{}", serde_json::to_string_pretty(&answers)?)?;
    }
    Ok(Exit::fail_if(!all))
}
