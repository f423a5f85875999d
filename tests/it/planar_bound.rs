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

/// Random line problems (every rule, latencies 0–3, the guard on and off, W below and
/// above V_a, short gaps) embedded in the plane: the planar bound never passes the planar
/// s* of the line's own worst case, max(s*_line, 0) (its gap crossing 0 is a distance of
/// 0); and where §11.7 says the bound is exact (the line certifies and the wrong-assumption
/// guard cannot fire), it proves the line's bound less 10⁻⁶.
#[test]
fn embedded_line_problems_are_bounded_soundly_and_tightly() {
    use proptest::prelude::*;
    use proptest::test_runner::TestRunner;

    use crate::common::spec::{any_spec, config};

    let mut runner = TestRunner::new(config(64));
    let strategy = any_spec().prop_map(|mut s| {
        s.g0 = s.g0.min(3.0);
        s
    });
    runner
        .run(&strategy, |spec| {
            let problem = spec.problem();
            let analysis = analyse(&problem).expect("the line analyses");
            let plane = embed(&problem);
            let tolerance = decimal(1e-6);
            let worst = match (analysis.never_stops, analysis.min_separation) {
                (false, Some(s)) => decimal(s.max(0.0)),
                (true, _) => Exact::ZERO,
                // No moving instant on the line (the robot never starts): none in the plane.
                (false, None) => {
                    let none = lower_bound(&plane, &Exact::ZERO, &BoundOptions::default())
                        .expect("embedded problems bound");
                    prop_assert!(
                        none.worst.is_none(),
                        "{spec:?}: a leaf where the line has none"
                    );
                    return Ok(());
                }
            };
            let sound = lower_bound(&plane, &(&worst + &tolerance), &BoundOptions::default())
                .expect("embedded problems bound");
            prop_assert!(
                sound.lower <= &worst + &tolerance,
                "{spec:?}: plane bound {} above the line's worst case {}",
                sound.lower.to_f64().value(),
                worst.to_f64().value()
            );
            let params = problem.params::<Exact>();
            let guard_quiet = !params.wrong_assumption_active();
            if let (true, Some(line)) = (guard_quiet, &analysis.lower_bound)
                && *line > params.clearance
            {
                let tight = lower_bound(&plane, &(line - &tolerance), &BoundOptions::default())
                    .expect("embedded problems bound");
                prop_assert!(
                    tight.lower > line - &tolerance,
                    "{spec:?}: plane bound {} below the line's {}",
                    tight.lower.to_f64().value(),
                    line.to_f64().value()
                );
            }
            Ok(())
        })
        .expect("every embedded problem is bounded soundly and tightly");
}
