//! A sweep's output: JSON Lines whose first line is the provenance record
//! ([`SweepProvenance`], under the key `"sweep"`) and then one object per cell (its number,
//! its axis values as top-level dotted keys, then the results), plus a CSV view of the cells
//! for spreadsheets. Merging shard outputs refuses anything that is not exactly the current
//! grid's cells, computed from the current grid and base problem by this version.
//!
//! Files: a whole sweep is `<grid>.jsonl`, shard `i/n` is `<grid>.shard-i-of-n.jsonl`;
//! [`results_in`] finds them in a directory.

use std::path::{Path, PathBuf};

use crate::analysis::sweep::{CellResult, Grid};
use crate::core::shard::Shard;
use crate::core::sweep_provenance::SweepProvenance;

/// The key of the provenance record on a sweep output's first line.
pub const PROVENANCE_KEY: &str = "sweep";

/// A sweep output: what ran, and its cells in cell order.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepFile {
    /// What ran.
    pub provenance: SweepProvenance,
    /// The cells (of its shard), in cell order.
    pub cells: Vec<CellResult>,
}

/// The output file stem of a grid's shard: `<grid>` or `<grid>.shard-i-of-n`.
pub fn file_stem(grid_name: &str, shard: Shard) -> String {
    if shard == Shard::ALL {
        grid_name.to_string()
    } else {
        format!("{grid_name}.shard-{}-of-{}", shard.index, shard.count)
    }
}

/// The sweep outputs of grid `grid_name` in `dir`: the whole sweep's `<grid>.jsonl` alone
/// when it is there (what a merge wrote), else every shard's, sorted by name.
pub fn results_in(dir: &Path, grid_name: &str) -> std::io::Result<Vec<PathBuf>> {
    let whole = dir.join(format!("{grid_name}.jsonl"));
    if whole.is_file() {
        return Ok(vec![whole]);
    }
    let prefix = format!("{grid_name}.shard-");
    let mut found: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with(&prefix) && n.ends_with(".jsonl"))
        })
        .collect();
    found.sort();
    Ok(found)
}

impl SweepFile {
    /// The JSON Lines text: the provenance line, then one line per cell.
    pub fn to_jsonl(&self) -> String {
        let mut out = serde_json::json!({ PROVENANCE_KEY: self.provenance }).to_string();
        out.push('\n');
        for r in &self.cells {
            let mut obj = serde_json::Map::new();
            obj.insert("cell".into(), r.cell.into());
            for (k, v) in &r.axes {
                obj.insert(k.clone(), v.clone());
            }
            let rest = serde_json::to_value(r).expect("cell results serialise");
            if let serde_json::Value::Object(fields) = rest {
                for (k, v) in fields {
                    if k != "cell" && k != "axes" {
                        obj.insert(k, v);
                    }
                }
            }
            out.push_str(&serde_json::Value::Object(obj).to_string());
            out.push('\n');
        }
        out
    }

    /// Reads a sweep output written by [`SweepFile::to_jsonl`]; errors start with `origin`
    /// and the line number.
    pub fn from_jsonl(text: &str, origin: &str) -> Result<SweepFile, String> {
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty());
        let (n, first) = lines
            .next()
            .ok_or_else(|| format!("{origin}: empty; not a sweep output"))?;
        let mut head: serde_json::Map<String, serde_json::Value> =
            serde_json::from_str(first).map_err(|e| format!("{origin}:{}: {e}", n + 1))?;
        let record = head
            .remove(PROVENANCE_KEY)
            .filter(|_| head.is_empty())
            .ok_or_else(|| {
                format!(
                    "{origin}:{}: no provenance record (a first line {{\"{PROVENANCE_KEY}\": …}}): \
                 written by an older safereach, or not a sweep output; run the sweep again",
                    n + 1
                )
            })?;
        let provenance: SweepProvenance = serde_json::from_value(record)
            .map_err(|e| format!("{origin}:{}: provenance record: {e}", n + 1))?;
        let mut cells = Vec::new();
        for (n, line) in lines {
            let mut obj: serde_json::Map<String, serde_json::Value> =
                serde_json::from_str(line).map_err(|e| format!("{origin}:{}: {e}", n + 1))?;
            let mut axes = serde_json::Map::new();
            for k in provenance.axes.keys() {
                let v = obj
                    .remove(k)
                    .ok_or_else(|| format!("{origin}:{}: no value for axis {k:?}", n + 1))?;
                axes.insert(k.clone(), v);
            }
            obj.insert("axes".into(), serde_json::Value::Object(axes));
            let r: CellResult = serde_json::from_value(serde_json::Value::Object(obj))
                .map_err(|e| format!("{origin}:{}: {e}", n + 1))?;
            cells.push(r);
        }
        Ok(SweepFile { provenance, cells })
    }

    /// The cells as CSV with a header: cell, the axes, then the results (scene cells add
    /// their worst case, planar cells their upper bound and closest obstacle). The CSV is a view; the JSON Lines file is what merges and reports
    /// read.
    pub fn to_csv(&self) -> String {
        let keys: Vec<String> = self.provenance.axes.keys().cloned().collect();
        cells_csv(&self.cells, &keys)
    }
}

fn csv_field(v: &serde_json::Value) -> String {
    match v {
        serde_json::Value::Null => String::new(),
        serde_json::Value::String(s) => csv_quoted(s),
        other => other.to_string(),
    }
}

/// Cell results as CSV with a header: cell, the axes, then the results.
pub fn cells_csv(results: &[CellResult], axis_keys: &[String]) -> String {
    let mut out = String::from("cell");
    for k in axis_keys {
        out.push(',');
        out.push_str(&csv_quoted(k));
    }
    out.push_str(",verdict,min_separation,never_stops,lower_bound,collisions,runs,simulated_min_separation,pieces,programs");
    // Scene cells add their worst case; single-obstacle CSV keeps its columns.
    let scene = results.iter().any(|r| r.worst.is_some());
    if scene {
        out.push_str(",worst_obstacle,worst_lane,worst_cause");
    }
    // Planar cells add the witness's bound and its closest obstacle.
    let planar = results
        .iter()
        .any(|r| r.upper_bound.is_some() || r.closest.is_some());
    if planar {
        out.push_str(",upper_bound,closest_obstacle,closest_at,closest_guard");
    }
    out.push('\n');
    for r in results {
        out.push_str(&r.cell.to_string());
        for k in axis_keys {
            out.push(',');
            out.push_str(&r.axes.get(k).map(csv_field).unwrap_or_default());
        }
        let opt = |x: Option<f64>| x.map(|v| v.to_string()).unwrap_or_default();
        out.push_str(&format!(
            ",{},{},{},{},{},{},{},{},{}",
            r.verdict.as_str(),
            opt(r.min_separation),
            r.never_stops,
            opt(r.lower_bound),
            r.collisions.map(|c| c.to_string()).unwrap_or_default(),
            r.runs.map(|c| c.to_string()).unwrap_or_default(),
            opt(r.simulated_min_separation),
            r.pieces,
            r.programs
        ));
        if scene {
            if let Some(w) = &r.worst {
                out.push_str(&format!(
                    ",{},{},{}",
                    csv_quoted(&w.name),
                    w.lane,
                    csv_quoted(&w.cause.tag())
                ));
            } else {
                out.push_str(",,,");
            }
        }
        if planar {
            out.push_str(&format!(",{}", opt(r.upper_bound)));
            match &r.closest {
                Some(c) => out.push_str(&format!(
                    ",{},{},{}",
                    csv_quoted(&c.obstacle),
                    c.at,
                    c.guard.as_deref().map(csv_quoted).unwrap_or_default()
                )),
                None => out.push_str(",,,"),
            }
        }
        out.push('\n');
    }
    out
}

/// A CSV field, quoted (quotes doubled) when it holds a comma, a quote or a line break.
fn csv_quoted(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Merges sweep outputs (each with the file it came from) into the whole sweep of `grid`:
/// every output must have been computed from the current grid and base problem by this
/// version, with the same runs and seed; the shards must be one whole set (`0/n … n−1/n`),
/// each holding exactly its own cells with the grid's axis values. Every refusal names the
/// file and what differs. A single whole-sweep output is checked the same way.
pub fn merge(grid: &Grid, parts: Vec<(String, SweepFile)>) -> Result<SweepFile, String> {
    let Some((first_origin, first)) = parts.first() else {
        return Err(format!("no sweep outputs of grid {} to merge", grid.name));
    };
    let (runs, seed) = (first.provenance.runs, first.provenance.seed);
    let expected = SweepProvenance::of(grid, Shard::ALL, runs, seed).map_err(|e| e.to_string())?;
    for (origin, part) in &parts {
        let stale = part.provenance.stale_against(&expected);
        if !stale.is_empty() {
            return Err(format!(
                "{origin}: not a result of {} as it is now: {}",
                grid.path.display(),
                stale.join("; ")
            ));
        }
        if (part.provenance.runs, part.provenance.seed) != (runs, seed) {
            return Err(format!(
                "{origin}: ran {} Monte Carlo runs per cell from seed {}, but {first_origin} ran \
                 {runs} from seed {seed}; outputs of different runs do not merge",
                part.provenance.runs, part.provenance.seed
            ));
        }
    }
    let count = first.provenance.shard_or_all().count;
    let mut owner: Vec<Option<&str>> = vec![None; count];
    for (origin, part) in &parts {
        let shard = part.provenance.shard_or_all();
        if shard.count != count {
            return Err(format!(
                "{origin} is shard {} but {first_origin} is shard {}: outputs of different \
                 shardings do not merge",
                describe(shard),
                describe(first.provenance.shard_or_all())
            ));
        }
        if let Some(other) = owner[shard.index] {
            return Err(format!(
                "{origin} and {other} are both shard {}",
                describe(shard)
            ));
        }
        owner[shard.index] = Some(origin);
        check_cells(grid, origin, shard, &part.cells)?;
    }
    if let Some(missing) = owner.iter().position(Option::is_none) {
        let shard = Shard {
            index: missing,
            count,
        };
        let mut cells: Vec<String> = (missing..grid.len())
            .step_by(count)
            .take(5)
            .map(|c| c.to_string())
            .collect();
        if cells.len() == 5 {
            cells[4] = "…".into();
        }
        return Err(format!(
            "shard {} of grid {} is missing (its cells {}): run it, or give its output",
            shard.label(),
            grid.name,
            cells.join(", ")
        ));
    }
    let mut cells: Vec<CellResult> = parts.into_iter().flat_map(|(_, p)| p.cells).collect();
    cells.sort_by_key(|r| r.cell);
    Ok(SweepFile {
        provenance: expected,
        cells,
    })
}

/// `0/4`, or `the whole sweep`.
fn describe(shard: Shard) -> String {
    if shard == Shard::ALL {
        "the whole sweep".into()
    } else {
        shard.label()
    }
}

/// A shard output holds exactly its shard's cells, in order, with the grid's axis values.
fn check_cells(
    grid: &Grid,
    origin: &str,
    shard: Shard,
    cells: &[CellResult],
) -> Result<(), String> {
    let mut expected = (shard.index..grid.len()).step_by(shard.count);
    for r in cells {
        match expected.next() {
            Some(c) if c == r.cell => {}
            Some(c) if r.cell < c => {
                return Err(format!(
                    "{origin}: cell {} appears twice or out of order",
                    r.cell
                ));
            }
            Some(c) => return Err(format!("{origin}: cell {c} is missing")),
            None => {
                return Err(format!(
                    "{origin}: cell {} is not one of shard {}'s cells",
                    r.cell,
                    describe(shard)
                ));
            }
        }
        let values = grid.cell_values(r.cell);
        let same = values.iter().all(|(k, v)| {
            r.axes.get(k) == Some(&serde_json::to_value(v).unwrap_or(serde_json::Value::Null))
        }) && r.axes.len() == values.len();
        if !same {
            return Err(format!(
                "{origin}: cell {}'s axis values are not the grid's for that cell",
                r.cell
            ));
        }
    }
    if let Some(c) = expected.next() {
        return Err(format!(
            "{origin}: cell {c} is missing (the output ends early)"
        ));
    }
    Ok(())
}
