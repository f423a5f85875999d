//! The smallest certified reaction radius of a scene (without lane changes), and the
//! largest certified obstacle speed bound, by bisection over the scene analyser's exact
//! verdict.
//!
//! A larger ρ makes every obstacle's guard fire no later, so the robot brakes no later, and
//! braking earlier never lowers a separation (docs/reductions.md, Lemmas R1, R2 and S2): the
//! certified radii form an interval up to the solver's duality gap. Past the farthest start
//! of an obstacle in the robot's lane a larger ρ changes nothing, and a sensing range R caps
//! ρ (ρ ≤ R): no radius is answered above either. Every answer is a scene analysis whose
//! certificate `check` accepts; the one just below is reported beside it.
//!
//! Along W the certified bounds form an interval from 0 up too: a larger bound only adds
//! behaviours (Lemma R3, per obstacle, whichever obstacles the bound is given to).

use crate::analysis::scene::SceneAnalysisError;
use crate::analysis::scene_answer::SceneAnswer;
use crate::core::budget::{Budget, Meter, Work};
use crate::core::scene::Scene;
use crate::proof::verdict::Verdict;

/// The bracket is closed to this width, as the single-obstacle searches'
/// ([`crate::analysis::radius::TOLERANCE`]); the answer is its certified end, moved onto
/// that decimal grid towards the certified side.
pub const TOLERANCE: f64 = crate::analysis::radius::TOLERANCE;

/// How far outside the answer the analysis reported beside it is taken
/// ([`crate::analysis::radius::PROBE_OFFSET`]): far enough from the root for a refutation.
const PROBE_OFFSET: f64 = crate::analysis::radius::PROBE_OFFSET;

/// The answer of a radius search.
#[derive(Clone, Debug)]
pub struct SceneRadius {
    /// The smallest certified radius found (within 2·[`TOLERANCE`] above the infimum, on
    /// its decimal grid), None if there is none up to the cap.
    pub value: Option<f64>,
    /// The largest radius searched: the sensing range, or the farthest start in the
    /// robot's lane (beyond which nothing changes).
    pub cap: f64,
    /// The analysis at `value` (certified), or at the cap when there is no radius.
    pub at: SceneAnswer,
    /// The analysis `PROBE_OFFSET` below `value` (not certified), when the search
    /// bracketed one.
    pub below: Option<SceneAnswer>,
}

impl SceneRadius {
    /// One line for people.
    pub fn describe(&self) -> String {
        match self.value {
            Some(v) => {
                // Ten decimals, as the single-obstacle radius: `value` lies on that grid, so
                // the number printed is the one certified.
                let mut s = format!("safe radius {v:.10} m (certified");
                if let Some(b) = &self.below {
                    s += &format!(
                        "; at {:.10}: {}",
                        b.scene().controller.reaction_radius,
                        b.verdict().as_str()
                    );
                }
                s + ")"
            }
            None => format!(
                "no safe radius up to {:.6} m ({}: {})",
                self.cap,
                if self.at.scene().sensing_range.is_some() {
                    "the sensing range"
                } else {
                    "the farthest obstacle start in the robot's lane"
                },
                self.at.verdict().as_str()
            ),
        }
    }
}

fn at(scene: &Scene, rho: f64, meter: &Meter) -> Result<SceneAnswer, SceneAnalysisError> {
    let mut s = scene.clone();
    s.controller.reaction_radius = rho;
    answer(&s, meter)
}

/// Analyses `scene` if its horizon fits in what is left of the search's budget of analysed
/// periods.
fn answer(scene: &Scene, meter: &Meter) -> Result<SceneAnswer, SceneAnalysisError> {
    let horizon = crate::core::scene::simulate::horizon(&scene.params::<f64>()) as u64;
    meter.charge_analysis("scene analysis", horizon)?;
    SceneAnswer::of(scene)
}

/// The certified end `x` of a search (its answer `at_x`) moved onto the decimal grid towards
/// the certified side (`toward_inside` > 0: up), when the analysis there (`analyse`)
/// certifies it too; otherwise `x` itself.
fn certified_on_grid(
    x: f64,
    at_x: SceneAnswer,
    toward_inside: f64,
    analyse: impl Fn(f64) -> Result<SceneAnswer, SceneAnalysisError>,
) -> Result<(f64, SceneAnswer), SceneAnalysisError> {
    let g = crate::analysis::radius::on_grid(x, toward_inside);
    if g == x {
        return Ok((x, at_x));
    }
    let a = analyse(g)?;
    Ok(if a.verdict() == Verdict::Certified {
        (g, a)
    } else {
        (x, at_x)
    })
}

/// Searches the smallest certified reaction radius of a (validated) scene without lane
/// changes. With lane changes the certified radii need not form an interval (a larger ρ can
/// start a lane change that a smaller one would have answered by braking), so bisection
/// would not find the smallest: such a scene is refused, and a sweep over
/// `controller.reaction_radius` answers it point by point.
pub fn scene_radius(scene: &Scene) -> Result<SceneRadius, SceneAnalysisError> {
    scene_radius_within(scene, Budget::default_for(Work::AnalysedPeriods))
}

/// [`scene_radius`] within `budget` of analysed periods (each analysis counts its scene's
/// horizon); past it, [`SceneAnalysisError::OverBudget`].
pub fn scene_radius_within(
    scene: &Scene,
    budget: Budget,
) -> Result<SceneRadius, SceneAnalysisError> {
    let meter = Meter::new(budget);
    if scene.lane_change.is_some() {
        return Err(SceneAnalysisError::Search(
            "the smallest safe radius is not searched with lane changes (the certified radii \
             need not form an interval); sweep controller.reaction_radius instead"
                .into(),
        ));
    }
    let farthest = scene
        .in_lane(0)
        .map(|i| scene.obstacles[i].position.max())
        .fold(TOLERANCE, f64::max);
    let cap = scene.sensing_range.unwrap_or(farthest);
    let top = at(scene, cap, &meter)?;
    if top.verdict() != Verdict::Certified {
        return Ok(SceneRadius {
            value: None,
            cap,
            at: top,
            below: None,
        });
    }
    let (mut lo, mut hi) = (0.0, cap);
    let mut best = top;
    let mut bracketed = false;
    while hi - lo > TOLERANCE {
        let mid = 0.5 * (lo + hi);
        let a = at(scene, mid, &meter)?;
        if a.verdict() == Verdict::Certified {
            hi = mid;
            best = a;
        } else {
            lo = mid;
            bracketed = true;
        }
    }
    let (value, best) = certified_on_grid(hi, best, 1.0, |x| at(scene, x, &meter))?;
    let below = if bracketed && value > PROBE_OFFSET {
        Some(at(scene, value - PROBE_OFFSET, &meter)?)
    } else {
        None
    };
    Ok(SceneRadius {
        value: Some(value),
        cap,
        at: best,
        below,
    })
}

/// The answer of a speed-bound search.
#[derive(Clone, Debug)]
pub struct SceneMaxSpeed {
    /// The largest certified bound found (within [`TOLERANCE`]); None if even 0 is not.
    pub value: Option<f64>,
    /// Certified up to the search's ceiling ([`SPEED_CEILING`]): no bound was found.
    pub unbounded: bool,
    /// The analysis at `value` (certified), or at 0 when there is none.
    pub at: SceneAnswer,
    /// The analysis `PROBE_OFFSET` above `value` (not certified).
    pub above: Option<SceneAnswer>,
}

/// The largest bound the speed search tries (m/s).
pub const SPEED_CEILING: f64 = 100.0;

/// The scene with bound `w` for the moving obstacles `targets` selects.
fn with_speed(scene: &Scene, targets: &impl Fn(usize) -> bool, w: f64) -> Scene {
    let mut s = scene.clone();
    for (i, o) in s.obstacles.iter_mut().enumerate() {
        if !o.is_static && targets(i) {
            o.max_speed = w;
        }
    }
    s
}

/// Searches the largest certified speed bound of the moving obstacles (all of them, or the
/// one `target` names by index) of a (validated) scene.
pub fn scene_max_speed(
    scene: &Scene,
    target: Option<usize>,
) -> Result<SceneMaxSpeed, SceneAnalysisError> {
    scene_max_speed_within(scene, target, Budget::default_for(Work::AnalysedPeriods))
}

/// [`scene_max_speed`] within `budget` of analysed periods (each analysis counts its
/// scene's horizon); past it, [`SceneAnalysisError::OverBudget`].
pub fn scene_max_speed_within(
    scene: &Scene,
    target: Option<usize>,
    budget: Budget,
) -> Result<SceneMaxSpeed, SceneAnalysisError> {
    let meter = Meter::new(budget);
    let targets = |i: usize| target.is_none_or(|t| t == i);
    let zero = answer(&with_speed(scene, &targets, 0.0), &meter)?;
    if zero.verdict() != Verdict::Certified {
        return Ok(SceneMaxSpeed {
            value: None,
            unbounded: false,
            at: zero,
            above: None,
        });
    }
    // Grow a bracket [lo certified, hi not], then bisect it.
    let (mut lo, mut best) = (0.0, zero);
    let mut hi = 0.1;
    loop {
        let a = answer(&with_speed(scene, &targets, hi), &meter)?;
        if a.verdict() != Verdict::Certified {
            break;
        }
        (lo, best) = (hi, a);
        if hi >= SPEED_CEILING {
            return Ok(SceneMaxSpeed {
                value: Some(lo),
                unbounded: true,
                at: best,
                above: None,
            });
        }
        hi = (hi * 2.0).min(SPEED_CEILING);
    }
    while hi - lo > TOLERANCE {
        let mid = 0.5 * (lo + hi);
        let a = answer(&with_speed(scene, &targets, mid), &meter)?;
        if a.verdict() == Verdict::Certified {
            (lo, best) = (mid, a);
        } else {
            hi = mid;
        }
    }
    let speed = |w: f64| answer(&with_speed(scene, &targets, w), &meter);
    let (value, best) = certified_on_grid(lo, best, -1.0, speed)?;
    let above = speed(value + PROBE_OFFSET)?;
    Ok(SceneMaxSpeed {
        value: Some(value),
        unbounded: false,
        at: best,
        above: Some(above),
    })
}

impl SceneMaxSpeed {
    /// One line for people.
    pub fn describe(&self) -> String {
        match (self.value, &self.above) {
            (Some(v), _) if self.unbounded => {
                format!("certified up to the search ceiling {v} m/s")
            }
            (Some(v), Some(a)) => format!(
                "max obstacle speed {v:.10} m/s (certified; at {:.10}: {})",
                v + PROBE_OFFSET,
                a.verdict().as_str()
            ),
            (Some(v), None) => format!("max obstacle speed {v:.10} m/s (certified)"),
            (None, _) => format!(
                "no certified speed bound: even static obstacles give {}",
                self.at.verdict().as_str()
            ),
        }
    }
}
