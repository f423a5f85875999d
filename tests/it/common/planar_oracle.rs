//! A brute-force planar oracle (issue 36, 5b): every sequence of velocities from finite sets
//! over the first n steps, from every start of a finite set, replayed exactly through
//! `core::planar::PlanarReplay` (prefixes shared by cloning), the obstacles standing still
//! afterwards; the least separation over all of those runs, and whether any collides.
//! Independent of every bound: it only replays concrete behaviours.

use safereach::core::num::Exact;
use safereach::core::planar::{PlanarParams, PlanarReplay, StepChoice};
use safereach::core::plane::point::Point;

/// What the oracle found.
#[derive(Clone, Debug)]
pub struct OracleAnswer {
    /// The least separation bracket's lower end over every run and obstacle.
    pub least_lower: Exact,
    /// The least upper end (a run's attained separation, up to the bracket).
    pub least_upper: Exact,
    /// Some run collides at the problem's clearance (decided exactly).
    pub collides: bool,
    /// Runs replayed.
    pub runs: usize,
}

/// W times the eight rational unit vectors (±1, 0), (0, ±1), (±3/5, ±4/5), and 0.
pub fn compass(w: &Exact) -> Vec<Point> {
    let (three, four) = (
        Exact::from(3) / Exact::from(5),
        Exact::from(4) / Exact::from(5),
    );
    let (one, zero) = (Exact::ONE, Exact::ZERO);
    let mut units = vec![
        Point::new(one.clone(), zero.clone()),
        Point::new(-one.clone(), zero.clone()),
        Point::new(zero.clone(), one.clone()),
        Point::new(zero, -one),
    ];
    for (sx, sy) in [(1, 1), (1, -1), (-1, 1), (-1, -1)] {
        units.push(Point::new(
            &three * Exact::from(sx),
            &four * Exact::from(sy),
        ));
    }
    let mut set: Vec<Point> = units.iter().map(|u| u * w).collect();
    set.push(Point::origin());
    set
}

/// The speeds W·i/parts, i = 0..=parts, along the unit vector `d`.
pub fn along(d: &Point, w: &Exact, parts: usize) -> Vec<Point> {
    (0..=parts)
        .map(|i| d * &(w * Exact::from(i) / Exact::from(parts)))
        .collect()
}

/// Explores every choice: each start of `starts` (one point per obstacle each), in each of
/// the first `n` steps each obstacle's velocity from its set in `sets`, then 0, for at most
/// `steps` steps. Branches that leave an obstacle's region are not behaviours and are
/// dropped.
pub fn explore(
    params: &PlanarParams,
    starts: &[Vec<Point>],
    sets: &[Vec<Point>],
    n: usize,
    steps: usize,
) -> OracleAnswer {
    let mut answer = OracleAnswer {
        least_lower: Exact::from(i64::MAX),
        least_upper: Exact::from(i64::MAX),
        collides: false,
        runs: 0,
    };
    for start in starts {
        let hides = vec![false; start.len()];
        let replay = PlanarReplay::new(params, start, &hides).expect("a valid start");
        branch(params, replay, sets, n, steps, &mut answer);
    }
    answer
}

fn branch(
    params: &PlanarParams,
    replay: PlanarReplay<'_>,
    sets: &[Vec<Point>],
    n: usize,
    steps: usize,
    answer: &mut OracleAnswer,
) {
    if replay.k() >= n || replay.k() >= steps || replay.stopped() {
        finish(params, replay, steps, answer);
        return;
    }
    // Every combination of one velocity per obstacle (mixed radix over the sets).
    let total: usize = sets.iter().map(Vec::len).product();
    for mut code in 0..total {
        let choices: Vec<StepChoice> = sets
            .iter()
            .map(|set| {
                let pick = code % set.len();
                code /= set.len();
                StepChoice::moving(set[pick].clone())
            })
            .collect();
        let mut next = replay.clone();
        if next.step(&choices).is_ok() {
            branch(params, next, sets, n, steps, answer);
        }
    }
}

fn finish(
    params: &PlanarParams,
    mut replay: PlanarReplay<'_>,
    steps: usize,
    answer: &mut OracleAnswer,
) {
    let still: Vec<StepChoice> = params
        .obstacles
        .iter()
        .map(|_| StepChoice::moving(Point::origin()))
        .collect();
    while replay.k() < steps && !replay.stopped() {
        replay.step(&still).expect("standing still is allowed");
    }
    let run = replay.finish();
    answer.runs += 1;
    answer.collides |= run.collides(&params.motion.clearance) == Some(true);
    for i in 0..params.obstacles.len() {
        if let Some(s) = run.separation(i) {
            if s.lower < answer.least_lower {
                answer.least_lower = s.lower;
            }
            if s.upper < answer.least_upper {
                answer.least_upper = s.upper;
            }
        }
    }
}
