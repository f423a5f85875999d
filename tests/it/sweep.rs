//! Sweeps and reports: cells equal single analyses, shards merge to the whole sweep, output
//! round-trips, and `safereach report` regenerates exactly what is committed in reports/.

use std::path::{Path, PathBuf};

use safereach::analysis::scene::analyse_scene;
use safereach::analysis::sweep::{Grid, Shard, SweepBudget};
use safereach::analysis::sweep_file::{self, SweepFile};
use safereach::analysis::{Verdict, analyse};
use safereach::core::num::f64_at_most;

use crate::common::cli::safereach;
use crate::common::paths::root;
use crate::common::tmp;

fn seed_grid() -> Grid {
    Grid::load(&root().join("problems/seed-grid.toml")).expect("the seed grid loads")
}

#[test]
fn cells_are_the_cartesian_product_last_axis_fastest() {
    let grid = seed_grid();
    assert_eq!(grid.len(), 16);
    let values = grid.cell_values(6);
    let shown: Vec<String> = values.iter().map(|(k, v)| format!("{k}={v}")).collect();
    assert_eq!(
        shown,
        [
            "controller.assumed_obstacle_speed=0.2",
            "environment.obstacle_speed=0.2",
            "controller.reaction_radius=1.4"
        ]
    );
}

#[test]
fn every_cell_equals_a_single_analysis() {
    let grid = seed_grid();
    let results = grid
        .run(Shard::ALL, 0, 0, &SweepBudget::default(), || {})
        .expect("sweeps");
    assert_eq!(results.len(), grid.len());
    for r in &results {
        let problem = grid.problem(r.cell).expect("cell problem");
        let a = analyse(&problem).expect("analyses");
        assert_eq!(r.verdict, a.verdict, "cell {}", r.cell);
        assert_eq!(
            r.lower_bound,
            a.lower_bound.as_ref().map(f64_at_most),
            "cell {}",
            r.cell
        );
        assert_eq!(r.never_stops, a.never_stops, "cell {}", r.cell);
        match (r.min_separation, a.min_separation) {
            (Some(x), Some(y)) => assert!((x - y).abs() <= 1e-6, "cell {}: {x} vs {y}", r.cell),
            (x, y) => assert_eq!(x, y, "cell {}", r.cell),
        }
    }
}

/// A grid over a scene: every cell is the scene analyser's answer for the scene with the
/// cell's overrides (an obstacle's bound by index, the radius), and Monte Carlo over a
/// certified cell never collides.
#[test]
fn every_scene_cell_equals_a_scene_analysis() {
    let grid = Grid::load(&root().join("problems/scene-oncoming-grid.toml")).expect("loads");
    assert_eq!(grid.kind, safereach::core::grid::BaseKind::Scene);
    let results = grid
        .run(Shard::ALL, 10, 3, &SweepBudget::default(), || {})
        .expect("sweeps");
    for r in &results {
        let safereach::analysis::sweep::CellInput::Scene(scene) = grid.input(r.cell).expect("cell")
        else {
            panic!("a scene grid's cells are scenes");
        };
        let w = r.axes["obstacle.1.max_speed"].as_f64().unwrap();
        assert_eq!(scene.obstacles[1].max_speed, w);
        let a = analyse_scene(&scene).expect("analyses");
        assert_eq!(r.verdict, a.verdict, "cell {}", r.cell);
        assert_eq!(r.lower_bound, a.lower_bound.as_ref().map(f64_at_most));
        assert_eq!(r.min_separation, a.min_separation, "cell {}", r.cell);
        if r.verdict == Verdict::Certified {
            assert_eq!(r.collisions, Some(0), "cell {}", r.cell);
        }
    }
}

fn shard_outputs(grid: &Grid, count: usize, runs: usize, seed: u64) -> Vec<(String, SweepFile)> {
    (0..count)
        .map(|index| {
            let f = grid
                .sweep(
                    Shard { index, count },
                    runs,
                    seed,
                    &SweepBudget::default(),
                    || {},
                )
                .expect("shard sweeps");
            (format!("shard-{index}"), f)
        })
        .collect()
}

#[test]
fn shards_merged_equal_the_whole_sweep() {
    let grid = seed_grid();
    let whole = grid
        .sweep(Shard::ALL, 20, 5, &SweepBudget::default(), || {})
        .expect("sweeps");
    let parts = shard_outputs(&grid, 3, 20, 5);
    assert!(
        parts
            .iter()
            .all(|(_, p)| !p.cells.is_empty() && p.cells.len() < whole.cells.len())
    );
    let merged = sweep_file::merge(&grid, parts.clone()).expect("merges");
    assert_eq!(merged, whole);
    // Written out, the merge is the unsharded sweep's output byte for byte.
    assert_eq!(merged.to_jsonl(), whole.to_jsonl());
    assert_eq!(merged.to_csv(), whole.to_csv());
}

/// Every way a set of outputs can fail to be the grid's whole sweep is refused, naming the
/// file and what differs.
#[test]
fn merges_refuse_missing_duplicated_foreign_and_mixed_outputs() {
    let grid = seed_grid();
    let parts = shard_outputs(&grid, 3, 20, 5);
    let refused = |parts: Vec<(String, SweepFile)>| sweep_file::merge(&grid, parts).unwrap_err();
    let e = refused(parts[..2].to_vec());
    assert!(e.contains("shard 2/3") && e.contains("missing"), "{e}");
    let mut twice = parts.clone();
    twice.push(("again".into(), parts[0].1.clone()));
    let e = refused(twice);
    assert!(e.contains("again and shard-0 are both shard 0/3"), "{e}");
    // Another sharding, other Monte Carlo runs, a cell dropped, a cell of another shard.
    let mut mixed = parts.clone();
    mixed[2] = shard_outputs(&grid, 4, 20, 5).remove(2);
    assert!(refused(mixed).contains("different shardings"));
    let mut other_runs = parts.clone();
    other_runs[1] = shard_outputs(&grid, 3, 10, 5).remove(1);
    assert!(refused(other_runs).contains("Monte Carlo runs"));
    let mut dropped = parts.clone();
    dropped[1].1.cells.remove(2);
    let e = refused(dropped);
    assert!(
        e.starts_with("shard-1: cell") && e.contains("missing"),
        "{e}"
    );
    let mut foreign = parts.clone();
    let stray = foreign[0].1.cells[0].clone();
    foreign[1].1.cells.push(stray);
    assert!(refused(foreign).starts_with("shard-1: cell 0"));
    let mut edited = parts.clone();
    edited[0].1.cells[1]
        .axes
        .insert("controller.reaction_radius".into(), 9.0.into());
    assert!(refused(edited).contains("axis values are not the grid's"));
    // Another version wrote it.
    let mut old = parts.clone();
    old[2].1.provenance.version = "0.0.1".into();
    let e = refused(old);
    assert!(
        e.starts_with("shard-2: ") && e.contains("safereach 0.0.1"),
        "{e}"
    );
}

/// The stale cases: results merged against a grid whose axes changed, or whose base
/// problem changed (braking 0.05 → 0.02 turns cell 2 from certified into refuted), are
/// refused with what changed.
#[test]
fn outputs_of_another_grid_or_base_problem_are_refused() {
    let grid = seed_grid();
    let parts = shard_outputs(&grid, 2, 0, 0);
    let dir = tmp();
    std::fs::copy(
        root().join("problems/seed.toml"),
        dir.path().join("seed.toml"),
    )
    .unwrap();
    let grid_text = std::fs::read_to_string(root().join("problems/seed-grid.toml")).unwrap();
    let at = dir.path().join("seed-grid.toml");
    let other_axes = Grid::from_toml_str(&grid_text.replace("0.25, 0.3]", "0.25, 0.5]"), &at)
        .expect("the edited grid loads");
    let e = sweep_file::merge(&other_axes, parts.clone()).unwrap_err();
    assert!(
        e.contains(
            "axis environment.obstacle_speed was [0.15,0.2,0.25,0.3], is now [0.15,0.2,0.25,0.5]"
        ),
        "{e}"
    );
    let base = std::fs::read_to_string(root().join("problems/seed.toml")).unwrap();
    assert!(base.contains("braking = 0.05"));
    std::fs::write(
        dir.path().join("seed.toml"),
        base.replace("braking = 0.05", "braking = 0.02"),
    )
    .unwrap();
    let other_base = Grid::from_toml_str(&grid_text, &at).unwrap();
    let e = sweep_file::merge(&other_base, parts.clone()).unwrap_err();
    assert!(
        e.contains("base problem has changed since: robot.braking was 0.05, is now 0.02"),
        "{e}"
    );
    // ...and it matters: cell 2 was certified, and is refuted now.
    assert_eq!(parts[0].1.cells[1].cell, 2);
    assert_eq!(parts[0].1.cells[1].verdict, Verdict::Certified);
    let now = other_base
        .sweep(Shard::ALL, 0, 0, &SweepBudget::default(), || {})
        .unwrap();
    assert_eq!(now.cells[2].verdict, Verdict::Refuted);
    // A comment added to the base changes nothing that was computed: still accepted.
    std::fs::write(dir.path().join("seed.toml"), format!("# a note\n{base}")).unwrap();
    let commented = Grid::from_toml_str(&grid_text, &at).unwrap();
    assert!(sweep_file::merge(&commented, parts).is_ok());
}

#[test]
fn jsonl_round_trips_and_csv_has_one_row_per_cell() {
    let grid = seed_grid();
    let file = grid
        .sweep(Shard::ALL, 10, 1, &SweepBudget::default(), || {})
        .expect("sweeps");
    let text = file.to_jsonl();
    assert_eq!(
        SweepFile::from_jsonl(&text, "test").expect("reads back"),
        file
    );
    let mut lines = text.lines();
    let head: serde_json::Value = serde_json::from_str(lines.next().unwrap()).unwrap();
    assert_eq!(head["sweep"]["grid"], "seed-grid");
    assert_eq!(head["sweep"]["cells"], 16);
    assert_eq!(head["sweep"]["runs"], 10);
    let first: serde_json::Value = serde_json::from_str(lines.next().unwrap()).unwrap();
    assert_eq!(first["environment.obstacle_speed"], 0.15);
    assert!(first["verdict"].is_string());
    let csv = file.to_csv();
    assert_eq!(csv.lines().count(), file.cells.len() + 1);
    assert!(csv.starts_with("cell,controller.assumed_obstacle_speed,environment.obstacle_speed,controller.reaction_radius,verdict"));
    // Without its provenance line, an output is not read.
    let headless: String = text.lines().skip(1).map(|l| format!("{l}\n")).collect();
    let e = SweepFile::from_jsonl(&headless, "old.jsonl").unwrap_err();
    assert!(e.starts_with("old.jsonl:1: no provenance record"), "{e}");
}

#[test]
fn simulation_never_contradicts_a_certified_cell() {
    let grid = seed_grid();
    let results = grid
        .run(Shard::ALL, 200, 11, &SweepBudget::default(), || {})
        .expect("sweeps");
    for r in results.iter().filter(|r| r.verdict == Verdict::Certified) {
        assert_eq!(r.collisions, Some(0), "cell {}", r.cell);
        assert!(r.simulated_min_separation.unwrap() >= r.lower_bound.unwrap() - 1e-9);
    }
}

#[test]
fn bad_grids_name_the_file_and_the_reason() {
    let dir = tmp();
    let write = |name: &str, text: &str| -> PathBuf {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    std::fs::copy(
        root().join("problems/seed.toml"),
        dir.path().join("seed.toml"),
    )
    .unwrap();
    let cases = [
        (
            "unknown-key.toml",
            "base = \"seed.toml\"\n[axes]\n\"robot.wheels\" = [1.0]\n",
            "robot.wheels",
        ),
        (
            "not-array.toml",
            "base = \"seed.toml\"\n[axes]\n\"robot.braking\" = 0.5\n",
            "array",
        ),
        (
            "bad-value.toml",
            "base = \"seed.toml\"\n[axes]\n\"robot.braking\" = [0.5, -1.0]\n",
            "must be > 0",
        ),
        (
            "no-base.toml",
            "base = \"missing.toml\"\n[axes]\n\"robot.braking\" = [0.5]\n",
            "missing.toml",
        ),
        (
            "no-axes.toml",
            "base = \"seed.toml\"\n[axes]\n",
            "names no key",
        ),
    ];
    for (name, text, expect) in cases {
        let path = write(name, text);
        let err = Grid::load(&path).expect_err(name).to_string();
        assert!(err.contains(expect), "{name}: {err}");
        assert!(err.contains(name) || err.contains("--set"), "{name}: {err}");
    }
}

/// The files in `dir`, by name, with their bytes.
fn contents(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| {
            (
                p.file_name().unwrap().to_string_lossy().into_owned(),
                std::fs::read(&p).unwrap(),
            )
        })
        .collect();
    out.sort();
    out
}

/// `safereach report` regenerates reports/ byte for byte: the committed report is what the
/// code says (regenerate with `cargo run --release -- report` after changing either).
#[test]
fn committed_reports_are_what_report_regenerates() {
    let dir = tmp();
    safereach(&root())
        .args(["report", "--out"])
        .arg(dir.path())
        .assert()
        .success();
    let fresh = contents(dir.path());
    let committed = contents(&root().join("reports"));
    let names = |v: &[(String, Vec<u8>)]| v.iter().map(|f| f.0.clone()).collect::<Vec<_>>();
    assert_eq!(
        names(&fresh),
        names(&committed),
        "reports/ holds other files than report writes"
    );
    for ((name, a), (_, b)) in fresh.iter().zip(&committed) {
        assert!(
            a == b,
            "reports/{name} differs from what `safereach report` writes now: regenerate it"
        );
    }
}

#[test]
fn sweep_cli_writes_shards_that_report_merges() {
    let dir = tmp();
    for i in 0..2 {
        safereach(&root())
            .args([
                "sweep",
                "problems/seed-grid.toml",
                "--runs",
                "10",
                "--shard",
                &format!("{i}/2"),
                "--out",
            ])
            .arg(dir.path().join("shards"))
            .assert()
            .success();
    }
    let out = dir.path().join("report");
    safereach(&root())
        .args(["report", "problems/seed-grid.toml", "--from"])
        .arg(dir.path().join("shards"))
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
    let md = std::fs::read_to_string(out.join("seed-grid.md")).unwrap();
    assert!(md.contains("16 cells"), "{md}");
    assert!(md.contains("(a) Too small a reaction radius collides even when the assumption holds"));
    // Merging half the shards fails with a message naming what is missing.
    std::fs::remove_file(dir.path().join("shards/seed-grid.shard-1-of-2.jsonl")).unwrap();
    safereach(&root())
        .args(["report", "problems/seed-grid.toml", "--from"])
        .arg(dir.path().join("shards"))
        .arg("--out")
        .arg(dir.path().join("report2"))
        .assert()
        .code(2)
        .stderr(predicates::str::contains("missing"));
}
