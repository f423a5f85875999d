//! The Markdown page of a sweep: header, axes and the base's values, the figures (with the
//! certified map of the (W, ρ) plane where the grid spans one), the table of cells, the
//! safe-radius table, a scene's or planar grid's worst cases and the findings, in that
//! order.

use std::fmt::Write as _;

use super::axes::label;
use super::base_values::write_base_values;
use super::cells::{axis_value, collisions_per_runs, fmt_opt, separation};
use super::figures::{slice_lines, write_figures};
use super::findings::{findings, scene_worst_cases};
use super::planar_views::PlanarView;
use super::region_plot::{self, PointCell};
use super::{ASSUMED_KEY, Curve, Report};
use crate::analysis::sweep::{CellResult, Grid};
use crate::core::grid::BaseKind;
use crate::core::model::Problem;
use crate::core::planar::PlanarProblem;
use crate::core::scene::Scene;
use crate::proof::region_map::RegionMap;

/// Builds the report of a grid from its (complete, ordered) cell results, curve and, for a
/// grid over W and ρ, the certified map of that plane; for a planar grid, `views` are its
/// worst cases drawn from above ([`super::planar_views`]).
pub fn grid_report(
    grid: &Grid,
    results: &[CellResult],
    curve: &Curve,
    map: Option<&RegionMap>,
    views: &[PlanarView],
) -> Report {
    let mut md = String::new();
    write_header(&mut md, grid, results.len());
    let assumed = assumed_speed(grid, results);
    let mut figures = write_figures(&mut md, grid, results, curve, assumed);
    if let Some(map) = map {
        figures.push(write_certified_map(&mut md, grid, results, map));
    }
    write_table(&mut md, grid, results);
    write_curve_table(&mut md, grid, curve);
    if grid.kind == BaseKind::Planar {
        write_planar_worst_cases(&mut md, results, views, &mut figures);
    }
    if grid.kind == BaseKind::Scene {
        let _ = writeln!(md, "\n## Worst cases\n");
        let _ = writeln!(
            md,
            "Which obstacle's separation is s* in each cell, in which lane, and why the robot \
             braked (as `safereach certify` names it):\n"
        );
        md.push_str(&scene_worst_cases(results));
    }
    let _ = writeln!(md, "\n## The seed paper's findings, checked\n");
    md.push_str(&findings(results, speed_axis(grid), assumed));
    Report {
        markdown: md,
        figures,
    }
}

/// The certified map's section: what it covers and its figure, the cells as dots.
fn write_certified_map(
    md: &mut String,
    grid: &Grid,
    results: &[CellResult],
    map: &RegionMap,
) -> (String, String) {
    let (w, rho) = (&map.ranges[0], &map.ranges[1]);
    let cells: Vec<PointCell> = results
        .iter()
        .filter_map(|r| {
            let x = r.axes.get(&w.key())?.as_f64()?;
            let y = r.axes.get(&rho.key())?.as_f64()?;
            Some((x, y, r.verdict))
        })
        .collect();
    let file = format!("{}-region.svg", grid.name);
    let _ = writeln!(md, "\n## Certified map of the plane\n");
    let _ = writeln!(
        md,
        "Not just the {} cells: every point of W ∈ [{}, {}] m/s × ρ ∈ [{}, {}] m, one proof per \
         leaf (`safereach region`, depth ≤ {}; `safereach check` verifies the map{}). **Certified: \
         {:.1}% of the plane**; refuted {:.1}% (each such leaf names a colliding point, and no \
         corner of it that was analysed certifies); undecided {:.1}% (leaves along the boundary \
         at the depth limit). The dots are the grid's cells, coloured by their own verdicts.\n",
        cells.len(),
        w.lo,
        w.hi,
        rho.lo,
        rho.hi,
        map.depth,
        if map.planar.is_some() {
            "; a planar leaf's proof is one planar certificate at its weak corner, \
             docs/reductions.md Lemma P7"
        } else {
            ""
        },
        100.0 * map.coverage.certified,
        100.0 * map.coverage.refuted,
        100.0 * map.coverage.undecided,
    );
    let _ = writeln!(md, "![certified map of the (W, ρ) plane]({file})\n");
    (file, region_plot::svg_with_points(map, &cells))
}

/// A planar grid's worst cases: each drawn cell's figure, and which obstacle comes closest
/// in which cells, when, and why the robot braked.
fn write_planar_worst_cases(
    md: &mut String,
    results: &[CellResult],
    views: &[PlanarView],
    figures: &mut Vec<(String, String)>,
) {
    let _ = writeln!(md, "\n## Worst cases seen from above\n");
    if views.is_empty() {
        let _ = writeln!(md, "No cell has a witness to draw.");
    }
    for v in views {
        let what = match v.verdict {
            crate::analysis::Verdict::Refuted => {
                "the refuted cell whose witness comes closest (its collision, replayed exactly)"
            }
            _ => "the certified cell with the least proved margin (its closest behaviour found)",
        };
        let name = results
            .iter()
            .find(|r| r.cell == v.cell)
            .map(cell_axes)
            .unwrap_or_default();
        let _ = writeln!(
            md,
            "Cell {} ({name}): {what}. The path (dashed), the robot's disc every few steps, \
             each obstacle's trajectory and disc, the danger zone when the robot brakes, and the \
             closest instant (filled discs, joined); metres, x right, y up.\n",
            v.cell
        );
        let _ = writeln!(md, "![cell {} seen from above]({})\n", v.cell, v.file);
        figures.push((v.file.clone(), v.svg.clone()));
    }
}

/// A cell's axis values as `key = value, …`.
fn cell_axes(r: &CellResult) -> String {
    let parts: Vec<String> = r.axes.iter().map(|(k, v)| format!("`{k}` = {v}")).collect();
    parts.join(", ")
}

/// The obstacle speed-bound axis the findings read W from: W, or the first scene or planar
/// obstacle bound the grid varies.
fn speed_axis(grid: &Grid) -> Option<&str> {
    let keys = || grid.axes.iter().map(|(k, _)| k.as_str());
    if grid.kind != BaseKind::Problem {
        keys().find(|k| super::axes::is_speed_bound(k))
    } else {
        keys().find(|k| *k == super::SPEED_KEY)
    }
}

/// A path's file name as text (empty when it has none).
fn file_name(path: &std::path::Path) -> String {
    path.file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Title, provenance line, the list of axes and the base's values.
fn write_header(md: &mut String, grid: &Grid, cells: usize) {
    let _ = writeln!(md, "# Sweep `{}`\n", grid.name);
    let runs = if grid.runs > 0 {
        format!(
            ", {} seeded Monte Carlo runs per cell (seed {})",
            grid.runs, grid.seed
        )
    } else {
        String::new()
    };
    let _ = writeln!(
        md,
        "Generated by `safereach report` from `{}` (base {} `{}`): {cells} cells{runs}. \
         Do not edit; regenerate.\n",
        file_name(&grid.path),
        grid.kind.as_str(),
        file_name(&grid.base_path),
    );
    let _ = writeln!(md, "Axes:\n");
    for (k, v) in &grid.axes {
        let vals: Vec<String> = v.iter().map(|x| x.to_string()).collect();
        let _ = writeln!(md, "- `{k}`: {}", vals.join(", "));
    }
    write_base_values(md, grid, &file_name(&grid.base_path));
}

/// The speed the controller assumes: the cells' axis value, else the base problem's or
/// scene's.
fn assumed_speed(grid: &Grid, results: &[CellResult]) -> Option<f64> {
    results
        .first()
        .and_then(|r| axis_value(r, ASSUMED_KEY))
        .or_else(|| match grid.kind {
            BaseKind::Scene => Scene::from_toml_str(&grid.base_text, "base")
                .ok()
                .map(|s| s.controller.assumed_obstacle_speed),
            BaseKind::Planar => PlanarProblem::from_toml_str(&grid.base_text, "base")
                .ok()
                .map(|p| p.controller.assumed_obstacle_speed),
            BaseKind::Problem => Problem::from_toml_str(&grid.base_text, "base")
                .ok()
                .map(|p| p.controller.assumed_obstacle_speed),
        })
}

/// The table of cells: one column per axis, then the verdict and the numbers, and for a
/// scene or planar grid the worst case.
fn write_table(md: &mut String, grid: &Grid, results: &[CellResult]) {
    let worst = grid.kind != BaseKind::Problem;
    let keys: Vec<&String> = grid.axes.iter().map(|(k, _)| k).collect();
    let _ = write!(md, "\n| cell |");
    for k in &keys {
        let _ = write!(md, " `{k}` |");
    }
    let _ = write!(
        md,
        " verdict | s* (m) | lower bound (m) | collisions / runs | closest simulated (m) |"
    );
    let _ = writeln!(md, "{}", if worst { " worst case |" } else { "" });
    let _ = write!(md, "|---|");
    for _ in &keys {
        let _ = write!(md, "---|");
    }
    let _ = writeln!(
        md,
        "---|---|---|---|---|{}",
        if worst { "---|" } else { "" }
    );
    for r in results {
        write_row(md, &keys, r, worst);
    }
}

/// One cell's row of the table (`scene`: with the worst-case column).
fn write_row(md: &mut String, keys: &[&String], r: &CellResult, scene: bool) {
    let _ = write!(md, "| {} |", r.cell);
    for k in keys {
        let value = r
            .axes
            .get(k.as_str())
            .map(|v| v.to_string())
            .unwrap_or_default();
        let _ = write!(md, " {value} |");
    }
    let _ = write!(
        md,
        " {} | {} | {} | {} | {} |",
        r.verdict.as_str(),
        separation(r),
        r.lower_bound
            .map(|x| crate::core::show::down(x, 6))
            .unwrap_or_else(|| "–".into()),
        collisions_per_runs(r).unwrap_or_else(|| "–".into()),
        fmt_opt(r.simulated_min_separation, 3)
    );
    if scene {
        let worst = match (&r.worst, &r.closest) {
            (Some(w), _) => {
                format!("\"{}\", lane {}: {}", w.name, w.lane, w.cause.short()).replace('|', "\\|")
            }
            (None, Some(c)) => format!(
                "\"{}\" at t = {:.2} s: {}",
                c.obstacle,
                c.at,
                c.guard.as_deref().unwrap_or("never brakes")
            )
            .replace('|', "\\|"),
            (None, None) => "–".into(),
        };
        let _ = write!(md, " {worst} |");
    }
    let _ = writeln!(md);
}

/// The safe-radius section, a table per slice (nothing for a single-obstacle grid without a
/// curve; for a scene grid without one, why).
fn write_curve_table(md: &mut String, grid: &Grid, curve: &Curve) {
    let (key, slices, total) = match curve {
        Curve::Radius { key, slices, total } => (key, slices, *total),
        Curve::NotApplicable(why) => {
            let _ = writeln!(md, "\n## Safe radius ρ*(W)\n");
            let _ = writeln!(md, "No safe-radius curve: {why}.");
            return;
        }
        Curve::None => return,
    };
    let l = label(grid, key);
    let w = l.symbol.clone().unwrap_or_else(|| "W".into());
    let _ = writeln!(md, "\n## Safe radius ρ*({w})\n");
    if grid.kind == BaseKind::Scene {
        let _ = writeln!(
            md,
            "The smallest certified reaction radius for each {}, every other key at its value \
             in the base scene or the grid's single value (`safereach radius` on the scene, to \
             {:e} m, each certified; none is searched above the farthest obstacle start in the robot's lane or \
             the sensing range):\n",
            l.meaning,
            crate::analysis::scene_radius::TOLERANCE
        );
    } else {
        let _ = writeln!(
            md,
            "The smallest certified reaction radius for each obstacle speed bound W \
             (`safereach radius`, to 1e-10 m, each certified), per slice: the base problem with the slice's \
             values of the other axes.\n"
        );
    }
    for (k, c) in slices.iter().enumerate() {
        if k > 0 {
            let _ = writeln!(md);
        }
        if !c.slice.is_empty() {
            let _ = writeln!(md, "Slice: {}.\n", slice_lines(grid, &c.slice).join(", "));
        }
        let _ = writeln!(md, "| {w} ({}) | ρ* (m) |\n|---|---|", l.unit);
        for (w, rho) in &c.points {
            // Ten decimals: the searches answer on that grid, so the number shown is the
            // certified radius itself (fewer would round it down, to the unsafe side).
            let rho = rho
                .map(|r| format!("{r:.10}"))
                .unwrap_or_else(|| "none".into());
            let _ = writeln!(md, "| {w} | {rho} |");
        }
    }
    if total > slices.len() {
        let _ = writeln!(
            md,
            "\nThe grid has {total} slices across its other axes; the first {} are computed.",
            slices.len()
        );
    }
}
