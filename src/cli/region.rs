//! `safereach region`: one proof for a whole box of parameter values, and where it does not
//! hold, a certified map of the box (leaves certified, refuted or undecided).

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use safereach::core::budget::Work;

use safereach::analysis::Verdict;
use safereach::analysis::region_search::{
    DEFAULT_DEPTH, PLANAR_DEFAULT_DEPTH, RegionOptions, map_planar_region, map_region,
    map_scene_region,
};
use safereach::analysis::report::region_plot;
use safereach::core::param_box::{Axis, ParamBox};
use safereach::core::scene::Scene;
use safereach::core::show;
use safereach::core::text_file;
use safereach::proof::region_check::{check_map, describe_box};
use safereach::proof::region_map::{LeafVerdict, RegionMap};

use super::exit::Exit;
use super::input::{self, Input};
use super::output::{Output, write_file};

/// Arguments of `safereach region`.
#[derive(clap::Args)]
pub struct RegionArgs {
    /// Problem or scene file (TOML).
    problem: PathBuf,
    /// A ranged parameter, `KEY=LO..HI` (repeatable): environment.obstacle_speed,
    /// controller.reaction_radius, controller.assumed_obstacle_speed, controller.buffer,
    /// environment.initial_gap, robot.clearance, sensing.gap_noise, sensing.speed_noise,
    /// sensing.first_detection_gap; in a scene the controller's keys, robot.clearance and
    /// each obstacle's obstacle.<i>.max_speed and obstacle.<i>.position; in a planar problem
    /// controller.reaction_radius, controller.assumed_obstacle_speed, controller.buffer,
    /// robot.clearance and obstacle.<i>.max_speed.
    #[arg(long = "range", value_name = "KEY=LO..HI", required = true)]
    ranges: Vec<String>,
    /// Override a key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Most halvings on the way from the whole box to a leaf (default 14; 8 for a planar
    /// problem, whose boxes each cost planar certifications).
    #[arg(long)]
    depth: Option<u32>,
    /// Budget: the most boxes decided (default 1,000,000); boxes past it are left undecided.
    #[arg(long, value_name = "N")]
    max_boxes: Option<u64>,
    /// Do not halve an axis narrower than this fraction of its whole range.
    #[arg(long, value_name = "FRACTION", default_value_t = 0.0)]
    min_width: f64,
    /// Write the map (JSON; `safereach check` verifies it).
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Draw the map of the first two ranged parameters (SVG).
    #[arg(long, value_name = "FILE")]
    svg: Option<PathBuf>,
    /// Print the map as JSON.
    #[arg(long)]
    json: bool,
}

/// Runs `safereach region`: exit 0 when every leaf is certified (the whole box is), 1 when
/// some leaf is refuted, 3 when some is undecided and none refuted.
pub fn run(args: RegionArgs, out: &mut Output) -> Result<Exit> {
    let axes = args
        .ranges
        .iter()
        .map(|r| parse_range(r))
        .collect::<Result<Vec<_>>>()?;
    // An obstacle's own key maps a problem file as the scene it is.
    let input = match input::problem_or_scene(&args.problem, &args.sets)? {
        Input::Problem(p) if axes.iter().any(|a| a.obstacle.is_some()) => {
            Input::Scene(Scene::from_problem(&p))
        }
        input => input,
    };
    let whole = ParamBox::new(axes).map_err(|e| anyhow::anyhow!("--range: {e}"))?;
    if !(args.min_width.is_finite() && (0.0..1.0).contains(&args.min_width)) {
        bail!(
            "--min-width {}: must be a fraction in [0, 1)",
            args.min_width
        );
    }
    let options = RegionOptions {
        depth: args.depth.unwrap_or(match input {
            Input::Planar(_) => PLANAR_DEFAULT_DEPTH,
            _ => DEFAULT_DEPTH,
        }),
        min_width: args.min_width,
        max_boxes: args
            .max_boxes
            .unwrap_or_else(|| Work::Boxes.default_limit()),
    };
    let bar = progress();
    let on_decided = |share: f64| bar.inc((share * 1000.0).round() as u64);
    let map = match &input {
        Input::Problem(problem) => map_region(problem, &whole, &options, &on_decided),
        Input::Scene(scene) => map_scene_region(scene, &whole, &options, &on_decided),
        Input::Planar(problem) => {
            let text = text_file::read_text(&args.problem, text_file::MAX_PROBLEM_BYTES)
                .map_err(|e| anyhow::anyhow!("reading {}: {e}", args.problem.display()))?;
            map_planar_region(&text, &args.sets, problem, &whole, &options, &on_decided)
        }
    }
    .map_err(|e| anyhow::anyhow!("{}: {e}", args.problem.display()))?;
    bar.finish_and_clear();
    if let Some(path) = &args.out {
        // Compact: a deep map holds thousands of multipliers and witness speeds.
        write_file(path, (serde_json::to_string(&map)? + "\n").as_bytes())?;
    }
    if let Some(path) = &args.svg {
        if map.ranges.len() < 2 {
            bail!("--svg draws a plane: range two parameters");
        }
        write_file(path, region_plot::svg(&map).as_bytes())?;
    }
    if args.json {
        writeln!(out, "{}", serde_json::to_string_pretty(&map)?)?;
    } else {
        describe(out, &map, &whole)?;
        for (flag, path) in [("map", &args.out), ("plot", &args.svg)] {
            if let Some(p) = path {
                writeln!(out, "wrote the {flag} to {}", p.display())?;
            }
        }
    }
    Ok(exit_of(&map))
}

/// `KEY=LO..HI`, the key one that region certificates range (in a scene, also an
/// obstacle's `obstacle.<i>.max_speed` or `obstacle.<i>.position`).
fn parse_range(text: &str) -> Result<Axis> {
    let flag = format!("--range {text}");
    let Some((key, span)) = text.split_once('=') else {
        bail!("{flag}: expected KEY=LO..HI, e.g. environment.obstacle_speed=0.10..0.20");
    };
    let key = key.trim();
    let axis = Axis::for_key(key, 0.0, 0.0).map_err(|e| anyhow::anyhow!("{flag}: {e}"))?;
    let Some((lo, hi)) = span.split_once("..") else {
        bail!("{flag}: {key}: expected LO..HI, e.g. {key}=0.10..0.20");
    };
    let number = |s: &str| -> Result<f64> {
        match s.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => bail!("{flag}: {key}: {:?} is not a finite number", s.trim()),
        }
    };
    let (lo, hi) = (number(lo)?, number(hi)?);
    if lo > hi {
        bail!("{flag}: {key}: the range is reversed (lower end first)");
    }
    Ok(Axis { lo, hi, ..axis })
}

fn progress() -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(1000);
    bar.set_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {percent}% of the box decided")
            .expect("static template")
            .progress_chars("=> "),
    );
    bar
}

fn percent(x: f64) -> String {
    format!("{:.2}%", 100.0 * x)
}

fn describe(out: &mut Output, map: &RegionMap, whole: &ParamBox) -> Result<()> {
    let count = |v: LeafVerdict| map.leaves.iter().filter(|l| l.verdict == v).count();
    writeln!(out, "{} over {}", map.name(), describe_box(whole))?;
    if map.all_certified() {
        let least = map
            .leaves
            .iter()
            .filter_map(|l| l.lower_bound)
            .fold(f64::INFINITY, f64::min);
        writeln!(
            out,
            "certified for every point of the box ({} {}): s* >= {} m everywhere \
             (clearance {} m)",
            map.leaves.len(),
            if map.leaves.len() == 1 {
                "leaf"
            } else {
                "leaves"
            },
            show::down(least, 6),
            show::value(map.clearance())
        )?;
    } else {
        writeln!(
            out,
            "{} leaves: certified {} ({} leaves), refuted {} ({}), undecided {} ({})",
            map.leaves.len(),
            percent(map.coverage.certified),
            count(LeafVerdict::Certified),
            percent(map.coverage.refuted),
            count(LeafVerdict::Refuted),
            percent(map.coverage.undecided),
            count(LeafVerdict::Undecided),
        )?;
    }
    writeln!(out, "{} programs solved", map.programs_solved)?;
    Ok(())
}

fn exit_of(map: &RegionMap) -> Exit {
    if map.all_certified() {
        Exit::Pass
    } else if map.leaves.iter().any(|l| l.verdict == LeafVerdict::Refuted) {
        Exit::Fail
    } else {
        Exit::Inconclusive
    }
}

/// `safereach check` of a map file (told apart by its format tag): exit 0 valid, 1 invalid.
/// With `require`, a valid map whose verdict for the whole box differs exits 1: certified
/// when every leaf is, refuted when some leaf is, else inconclusive.
pub fn check_file(
    path: &Path,
    text: &str,
    require: Option<Verdict>,
    out: &mut Output,
) -> Result<Exit> {
    let map: RegionMap = safereach::proof::json_read::from_json(text)
        .map_err(|e| anyhow::anyhow!("{}: not a safereach region map: {e}", path.display()))?;
    let whole = if map.all_certified() {
        Verdict::Certified
    } else if map.leaves.iter().any(|l| l.verdict == LeafVerdict::Refuted) {
        Verdict::Refuted
    } else {
        Verdict::Inconclusive
    };
    match check_map(&map) {
        Ok(_) if require.is_some_and(|r| r != whole) => {
            writeln!(
                out,
                "{}: valid, but its verdict for the whole box is {}, not the required {}",
                path.display(),
                whole.as_str(),
                require.map_or("", Verdict::as_str),
            )?;
            Ok(Exit::Fail)
        }
        Ok(report) => {
            writeln!(
                out,
                "{}: valid; {} leaves re-verified in exact arithmetic: certified {}, refuted {}, \
                 undecided {}{}",
                path.display(),
                report.leaves,
                percent(report.coverage.certified),
                percent(report.coverage.refuted),
                percent(report.coverage.undecided),
                if report.all_certified {
                    " (the whole box is certified)"
                } else {
                    ""
                }
            )?;
            Ok(Exit::Pass)
        }
        Err(e) => {
            writeln!(out, "{}: INVALID: {e}", path.display())?;
            Ok(Exit::Fail)
        }
    }
}
