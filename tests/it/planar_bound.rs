//! The plane's lower bound (docs/reductions.md §11) against the line's exact answers: a line
//! problem embedded in the plane (semantics.md §13.7) has the same s* wherever the line's
//! is ≥ 0, so the planar bound must never exceed the line's s* (soundness: the line's
//! worst case is a planar behaviour) and, for the post-brake pieces that §11.7 says are
//! exact there, must reach it.

use safereach::analysis::analyse;
use safereach::analysis::planar::{BoundOptions, lower_bound};
use safereach::core::model::Problem;
use safereach::core::num::Exact;

use crate::common::line_in_plane::{decimal, embed};
use crate::common::paths::seed_file;

fn line_s_star(problem: &Problem) -> Exact {
    analyse(problem)
        .expect("the line analyses")
        .lower_bound
        .expect("a finite line bound")
}

#[test]
fn the_embedded_seed_has_the_lines_s_star() {
    let problem = Problem::load(&seed_file()).expect("the seed loads");
    let line = line_s_star(&problem);
    let plane = embed(&problem);
    let tolerance = decimal(1e-6);
    // Asked to prove more than the line's s*, it must stop at or below it.
    let above = lower_bound(&plane, &(&line + &tolerance), &BoundOptions::default())
        .expect("the seed's plane bounds");
    eprintln!(
        "line s* {} plane bound {} after {} programs, worst {:?}",
        line.to_f64().value(),
        above.lower.to_f64().value(),
        above.programs,
        above
            .worst
            .as_ref()
            .map(|w| (w.kind, w.from.to_f64().value()))
    );
    assert!(
        above.lower <= &line + &tolerance,
        "the plane's bound passes the line's s*"
    );
    assert!(!above.exhausted);
    // Asked to prove a little less than the line's s*, it must.
    let below = lower_bound(&plane, &(&line - &tolerance), &BoundOptions::default())
        .expect("the seed's plane bounds");
    assert!(
        below.lower > &line - &tolerance,
        "bound {}",
        below.lower.to_f64().value()
    );
}
