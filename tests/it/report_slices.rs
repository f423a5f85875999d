//! Reports never mix slices: for a single-obstacle grid over W, ρ and two more axes, every
//! heat map and every radius curve draws exactly its own slice's cells and names its slice,
//! and each slice's curve is `safe_radius` run afresh on that slice's problem. A grid
//! without W and ρ gets heat maps over the axes it has; one with a single numeric axis says
//! why it has none; the header lists the base problem's values with units.

use std::path::Path;

use safereach::analysis::radius::safe_radius;
use safereach::core::model::Problem;

use crate::common::cli::{files, safereach};
use crate::common::paths::root;
use crate::common::tmp;
use crate::sweep_report::{attr, parse, tiles};

/// Writes `grid` as `<name>.toml` beside a copy of the seed problem, runs `report` on it
/// and returns the page and the output directory.
fn report(dir: &Path, name: &str, grid: &str) -> (String, std::path::PathBuf) {
    std::fs::copy(root().join("problems/seed.toml"), dir.join("seed.toml")).unwrap();
    std::fs::write(dir.join(format!("{name}.toml")), grid).unwrap();
    let out = dir.join("out");
    safereach(dir)
        .args(["report", &format!("{name}.toml"), "--out"])
        .arg(&out)
        .assert()
        .success();
    let md = std::fs::read_to_string(out.join(format!("{name}.md"))).unwrap();
    (md, out)
}

/// The fills of an SVG's `<circle>` elements (the curve plot's cell dots), sorted.
fn dot_fills(svg: &str) -> Vec<String> {
    let mut fills: Vec<String> = svg
        .lines()
        .filter(|l| l.starts_with("<circle"))
        .map(|l| attr(l, "fill").unwrap())
        .collect();
    fills.sort();
    fills
}

/// The rows `(W, ρ*)` of the radius table under the page's line `Slice: <slice>.`.
fn slice_table(md: &str, slice: &str) -> Vec<(String, Option<f64>)> {
    let section = &md[md.find("## Safe radius").expect("a radius section")..];
    let start = section
        .find(&format!("Slice: {slice}.\n"))
        .unwrap_or_else(|| panic!("a table for slice {slice}: {section}"));
    section[start..]
        .lines()
        .skip_while(|l| !l.starts_with("|---"))
        .skip(1)
        .take_while(|l| l.starts_with("| "))
        .map(|l| {
            let cols: Vec<&str> = l.split('|').map(str::trim).collect();
            (cols[1].to_string(), cols[2].parse().ok())
        })
        .collect()
}

const FOUR_AXES: &str = "base = \"seed.toml\"\n[axes]\n\
    \"environment.obstacle_speed\" = [0.15, 0.2, 0.25]\n\
    \"controller.reaction_radius\" = [1.2, 1.4]\n\
    \"robot.latency\" = [0, 2]\n\
    \"controller.danger_rule\" = [\"area\", \"kinematic\"]\n";

/// Four slices (latency × danger rule) of a W × ρ grid: each heat map and each curve
/// figure names its slice and draws its 6 cells and no other (the curve's dots in the
/// colours of the same slice's heat-map tiles), and the slice's curve is `safe_radius` on
/// the seed with the slice's values at every W the grid and the table share.
#[test]
fn every_figure_of_a_four_axis_grid_shows_only_its_slice() {
    let dir = tmp();
    let (md, out) = report(dir.path(), "four", FOUR_AXES);
    let seed = std::fs::read_to_string(dir.path().join("seed.toml")).unwrap();
    let mut k = 0;
    for latency in ["0", "2"] {
        for rule in ["area", "kinematic"] {
            k += 1;
            let lines = [
                format!("latency L = {latency} periods"),
                format!("danger rule = \"{rule}\""),
            ];
            let heat = std::fs::read_to_string(out.join(format!("four-verdicts-{k}.svg")))
                .unwrap_or_else(|e| panic!("heat map {k}: {e}"));
            let curve = std::fs::read_to_string(out.join(format!("four-radius-{k}.svg")))
                .unwrap_or_else(|e| panic!("curve {k}: {e}"));
            for svg in [&heat, &curve] {
                let (texts, _) = parse(svg);
                for line in &lines {
                    let named = texts.iter().any(|t| t.body == format!("slice: {line}"));
                    assert!(named, "figure {k} names {line}: {svg}");
                }
            }
            let (tiles, _, _) = tiles(&heat);
            assert_eq!(
                tiles.len(),
                6,
                "heat map {k}: one tile per (W, ρ) of its slice"
            );
            let mut tile_fills: Vec<String> = tiles.iter().map(|t| t.fill.clone()).collect();
            tile_fills.sort();
            assert_eq!(
                dot_fills(&curve),
                tile_fills,
                "curve {k}: the slice's 6 cells as dots, coloured as its heat map"
            );
            let alt = format!("![safe radius curve, slice {}](four-radius-{k}.svg)", {
                lines.join(", ")
            });
            assert!(md.contains(&alt), "{md}");
            let table = slice_table(&md, &lines.join(", "));
            for w in ["0.1", "0.15", "0.2", "0.25"] {
                let shown = table
                    .iter()
                    .find(|(x, _)| x == w)
                    .unwrap_or_else(|| panic!("W = {w} in slice {k}'s table"))
                    .1;
                let sets = [
                    format!("environment.obstacle_speed={w}"),
                    format!("robot.latency={latency}"),
                    format!("controller.danger_rule={rule}"),
                ];
                let p = Problem::from_toml_str_with_overrides(&seed, "seed", &sets).unwrap();
                let rho = safe_radius(&p).unwrap().value;
                match (shown, rho) {
                    (Some(a), Some(b)) => assert!((a - b).abs() <= 1e-6, "{sets:?}: {a} vs {b}"),
                    (a, b) => assert_eq!(a.is_some(), b.is_some(), "{sets:?}: {a:?} vs {b:?}"),
                }
            }
        }
    }
    let svgs: Vec<String> = files(&out)
        .into_iter()
        .filter(|f| f.ends_with(".svg"))
        .collect();
    assert_eq!(svgs.len(), 8, "4 heat maps and 4 curves: {svgs:?}");
    for row in [
        "| `robot.latency` | latency L | (varied: see axes) |",
        "| `controller.danger_rule` | danger rule | (varied: see axes) |",
        "| `robot.braking` | robot braking b | 0.05 m/s^2 |",
        "| `robot.control_period` | control period dt | 0.1 s |",
        "| `controller.assumed_obstacle_speed` | assumed obstacle speed V_a | 0.2 m/s |",
    ] {
        assert!(md.contains(row), "header lists {row}: {md}");
    }
}

/// A grid over latency and braking (no W, no ρ) gets a heat map over them, each axis titled
/// with its meaning and unit, one tile per cell.
#[test]
fn a_grid_without_w_and_rho_gets_a_heat_map_over_its_own_axes() {
    let dir = tmp();
    let grid = "base = \"seed.toml\"\n[axes]\n\
        \"robot.latency\" = [0, 1, 2]\n\"robot.braking\" = [0.05, 0.1]\n";
    let (md, out) = report(dir.path(), "lb", grid);
    assert!(md.contains("![verdicts per cell](lb-verdicts.svg)"), "{md}");
    assert!(!md.contains("No heat map"), "{md}");
    let svg = std::fs::read_to_string(out.join("lb-verdicts.svg")).unwrap();
    let (tiles, _, texts) = tiles(&svg);
    let has = |body: &str| texts.iter().any(|t| t.body == body);
    assert!(has("latency L (periods)"), "{svg}");
    assert!(has("robot braking b (m/s^2)"), "{svg}");
    assert_eq!(tiles.len(), 6, "{tiles:?}");
    for t in &tiles {
        assert!(t.column.ends_with(" periods"), "{t:?}");
        assert!(t.row.ends_with(" m/s^2"), "{t:?}");
    }
}

/// A grid with one numeric axis says in its page why it has no heat map, and draws nothing.
#[test]
fn a_grid_with_one_numeric_axis_says_why_it_has_no_heat_map() {
    let dir = tmp();
    let grid = "base = \"seed.toml\"\n[axes]\n\"robot.latency\" = [0, 1]\n\
        \"controller.danger_rule\" = [\"area\", \"paper\"]\n";
    let (md, out) = report(dir.path(), "one", grid);
    assert!(
        md.contains(
            "No heat map: a heat map needs two axes of numbers with more than one value each; \
             this grid has 1."
        ),
        "{md}"
    );
    let svgs: Vec<String> = files(&out)
        .into_iter()
        .filter(|f| f.ends_with(".svg"))
        .collect();
    assert!(svgs.is_empty(), "{svgs:?}");
}

/// More slices than a report draws: the first 12 heat maps and curves are drawn and
/// tabled, and the page says the grid has 13.
#[test]
fn a_grid_with_more_slices_than_drawn_says_so() {
    let dir = tmp();
    let latencies: Vec<String> = (0..13).map(|l| l.to_string()).collect();
    let grid = format!(
        "base = \"seed.toml\"\n[axes]\n\"environment.obstacle_speed\" = [0.05]\n\
         \"controller.reaction_radius\" = [1.0, 1.4]\n\"robot.latency\" = [{}]\n",
        latencies.join(", ")
    );
    let (md, out) = report(dir.path(), "many", &grid);
    let names = files(&out);
    for k in 1..=12 {
        for kind in ["verdicts", "radius"] {
            assert!(names.contains(&format!("many-{kind}-{k}.svg")), "{names:?}");
        }
    }
    assert!(!names.iter().any(|n| n.contains("-13.svg")), "{names:?}");
    let drawn = "The grid has 13 slices across its other axes; the first 12 are drawn";
    assert_eq!(md.matches(drawn).count(), 2, "heat maps and curves: {md}");
    assert!(md.contains("the first 12 are computed"), "{md}");
    assert_eq!(md.matches("\nSlice: latency L = ").count(), 12, "{md}");
}
