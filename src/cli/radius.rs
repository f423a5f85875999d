//! `safereach radius`: the smallest reaction radius that is still certified, per obstacle
//! speed bound — where certification ends along ρ.

use safereach::core::show::value;
use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result};
use safereach::core::budget::{Budget, Work};

use safereach::analysis::radius;
use safereach::core::scene::Scene;

use super::boundary::{answer, certificate_text, region_at};
use super::exit::Exit;
use super::input::{self, Input};
use super::output::{Output, create_dir, write_file};

/// Why `--region` refuses a scene.
pub(super) const NO_SCENE_REGION: &str = "--region: region statements need region certificates, which cover single-obstacle \
     problems, not scenes, so far";

/// Why `--region` refuses a planar problem.
pub(super) const NO_PLANAR_REGION: &str = "--region: region statements cover single-obstacle problems on a line, not planar problems, so far";

/// Arguments of `safereach radius`.
#[derive(clap::Args)]
pub struct RadiusArgs {
    /// Problem file (TOML).
    problem: PathBuf,
    /// Override a key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Obstacle speed bounds W to answer for, in m/s (comma-separated, repeatable; default:
    /// the problem's).
    #[arg(long, value_name = "W,W,...", allow_hyphen_values = true)]
    speeds: Vec<String>,
    /// Print JSON.
    #[arg(long)]
    json: bool,
    /// Write the certificate just above each safe radius into this directory (and, with
    /// `--region`, each statement's map).
    #[arg(long, value_name = "DIR")]
    certificates: Option<PathBuf>,
    /// Also prove a region statement per speed: certified for every W ≤ W0 at every
    /// ρ ≥ the safe radius (one region map; exit 3 when one is not established).
    #[arg(long)]
    region: bool,
    /// Budget: the most control periods the search may analyse in all, each analysis
    /// counting its problem's horizon (default 20,000,000).
    #[arg(long, value_name = "N")]
    max_periods: Option<u64>,
    /// In a scene: the obstacle (by name) whose bound `--speeds` sets; default every moving
    /// obstacle's.
    #[arg(long, value_name = "NAME")]
    obstacle: Option<String>,
}

/// Runs `safereach radius`: exit 0 when every speed has a safe radius, 1 otherwise.
pub fn run(args: RadiusArgs, out: &mut Output) -> Result<Exit> {
    let speeds = speed_list(&args.speeds)?;
    let base = match input::problem_or_scene(&args.problem, &args.sets)? {
        Input::Problem(p) => p,
        Input::Scene(_) if args.region => anyhow::bail!(NO_SCENE_REGION),
        Input::Scene(scene) => return scene_radius(&scene, &args, &speeds, out),
        Input::Planar(_) if args.region => anyhow::bail!(NO_PLANAR_REGION),
        Input::Planar(_) => {
            return super::planar_boundary::radius(
                &args.problem,
                &args.sets,
                &speeds,
                args.obstacle.as_deref(),
                args.certificates.as_deref(),
                args.json,
                out,
            );
        }
    };
    if args.obstacle.is_some() {
        anyhow::bail!("--obstacle names an obstacle of a scene; this is a problem file");
    }
    let speeds = if speeds.is_empty() {
        vec![base.environment.obstacle_speed]
    } else {
        speeds
    };
    let mut answers = Vec::new();
    let mut all = true;
    let mut every_region = true;
    for &w in &speeds {
        let mut problem = base.clone();
        problem.environment.obstacle_speed = w;
        problem.validate(&format!("--speeds {}", value(w)))?;
        let b = radius::safe_radius_within(
            &problem,
            Budget::new(Work::AnalysedPeriods, args.max_periods),
        )
        .context("radius search failed")?;
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
        let region = args.region.then(|| region_at(&b)).flatten();
        if let Some((statement, map)) = &region {
            every_region &= statement.holds();
            if !args.json {
                writeln!(out, "  region: {}", statement.text())?;
            }
            if let (Some(dir), Some(map)) = (&args.certificates, map) {
                create_dir(dir)?;
                let text = serde_json::to_string(map)? + "\n";
                write_file(
                    &dir.join(format!("radius-W{w}.region.json")),
                    text.as_bytes(),
                )?;
            }
        }
        answers.push(answer(&problem, &b).with_region(region.map(|(s, _)| s)));
    }
    if args.json {
        if args.speeds.is_empty() {
            writeln!(out, "{}", serde_json::to_string_pretty(&answers[0])?)?;
        } else {
            writeln!(out, "{}", serde_json::to_string_pretty(&answers)?)?;
        }
    }
    Ok(region_exit(all, every_region))
}

/// `radius`/`max-speed` exit: 1 when a point answer is missing, else 3 when a region
/// statement asked for was not established, else 0.
pub(super) fn region_exit(answered: bool, every_region: bool) -> Exit {
    match (answered, every_region) {
        (false, _) => Exit::Fail,
        (true, false) => Exit::Inconclusive,
        (true, true) => Exit::Pass,
    }
}

/// The speeds of every `--speeds` list, in order: each element a finite number (an empty
/// element, as in `0.1,,0.2`, is an error, not skipped); the range is the problem's check.
fn speed_list(lists: &[String]) -> Result<Vec<f64>> {
    let mut speeds = Vec::new();
    for list in lists {
        for (i, element) in list.split(',').enumerate() {
            let element = element.trim();
            let at = format!("--speeds {list}: element {}", i + 1);
            if element.is_empty() {
                anyhow::bail!("{at} is empty");
            }
            let w: f64 = element
                .parse()
                .map_err(|_| anyhow::anyhow!("{at} (`{element}`) is not a number"))?;
            if !w.is_finite() {
                anyhow::bail!("{at} (`{element}`) is not a finite number");
            }
            speeds.push(w);
        }
    }
    Ok(speeds)
}

/// `radius` on a scene: per speed bound (given to every moving obstacle, or to the one
/// `--obstacle` names), the smallest certified reaction radius up to the sensing range.
fn scene_radius(
    scene: &Scene,
    args: &RadiusArgs,
    speeds: &[f64],
    out: &mut Output,
) -> Result<Exit> {
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
    let speeds: Vec<Option<f64>> = if speeds.is_empty() {
        vec![None]
    } else {
        speeds.iter().map(|&w| Some(w)).collect()
    };
    let mut answers = Vec::new();
    let mut all = true;
    for w in speeds {
        let mut s = scene.clone();
        if let Some(w) = w {
            for i in (0..s.obstacles.len()).filter(|&i| moving(i)) {
                s.obstacles[i].max_speed = w;
            }
            s.validate(&format!("--speeds {}", value(w)))?;
        }
        let budget = Budget::new(Work::AnalysedPeriods, args.max_periods);
        let r = safereach::analysis::scene_radius::scene_radius_within(&s, budget)
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
