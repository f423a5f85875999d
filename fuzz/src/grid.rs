//! The sweep grid loader ([`Grid::from_toml_str`], what `Grid::load` runs on a file's text).
//!
//! Input: a grid file's text, read as if it were `problems/fuzz-grid.toml`, so a base such as
//! `"seed.toml"` names a shipped problem. Bases outside `problems/` are skipped (a base such
//! as `/dev/zero` is read without a size limit: unbounded input, issue 15 item 6, not this
//! target's business). Properties: a grid read has at least one cell, its cell count is the
//! product of its axes' lengths without overflow, and the first, middle and last cells have
//! one value of each axis, in axis order, and make a valid problem, scene or planar problem (whose
//! exact parameters build) or an error in
//! the user's terms; a grid refused says why in the user's terms.

use std::path::Path;

use safereach::core::grid::{CellInput, Grid};

use super::assert_user_message;

/// Whether the base the grid `text` names (if it names one) would be read from outside
/// `problems/`.
fn base_outside(text: &str, problems: &Path) -> bool {
    let Ok(doc) = text.parse::<toml::Table>() else {
        return false; // the grid reader refuses it before reading any base
    };
    let Some(toml::Value::String(base)) = doc.get("base") else {
        return false;
    };
    match problems.join(base).canonicalize() {
        Ok(path) => !path.starts_with(problems),
        Err(_) => false, // does not exist: refused without reading
    }
}

/// The `grid` target's body (see the module docs); `problems` is the canonical path of the
/// repository's `problems/` directory.
pub fn fuzz_grid(data: &[u8], problems: &Path) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if base_outside(text, problems) {
        return;
    }
    let path = problems.join("fuzz-grid.toml");
    let grid = match Grid::from_toml_str(text, &path) {
        Ok(grid) => grid,
        Err(e) => return assert_user_message(&e.to_string(), text),
    };
    let cells = grid
        .axes
        .iter()
        .try_fold(1usize, |n, (_, values)| n.checked_mul(values.len()))
        .expect("a grid read has a countable number of cells");
    assert!(cells >= 1, "a grid read has no cell");
    assert_eq!(
        grid.len(),
        cells,
        "the cell count is not the product of the axes"
    );
    for cell in [0, cells / 2, cells - 1] {
        let values = grid.cell_values(cell);
        assert_eq!(values.len(), grid.axes.len());
        for ((key, value), (axis, axis_values)) in values.iter().zip(&grid.axes) {
            assert_eq!(key, axis, "a cell's values are out of axis order");
            assert!(
                axis_values
                    .iter()
                    .any(|v| v.to_string() == value.to_string()),
                "a cell's value is not on its axis"
            );
        }
        match grid.input(cell) {
            Ok(CellInput::Problem(p)) => p.validate("cell").expect("a cell's problem is valid"),
            Ok(CellInput::Scene(s)) => s.validate("cell").expect("a cell's scene is valid"),
            // Read and validated by the planar reader; what the engines take must build.
            Ok(CellInput::Planar(p)) => drop(p.params()),
            Err(e) => assert_user_message(&e.to_string(), text),
        }
        if let Err(e) = grid.problem(cell) {
            assert_user_message(&e.to_string(), text);
        }
    }
}
