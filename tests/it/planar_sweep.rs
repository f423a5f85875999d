//! Sweeps and reports on planar grids: a cell is the planar certification of its problem
//! (and its certificate checks), the planar seed grid answers cell for cell as the line's
//! seed grid does (the embedding of docs/semantics.md §13.7), shards merge to the whole, the
//! report draws the worst cases from above, and bad axes exit 2 naming the grid and axis.

use std::path::Path;

use safereach::analysis::planar::certify_text;
use safereach::analysis::sweep::{Grid, Shard, SweepBudget};
use safereach::analysis::sweep_file::SweepFile;
use safereach::analysis::{Verdict, analyse};
use safereach::core::model::Problem;
use safereach::proof::planar::check::check_planar;

use crate::common::cli::safereach;
use crate::common::paths::root;
use crate::common::tmp;

/// A grid file in `dir` over the planar seed, with `axes` (TOML lines under `[axes]`).
fn planar_seed_grid(dir: &Path, name: &str, axes: &str) -> std::path::PathBuf {
    let base = root().join("problems/planar/seed-in-plane.toml");
    let text = format!("base = {:?}\n[axes]\n{axes}\n", base.display().to_string());
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// The line's seed with W and ρ set.
fn line_seed(w: f64, rho: f64) -> Problem {
    Problem::load_with_overrides(
        &root().join("problems/seed.toml"),
        &[
            format!("environment.obstacle_speed={w}"),
            format!("controller.reaction_radius={rho}"),
        ],
    )
    .unwrap()
}

/// Four cells across the boundary (two refuted, two certified at a margin of 0.11–0.33 m):
/// each planar cell's verdict is the line's, its bracket holds the line's s*, its certificate
/// (certified again from the cell's overrides) passes `check`, and a refuted cell's witness
/// reaches the clearance.
#[test]
fn planar_cells_answer_as_the_line_does() {
    let dir = tmp();
    let path = planar_seed_grid(
        dir.path(),
        "corners",
        "\"obstacle.0.max_speed\" = [0.15, 0.25]\n\"controller.reaction_radius\" = [1.0, 1.6]",
    );
    let grid = Grid::load(&path).unwrap();
    let cells = grid
        .run(Shard::ALL, 0, 0, &SweepBudget::default(), || {})
        .unwrap();
    assert_eq!(cells.len(), 4);
    let mut verdicts = Vec::new();
    for r in &cells {
        let w = r.axes["obstacle.0.max_speed"].as_f64().unwrap();
        let rho = r.axes["controller.reaction_radius"].as_f64().unwrap();
        let line = analyse(&line_seed(w, rho)).unwrap();
        assert_eq!(
            r.verdict, line.verdict,
            "cell {} (W = {w}, ρ = {rho})",
            r.cell
        );
        let lower = r.lower_bound.expect("a planar cell states its lower bound");
        let upper = r.upper_bound.expect("every seed cell has a witness");
        assert!(lower <= upper, "cell {}: [{lower}, {upper}]", r.cell);
        if line.verdict == Verdict::Certified {
            // Euclidean separation is the line's gap here (a point on the x axis).
            let s = line.min_separation.unwrap();
            assert!(
                lower <= s + 1e-9 && s <= upper + 1e-9,
                "cell {}: {s} ∉ [{lower}, {upper}]",
                r.cell
            );
            assert!(
                upper - lower <= 1e-6 + 1e-12,
                "cell {}: bracket wider than 1e-6",
                r.cell
            );
        } else {
            // Distances are ≥ 0 in the plane: the line's penetration is a touch here.
            assert!(
                upper <= 0.0,
                "cell {}: refuted with a witness at {upper}",
                r.cell
            );
            let c = r
                .closest
                .as_ref()
                .expect("a refuted cell names its closest obstacle");
            assert_eq!(c.obstacle, "oncoming");
        }
        let sets: Vec<String> = grid
            .cell_values(r.cell)
            .iter()
            .map(|(k, v)| format!("{k}={v}"))
            .collect();
        let (_, cert) = certify_text(&grid.base_text, "base", &sets).unwrap();
        check_planar(&cert).unwrap();
        assert_eq!(cert.lower_bound, lower);
        verdicts.push(r.verdict);
    }
    assert!(verdicts.contains(&Verdict::Certified) && verdicts.contains(&Verdict::Refuted));
}

/// The committed report of the whole planar seed grid (which `committed_reports_are_what_
/// report_regenerates` holds current) says what the committed line seed grid says, cell for
/// cell: the same verdict, and the planar bracket around the line's s* where certified; no
/// certified cell collided in its random planar runs.
#[test]
fn the_planar_seed_grid_report_agrees_with_the_line_seed_grid_report() {
    let read = |name: &str| {
        let path = root().join("reports").join(name);
        SweepFile::from_jsonl(&std::fs::read_to_string(&path).unwrap(), name).unwrap()
    };
    let plane = read("seed-in-plane-grid.jsonl");
    let line = read("seed-grid.jsonl");
    assert_eq!(plane.cells.len(), 16);
    for p in &plane.cells {
        let w = &p.axes["obstacle.0.max_speed"];
        let rho = &p.axes["controller.reaction_radius"];
        let l = line
            .cells
            .iter()
            .find(|l| {
                &l.axes["environment.obstacle_speed"] == w
                    && &l.axes["controller.reaction_radius"] == rho
            })
            .unwrap_or_else(|| panic!("the line grid has no cell W = {w}, ρ = {rho}"));
        assert_eq!(p.verdict, l.verdict, "W = {w}, ρ = {rho}");
        if p.verdict == Verdict::Certified {
            let s = l.min_separation.unwrap();
            let (lo, up) = (p.lower_bound.unwrap(), p.upper_bound.unwrap());
            assert!(
                lo <= s + 1e-9 && s <= up + 1e-9,
                "W = {w}, ρ = {rho}: {s} ∉ [{lo}, {up}]"
            );
            assert_eq!(p.collisions, Some(0), "W = {w}, ρ = {rho}");
        }
    }
}

/// `sweep` of a planar grid in two shards, merged by `report --from`, reports the cells the
/// whole sweep has (the same bytes in JSON Lines); the report draws the refuted cell from
/// above with a scale bar and legend, and lists the planar obstacle.
#[test]
fn planar_shards_merge_to_the_whole_and_the_report_draws_from_above() {
    let dir = tmp();
    let path = planar_seed_grid(
        dir.path(),
        "two",
        "\"obstacle.0.max_speed\" = [0.15]\n\"controller.reaction_radius\" = [1.0, 1.4]",
    );
    for i in 0..2 {
        safereach(&root())
            .args(["sweep"])
            .arg(&path)
            .args(["--runs", "3", "--shard", &format!("{i}/2"), "--out"])
            .arg(dir.path().join("shards"))
            .assert()
            .success();
    }
    safereach(&root())
        .args(["sweep"])
        .arg(&path)
        .args(["--runs", "3", "--out"])
        .arg(dir.path().join("whole"))
        .assert()
        .success();
    safereach(&root())
        .args(["report"])
        .arg(&path)
        .arg("--from")
        .arg(dir.path().join("shards"))
        .arg("--out")
        .arg(dir.path().join("report"))
        .assert()
        .success();
    let whole = std::fs::read_to_string(dir.path().join("whole/two.jsonl")).unwrap();
    let merged = std::fs::read_to_string(dir.path().join("report/two.jsonl")).unwrap();
    assert_eq!(whole, merged);
    let md = std::fs::read_to_string(dir.path().join("report/two.md")).unwrap();
    assert!(
        md.contains("base planar problem `seed-in-plane.toml`"),
        "{md}"
    );
    assert!(md.contains("| 0 | \"oncoming\" | 0 | (10, 0) | 0.15 (the axis' one value) | fixed along (-1, 0) | the plane |"), "{md}");
    assert!(
        md.contains("![cell 0 seen from above](two-cell-0-top.svg)"),
        "{md}"
    );
    assert!(
        md.contains("![cell 1 seen from above](two-cell-1-top.svg)"),
        "{md}"
    );
    let svg = std::fs::read_to_string(dir.path().join("report/two-cell-0-top.svg")).unwrap();
    for label in [
        "x (m)",
        "y (m)",
        "oncoming",
        "closest approach",
        " m</text>",
    ] {
        assert!(svg.contains(label), "the top view lacks {label:?}");
    }
    // The seed's path runs 10⁵ m along x; the view keeps to where the robot and obstacle are.
    assert!(
        !svg.contains(">100000<") && !svg.contains(">200000<"),
        "the path is drawn whole"
    );
}

/// Axis values a planar problem refuses, and keys it does not have, stop the sweep with exit
/// 2 naming the grid file and the axis.
#[test]
fn bad_planar_axes_exit_2_naming_the_grid_and_the_axis() {
    let dir = tmp();
    let cases = [
        (
            "negative",
            "\"obstacle.0.max_speed\" = [0.1, -0.2]",
            "obstacle.0.max_speed",
        ),
        ("radius", "\"robot.radius\" = [-1.0]", "robot.radius"),
        (
            "line-key",
            "\"environment.obstacle_speed\" = [0.2]",
            "environment.obstacle_speed",
        ),
        (
            "no-obstacle",
            "\"obstacle.3.max_speed\" = [0.2]",
            "obstacle.3",
        ),
    ];
    for (name, axes, key) in cases {
        let path = planar_seed_grid(dir.path(), name, axes);
        let out = safereach(&root())
            .arg("sweep")
            .arg(&path)
            .arg("--out")
            .arg(dir.path().join("out"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {err}");
        assert!(err.contains(&format!("{name}.toml")), "{name}: {err}");
        assert!(err.contains(key), "{name}: {err}");
    }
}
