//! The exact key of a scene state: what of a [`SceneWorld`] decides its future, and nothing
//! else, so that two states with equal keys have the same futures step for step (the
//! argument is in the module docs of `scene`, "States").

use crate::core::num::{Exact, Scalar};
use crate::core::rational::Rational;
use crate::core::scene::SceneWorld;
use crate::core::scene::safety::Side;
use crate::core::semantics::Mode;

/// An exact number as a key: the canonical form of a [`Rational`] (a small one in lowest
/// terms with a positive denominator, else the big one), so that equal numbers hash alike.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum Num {
    Small(i128, i128),
    Big(Exact),
}

impl Num {
    fn of(r: &Rational) -> Num {
        match r {
            Rational::Small(n, d) => Num::Small(*n, *d),
            // A big number that fits is stored small, as every small one is.
            Rational::Big(x) => match Rational::from_exact(x) {
                Rational::Small(n, d) => Num::Small(n, d),
                Rational::Big(x) => Num::Big(x),
            },
        }
    }
}

/// The part of a scene state that determines its future: equal keys, equal futures.
/// Stored in full in the visited set.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct SceneKey(Repr);

#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum Repr {
    /// Accelerating or driving: guards are still evaluated.
    Live {
        mode: Mode,
        speed: Num,
        /// Only with a goal (the destination guard reads it).
        position: Option<Num>,
        /// min(k, L+1): whether observations have begun, and with speed 0 or a real one.
        early: usize,
        lateral: LateralKey,
        tracks: Box<[LiveTrack]>,
    },
    /// Braking: no guard is evaluated again; only the lanes still occupied matter.
    Braking {
        speed: Num,
        lateral: LateralKey,
        tracks: Box<[(usize, Num, Option<bool>)]>,
    },
    /// A state with no successors (at rest, settled, or driving on for ever): its future
    /// is not explored, so one key for each kind.
    Ended(u8),
}

/// The lane the robot is in (or moving into) and, during a change, the lane it leaves and
/// the periods the change still lasts.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct LateralKey {
    lane: i32,
    change: Option<(i32, usize)>,
}

/// One obstacle while guards are evaluated.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct LiveTrack {
    gap: Num,
    /// The remembered gaps a later observation will still show (the newest min(·, L)),
    /// as the guards will read them.
    gaps: Box<[Seen]>,
    /// For each remembered speed: whether a guard will read it as faster than V_a.
    fast: Box<[bool]>,
    /// The side of the current occupancy interval (true: ahead).
    side: Option<bool>,
    /// With noise or occlusion (the `fast` bits are then empty).
    sensed: Option<Sensed>,
}

/// What the environment's observation choices read of one obstacle.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct Sensed {
    /// For each remembered speed: whether some error shows it above V_a, and whether some
    /// shows it at or below.
    shows: Box<[(bool, bool)]>,
    /// The obstacle is still hidden.
    hidden: bool,
}

/// A remembered gap as every later reader of it sees it.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum Seen {
    /// Beyond ρ: never relevant, and a lane with it is free (seen or beyond the sensing
    /// range R ≥ ρ alike); not ≤ 0.
    Far,
    /// ≤ 0 with lane changes off: never relevant, and ≤ 0 (no free-lane test reads it).
    Passed,
    /// Anything else, exactly.
    Exactly(Num),
}

/// What kind of ended state a key stands for.
#[derive(Clone, Copy, Debug)]
pub(super) enum Ending {
    Stopped = 0,
    Settled = 1,
    NeverBrakes = 2,
}

impl SceneKey {
    /// The key of an ended state.
    pub(super) fn ended(kind: Ending) -> SceneKey {
        SceneKey(Repr::Ended(kind as u8))
    }

    /// The key of a running world; `keep[i]`: obstacle i can still matter while guards are
    /// evaluated (the module docs say which can be left out). `hidden`: with noise or
    /// occlusion, which obstacles are still hidden; the history is then kept exactly (an
    /// error can move an observation across any threshold within σ of it).
    pub(super) fn running(
        world: &SceneWorld<Rational>,
        keep: &[bool],
        hidden: Option<&[bool]>,
    ) -> SceneKey {
        let p = world.params();
        let l = p.robot.L;
        let lateral = world.lateral();
        let periods = p.lane_change_periods();
        let lateral_key = LateralKey {
            lane: lateral.lane,
            change: lateral
                .change
                .map(|c| (c.from, c.step + periods - world.k())),
        };
        let robot = world.robot();
        let side = |i: usize| world.side(i).map(|s| s == Side::Ahead);
        if robot.mode == Mode::Brake {
            let tracks = (0..p.obstacles.len())
                .filter(|&i| lateral.occupies(p.obstacles[i].lane))
                .map(|i| (i, Num::of(world.gap(i)), side(i)))
                .collect();
            return SceneKey(Repr::Braking {
                speed: Num::of(&robot.speed),
                lateral: lateral_key,
                tracks,
            });
        }
        let zero = Rational::zero();
        // With noise every threshold moves by σ_g, and "far" must also settle d_det (a
        // hidden obstacle's next observation is compared with it).
        let sigma = &p.robot.sigma_g;
        let far = match &p.robot.d_det {
            Some(d) if *d > p.robot.rho.clone() + sigma.clone() => d.clone(),
            _ => p.robot.rho.clone() + sigma.clone(),
        };
        let past = -sigma.clone();
        let seen = |gap: &Rational| {
            if hidden.is_some() {
                if *gap > far {
                    Seen::Far
                } else if p.lane_change.is_none() && *gap <= past {
                    Seen::Passed
                } else {
                    Seen::Exactly(Num::of(gap))
                }
            } else if *gap > p.robot.rho {
                Seen::Far
            } else if p.lane_change.is_none() && *gap <= zero {
                Seen::Passed
            } else {
                Seen::Exactly(Num::of(gap))
            }
        };
        // A gap a guard may find relevant: in (0, ρ] (as shown: within σ_g of it).
        let in_area = |gap: &Rational| *gap > zero && *gap <= p.robot.rho;
        let may_be_in_area = |gap: &Rational| {
            gap.clone() + sigma.clone() > zero && gap.clone() - sigma.clone() <= p.robot.rho
        };
        let sigma_w = &p.robot.sigma_w;
        let tracks = (0..p.obstacles.len())
            .filter(|&i| keep[i])
            .map(|i| {
                let (gaps, speeds) = world.history(i);
                let reads_speed = p.robot.wrong_assumption_brake && !p.obstacles[i].is_static;
                // The speed over period p is observed with the gap at the start of p + 1
                // (the next remembered gap, or the current one), and read only when that
                // gap is relevant.
                let partner = |j: usize| gaps.get(j + 1).unwrap_or_else(|| world.gap(i));
                // A speed never read can only look slow.
                let sensed = hidden.map(|h| {
                    let shows = speeds
                        .iter()
                        .enumerate()
                        .map(|(j, w)| {
                            if reads_speed && may_be_in_area(partner(j)) {
                                (
                                    w.clone() + sigma_w.clone() > p.robot.V_a,
                                    w.clone() - sigma_w.clone() <= p.robot.V_a,
                                )
                            } else {
                                (false, true)
                            }
                        })
                        .collect();
                    Sensed {
                        shows,
                        hidden: h[i],
                    }
                });
                let fast = speeds
                    .iter()
                    .enumerate()
                    .filter(|_| sensed.is_none())
                    .map(|(j, w)| reads_speed && in_area(partner(j)) && *w > p.robot.V_a)
                    .collect();
                LiveTrack {
                    gap: Num::of(world.gap(i)),
                    gaps: gaps
                        .iter()
                        .skip(gaps.len().saturating_sub(l))
                        .map(seen)
                        .collect(),
                    fast,
                    side: side(i),
                    sensed,
                }
            })
            .collect();
        SceneKey(Repr::Live {
            mode: robot.mode,
            speed: Num::of(&robot.speed),
            position: p.goal.as_ref().map(|_| Num::of(&robot.position)),
            early: world.k().min(l + 1),
            lateral: lateral_key,
            tracks,
        })
    }
}
