//! The smallest certified reaction radius of a scene (without lane changes), by bisection
//! over the scene analyser's exact verdict.
//!
//! A larger ρ makes every obstacle's guard fire no later, so the robot brakes no later, and
//! braking earlier never lowers a separation (docs/reductions.md, Lemmas R1, R2 and S2): the
//! certified radii form an interval up to the solver's duality gap. Past the farthest start
//! of an obstacle in the robot's lane a larger ρ changes nothing, and a sensing range R caps
//! ρ (ρ ≤ R): no radius is answered above either. Every answer is a scene analysis whose
//! certificate `check` accepts; the one just below is reported beside it.

use crate::analysis::scene::{SceneAnalysis, SceneAnalysisError, analyse_scene};
use crate::core::scene::Scene;
use crate::proof::verdict::Verdict;

/// The bracket is closed to this width (m).
pub const TOLERANCE: f64 = 1e-6;

/// The answer of a radius search.
#[derive(Clone, Debug)]
pub struct SceneRadius {
    /// The smallest certified radius found (within [`TOLERANCE`]), None if there is none
    /// up to the cap.
    pub value: Option<f64>,
    /// The largest radius searched: the sensing range, or the farthest start in the
    /// robot's lane (beyond which nothing changes).
    pub cap: f64,
    /// The analysis at `value` (certified), or at the cap when there is no radius.
    pub at: SceneAnalysis,
    /// The analysis just below `value` (not certified), when the search bracketed one.
    pub below: Option<SceneAnalysis>,
}

impl SceneRadius {
    /// One line for people.
    pub fn describe(&self) -> String {
        match self.value {
            Some(v) => {
                let mut s = format!("safe radius {v:.6} m (certified");
                if let Some(b) = &self.below {
                    s += &format!(
                        "; at {:.6}: {}",
                        b.scene.controller.reaction_radius,
                        b.verdict.as_str()
                    );
                }
                s + ")"
            }
            None => format!(
                "no safe radius up to {:.6} m ({}: {})",
                self.cap,
                if self.at.scene.sensing_range.is_some() {
                    "the sensing range"
                } else {
                    "the farthest obstacle start in the robot's lane"
                },
                self.at.verdict.as_str()
            ),
        }
    }
}

fn at(scene: &Scene, rho: f64) -> Result<SceneAnalysis, SceneAnalysisError> {
    let mut s = scene.clone();
    s.controller.reaction_radius = rho;
    analyse_scene(&s)
}

/// Searches the smallest certified reaction radius of a (validated) scene.
pub fn scene_radius(scene: &Scene) -> Result<SceneRadius, SceneAnalysisError> {
    let farthest = scene
        .in_lane(0)
        .map(|i| scene.obstacles[i].position.max())
        .fold(TOLERANCE, f64::max);
    let cap = scene.sensing_range.unwrap_or(farthest);
    let top = at(scene, cap)?;
    if top.verdict != Verdict::Certified {
        return Ok(SceneRadius {
            value: None,
            cap,
            at: top,
            below: None,
        });
    }
    let (mut lo, mut hi) = (0.0, cap);
    let mut best = top;
    let mut below = None;
    while hi - lo > TOLERANCE {
        let mid = 0.5 * (lo + hi);
        let a = at(scene, mid)?;
        if a.verdict == Verdict::Certified {
            hi = mid;
            best = a;
        } else {
            lo = mid;
            below = Some(a);
        }
    }
    Ok(SceneRadius {
        value: Some(hi),
        cap,
        at: best,
        below,
    })
}
