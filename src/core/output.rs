//! Writing results: atomically (temp file + rename), so a reader never sees half a file and
//! a failed run never destroys the previous result.

use std::io::Write;
use std::path::Path;

use crate::core::simulate::TraceRow;

/// Writes `bytes` to `path` via a temporary file in the same directory and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
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
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// A trace as CSV in the monitor's format: `t,robot_x,robot_v,robot_mode,obstacle_id,
/// obstacle_x,obstacle_v`, where a row's `obstacle_v` is the obstacle's speed over the
/// period that ends at `t` (0 at the start).
pub fn trace_csv(rows: &[TraceRow], obstacle_id: &str) -> String {
    let mut out = String::from("t,robot_x,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_v\n");
    let mut previous = 0.0;
    for r in rows {
        out.push_str(&format!(
            "{},{},{},{},{},{},{}\n",
            r.t,
            r.robot_position,
            r.robot_speed,
            r.robot_mode.as_str(),
            obstacle_id,
            r.obstacle_position,
            previous
        ));
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
        out.push_str(&format!(
            "{{\"t\":{},\"robot_x\":{},\"robot_v\":{},\"robot_mode\":\"{}\",\"obstacle_id\":{id},\"obstacle_x\":{},\"obstacle_v\":{}}}\n",
            r.t,
            r.robot_position,
            r.robot_speed,
            r.robot_mode.as_str(),
            r.obstacle_position,
            previous
        ));
        previous = r.obstacle_speed;
    }
    out
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
