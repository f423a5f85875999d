//! Writing results: atomically (temp file + rename), so a reader never sees half a file and
//! a failed run never destroys the previous result.

use std::io::Write;
use std::path::Path;

use crate::core::scene::simulate::SceneTraceRow;
use crate::core::simulate::TraceRow;

/// Writes `bytes` to `path` via a temporary file in the same directory and a rename.
///
/// Only a regular file is ever replaced: a rename over a symlink, a directory or a device
/// node would put a regular file in its place (as root, `--out /dev/null` would replace
/// `/dev/null`), so such a target is an [`std::io::ErrorKind::InvalidInput`] error saying
/// what it is. A symlink is refused rather than followed, so that what is replaced is
/// always the path the user named.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    if let Ok(meta) = std::fs::symlink_metadata(path) {
        let kind = meta.file_type();
        let what = if kind.is_symlink() {
            Some("a symbolic link")
        } else if kind.is_dir() {
            Some("a directory")
        } else if !kind.is_file() {
            Some("a device, pipe or socket")
        } else {
            None
        };
        if let Some(what) = what {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!(
                    "it is {what}, not a regular file; outputs are written to a new file \
                     and renamed into place, which would replace it (name a regular file \
                     or a new path)"
                ),
            ));
        }
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| {
        // `create_new`: never write through something already at the temporary name.
        let mut f = std::fs::File::options()
            .write(true)
            .create_new(true)
            .open(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

#[cfg(all(test, unix))]
mod atomic_tests {
    use super::*;

    #[test]
    fn only_a_regular_file_is_replaced() {
        let dir = std::env::temp_dir().join(format!("safereach-out-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("result.json");
        write_atomic(&file, b"one").unwrap();
        write_atomic(&file, b"two").unwrap();
        assert_eq!(std::fs::read(&file).unwrap(), b"two");
        let link = dir.join("link.json");
        std::os::unix::fs::symlink(&file, &link).unwrap();
        for (target, what) in [
            (link.as_path(), "a symbolic link"),
            (dir.as_path(), "a directory"),
            (Path::new("/dev/null"), "a device"),
        ] {
            let err = write_atomic(target, b"three").unwrap_err();
            assert!(err.to_string().contains(what), "{target:?}: {err}");
        }
        assert_eq!(std::fs::read(&file).unwrap(), b"two");
        assert!(
            std::fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        use std::os::unix::fs::FileTypeExt;
        let null = std::fs::metadata("/dev/null").unwrap().file_type();
        assert!(null.is_char_device());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

/// A trace as CSV in the monitor's format: `t,robot_x,robot_v,robot_mode,obstacle_id,
/// obstacle_x,obstacle_v`, where a row's `obstacle_v` is the obstacle's speed over the
/// period that ends at `t` (0 at the start).
pub fn trace_csv(rows: &[TraceRow], obstacle_id: &str) -> String {
    let mut out = String::from(CSV_HEADER);
    out.push('\n');
    let mut previous = 0.0;
    for r in rows {
        csv_fields(&mut out, r, obstacle_id, previous);
        out.push('\n');
        previous = r.obstacle_speed;
    }
    out
}

/// The same trace as JSON Lines, one object per row with the keys of [`trace_csv`]'s columns
/// (`obstacle_id` a string).
pub fn trace_jsonl(rows: &[TraceRow], obstacle_id: &str) -> String {
    let id = serde_json::to_string(obstacle_id).expect("a string serialises");
    let mut out = String::new();
    let mut previous = 0.0;
    for r in rows {
        json_fields(&mut out, r, &id, previous);
        out.push_str("}\n");
        previous = r.obstacle_speed;
    }
    out
}

/// The columns every trace has.
const CSV_HEADER: &str = "t,robot_x,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_v";

/// A row's common CSV fields (no line end); `id` is written as given.
fn csv_fields(out: &mut String, r: &TraceRow, id: &str, previous: f64) {
    out.push_str(&format!(
        "{},{},{},{},{},{},{}",
        r.t,
        r.robot_position,
        r.robot_speed,
        r.robot_mode.as_str(),
        id,
        r.obstacle_position,
        previous
    ));
}

/// A row's common JSON keys, the object left open; `id` is already JSON.
fn json_fields(out: &mut String, r: &TraceRow, id: &str, previous: f64) {
    out.push_str(&format!(
        "{{\"t\":{},\"robot_x\":{},\"robot_v\":{},\"robot_mode\":\"{}\",\"obstacle_id\":{id},\"obstacle_x\":{},\"obstacle_v\":{}",
        r.t,
        r.robot_position,
        r.robot_speed,
        r.robot_mode.as_str(),
        r.obstacle_position,
        previous
    ));
}

/// A scene trace as CSV: [`trace_csv`]'s columns, `obstacle_id` the obstacle's name (quoted
/// when it holds a comma, a quote or a line break), then `robot_lane` (the lane the robot
/// is in, or moving into during a lane change), `obstacle_lane`, and `leaving_lane` (the lane
/// a lane change leaves; empty when none is in progress). Each obstacle's `obstacle_v` is
/// its own speed over the period that ends at `t`.
pub fn scene_trace_csv(rows: &[SceneTraceRow]) -> String {
    let mut out = format!("{CSV_HEADER},robot_lane,obstacle_lane,leaving_lane\n");
    let mut previous = PreviousSpeeds::default();
    for r in rows {
        csv_fields(&mut out, &r.row, &csv_text(&r.obstacle), previous.take(r));
        let leaving = r.leaving_lane.map(|l| l.to_string()).unwrap_or_default();
        out.push_str(&format!(
            ",{},{},{leaving}\n",
            r.robot_lane, r.obstacle_lane
        ));
    }
    out
}

/// The same scene trace as JSON Lines, with the keys of [`scene_trace_csv`]'s columns
/// (`leaving_lane` null when no lane change is in progress).
pub fn scene_trace_jsonl(rows: &[SceneTraceRow]) -> String {
    let mut out = String::new();
    let mut previous = PreviousSpeeds::default();
    for r in rows {
        let id = serde_json::to_string(&r.obstacle).expect("a string serialises");
        json_fields(&mut out, &r.row, &id, previous.take(r));
        let leaving = r
            .leaving_lane
            .map_or_else(|| "null".to_string(), |l| l.to_string());
        out.push_str(&format!(
            ",\"robot_lane\":{},\"obstacle_lane\":{},\"leaving_lane\":{leaving}}}\n",
            r.robot_lane, r.obstacle_lane
        ));
    }
    out
}

/// The scene trace in the format `path`'s extension names, as [`trace_for_path`].
pub fn scene_trace_for_path(path: &Path, rows: &[SceneTraceRow]) -> String {
    match TraceFormat::from_path(path) {
        Some(TraceFormat::Jsonl) => scene_trace_jsonl(rows),
        _ => scene_trace_csv(rows),
    }
}

/// Each obstacle's speed over the period before its current row (0 before its first).
#[derive(Default)]
struct PreviousSpeeds<'a>(rustc_hash::FxHashMap<&'a str, f64>);

impl<'a> PreviousSpeeds<'a> {
    /// The speed to write in `row`'s `obstacle_v`; remembers the row's own speed.
    fn take(&mut self, row: &'a SceneTraceRow) -> f64 {
        self.0
            .insert(&row.obstacle, row.row.obstacle_speed)
            .unwrap_or(0.0)
    }
}

/// A CSV field: as is, or quoted (quotes doubled) when it holds a comma, a quote or a line
/// break.
fn csv_text(text: &str) -> std::borrow::Cow<'_, str> {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\"")).into()
    } else {
        text.into()
    }
}

/// The trace in the format `path`'s extension names: JSON Lines for `.jsonl` or `.ndjson`,
/// CSV otherwise.
pub fn trace_for_path(path: &Path, rows: &[TraceRow], obstacle_id: &str) -> String {
    match TraceFormat::from_path(path) {
        Some(TraceFormat::Jsonl) => trace_jsonl(rows, obstacle_id),
        _ => trace_csv(rows, obstacle_id),
    }
}

/// A trace's format: what `simulate --trace` writes and the monitor reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TraceFormat {
    /// Comma-separated values with a header.
    Csv,
    /// One JSON object per line.
    Jsonl,
}

impl TraceFormat {
    /// The format a file's extension names: `.csv`, `.jsonl` or `.ndjson`.
    pub fn from_path(path: &Path) -> Option<TraceFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "csv" => Some(TraceFormat::Csv),
            "jsonl" | "ndjson" => Some(TraceFormat::Jsonl),
            _ => None,
        }
    }

    /// The name used on the command line.
    pub fn as_str(self) -> &'static str {
        match self {
            TraceFormat::Csv => "csv",
            TraceFormat::Jsonl => "jsonl",
        }
    }
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::model::Problem;
    use crate::core::num::Exact;
    use crate::core::scene::simulate::{replay_exact, trace};
    use crate::core::scene::{LaneChange, Obstacle, Position, Scene, SceneParams};

    fn seed() -> Problem {
        Problem::load(Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/problems/seed.toml"
        )))
        .expect("the shipped seed reads")
    }

    /// A one-obstacle scene's trace is the single-obstacle trace, line by line, with the
    /// lane columns appended.
    #[test]
    fn a_one_obstacle_scene_trace_extends_the_single_obstacle_trace() {
        let problem = seed();
        let params = problem.params::<Exact>();
        let speeds = [0.1, 0.15, 0.0, 0.05];
        let old = crate::core::simulate::replay_exact(&params, &speeds, 3000, false);
        let old_rows = crate::core::simulate::trace(&params, &old);
        let scene = Scene::from_problem(&problem);
        let p: SceneParams<Exact> = scene.params();
        let new = replay_exact(&p, &[speeds.to_vec()], &p.nearest_starts(), 3000, false);
        let new_rows = trace(&p, &new);
        for (old, new) in [
            (
                trace_csv(&old_rows, "obstacle-0"),
                scene_trace_csv(&new_rows),
            ),
            (
                trace_jsonl(&old_rows, "obstacle-0"),
                scene_trace_jsonl(&new_rows),
            ),
        ] {
            let (old, new): (Vec<_>, Vec<_>) = (old.lines().collect(), new.lines().collect());
            assert_eq!(old.len(), new.len());
            for (a, b) in old.iter().zip(&new) {
                let (a, b) = (a.trim_end_matches('}'), b.trim_end_matches('}'));
                assert!(b.starts_with(a), "{b} extends {a}");
                assert!(b.len() > a.len());
            }
        }
    }

    /// Names are quoted where CSV needs it, each obstacle's `obstacle_v` is its own previous
    /// speed, and the lane columns say where the robot and the obstacle are.
    #[test]
    fn scene_traces_read_back_per_obstacle() {
        let problem = seed();
        let mut scene = Scene::from_problem(&problem);
        scene.lanes = vec![0, 1];
        scene.lane_change = Some(LaneChange {
            periods: 3,
            rear_gap: 0.5,
        });
        scene.obstacles[0].name = "a, \"quoted\" one".into();
        scene.obstacles.push(Obstacle {
            name: "b".into(),
            lane: 1,
            position: Position::At(4.0),
            max_speed: 0.1,
            is_static: false,
        });
        let p: SceneParams<Exact> = scene.params();
        let speeds = vec![vec![0.15, 0.05, 0.1], vec![0.02, 0.07]];
        let run = replay_exact(&p, &speeds, &p.nearest_starts(), 3000, false);
        let rows = trace(&p, &run);
        assert!(
            rows.iter().any(|r| r.leaving_lane == Some(0)),
            "a lane change"
        );
        let csv = scene_trace_csv(&rows);
        let mut reader = ::csv::Reader::from_reader(csv.as_bytes());
        let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
        assert_eq!(
            header[7..],
            ["robot_lane", "obstacle_lane", "leaving_lane"].map(String::from)
        );
        let mut last_speed = rustc_hash::FxHashMap::default();
        let parsed: Vec<_> = reader.records().map(|r| r.unwrap()).collect();
        assert_eq!(parsed.len(), rows.len());
        for (record, row) in parsed.iter().zip(&rows) {
            assert_eq!(&record[4], row.obstacle);
            let previous = last_speed.insert(row.obstacle.clone(), row.row.obstacle_speed);
            assert_eq!(record[6].parse::<f64>().unwrap(), previous.unwrap_or(0.0));
            assert_eq!(record[7].parse::<i32>().unwrap(), row.robot_lane);
            assert_eq!(record[8].parse::<i32>().unwrap(), row.obstacle_lane);
            assert_eq!(record[9].parse::<i32>().ok(), row.leaving_lane);
        }
        for (line, row) in scene_trace_jsonl(&rows).lines().zip(&rows) {
            let v: serde_json::Value = serde_json::from_str(line).unwrap();
            assert_eq!(v["obstacle_id"], row.obstacle.as_str());
            assert_eq!(v["robot_lane"], row.robot_lane);
            assert_eq!(v["obstacle_lane"], row.obstacle_lane);
            assert_eq!(v["leaving_lane"].as_i64(), row.leaving_lane.map(i64::from));
        }
    }
}
