//! Runs that differ only in their past (Lemma R9, docs/reductions.md §7).
//!
//! Two nodes at the same step, with the robot in the same lateral state, where every
//! obstacle that can still be read allows below the second node only behaviours it allows
//! below the first: each future of the second is a future of the first, with the same
//! commands. What differs is what each is worth, through the past: the lane changes made,
//! and the obstacles already passed for good (behind the robot beyond the rear gap whatever
//! they did, so never read again). When every behaviour below a node is worth, obstacle by
//! obstacle, at least a leaf below a node already searched, the node is left out: every
//! obstacle's s* and the overall worst case are reached below the other. After a lane
//! change away from an oncoming obstacle and back, the runs of every swerving step meet
//! again like this.

use std::collections::HashMap;
use std::hash::{DefaultHasher, Hash, Hasher};

use crate::core::num::Scalar;
use crate::core::rational::Rational;
use crate::core::scene::SceneParams;
use crate::core::scene::lateral::{LaneChangeEvent, Lateral};

use super::chain::Chain;
use super::leaf::{Motion, Occupancy, Worst, occupancies, worst_of};
use super::sense::{Sense, Sight};
use super::tree::Profile;

/// The nodes searched so far, by what their futures share.
#[derive(Default)]
pub(super) struct Dominance {
    buckets: HashMap<u64, Vec<Seen>>,
}

/// A node as the dominance test reads it.
pub(super) struct NodeView<'a> {
    pub k: usize,
    pub lateral: &'a Lateral,
    pub changes: &'a [LaneChangeEvent],
    pub chains: &'a [Chain],
    pub sights: &'a [Sight],
}

/// A node searched: what its future reads, and (once asked) what its past makes of each
/// obstacle.
struct Seen {
    k: usize,
    lateral: Lateral,
    passed: Vec<bool>,
    chains: Vec<Chain>,
    sights: Vec<Sight>,
    changes: Vec<LaneChangeEvent>,
    parts: Option<Vec<Part>>,
}

/// What a node's past makes of one obstacle in every leaf below it.
#[derive(Debug)]
enum Part {
    /// Passed for good, with every stay of the robot in its lane so far already worth its
    /// final amount: in a leaf below, the obstacle is worth min(`settled`, x − `highest`)
    /// with x the least position at which the robot enters its lane later (Behind, §11.6:
    /// −gap at the entry, and its highest position never falls below where it is now
    /// standing still); with `behind`, a stay that began with it behind is worth no more
    /// than any later entry, so min(`settled`, …) = `settled`.
    Passed {
        /// None: +∞ (never in its lane so far).
        settled: Option<Rational>,
        behind: bool,
        highest: Rational,
    },
    /// Still read, or not yet settled: its chain must allow no behaviour the kept node's
    /// does not, its sight must be the same, and its past stays in its lane must count
    /// the same.
    Live(Past),
}

/// How an obstacle's past stays in its lane enter a leaf's worst case.
#[derive(Debug, PartialEq)]
enum Past {
    /// Ahead whatever it did when the robot last entered its lane: every earlier stay ended
    /// before that one began, with it ahead, at a larger gap (gaps never grow), so only when
    /// the last stay ends counts.
    AheadSince { end: Option<usize> },
    /// The stays as they are.
    Stays(Vec<Occupancy>),
}

impl Dominance {
    /// Whether the node must be searched: false when a node already searched dominates it.
    /// A node searched is remembered.
    pub fn admit(
        &mut self,
        p: &SceneParams<Rational>,
        sense: &Sense,
        profile: &mut Profile,
        node: NodeView<'_>,
    ) -> bool {
        let passed = passed_for_good(p, sense, profile, &node);
        let mut hasher = DefaultHasher::new();
        node.k.hash(&mut hasher);
        lateral_key(node.lateral).hash(&mut hasher);
        passed.hash(&mut hasher);
        for (i, sight) in node.sights.iter().enumerate() {
            if !passed[i] {
                sight_key(sight).hash(&mut hasher);
            }
        }
        let bucket = self.buckets.entry(hasher.finish()).or_default();
        let mut mine: Option<Vec<Part>> = None;
        for seen in bucket.iter_mut() {
            if seen.k != node.k || seen.lateral != *node.lateral || seen.passed != passed {
                continue;
            }
            // Cheap tests for every obstacle first: most pairs fail one.
            let (a, b) = (&seen.chains, node.chains);
            let within_future = (0..passed.len())
                .all(|i| passed[i] || (seen.sights[i] == node.sights[i] && b[i].may_imply(&a[i])))
                && (0..passed.len()).all(|i| passed[i] || b[i].implies(&a[i]));
            if !within_future {
                continue;
            }
            let theirs = seen.parts.get_or_insert_with(|| {
                parts(
                    p,
                    profile,
                    node.k,
                    &seen.changes,
                    &seen.chains,
                    &seen.passed,
                )
            });
            let mine = mine.get_or_insert_with(|| {
                parts(p, profile, node.k, node.changes, node.chains, &passed)
            });
            // A passed obstacle not yet settled counts as still read.
            let open_alike = (0..passed.len()).all(|i| {
                !(passed[i] && matches!(mine[i], Part::Live(_)))
                    || (seen.sights[i] == node.sights[i] && node.chains[i].implies(&seen.chains[i]))
            });
            if open_alike && dominates(theirs, mine) {
                #[cfg(test)]
                tests::record(seen, &node);
                return false;
            }
        }
        bucket.push(Seen {
            k: node.k,
            lateral: *node.lateral,
            passed,
            chains: node.chains.to_vec(),
            sights: node.sights.to_vec(),
            changes: node.changes.to_vec(),
            parts: mine,
        });
        true
    }
}

/// Per obstacle, whether it is passed for good at the node: shown, and at the observation
/// read at this step its true gap is below −(rear gap + σ_g) whatever it did. Then every
/// error shows it below −rear gap at this and every later read (gaps never grow): never in
/// the reaction area, never blocking a lane, so no guard reads it again and its chain gains
/// only rows it already meets.
fn passed_for_good(
    p: &SceneParams<Rational>,
    sense: &Sense,
    profile: &mut Profile,
    node: &NodeView<'_>,
) -> Vec<bool> {
    let Some(n) = node.k.checked_sub(p.robot.L) else {
        return vec![false; node.chains.len()];
    };
    let rear = p
        .lane_change
        .as_ref()
        .map_or_else(Rational::zero, |lc| lc.rear_gap.clone());
    let below = profile.at(p, n).position.clone() - rear - sense.sigma_g.clone();
    node.chains
        .iter()
        .zip(node.sights)
        .map(|(chain, sight)| {
            matches!(sight, Sight::Shown { .. })
                && chain
                    .reach_at(n.max(chain.last_step()))
                    .hi
                    .is_some_and(|h| h.at < below)
        })
        .collect()
}

/// What the node's past makes of each obstacle.
fn parts(
    p: &SceneParams<Rational>,
    profile: &mut Profile,
    k: usize,
    changes: &[LaneChangeEvent],
    chains: &[Chain],
    passed: &[bool],
) -> Vec<Part> {
    let stays = occupancies(changes, p.lane_change_periods());
    (0..chains.len())
        .map(|i| {
            let lane = p.obstacles[i].lane;
            let mine: Vec<Occupancy> = stays.iter().filter(|o| o.lane == lane).cloned().collect();
            let settled = match passed[i] {
                true => settled(p, profile, k, changes, &chains[i], lane, &mine),
                false => None,
            };
            settled.unwrap_or_else(|| Part::Live(past(p, profile, &chains[i], mine)))
        })
        .collect()
}

/// A passed obstacle's worth so far, when no stay in its lane is still open to the future:
/// every stay that has not ended before step k (it may still end, or be continued by a
/// change straight back) began with it behind whatever it did, so it is worth −gap at its
/// start; the others ended while the robot moved, worth their gap at the exit. None when
/// some stay is still open.
fn settled(
    p: &SceneParams<Rational>,
    profile: &mut Profile,
    k: usize,
    changes: &[LaneChangeEvent],
    chain: &Chain,
    lane: i32,
    stays: &[Occupancy],
) -> Option<Part> {
    let mut behind = false;
    for stay in stays {
        let robot = profile.at(p, stay.start).position.clone();
        let ahead_possible = chain
            .marginal(stay.start, &[])
            .hi
            .is_none_or(|h| h.at > robot);
        if !ahead_possible {
            behind = true;
        } else if stay.end.is_none_or(|e| e >= k) {
            return None;
        }
    }
    let settled = match worst_of(p, profile, changes, chain, lane, &Motion::driving_on()) {
        None => None,
        Some(Worst { value: Some(v), .. }) => Some(v),
        Some(Worst { value: None, .. }) => return None,
    };
    let highest = chain.reach_at(chain.last_step()).hi?.at;
    Some(Part::Passed {
        settled,
        behind,
        highest,
    })
}

/// How a live obstacle's past stays in its lane count.
fn past(
    p: &SceneParams<Rational>,
    profile: &mut Profile,
    chain: &Chain,
    stays: Vec<Occupancy>,
) -> Past {
    if let Some(last) = stays.iter().max_by_key(|o| o.start) {
        let robot = profile.at(p, last.start).position.clone();
        let ahead = chain
            .marginal(last.start, &[])
            .lo
            .is_some_and(|l| l.at > robot || (l.at == robot && !l.closed));
        if ahead {
            return Past::AheadSince { end: last.end };
        }
    }
    Past::Stays(stays)
}

/// Whether every leaf below a node with `theirs` is worth, per obstacle, at most what the
/// same leaf below a node with `mine` is worth (the futures being the same).
fn dominates(theirs: &[Part], mine: &[Part]) -> bool {
    theirs.iter().zip(mine).all(|(a, b)| match (a, b) {
        (Part::Live(x), Part::Live(y)) => x == y,
        (
            Part::Passed {
                settled: sa,
                highest: ha,
                ..
            },
            Part::Passed {
                settled: sb,
                behind: bb,
                highest: hb,
            },
        ) => {
            // Mine is min(sb, x − hb), or sb when bb; theirs is at most sa and x − ha.
            let no_lower = match (sa, sb) {
                (_, None) => true,
                (None, Some(_)) => false,
                (Some(a), Some(b)) => b >= a,
            };
            no_lower && (*bb || hb <= ha)
        }
        _ => false,
    })
}

/// The lateral state as plain numbers, for hashing.
fn lateral_key(l: &Lateral) -> (i32, Option<(usize, i32, i32)>) {
    (l.lane, l.change.map(|c| (c.step, c.from, c.to)))
}

/// A sight as plain numbers, for hashing.
fn sight_key(s: &Sight) -> (u8, usize, bool) {
    match *s {
        Sight::Shown { from, far_only } => (0, from, far_only),
        Sight::Hidden { since } => (1, since, false),
    }
}

#[cfg(test)]
mod tests {
    use std::cell::RefCell;

    use super::*;
    use crate::core::scene::Scene;
    use crate::core::scene::simulate;
    use crate::proof::scene_search::SearchOptions;
    use crate::proof::scene_search::leaf::worst;
    use crate::proof::scene_search::tree::{Start, walk_below};

    thread_local! {
        /// While set, the search's dominance decisions (kept, left out), in order.
        static DECISIONS: RefCell<Option<Vec<(Start, Start)>>> = const { RefCell::new(None) };
    }

    /// Records a decision when recording.
    pub(super) fn record(kept: &Seen, left: &NodeView<'_>) {
        DECISIONS.with(|d| {
            if let Some(list) = d.borrow_mut().as_mut() {
                list.push((
                    Start {
                        k: kept.k,
                        lateral: kept.lateral,
                        changes: kept.changes.clone(),
                        chains: kept.chains.clone(),
                        sights: kept.sights.clone(),
                    },
                    Start {
                        k: left.k,
                        lateral: *left.lateral,
                        changes: left.changes.to_vec(),
                        chains: left.chains.to_vec(),
                        sights: left.sights.to_vec(),
                    },
                ));
            }
        })
    }

    /// Every decision the search takes on `scene`.
    fn decisions(scene: &Scene) -> Vec<(Start, Start)> {
        DECISIONS.with(|d| *d.borrow_mut() = Some(Vec::new()));
        crate::proof::scene_search::search_scene(scene).expect("searched");
        DECISIONS.with(|d| d.borrow_mut().take().expect("recording"))
    }

    /// Per obstacle, its least worth over the runs below `start`, searched without pruning
    /// (None: the robot is never in its lane).
    fn least_below(scene: &Scene, start: Start) -> Vec<Option<Worst>> {
        let p: SceneParams<Rational> = scene
            .params::<crate::core::num::Exact>()
            .map(Rational::from_exact);
        let horizon = simulate::horizon(&p.map(|x| x.as_f64()));
        let mut profile = Profile::new(&p);
        let mut least: Vec<Option<Worst>> = vec![None; p.obstacles.len()];
        let mut curves = Vec::new();
        let every_run = SearchOptions {
            prune_dominated: false,
            ..SearchOptions::default()
        };
        walk_below(
            &p,
            &mut profile,
            horizon,
            every_run,
            start,
            |leaf, profile| {
                let motion = Motion::of_with(&p, profile, &leaf.ending, &mut curves);
                for (i, slot) in least.iter_mut().enumerate() {
                    if let Some(w) = worst(&p, profile, leaf, &motion, i)
                        && slot.as_ref().is_none_or(|s| w.below(s))
                    {
                        *slot = Some(w);
                    }
                }
            },
        )
        .expect("searched below");
        least
    }

    /// Oncoming traffic for a coarse robot that swerves, drawn from `seed`: two or three
    /// obstacles down its lane (sometimes one down lane 1, which the robot passes and may
    /// swerve in behind), parked cars, lane changes of 2–5 periods, rear gaps 0–0.6 m, and
    /// at random the guard, the rule, latency, gap noise, occlusion.
    fn traffic(seed: u64) -> Scene {
        let mut state = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
        let mut draw = |n: usize| {
            // xorshift64*: enough spread for picking test cases.
            state ^= state >> 12;
            state ^= state << 25;
            state ^= state >> 27;
            (state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 33) as usize % n
        };
        let mut obstacles = String::new();
        for i in 0..2 + draw(2) {
            let lane = if i == 2 && draw(2) == 0 { 1 } else { 0 };
            obstacles += &format!(
                "[[obstacle]]\nname = \"o{i}\"\nlane = {lane}\nposition = {}\nmax_speed = {}\n",
                (8 + draw(17)) as f64 / 4.0 + 1.5 * i as f64,
                ["0.05", "0.1", "0.2", "0.3"][draw(4)],
            );
        }
        for (lane, name) in [(1, "right"), (-1, "left")] {
            if draw(4) > 0 {
                obstacles += &format!(
                    "[[obstacle]]\nname = \"parked-{name}\"\nlane = {lane}\nposition = {}\nmax_speed = 0.0\nstatic = true\n",
                    (6 + draw(23)) as f64 / 4.0,
                );
            }
        }
        let text = format!(
            "name = \"traffic\"\n[robot]\nmax_speed = 0.4\nacceleration = 0.4\nbraking = {}\n\
             control_period = 0.25\nlatency = {}\nclearance = 0.0\n[controller]\n\
             assumed_obstacle_speed = 0.2\nreaction_radius = {}\ndanger_rule = \"{}\"\n\
             buffer = 0.1\nwrong_assumption_brake = {}\nlane_change = true\n\
             lane_change_periods = {}\nlane_change_rear_gap = {}\n[scene]\nlanes = [-1, 0, 1]\n\
             {obstacles}{}",
            ["0.2", "0.4"][draw(2)],
            draw(3),
            ["1.5", "2.0", "2.5"][draw(3)],
            ["paper", "kinematic", "area"][draw(3)],
            draw(2) == 1,
            2 + draw(4),
            ["0.0", "0.3", "0.6"][draw(3)],
            [
                "",
                "",
                "",
                "[sensing]\ngap_noise = 0.03\n",
                "[sensing]\nfirst_detection_gap = 0.9\n"
            ][draw(5)],
        );
        Scene::from_toml_str(&text, "traffic").unwrap_or_else(|e| panic!("{e}\n{text}"))
    }

    /// Lemma R9 decision by decision: wherever the search would leave a node out, every
    /// obstacle's least worth over the runs below it (searched without pruning) is at
    /// least its least worth below the node kept. This is what keeps every obstacle's s*:
    /// an independent check of each comparison the lemma makes (settled worth, highest
    /// position, past stays), not only of the answers it gives.
    #[test]
    fn every_node_left_out_is_worth_no_less_below_than_the_one_kept() {
        let mut checked = 0;
        let mut scenes_with_decisions = 0;
        for o in 0..120 {
            let scene = traffic(o);
            let all = decisions(&scene);
            scenes_with_decisions += usize::from(!all.is_empty());
            // Spread the checks over the search when there are many.
            let every = all.len().div_ceil(150).max(1);
            for (kept, left) in all.into_iter().step_by(every) {
                let k = kept.k;
                let a = least_below(&scene, kept);
                let b = least_below(&scene, left);
                for (i, (a, b)) in a.iter().zip(&b).enumerate() {
                    let lower = match (a, b) {
                        (_, None) => false,
                        (None, Some(_)) => true,
                        (Some(a), Some(b)) => b.below(a),
                    };
                    assert!(
                        !lower,
                        "scene {o}, step {k}, obstacle {i}: {b:?} below the node left out, {a:?} below the one kept\n{}",
                        scene.to_toml_string()
                    );
                }
                checked += 1;
            }
        }
        assert!(
            scenes_with_decisions >= 30 && checked >= 1500,
            "{checked} decisions in {scenes_with_decisions} scenes"
        );
    }
}
