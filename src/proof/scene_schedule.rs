//! Scenes without lane changes: the schedule decomposition of every obstacle in the robot's
//! lane, composed exactly (docs/reductions.md, "Scenes").
//!
//! # Which obstacles count
//! Without lane changes the robot occupies lane 0 for good. Guards consider only obstacles
//! in the robot's lane ("relevant"), and a lane's being free is asked only when a lane
//! change is considered, so an obstacle in another lane neither moves the robot nor counts
//! for its safety: it is out of reach, and no piece is built for it.
//!
//! # Composition
//! Before it brakes the robot drives the same profile whatever the obstacles do, and each
//! obstacle picks its speeds independently. Alone, obstacle i would make the robot brake
//! at its own step T_i (or pass through the area). In the scene the robot brakes at
//! T = min(G, min_i T_i), G the destination's step. Two facts bound what matters:
//! - an obstacle at speed 0 stays farthest out, so it is the quietest behaviour: any
//!   behaviour that neither fires nor has passed before step T keeps the speed-0 behaviour
//!   quiet too. So obstacle k can stay quiet through step T−1 iff T ≤ z_k, its speed-0
//!   firing step ([`ObstacleSchedule::quiet_until`]);
//! - the robot brakes no later than G and no later than min_k z_k over the other obstacles.
//!
//! For obstacle i the behaviours split into
//! - *own* pieces: i fires (or passes through) at t ≤ T_max,i = min(G, min_{k≠i} z_k), the
//!   others staying quiet at speed 0 — the single-obstacle pieces of i, cut at T_max,i;
//! - *bystander* pieces at T': the robot brakes at T' for another reason while i has not
//!   fired before T' ([`crate::proof::schedule::Ending::Bystander`]). T' is the destination's
//!   step G when every other obstacle can stay quiet through G−1, or the step of a firing
//!   piece of another obstacle j (the single-obstacle pieces of j are cut at T_max,j, so
//!   the rest can stay quiet). A bystander step is needed only if one of those firing pieces
//!   is not proved empty ([`SceneDecomposition::bystander_steps`] lists, per step, the
//!   pieces that make it possible).
//!
//! Every scene behaviour falls in one of these (the obstacle whose guard fires first, or the
//! destination, decides T; every other obstacle is a bystander at T), and every listed piece
//! is realised by a scene behaviour (the others at speed 0, the firing one by its own piece),
//! so s* = least optimum over the pieces, exactly.
//!
//! # Merging
//! Own pieces merge over shifts as alone, up to the cut T_max,i (a merged piece's anchor gap
//! then ends below at its last shift's lower end), and a merged firing piece makes every one
//! of its shifts up to z_j a bystander step of the others. An obstacle's bystander steps stop
//! at its own z_i and below its `last_brake`; an unbroken run of them reaching that end merges
//! into one bystander piece (docs/reductions.md, Lemma 11′).

use crate::core::model::Params;
use crate::core::num::{Exact, Scalar};
use crate::core::param_box::ParamBox;
use crate::core::rational::Rational;
use crate::core::scene::{Position, Scene};
use crate::core::simulate;
use crate::proof::schedule::{Decomposition, Ending, Piece};

/// The lane the robot drives in (and, without lane changes, never leaves).
pub const ROBOT_LANE: i32 = 0;

/// Why a scene is outside what the analyser decides yet.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct Unsupported(pub String);

/// One obstacle of the robot's lane and its pieces.
#[derive(Clone, Debug)]
pub struct ObstacleSchedule {
    /// Index of the obstacle in the scene.
    pub obstacle: usize,
    /// z: the step at whose start the robot, driving on, would brake for this obstacle at
    /// speed 0 (None: at speed 0 it would pass through the area unseen by the guard). It can
    /// stay quiet through step T−1 iff T ≤ z.
    pub quiet_until: Option<usize>,
    /// T_max: no piece of this obstacle brakes later (None: no limit).
    pub limit: Option<usize>,
    /// Its own pieces (single-obstacle schedule with its W, start and danger rule).
    pub decomposition: Decomposition,
}

/// A step at which the robot may brake for another reason while an obstacle has not
/// fired, and what makes it possible.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BystanderStep {
    /// The brake step T'.
    pub step: usize,
    /// The destination's step is T' and every other obstacle can stay quiet until then.
    pub by_goal: bool,
    /// Firing pieces of other obstacles at T': (index into `obstacles`, piece index).
    pub by_pieces: Vec<(usize, usize)>,
}

/// A scene's pieces: per obstacle of the robot's lane, its own pieces cut where the scene
/// makes the robot brake anyway.
#[derive(Clone, Debug)]
pub struct SceneDecomposition {
    /// The scene.
    pub scene: Scene,
    /// G: the step at whose start the destination makes the robot brake (None: no goal).
    pub goal_step: Option<usize>,
    /// The obstacles of the robot's lane, in scene order.
    pub obstacles: Vec<ObstacleSchedule>,
}

impl SceneDecomposition {
    /// Whether the schedule analyser decides the scene (no lane changes, no position
    /// ranges, exact observations of visible obstacles), without building anything.
    pub fn decides(scene: &Scene) -> Result<(), Unsupported> {
        if scene.sensing.is_some() {
            return Err(Unsupported(
                "the schedule analyser composes scenes with exact observations only (the run \
                 search decides [sensing] settings)"
                    .into(),
            ));
        }
        if scene.lane_change.is_some() {
            return Err(Unsupported(
                "the schedule analyser does not take lane changes (the run search decides them)"
                    .into(),
            ));
        }
        if let Some(o) = scene
            .obstacles
            .iter()
            .find(|o| matches!(o.position, Position::Range(..)))
        {
            return Err(Unsupported(format!(
                "obstacle \"{}\": the schedule analyser does not take position ranges (the run \
                 search decides them)",
                o.name
            )));
        }
        Ok(())
    }

    /// Builds the pieces of a (validated) scene.
    pub fn new(scene: &Scene) -> Result<Self, Unsupported> {
        Self::decides(scene)?;
        let lane: Vec<usize> = scene.in_lane(ROBOT_LANE).collect();
        let params: Vec<Params<Exact>> = lane.iter().map(|&i| scene.obstacle_params(i)).collect();
        let quiet: Vec<Option<usize>> = params.iter().map(quiet_until).collect();
        let lane = lane.into_iter().zip(params).map(|(i, p)| (i, p, None));
        Ok(Self::compose(scene, lane.collect(), quiet))
    }

    /// The pieces of the robot's lane's obstacles — each `(scene index, numbers, box)`,
    /// the numbers a box's centre when it has one — given each one's quiet step z.
    pub(crate) fn compose(
        scene: &Scene,
        lane: Vec<(usize, Params<Exact>, Option<ParamBox>)>,
        quiet: Vec<Option<usize>>,
    ) -> Self {
        let goal_step = scene.goal.map(|g| goal_step(&scene.robot_params(), g));
        let obstacles = lane
            .into_iter()
            .enumerate()
            .map(|(a, (i, params, region))| {
                let others = (0..quiet.len())
                    .filter(|&b| b != a)
                    .filter_map(|b| quiet[b]);
                let limit = others.chain(goal_step).min();
                ObstacleSchedule {
                    obstacle: i,
                    quiet_until: quiet[a],
                    limit,
                    // A merged piece stands for every shift up to the limit; another
                    // obstacle's bystander steps take each of its brake steps.
                    decomposition: Decomposition::build(params, limit, true, region),
                }
            })
            .collect();
        SceneDecomposition {
            scene: scene.clone(),
            goal_step,
            obstacles,
        }
    }

    /// The steps at which obstacle `a` (index into `obstacles`) may be a bystander, each
    /// with what makes it possible, ascending.
    pub fn bystander_steps(&self, a: usize) -> Vec<BystanderStep> {
        let mut steps: Vec<BystanderStep> = Vec::new();
        if let Some(g) = self.goal_step {
            let others_quiet = self
                .obstacles
                .iter()
                .enumerate()
                .all(|(b, o)| b == a || o.quiet_until.is_none_or(|z| g <= z));
            if others_quiet {
                step_entry(&mut steps, g).by_goal = true;
            }
        }
        for (b, o) in self.obstacles.iter().enumerate() {
            if b == a {
                continue;
            }
            for (p, piece) in o.decomposition.pieces.iter().enumerate() {
                if matches!(piece.ending, Ending::Danger | Ending::WrongAssumption) {
                    // No behaviour fires after the step at which standing still does
                    // (Lemma S3): a merged piece's later shifts are empty.
                    let steps_of = o.decomposition.brake_steps(piece);
                    let last = o
                        .quiet_until
                        .map_or(steps_of.end, |z| steps_of.end.min(z + 1));
                    for t in steps_of.start..last.max(steps_of.start + 1) {
                        step_entry(&mut steps, t).by_pieces.push((b, p));
                    }
                }
            }
        }
        steps
    }

    /// The bystander pieces obstacle `a` needs, given which of its bystander steps are
    /// possible (`possible`: the destination brakes then, or some firing piece there is not
    /// proved empty). Of the possible steps at or before the obstacle's `first_brake` only
    /// the last is kept: before `first_brake` even the fastest behaviour of the obstacle is
    /// observed outside the reaction area, so its bystander rows hold for every behaviour
    /// and the pieces of those steps have the same behaviours; braking later never raises a
    /// behaviour's gap at rest (reductions.md, Lemma R1), so the last one is the worst.
    pub fn bystanders_needed(
        &self,
        a: usize,
        possible: impl Fn(&BystanderStep) -> bool,
    ) -> Vec<Piece> {
        let d = &self.obstacles[a].decomposition;
        // No bystander step is at or past `last_brake`: past the cut T_max every other
        // obstacle (or the destination) has made the robot brake (Lemma S3), and from the
        // end of the obstacle's own steps the robot has reached its start, so the piece is
        // empty (Lemma 10).
        let steps: Vec<usize> = self
            .bystander_steps(a)
            .iter()
            .filter(|s| possible(s) && s.step < d.last_brake)
            .map(|s| s.step)
            .collect();
        let last_far = steps.iter().copied().filter(|&t| t <= d.first_brake).max();
        let kept: Vec<usize> = steps
            .into_iter()
            .filter(|&t| t > d.first_brake || Some(t) == last_far)
            .collect();
        let merged_from = bystander_merge_from(d, &kept, self.obstacles[a].quiet_until);
        let mut pieces: Vec<Piece> = kept
            .iter()
            .filter(|&&t| merged_from.is_none_or(|m| t < m))
            .flat_map(|&t| d.bystander_pieces(t))
            .collect();
        if let Some(m) = merged_from {
            pieces.push(Piece {
                merged: true,
                ..d.bystander_pieces(m)[0]
            });
        }
        pieces
    }
}

/// Where the bystander steps `kept` (ascending) merge into one piece (Lemmas 11, 11′): the
/// first step of their unbroken tail that ends at the last step with a behaviour — below
/// `last_brake`, and no later than the obstacle's own quiet step `z` (Lemma S3: past it
/// every behaviour has fired) — when the robot cruises there and shifted boxes overlap (from
/// the own pieces' merge step on), and the tail has two steps or more. The merged piece
/// stands for every shift up to `last_brake`, the ones past the tail's end being empty.
/// Only without the wrong-assumption guard (then a step has one bystander piece).
fn bystander_merge_from(d: &Decomposition, kept: &[usize], z: Option<usize>) -> Option<usize> {
    let last = d.last_brake.checked_sub(1)?;
    let end = z.map_or(last, |z| z.min(last));
    if d.wrong_assumption_active() || kept.last() != Some(&end) {
        return None;
    }
    let cut = end;
    let from = d.merge_step()?.max(d.first_brake + 1);
    let mut start = cut;
    for pair in kept.windows(2).rev() {
        if pair[1] != pair[0] + 1 || pair[0] < from {
            break;
        }
        start = pair[0];
    }
    (start < cut && start >= from).then_some(start)
}

/// The entry of `step` in the ascending list, inserted empty if missing.
fn step_entry(steps: &mut Vec<BystanderStep>, step: usize) -> &mut BystanderStep {
    let pos = match steps.binary_search_by_key(&step, |s| s.step) {
        Ok(p) => p,
        Err(p) => {
            steps.insert(
                p,
                BystanderStep {
                    step,
                    by_goal: false,
                    by_pieces: Vec::new(),
                },
            );
            p
        }
    };
    &mut steps[pos]
}

/// z for one obstacle: its speed-0 behaviour run through the step function until the robot
/// brakes (None: it passes through unbraked).
pub(crate) fn quiet_until(params: &Params<Exact>) -> Option<usize> {
    let p: Params<Rational> = params.map(Rational::from_exact);
    let steps = simulate::horizon(&params.map(|x| x.to_f64().value()));
    // Run on past a collision: with latency or a clearance the gap can reach the clearance
    // before the (delayed) guard fires, and the robot still brakes then (stopping at the
    // collision read that as "never brakes" and dropped this obstacle's limit).
    let run = simulate::run(p, |_| Rational::zero(), steps, false);
    run.outcome.brake.map(|(k, _)| k)
}

/// G: the first step at whose start the robot, driving on, has x + v²/(2b) ≥ goal.
fn goal_step(params: &Params<Exact>, goal: f64) -> usize {
    let p: Params<Rational> = params.map(Rational::from_exact);
    let goal = Rational::from_exact(&<Exact as Scalar>::decimal(goal));
    let two_b = Rational::int(2) * p.b.clone();
    let mut state = crate::core::semantics::RobotState::initial(&p);
    let mut k = 0;
    loop {
        let reach =
            state.position.clone() + state.speed.clone() * state.speed.clone() / two_b.clone();
        if reach >= goal {
            return k;
        }
        state = crate::core::semantics::robot_motion(&p, &state).end;
        k += 1;
    }
}
