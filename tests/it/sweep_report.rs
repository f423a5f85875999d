//! Reports of scene grids: the heat maps' SVG read back as text (axis titles, the slice, one
//! tile per cell) and every tile checked against the scene analyser run afresh on its cell;
//! the safe-radius curve of the shipped scene grid checked against the single-obstacle
//! answer it must equal and against the verdicts on either side of it.

use std::path::Path;

use safereach::analysis::radius::safe_radius;
use safereach::analysis::scene::{SceneAnalysis, analyse_scene};
use safereach::core::scene::Scene;

use crate::common::cli::safereach;
use crate::common::paths::{load_problem, root};
use crate::common::tmp;

/// A `<text>` element: its position, attributes and body (unescaped).
#[derive(Debug)]
pub(crate) struct Text {
    pub(crate) x: f64,
    pub(crate) y: f64,
    pub(crate) attrs: String,
    pub(crate) body: String,
}

/// A `<rect>` element with a position.
#[derive(Debug)]
pub(crate) struct Rect {
    pub(crate) x: f64,
    pub(crate) y: f64,
    pub(crate) width: f64,
    pub(crate) height: f64,
    pub(crate) fill: String,
}

/// The value of attribute `name` in an element's text.
pub(crate) fn attr(element: &str, name: &str) -> Option<String> {
    let start = element.find(&format!(" {name}=\""))? + name.len() + 3;
    let len = element[start..].find('"')?;
    Some(element[start..start + len].to_string())
}

/// The texts and positioned rectangles of an SVG (one element per line, as the report
/// writes it).
pub(crate) fn parse(svg: &str) -> (Vec<Text>, Vec<Rect>) {
    let num = |e: &str, n: &str| attr(e, n).and_then(|v| v.parse::<f64>().ok());
    let mut texts = Vec::new();
    let mut rects = Vec::new();
    for line in svg.lines() {
        if let Some(rest) = line.strip_prefix("<text") {
            let open = rest.find('>').expect("text element closes its tag");
            let body = rest[open + 1..]
                .strip_suffix("</text>")
                .expect("one text per line");
            texts.push(Text {
                x: num(line, "x").unwrap(),
                y: num(line, "y").unwrap(),
                attrs: rest[..open].to_string(),
                body: body.replace("&lt;", "<").replace("&amp;", "&"),
            });
        } else if line.starts_with("<rect")
            && let (Some(x), Some(y)) = (num(line, "x"), num(line, "y"))
        {
            rects.push(Rect {
                x,
                y,
                width: num(line, "width").unwrap(),
                height: num(line, "height").unwrap(),
                fill: attr(line, "fill").unwrap(),
            });
        }
    }
    (texts, rects)
}

/// A cell as a heat map draws it: the tile's fill and the lines written on it.
#[derive(Debug)]
pub(crate) struct Tile {
    pub(crate) column: String,
    pub(crate) row: String,
    pub(crate) fill: String,
    pub(crate) lines: Vec<String>,
}

/// The tiles of a heat map, each placed by the tick labels under its column and left of
/// its row, with the legend's colours (label → fill).
pub(crate) fn tiles(svg: &str) -> (Vec<Tile>, Vec<(String, String)>, Vec<Text>) {
    let (texts, rects) = parse(svg);
    let legend: Vec<(String, String)> = rects
        .iter()
        .filter(|r| r.width == 14.0)
        .map(|r| {
            let label = texts
                .iter()
                .find(|t| t.x == r.x + 20.0 && t.y == r.y + 11.0)
                .expect("a legend swatch has its label");
            (label.body.clone(), r.fill.clone())
        })
        .collect();
    let bottom = rects
        .iter()
        .filter(|r| r.width == 130.0)
        .map(|r| r.y + r.height)
        .fold(0.0, f64::max);
    let tiles = rects
        .iter()
        .filter(|r| r.width == 130.0)
        .map(|r| {
            let centre = r.x + r.width / 2.0;
            let column = texts
                .iter()
                .filter(|t| t.x == centre && t.y > bottom && t.attrs.contains("middle"))
                .min_by(|a, b| a.y.total_cmp(&b.y))
                .expect("a column label under the tile");
            let row = texts
                .iter()
                .find(|t| t.attrs.contains("end") && t.y == r.y + r.height / 2.0 + 4.0)
                .expect("a row label left of the tile");
            let mut inside: Vec<&Text> = texts
                .iter()
                .filter(|t| t.x == centre && t.y > r.y && t.y < r.y + r.height)
                .collect();
            inside.sort_by(|a, b| a.y.total_cmp(&b.y));
            Tile {
                column: column.body.clone(),
                row: row.body.clone(),
                fill: r.fill.clone(),
                lines: inside.iter().map(|t| t.body.clone()).collect(),
            }
        })
        .collect();
    (tiles, legend, texts)
}

/// s* as a tile writes it, from an independent analysis.
fn shown_separation(a: &SceneAnalysis) -> String {
    if a.never_stops {
        "−∞".into()
    } else {
        a.min_separation.map_or("–".into(), |v| format!("{v:.3}"))
    }
}

const GRID: &str = "base = \"scene-oncoming.toml\"\n\
    [axes]\n\
    \"obstacle.1.max_speed\" = [0.2, 0.3]\n\
    \"controller.reaction_radius\" = [1.4, 1.8]\n\
    \"obstacle.0.max_speed\" = [0.1, 0.15]\n";

/// A scene grid over three axes: a heat map per value of the third, titled by what each
/// axis is (the obstacle by index and name, with units), stating its slice; each tile shows
/// the verdict, s* and worst-case obstacle the scene analyser gives its cell, in the
/// legend's colour for that verdict. The curve is refused with the reason.
#[test]
fn scene_grid_heat_maps_show_each_cell_as_the_analyser_answers_it() {
    let dir = tmp();
    std::fs::copy(
        root().join("problems/scene-oncoming.toml"),
        dir.path().join("scene-oncoming.toml"),
    )
    .unwrap();
    std::fs::write(dir.path().join("three.toml"), GRID).unwrap();
    let out = dir.path().join("out");
    safereach(dir.path())
        .args(["report", "three.toml", "--out"])
        .arg(&out)
        .assert()
        .success();
    let md = std::fs::read_to_string(out.join("three.md")).unwrap();
    assert!(md.contains("![verdicts per cell, slice obstacle 0 (\"first\") max speed W_0 = 0.1 m/s](three-verdicts-1.svg)"), "{md}");
    assert!(
        md.contains("No safe-radius curve:") && md.contains("`obstacle.0.max_speed`"),
        "{md}"
    );
    assert!(md.contains("## Worst cases"), "{md}");
    for row in [
        "| `controller.reaction_radius` | reaction radius ρ | (varied: see axes) |",
        "| `scene.lanes` | lanes | [0, 1] |",
        "| 0 | \"first\" | 0 | 10 | (varied: see axes) | false |",
        "| 1 | \"second\" | 0 | 12.5 | (varied: see axes) | false |",
        "| 3 | \"box\" | 1 | 5 | 0 | true |",
    ] {
        assert!(md.contains(row), "header lists {row}: {md}");
    }
    let base = std::fs::read_to_string(dir.path().join("scene-oncoming.toml")).unwrap();
    for (k, w0) in ["0.1", "0.15"].iter().enumerate() {
        let svg = std::fs::read_to_string(out.join(format!("three-verdicts-{}.svg", k + 1)))
            .unwrap_or_else(|e| panic!("heat map {}: {e}", k + 1));
        let (tiles, legend, texts) = tiles(&svg);
        let has = |body: &str| texts.iter().any(|t| t.body == body);
        assert!(has("obstacle 1 (\"second\") max speed W_1 (m/s)"), "{svg}");
        assert!(has("reaction radius ρ (m)"), "{svg}");
        assert!(
            has(&format!(
                "slice: obstacle 0 (\"first\") max speed W_0 = {w0} m/s"
            )),
            "{svg}"
        );
        assert_eq!(tiles.len(), 4, "one tile per (W_1, ρ) pair: {tiles:?}");
        let colour = |label: &str| legend.iter().find(|(l, _)| l == label).unwrap().1.clone();
        for tile in &tiles {
            let w1 = tile.column.trim_end_matches(" (> V_a)");
            let w1 = w1.strip_suffix(" m/s").expect("W_1 in m/s");
            // The scene's V_a is 0.2 m/s: only faster bounds are marked.
            assert_eq!(tile.column.ends_with("(> V_a)"), w1 == "0.3", "{tile:?}");
            let rho = tile.row.strip_suffix(" m").expect("ρ in m");
            let sets = [
                format!("obstacle.1.max_speed={w1}"),
                format!("controller.reaction_radius={rho}"),
                format!("obstacle.0.max_speed={w0}"),
            ];
            let scene = Scene::from_toml_str_with_overrides(&base, "base", &sets).unwrap();
            let a = analyse_scene(&scene).unwrap();
            let verdict = a.verdict.as_str();
            assert_eq!(tile.lines[0], verdict, "{sets:?}: {tile:?}");
            assert_eq!(
                tile.lines[1],
                format!("s* = {}", shown_separation(&a)),
                "{sets:?}"
            );
            let w = a.witness.as_ref().expect("every cell here has a witness");
            let worst = format!("\"{}\", lane {}", scene.obstacles[w.obstacle].name, w.lane);
            assert_eq!(tile.lines.last().unwrap(), &worst, "{sets:?}: {tile:?}");
            match verdict {
                "certified" | "inconclusive" => assert_eq!(tile.fill, colour(verdict)),
                _ => assert!(
                    legend
                        .iter()
                        .any(|(l, c)| l.starts_with("refuted") && *c == tile.fill),
                    "{tile:?}"
                ),
            }
        }
    }
}

/// The single-obstacle seed grid's heat map states its slice (the one assumed speed), and
/// keeps its axis titles without units (the ticks carry them).
#[test]
fn seed_grid_heat_map_states_its_slice() {
    let svg = std::fs::read_to_string(root().join("reports/seed-grid-verdicts.svg")).unwrap();
    let (tiles, _, texts) = tiles(&svg);
    let has = |body: &str| texts.iter().any(|t| t.body == body);
    assert!(has("slice: assumed obstacle speed V_a = 0.2 m/s"));
    assert!(has("obstacle speed bound W") && has("reaction radius ρ"));
    assert_eq!(tiles.len(), 16);
}

/// The row of `md`'s safe-radius table whose first column is `w`: its ρ*.
fn curve_point(md: &str, w: &str) -> Option<f64> {
    let section = &md[md.find("## Safe radius")?..];
    section
        .lines()
        .find(|l| l.starts_with(&format!("| {w} | ")))
        .and_then(|l| l.split('|').nth(2))
        .and_then(|v| v.trim().parse().ok())
}

/// The shipped scene grid's curve ρ*(W_1): where "second" is no faster than "first"
/// (0.15 m/s), "first" decides, and ρ* is the seed's single-obstacle answer at 0.15; above,
/// each ρ* is certified and a hair less is not.
#[test]
fn scene_grid_curve_matches_single_obstacle_and_the_analyser() {
    let md = std::fs::read_to_string(root().join("reports/scene-oncoming-grid.md")).unwrap();
    let seed = safe_radius(&load_problem(
        "seed.toml",
        &["environment.obstacle_speed=0.15"],
    ))
    .unwrap()
    .value
    .unwrap();
    for w in ["0", "0.1", "0.15"] {
        let rho = curve_point(&md, w).unwrap_or_else(|| panic!("W_1 = {w} in the table"));
        assert!((rho - seed).abs() <= 2e-6, "W_1 = {w}: {rho} vs {seed}");
    }
    let base = std::fs::read_to_string(root().join("problems/scene-oncoming.toml")).unwrap();
    let verdict = |w: &str, rho: f64| {
        let sets = [
            format!("obstacle.1.max_speed={w}"),
            format!("controller.reaction_radius={rho}"),
        ];
        let scene = Scene::from_toml_str_with_overrides(&base, "base", &sets).unwrap();
        analyse_scene(&scene).unwrap().verdict.as_str()
    };
    let rho = curve_point(&md, "0.2").expect("W_1 = 0.2 in the table");
    assert_eq!(verdict("0.2", rho), "certified");
    assert_ne!(verdict("0.2", rho - 3e-6), "certified");
    assert!(md.contains("| 0.3 | none |"), "{md}");
    assert!(Path::new(&root().join("reports/scene-oncoming-grid-radius.svg")).exists());
}

/// A scene grid that varies one axis, and not an obstacle's bound, gets neither a heat map
/// nor a curve, and its page says why for each.
#[test]
fn scene_grid_without_two_axes_says_why_it_has_no_figures() {
    let dir = tmp();
    std::fs::copy(
        root().join("problems/scene-oncoming.toml"),
        dir.path().join("scene-oncoming.toml"),
    )
    .unwrap();
    let grid =
        "base = \"scene-oncoming.toml\"\n[axes]\n\"controller.reaction_radius\" = [1.4, 1.8]\n";
    std::fs::write(dir.path().join("one.toml"), grid).unwrap();
    let out = dir.path().join("out");
    safereach(dir.path())
        .args(["report", "one.toml", "--out"])
        .arg(&out)
        .assert()
        .success();
    let md = std::fs::read_to_string(out.join("one.md")).unwrap();
    assert!(
        md.contains("No heat map: a heat map needs two axes"),
        "{md}"
    );
    assert!(
        md.contains("No safe-radius curve: the grid varies no obstacle's speed bound"),
        "{md}"
    );
    assert!(!md.contains(".svg"), "{md}");
    let files = crate::common::cli::files(&out);
    assert!(files.iter().all(|f| !f.ends_with(".svg")), "{files:?}");
}

/// A scene cell's worst case survives JSON Lines (so `report --from` merges it) and is a
/// CSV column; it is the analyser's witness obstacle.
#[test]
fn scene_worst_cases_round_trip_through_jsonl_and_csv() {
    use safereach::analysis::sweep::{self, Grid, Shard, SweepBudget};
    use safereach::analysis::sweep_file::SweepFile;
    let grid = Grid::load(&root().join("problems/scene-oncoming-grid.toml")).unwrap();
    let file = grid
        .sweep(
            Shard { index: 0, count: 8 },
            0,
            0,
            &SweepBudget::default(),
            || {},
        )
        .unwrap();
    let back = SweepFile::from_jsonl(&file.to_jsonl(), "test").unwrap();
    assert_eq!(back, file);
    let csv = file.to_csv();
    assert!(
        csv.lines()
            .next()
            .unwrap()
            .ends_with(",worst_obstacle,worst_lane,worst_cause")
    );
    let results = file.cells;
    for r in &results {
        let sweep::CellInput::Scene(scene) = grid.input(r.cell).unwrap() else {
            panic!("scene cells");
        };
        let w = analyse_scene(&scene).unwrap().witness.unwrap();
        let worst = r.worst.as_ref().expect("a worst case");
        assert_eq!(
            (worst.obstacle, worst.lane),
            (w.obstacle, w.lane),
            "cell {}",
            r.cell
        );
        assert_eq!(worst.name, scene.obstacles[w.obstacle].name);
    }
}
