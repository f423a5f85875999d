//! Issue 36, 5a: every shipped problem on the line embedded in the plane (semantics.md
//! §13.7: the x axis, the obstacle on it moving along (−1, 0), radii 0, the disc zone)
//! gets the line's answer from the planar engines: the same verdict, and s* to 10⁻⁹ — the
//! line's exact s* inside the planar bracket, which is at most 10⁻⁹ wide. A distance in
//! the plane is never negative, so where the line's gap goes below 0 (a collision) the
//! planar s* is 0: the planar bracket must then reach 0 from below and stay at or below it.

use std::path::PathBuf;

use safereach::analysis::planar::{BoundOptions, PlanarVerdict, certify_planar};
use safereach::analysis::scene_answer::SceneAnswer;
use safereach::analysis::{Verdict, analyse};
use safereach::core::model::Problem;
use safereach::core::num::Exact;
use safereach::core::scene::Scene;

use crate::common::line_in_plane::{decimal, embed};
use crate::common::paths::root;

/// The shipped problems on the line with one obstacle (scene files and grids are not
/// problems; a range of gaps becomes a start box of height 0).
fn shipped_line_problems() -> Vec<(PathBuf, Problem)> {
    let mut out: Vec<(PathBuf, Problem)> = std::fs::read_dir(root().join("problems"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .filter_map(|p| Problem::load(&p).ok().map(|problem| (p, problem)))
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

/// The line's verdict and s* (exact from the single-obstacle engines; a range of gaps is
/// answered by the scene engines, whose bound is a float rounded down: `slack` is its
/// rounding).
fn line_answer(problem: &Problem, name: &str) -> (Verdict, Exact, Exact) {
    if problem.environment.initial_gap.is_range() {
        let a = SceneAnswer::of(&Scene::from_problem(problem))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let s = a
            .lower_bound()
            .unwrap_or_else(|| panic!("{name}: no line s*"));
        return (a.verdict(), decimal(s), decimal(1e-12));
    }
    let line = analyse(problem).unwrap_or_else(|e| panic!("{name}: {e}"));
    let s = line
        .lower_bound
        .unwrap_or_else(|| panic!("{name}: no line s*"));
    (line.verdict, s, Exact::ZERO)
}

#[test]
fn every_shipped_line_problem_gets_the_lines_answer_in_the_plane_to_1e_9() {
    let problems = shipped_line_problems();
    let names: Vec<String> = problems
        .iter()
        .map(|(p, _)| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    assert!(
        names.len() >= 7 && names.iter().any(|n| n == "weaker-brakes"),
        "the shipped line problems: {names:?}"
    );
    let tolerance = decimal(1e-9);
    for ((_, problem), name) in problems.iter().zip(&names) {
        let (line_verdict, s, slack) = line_answer(problem, name);
        let plane = embed(problem);
        let answer = certify_planar(&plane, &BoundOptions::default(), &tolerance)
            .unwrap_or_else(|e| panic!("{name} in the plane: {e}"));
        let verdict = match answer.verdict {
            PlanarVerdict::Certified => Verdict::Certified,
            PlanarVerdict::Refuted => Verdict::Refuted,
            PlanarVerdict::Inconclusive => Verdict::Inconclusive,
        };
        assert_eq!(verdict, line_verdict, "{name}");
        let upper = answer
            .upper
            .clone()
            .unwrap_or_else(|| panic!("{name}: no witness in the plane"));
        let s = if s < Exact::ZERO { Exact::ZERO } else { s };
        let shown = |x: &Exact| x.to_f64().value();
        assert!(
            answer.lower <= &s + &slack && &s - &slack <= upper,
            "{name}: the line's s* {} is not in the planar bracket [{}, {}]",
            shown(&s),
            shown(&answer.lower),
            shown(&upper)
        );
        if line_verdict == Verdict::Certified {
            assert!(
                &upper - &answer.lower <= tolerance,
                "{name}: the planar bracket [{}, {}] is wider than 1e-9",
                shown(&answer.lower),
                shown(&upper)
            );
        }
    }
}

/// With the clearance raised above the line's s*, every certified shipped problem collides
/// on the line, and must be refuted in the plane, never certified: the weaker brakes' range
/// of gaps (a start box of height 0 in the plane) was certified with s* ≈ 5 m before the
/// arc sectors' rows were closed (docs/reductions.md §11.8, Covers).
#[test]
fn a_clearance_above_the_lines_s_star_is_refuted_in_the_plane() {
    for name in ["weaker-brakes", "seed"] {
        let path = root().join("problems").join(format!("{name}.toml"));
        let problem = Problem::load_with_overrides(&path, &["robot.clearance=0.5".into()]).unwrap();
        let (line_verdict, s, _) = line_answer(&problem, name);
        assert_eq!(
            line_verdict,
            Verdict::Refuted,
            "{name}: s* {}",
            s.to_f64().value()
        );
        let answer = certify_planar(&embed(&problem), &BoundOptions::default(), &decimal(1e-9))
            .unwrap_or_else(|e| panic!("{name} in the plane: {e}"));
        assert_eq!(
            answer.verdict,
            PlanarVerdict::Refuted,
            "{name} in the plane"
        );
        assert!(
            answer.lower <= s,
            "{name}: a planar bound above the line's s*"
        );
    }
}
