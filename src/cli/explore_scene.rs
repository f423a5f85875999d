//! `safereach explore` on a scene file: every joint behaviour in which each obstacle picks a
//! speed from its own finite set, through the scene's step function
//! ([`safereach::crosscheck::explore::scene`]); the summary, the JSON and the trace.

use safereach::core::show::value;
use std::io::Write;
use std::path::Path;

use anyhow::Result;
use serde_json::{Value, json};

use safereach::core::num::Exact;
use safereach::core::output::scene_trace_for_path;
use safereach::core::scene::Scene;
use safereach::crosscheck::explore::scene::{
    SceneExploration, ScenePath, SceneSpeeds, explore_scene,
};
use safereach::crosscheck::explore::{self, ExploreVerdict, Options, show_exact};
use safereach::crosscheck::uppaal;

use super::exit::Exit;
use super::output::{Output, write_file};

/// Explores `scene` with `--speeds` (None: {0, W_i} for every obstacle), printing the
/// summary or JSON and writing the counterexample (or closest approach) to `trace`.
pub fn run(
    scene: &Scene,
    speeds: Option<&str>,
    options: &Options,
    json: bool,
    trace: Option<&Path>,
    out: &mut Output,
) -> Result<Exit> {
    let params = scene.params::<Exact>();
    let speeds = match speeds {
        Some(spec) => SceneSpeeds::parse(spec, &params)?,
        None => SceneSpeeds::extremes(&params),
    };
    let result = explore_scene(scene, speeds, options)?;
    let witness = result.counterexample.as_ref().or(result.closest());
    if let (Some(path), Some(w)) = (trace, witness) {
        write_file(
            path,
            scene_trace_for_path(path, &w.replay.trace()).as_bytes(),
        )?;
    }
    if json {
        let v = to_json(scene, &result, options);
        writeln!(out, "{}", serde_json::to_string_pretty(&v)?)?;
    } else {
        write!(out, "{}", summary(scene, &result, options, trace))?;
    }
    Ok(result.verdict.into())
}

/// `explore --grid` on a scene: its exported UPPAAL network explored on the integer grid
/// (what UPPAAL would answer for `export-uppaal` with the same `--speeds`).
pub fn run_grid(
    scene: &Scene,
    speeds: Option<&str>,
    options: &Options,
    json: bool,
    out: &mut Output,
) -> Result<Exit> {
    let params = scene.params::<Exact>();
    let speeds = match speeds {
        Some(spec) => SceneSpeeds::parse(spec, &params)?,
        None => SceneSpeeds::extremes(&params),
    };
    let model = uppaal::export_scene(scene, &speeds)?;
    let result = uppaal::explore_scene_grid(&model, options)?;
    let seps: Vec<Option<f64>> = result
        .min_separation
        .iter()
        .map(|s| s.as_ref().map(|s| s.to_f64().value()))
        .collect();
    if json {
        let obstacles: Vec<Value> = scene
            .obstacles
            .iter()
            .zip(&seps)
            .zip(&result.min_separation_grid)
            .map(|((o, s), g)| {
                json!({"name": o.name, "min_separation": s, "min_separation_grid": g})
            })
            .collect();
        let v = json!({
            "scene": scene.name,
            "grid": true,
            "verdict": result.verdict.as_str(),
            "complete": result.complete,
            "states": result.states,
            "scale_per_metre": model.grid.scale.to_string(),
            "collision_period": result.collision_period,
            "obstacles": obstacles,
        });
        writeln!(out, "{}", serde_json::to_string_pretty(&v)?)?;
        return Ok(result.verdict.into());
    }
    writeln!(
        out,
        "{}: {} (UPPAAL scene network on the integer grid, 1 unit = 1/{} m, 1 time unit = {} s)",
        scene.name,
        result.verdict.as_str(),
        model.grid.scale,
        scene.robot.control_period
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
    if result.verdict == ExploreVerdict::Safe {
        for ((o, s), g) in scene
            .obstacles
            .iter()
            .zip(&seps)
            .zip(&result.min_separation_grid)
        {
            match (s, g) {
                (Some(s), Some(g)) => writeln!(
                    out,
                    "  {:?} (lane {}): least separation {g} units = {} m",
                    o.name,
                    o.lane,
                    value(*s)
                )?,
                _ => writeln!(
                    out,
                    "  {:?} (lane {}): never met (the robot never moves in its lane)",
                    o.name, o.lane
                )?,
            }
        }
    }
    Ok(result.verdict.into())
}

/// Why the search is incomplete, if it is.
fn message(result: &SceneExploration, options: &Options) -> Option<String> {
    if result.complete {
        return None;
    }
    let head = if result.verdict == ExploreVerdict::Inconclusive {
        "inconclusive: "
    } else {
        "incomplete: "
    };
    Some(if result.budget_exhausted {
        format!(
            "{head}{}",
            explore::budget_reached(result.states, result.state_limit, options)
        )
    } else {
        format!(
            "{head}a behaviour was still running at the horizon ({} periods)",
            result.horizon
        )
    })
}

/// An exact number as text, with its float beside it when it is not a short decimal.
fn show(x: &Exact) -> String {
    let text = show_exact(x);
    if text.contains('/') || text.len() > 14 {
        format!("{text} (~{:.9})", x.to_f64().value())
    } else {
        text
    }
}

/// `"name"`, as the summary names an obstacle.
fn label(scene: &Scene, i: usize) -> String {
    format!("{:?}", scene.obstacles[i].name)
}

/// Speeds along a path, run-length encoded: `0.15 x12, 0 x3`.
fn speeds_rle(speeds: &[Exact]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut i = 0;
    while i < speeds.len() {
        let j = i + speeds[i..].iter().take_while(|s| **s == speeds[i]).count();
        parts.push(format!("{} x{}", show_exact(&speeds[i]), j - i));
        i = j;
    }
    parts.join(", ")
}

/// What the robot did on a path: its brake and lane changes, with their instants.
fn story(scene: &Scene, path: &ScenePath) -> String {
    let dt = scene.robot.control_period;
    let outcome = &path.replay.run.outcome;
    let mut parts: Vec<String> = outcome
        .lane_changes
        .iter()
        .map(|c| {
            format!(
                "changes lane {} -> {} at t = {} s",
                c.from,
                c.to,
                value(c.step as f64 * dt)
            )
        })
        .collect();
    match outcome.brake {
        Some((k, reason)) => parts.push(format!(
            "brakes at t = {} s ({})",
            value(k as f64 * dt),
            serde_json::to_value(reason)
                .ok()
                .and_then(|v| v.as_str().map(str::to_string))
                .unwrap_or_default()
        )),
        None => parts.push("never brakes".into()),
    }
    format!("robot {}", parts.join(", "))
}

fn summary(
    scene: &Scene,
    result: &SceneExploration,
    options: &Options,
    trace: Option<&Path>,
) -> String {
    let mut s = format!("{}: {}\n", scene.name, result.verdict.as_str());
    if let Some(m) = message(result, options) {
        s += &format!("  {m}\n");
    }
    let sets: Vec<String> = (0..scene.obstacles.len())
        .map(|i| format!("{} {}", label(scene, i), result.speeds.of(i)))
        .collect();
    s += &format!("  obstacle speeds per period (m/s): {}\n", sets.join(", "));
    let ranges: Vec<String> = (0..scene.obstacles.len())
        .filter(|&i| result.starts[i].len() > 1)
        .map(|i| {
            let xs: Vec<String> = result.starts[i].iter().map(show_exact).collect();
            format!("{} {{{}}}", label(scene, i), xs.join(", "))
        })
        .collect();
    if !ranges.is_empty() {
        s += &format!("  starts explored (m): {}\n", ranges.join(", "));
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
    let least = if result.never_stops() {
        "-inf (some behaviour passes an obstacle without braking)".to_string()
    } else {
        match result.min_separation() {
            Some(x) => format!("{} m", show(&x)),
            None => "none (the robot never moves in an obstacle's lane)".into(),
        }
    };
    s += &format!(
        "  least separation over {over} behaviours: {least} (clearance {} m)\n",
        value(scene.robot.clearance)
    );
    for (i, o) in result.obstacles.iter().enumerate() {
        let what = if o.unbounded {
            "-inf (passed without braking)".to_string()
        } else {
            match &o.min_separation {
                Some(x) => format!("{} m", show(x)),
                None => "never met (the robot never moves in its lane)".into(),
            }
        };
        s += &format!(
            "    {} (lane {}): {what}{}\n",
            label(scene, i),
            scene.obstacles[i].lane,
            if o.collides { ", collides" } else { "" }
        );
    }
    let path_speeds = |s: &mut String, path: &ScenePath| {
        for (i, speeds) in path.speeds.iter().enumerate() {
            *s += &format!("    {}: {}\n", scene.obstacles[i].name, speeds_rle(speeds));
        }
        *s += &observations(scene, path);
    };
    if let Some(c) = &result.counterexample {
        let hit: Vec<String> = c
            .replay
            .run
            .records
            .last()
            .map(|r| {
                (0..r.obstacles.len())
                    .filter(|&i| r.obstacles[i].collision())
                    .map(|i| label(scene, i))
                    .collect()
            })
            .unwrap_or_default();
        s += &format!(
            "  counterexample (shortest path, {} periods): {}, collides with {} by t = {} s\n",
            c.periods(),
            story(scene, c),
            hit.join(", "),
            value(c.periods() as f64 * scene.robot.control_period)
        );
        s += "    obstacle speeds per period:\n";
        path_speeds(&mut s, c);
    } else if let Some(c) = result.closest() {
        s += &format!(
            "  closest approach ({} periods): {}\n",
            c.periods(),
            story(scene, c)
        );
        s += "    obstacle speeds per period:\n";
        path_speeds(&mut s, c);
    }
    if let Some(path) = trace {
        let what = if result.counterexample.is_some() {
            "counterexample"
        } else if result.closest().is_some() {
            "closest approach"
        } else {
            "nothing (no path to write)"
        };
        s += &format!("  trace: {what} written to {}\n", path.display());
    }
    s
}

/// Observation errors listed per obstacle in the text summary.
const SHOWN_ERRORS: usize = 4;

/// What the environment showed on a path with noise or occlusion: each obstacle's first
/// sighting and the observation errors it chose (nothing for exact observations).
fn observations(scene: &Scene, path: &ScenePath) -> String {
    if path.plan.is_exact() {
        return String::new();
    }
    let dt = scene.robot.control_period;
    let mut s = String::from("    observations (the environment's choices):\n");
    for (i, o) in scene.obstacles.iter().enumerate() {
        let first = path.plan.hidden_until[i];
        let all = path.plan.errors.range((i, 0)..(i + 1, 0));
        let count = all.clone().count();
        let mut errors: Vec<String> = all
            .take(SHOWN_ERRORS)
            .map(|(&(_, k), (g, w))| {
                format!(
                    "t = {} s: gap {:+} m, speed {:+} m/s",
                    value(k as f64 * dt),
                    g.to_f64().value(),
                    w.to_f64().value()
                )
            })
            .collect();
        if count > SHOWN_ERRORS {
            errors.push(format!(
                "… {} more (--json lists them)",
                count - SHOWN_ERRORS
            ));
        }
        let sighting = if first == 0 {
            "seen from the start".to_string()
        } else if first >= path.periods() {
            "never shown".to_string()
        } else {
            format!("first shown at t = {} s", value(first as f64 * dt))
        };
        s += &format!("    {}: {sighting}", o.name);
        if !errors.is_empty() {
            s += &format!("; errors {}", errors.join("; "));
        }
        s += "\n";
    }
    s
}

fn number(x: Option<&Exact>) -> (Value, Value) {
    match x {
        Some(x) => (json!(x.to_f64().value()), json!(show_exact(x))),
        None => (Value::Null, Value::Null),
    }
}

fn path_json(path: &ScenePath) -> Value {
    let outcome = &path.replay.run.outcome;
    let mut v = json!({
        "periods": path.periods(),
        "starts": path.starts.iter().map(|x| x.to_f64().value()).collect::<Vec<_>>(),
        "starts_exact": path.starts.iter().map(show_exact).collect::<Vec<_>>(),
        "obstacle_speeds": path.speeds.iter()
            .map(|s| s.iter().map(|x| x.to_f64().value()).collect::<Vec<_>>())
            .collect::<Vec<_>>(),
        "obstacle_speeds_exact": path.speeds.iter()
            .map(|s| s.iter().map(show_exact).collect::<Vec<_>>())
            .collect::<Vec<_>>(),
        "collides": outcome.collided,
        "brake": outcome.brake.map(|(step, reason)| json!({"step": step, "reason": reason})),
        "lane_changes": outcome.lane_changes,
        "steps": path.replay.trace(),
    });
    // Only with noise or occlusion, so that exact observations print as before.
    if !path.plan.is_exact() {
        v["first_shown_step"] = json!(path.plan.hidden_until);
        v["observation_errors"] = path
            .plan
            .errors
            .iter()
            .map(|(&(i, k), (g, w))| {
                json!({
                    "obstacle": i, "step": k,
                    "gap": g.to_f64().value(), "speed": w.to_f64().value(),
                    "gap_exact": show_exact(g), "speed_exact": show_exact(w),
                })
            })
            .collect();
    }
    v
}

fn to_json(scene: &Scene, result: &SceneExploration, options: &Options) -> Value {
    let (least, least_exact) = if result.never_stops() {
        (Value::Null, Value::Null)
    } else {
        number(result.min_separation().as_ref())
    };
    let obstacles: Vec<Value> = result
        .obstacles
        .iter()
        .enumerate()
        .map(|(i, o)| {
            let (sep, sep_exact) = if o.unbounded {
                (Value::Null, Value::Null)
            } else {
                number(o.min_separation.as_ref())
            };
            let set = result.speeds.of(i).speeds();
            json!({
                "name": scene.obstacles[i].name,
                "lane": scene.obstacles[i].lane,
                "speeds": set.iter().map(|x| x.to_f64().value()).collect::<Vec<_>>(),
                "speeds_exact": set.iter().map(show_exact).collect::<Vec<_>>(),
                "starts_exact": result.starts[i].iter().map(show_exact).collect::<Vec<_>>(),
                "min_separation": sep,
                "min_separation_exact": sep_exact,
                "unbounded": o.unbounded,
                "collides": o.collides,
            })
        })
        .collect();
    json!({
        "scene": scene.name,
        "verdict": result.verdict.as_str(),
        "message": message(result, options),
        "complete": result.complete,
        "budget_exhausted": result.budget_exhausted,
        "horizon_reached": result.horizon_reached,
        "horizon": result.horizon,
        "states": result.states,
        "transitions": result.transitions,
        "depth": result.depth,
        "property": "always: never moving in an obstacle's lane with separation <= clearance",
        "min_separation": least,
        "min_separation_exact": least_exact,
        "never_stops": result.never_stops(),
        "worst_obstacle": result.worst().map(|i| scene.obstacles[i].name.clone()),
        "clearance": scene.robot.clearance,
        "obstacles": obstacles,
        "path": result.counterexample.as_ref().map(path_json),
        "closest": result.closest().map(path_json),
    })
}
