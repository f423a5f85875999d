//! Scenes over a box of parameter values: the scene composition
//! ([`crate::proof::scene_schedule`]) made valid for every point of the box
//! (docs/reductions.md §9).
//!
//! Each obstacle of the robot's lane gets the box decomposition
//! ([`crate::proof::region_schedule`]) of the box as it bears on it
//! ([`ParamBox::for_obstacle`]: its own W_i and start, and the shared ρ, V_a, buffer,
//! clearance). What couples the obstacles is made a union over the box:
//!
//! - **quiet steps**: z_k, the step at which obstacle k at speed 0 makes the robot brake,
//!   is taken at the corner that fires latest (least ρ, V_a and buffer, farthest start).
//!   Each step's firing test `o ≤ min(ρ, d_coll)` only gets easier towards any other
//!   point, so no point's z_k is later. The limits T_max and the destination's bystander
//!   step then admit every brake step some point admits.
//! - **bystander steps**: every step at which a firing piece of another obstacle's box
//!   decomposition brakes (a superset of each point's own), with none dropped for being
//!   proved empty; of those at or before the obstacle's first brake step (the box's
//!   earliest) only the last is kept, by the point argument: before it every behaviour at
//!   every point is observed outside the area.
//!
//! Every piece a point needs is then listed for the box, or is dominated by one that is
//! (the last early bystander step), and each box program relaxes the point's: the least
//! box bound bounds s* below at every point.

use crate::core::model::Params;
use crate::core::num::Exact;
use crate::core::param_box::{End, ParamBox};
use crate::core::parameter::Parameter;
use crate::core::scene::Scene;
use crate::proof::scene_schedule::{ROBOT_LANE, SceneDecomposition, Unsupported, quiet_until};
use crate::proof::schedule::Piece;

impl SceneDecomposition {
    /// The pieces of every point of `region` (a scene box: shared axes and per-obstacle
    /// ones) for a (valid) scene the schedule analyser decides.
    pub fn for_box(scene: &Scene, region: &ParamBox) -> Result<Self, Unsupported> {
        Self::decides(scene)?;
        let mut lane = Vec::new();
        let mut quiet = Vec::new();
        for i in scene.in_lane(ROBOT_LANE) {
            let b = region.for_obstacle(i, scene.obstacles[i].is_static);
            let base: Params<Exact> = scene.obstacle_params(i);
            quiet.push(quiet_until(&b.corner(&base, latest_firing)));
            lane.push((i, b.center(&base), Some(b)));
        }
        Ok(Self::compose(scene, lane, quiet))
    }

    /// The bystander pieces obstacle `a` needs over the box: every bystander step is taken
    /// as possible (at some point of the box it may be).
    pub fn box_bystanders(&self, a: usize) -> Vec<Piece> {
        self.bystanders_needed(a, |_| true)
    }

    /// Every piece of obstacle `a` over the box: its own, then its bystanders.
    pub fn box_pieces(&self, a: usize) -> Vec<Piece> {
        let mut pieces = self.obstacles[a].decomposition.pieces.clone();
        pieces.extend(self.box_bystanders(a));
        pieces
    }
}

/// The end of each axis at which an obstacle standing still is fired at latest: the
/// smallest reaction radius and danger distance, the farthest start.
fn latest_firing(p: Parameter) -> End {
    match p {
        Parameter::InitialGap => End::High,
        _ => End::Low,
    }
}
