//! The fuzz campaign's findings (README, "Fuzzing"), each a test named after what it found,
//! and every committed fuzz input — the seed corpora and the inputs that found bugs,
//! `fuzz/corpus/<target>/` — run through the same properties the fuzz targets assert
//! (`fuzz/src/`, included here as [`crate::fuzz_properties`]), so `cargo test` holds them
//! without cargo-fuzz.

use std::path::Path;

use safereach::core::grid::Grid;
use safereach::monitor::trace::Format;
use safereach::proof::certificate_file::CertificateFile;
use safereach::proof::region_check::check_map;
use safereach::proof::region_map::RegionMap;

use crate::common::cli::safereach;
use crate::common::paths::root;
use crate::common::tmp;
use crate::fuzz_properties::{bag, certificate, grid, problem, trace};

/// The committed inputs of a fuzz target, by file name.
fn corpus(target: &str) -> Vec<(String, Vec<u8>)> {
    let dir = root().join("fuzz").join("corpus").join(target);
    let mut inputs: Vec<(String, Vec<u8>)> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| {
            let path = e.expect("entry").path();
            let name = path
                .file_name()
                .expect("a name")
                .to_string_lossy()
                .into_owned();
            (name, std::fs::read(&path).expect("readable"))
        })
        .collect();
    inputs.sort();
    assert!(!inputs.is_empty(), "{} has no inputs", dir.display());
    inputs
}

/// Runs `body` on every committed input of `target`, naming the input that fails.
fn replay(target: &str, body: impl Fn(&[u8])) {
    for (name, data) in corpus(target) {
        let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| body(&data)));
        assert!(
            run.is_ok(),
            "fuzz/corpus/{target}/{name} breaks the target's properties"
        );
    }
}

#[test]
fn committed_problem_inputs_keep_the_problem_targets_properties() {
    replay("problem", problem::fuzz_problem);
}

#[test]
fn committed_grid_inputs_keep_the_grid_targets_properties() {
    let problems = root().join("problems").canonicalize().expect("problems/");
    replay("grid", |data| grid::fuzz_grid(data, &problems));
}

#[test]
fn committed_certificate_inputs_keep_the_certificate_targets_properties() {
    replay("certificate", certificate::fuzz_certificate);
}

#[test]
fn committed_csv_traces_keep_the_trace_targets_properties() {
    replay("trace_csv", |data| trace::fuzz_trace(data, Format::Csv));
}

#[test]
fn committed_bags_keep_the_bag_targets_properties() {
    replay("bag", bag::fuzz_bag);
}

#[test]
fn committed_jsonl_traces_keep_the_trace_targets_properties() {
    replay("trace_jsonl", |data| trace::fuzz_trace(data, Format::Jsonl));
}

/// Found by the `certificate` target (`finding-not-an-object.json`, a JSON string): a
/// certificate that is not a JSON object was refused in the reader's own words, "invalid
/// type: string …, expected struct Tag", and an array was read field by field.
#[test]
fn a_certificate_that_is_not_a_json_object_is_refused_in_the_users_terms() {
    for text in [
        "\"x\"",
        "[1]",
        "[\"safereach-certificate/2\"]",
        "1",
        "null",
        " true",
    ] {
        let e = CertificateFile::from_json(text)
            .expect_err("not a certificate")
            .to_string();
        assert!(e.contains("a certificate is a JSON object"), "{text}: {e}");
        assert!(
            !e.contains("Tag") && !e.contains("invalid type"),
            "{text}: {e}"
        );
    }
    let dir = tmp();
    std::fs::write(dir.path().join("string.json"), "\"x\"\n").expect("writable");
    let out = safereach(dir.path())
        .args(["check", "string.json"])
        .assert()
        .code(2)
        .get_output()
        .clone();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("string.json") && err.contains("a certificate is a JSON object"),
        "{err}"
    );
}

/// Found by the `certificate` target (`finding-map-stated-bound.json`: a region map with a
/// multiplier edited and its digest recomputed): the map check showed the stated bound in
/// Rust's debug syntax, "proof 0: stated bound Some(0.1199999999991538), the multipliers
/// prove -1.28…"; likewise a leaf's stated lower bound.
#[test]
fn a_region_maps_stated_bounds_are_shown_as_numbers() {
    let text =
        std::fs::read_to_string(root().join("fuzz/corpus/certificate/map.json")).expect("readable");
    let map: RegionMap = serde_json::from_str(&text).expect("a map");
    check_map(&map).expect("the committed map is valid");
    let resigned = |mut m: RegionMap| {
        m.digest = m.compute_digest();
        check_map(&m).expect_err("an edited map").to_string()
    };

    let mut edited = map.clone();
    edited.leaves[0].proofs[0].multipliers[0] = 0.0000000000051736;
    let e = resigned(edited);
    assert!(
        e.contains("proof 0: stated bound 0.1199999999991538, the multipliers prove"),
        "{e}"
    );

    let mut edited = map.clone();
    edited.leaves[0].lower_bound = Some(0.11);
    let e = resigned(edited);
    assert!(
        e.contains("stated lower bound 0.11, the proofs give 0.1199"),
        "{e}"
    );

    let mut edited = map;
    edited.leaves[0].lower_bound = None;
    let e = resigned(edited);
    assert!(
        e.contains("stated lower bound none, the proofs give 0.1199"),
        "{e}"
    );
    assert!(!e.contains("Some(") && !e.contains("None"), "{e}");
}

/// `Grid::from_toml_str` (added for the `grid` target) reads a grid as `Grid::load` does.
#[test]
fn a_grid_read_from_text_is_the_grid_loaded_from_its_file() {
    let path = root().join("problems").join("seed-grid.toml");
    let text = std::fs::read_to_string(&path).expect("readable");
    let (a, b) = (
        Grid::load(&path).expect("loads"),
        Grid::from_toml_str(&text, Path::new(&path)).expect("reads"),
    );
    assert_eq!(
        (a.len(), &a.axes, &a.base_text),
        (b.len(), &b.axes, &b.base_text)
    );
    assert_eq!(
        (a.name, a.runs, a.seed, a.kind),
        (b.name, b.runs, b.seed, b.kind)
    );
}
