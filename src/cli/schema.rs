//! `safereach schema`: the JSON Schemas (2020-12) of what safereach writes, derived from the
//! types that write it. `schemas/` in the repository holds them; a test keeps it current.

use std::io::Write;
use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use schemars::{JsonSchema, Schema, SchemaGenerator, json_schema};
use serde_json::{Value, json};

use safereach::analysis::sweep::CellResult;
use safereach::core::sweep_provenance::SweepProvenance;
use safereach::proof::certificate::{Certificate, FORMAT};
use safereach::proof::planar::certificate::{PLANAR_FORMAT, PlanarCertificate};
use safereach::proof::region_map::{self, RegionMap};
use safereach::proof::scene_certificate::{SCENE_FORMAT, SceneCertificate};
use safereach::proof::search_certificate::{SEARCH_FORMAT, SearchCertificate};

use crate::cli::exit::Exit;
use crate::cli::monitor::{EventJson, SummaryJson};
use crate::cli::output::{Output, create_dir, write_file};

#[derive(Args)]
pub struct SchemaArgs {
    /// Write every schema into DIR (NAME.schema.json) instead of listing them.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

/// Lists the schemas, or writes them into `--out`.
pub fn run(args: SchemaArgs, out: &mut Output) -> Result<Exit> {
    let all = schemas();
    let Some(dir) = args.out else {
        for (name, what, _) in &all {
            writeln!(out, "{name:<20} {what}")?;
        }
        return Ok(Exit::Pass);
    };
    create_dir(&dir)?;
    for (name, _, schema) in &all {
        let text = serde_json::to_string_pretty(schema)? + "\n";
        write_file(&dir.join(format!("{name}.schema.json")), text.as_bytes())?;
    }
    writeln!(out, "wrote {} schemas into {}", all.len(), dir.display())?;
    Ok(Exit::Pass)
}

/// Every schema: its file name, what it describes, and the schema.
pub fn schemas() -> Vec<(&'static str, &'static str, Schema)> {
    vec![
        (
            "certificate",
            "a single-obstacle certificate (certify --out / --json)",
            tagged::<Certificate>(FORMAT),
        ),
        (
            "scene-certificate",
            "a scene certificate proved by linear programs",
            tagged::<SceneCertificate>(SCENE_FORMAT),
        ),
        (
            "search-certificate",
            "a scene certificate decided by the exact run search",
            tagged::<SearchCertificate>(SEARCH_FORMAT),
        ),
        (
            "planar-certificate",
            "a planar certificate (certify --out / --json on a planar problem)",
            tagged::<PlanarCertificate>(PLANAR_FORMAT),
        ),
        (
            "region-map",
            "a region map (region --out, radius/max-speed --region)",
            tagged::<RegionMap>(region_map::FORMAT),
        ),
        (
            "sweep-line",
            "a line of a sweep's JSON Lines output: the provenance line or a cell",
            sweep_line(),
        ),
        ("monitor-event", "an event line of monitor --json", event()),
        (
            "monitor-summary",
            "the summary line of monitor --json",
            summary(),
        ),
    ]
}

fn generator() -> SchemaGenerator {
    SchemaGenerator::default()
}

/// The schema of `T` with its `format` field pinned to `format`, so each kind of file is
/// told apart by its schema as by its reader.
fn tagged<T: JsonSchema>(format: &str) -> Schema {
    let mut schema = generator().into_root_schema_for::<T>();
    if let Some(Value::Object(properties)) = schema.get_mut("properties")
        && let Some(field) = properties.get_mut("format")
    {
        *field = json!({ "const": format, "description": "The file's format and version." });
    }
    schema
}

/// A sweep line: `{"sweep": provenance}` first, then one object per cell whose axis values
/// sit beside its results, keyed by dotted key (`"environment.obstacle_speed": 0.2`).
fn sweep_line() -> Schema {
    let mut generator = generator();
    let provenance = generator.subschema_for::<SweepProvenance>();
    let mut cell = generator.subschema_for::<CellResult>();
    // The cell's schema is a reference into $defs: edit the definition it points at.
    let defs = generator.definitions_mut();
    if let Some(Value::Object(def)) = defs.get_mut("CellResult") {
        if let Some(Value::Object(p)) = def.get_mut("properties") {
            p.remove("axes");
        }
        if let Some(Value::Array(required)) = def.get_mut("required") {
            required.retain(|k| k != "axes");
        }
        def.insert(
            "additionalProperties".into(),
            json!({ "description": "An axis value of the cell, keyed by its dotted key." }),
        );
    }
    cell.insert(
        "description".into(),
        "A cell: its number, its axis values (keyed by dotted key) and its results.".into(),
    );
    let line = json_schema!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "SweepLine",
        "description": "A line of a sweep's JSON Lines output (sweep --out): the first is the provenance, each other one a cell.",
        "anyOf": [
            {
                "type": "object",
                "properties": { (safereach::analysis::sweep_file::PROVENANCE_KEY): provenance },
                "required": [safereach::analysis::sweep_file::PROVENANCE_KEY],
                "additionalProperties": false,
            },
            cell,
        ],
    });
    with_defs(line, generator)
}

/// An event line.
fn event() -> Schema {
    let mut schema = generator().into_root_schema_for::<EventJson<'static>>();
    schema.insert("title".into(), "MonitorEvent".into());
    schema
}

/// The summary line: `{"summary": …}`.
fn summary() -> Schema {
    let mut generator = generator();
    let inner = generator.subschema_for::<SummaryJson<'static>>();
    let line = json_schema!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "MonitorSummaryLine",
        "description": "The last line of monitor --json.",
        "type": "object",
        "properties": { "summary": inner },
        "required": ["summary"],
        "additionalProperties": false,
    });
    with_defs(line, generator)
}

/// `schema` with the definitions `generator` collected, as `$defs`.
fn with_defs(mut schema: Schema, mut generator: SchemaGenerator) -> Schema {
    let defs: serde_json::Map<String, Value> = std::mem::take(generator.definitions_mut());
    if !defs.is_empty() {
        schema.insert("$defs".into(), Value::Object(defs));
    }
    schema
}
