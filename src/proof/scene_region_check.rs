//! Region maps of scenes: which scene boxes they cover, and `check` of a scene map's
//! leaves (the rest of [`crate::proof::region_check`] — digest, partition, coverage — is
//! shared).
//!
//! A certified leaf's proofs list, per obstacle of the robot's lane in scene order, one
//! proof per piece of [`SceneDecomposition::for_box`] (own pieces, then bystanders),
//! each tagged with the obstacle; each obstacle's proofs are checked against its own box
//! ([`box_margin`]). A refuted leaf's behaviour is replayed exactly through the scene's
//! step function at its point and must collide with the obstacle it names.

use crate::core::num::Exact;
use crate::core::param_box::ParamBox;
use crate::core::parameter::Parameter;
use crate::core::scene::{Scene, simulate};
use crate::proof::check::{Invalid, first_outside};
use crate::proof::region_check::{box_margin, point_in_leaf, shape_refusal};
use crate::proof::region_map::{BoxProof, SceneRefutation};
use crate::proof::scene_schedule::{ROBOT_LANE, SceneDecomposition};

fn invalid<T>(msg: impl Into<String>) -> Result<T, Invalid> {
    Err(Invalid(msg.into()))
}

/// Why region certificates do not cover `scene` over `whole` (None: they do).
pub fn scene_refusal(scene: &Scene, whole: &ParamBox) -> Option<String> {
    if let Some(reason) = shape_refusal(whole) {
        return Some(reason);
    }
    if let Err(e) = SceneDecomposition::decides(scene) {
        return Some(format!(
            "region certificates cover scenes the schedule analyser decides: {e}"
        ));
    }
    if scene.in_lane(ROBOT_LANE).next().is_none() {
        return Some("no obstacle is in the robot's lane: there is nothing to map".into());
    }
    for a in &whole.axes {
        let mut probe = scene.clone();
        if let Err(reason) = a.set_in_scene(&mut probe, a.lo) {
            return Some(reason);
        }
        if let Some(i) = a.obstacle {
            let o = &scene.obstacles[i];
            if o.lane != ROBOT_LANE {
                return Some(format!(
                    "{}: obstacle {i} ({:?}) is in lane {}; without lane changes the robot \
                     never meets it, so it cannot change the verdict",
                    a.key(),
                    o.name,
                    o.lane
                ));
            }
            if o.is_static && a.parameter == Parameter::ObstacleSpeed {
                return Some(format!(
                    "{}: obstacle {i} ({:?}) is static (its max_speed is 0)",
                    a.key(),
                    o.name
                ));
            }
        }
    }
    // Every constraint on these keys is an interval, so validity at every corner is validity
    // everywhere in the box.
    for mask in 0..(1u32 << whole.axes.len()) {
        let mut s = scene.clone();
        for (i, a) in whole.axes.iter().enumerate() {
            let v = if mask >> i & 1 == 1 { a.hi } else { a.lo };
            a.set_in_scene(&mut s, v).expect("checked above");
        }
        if let Err(e) = s.validate("the box's corner") {
            return Some(format!("the scene is invalid at a corner of the box: {e}"));
        }
    }
    None
}

/// The least margin s* − clearance and the least lower bound on s* that a certified scene
/// leaf's proofs establish over its box `b`.
pub fn scene_box_margin(
    scene: &Scene,
    b: &ParamBox,
    proofs: &[BoxProof],
) -> Result<(Exact, Exact), Invalid> {
    let dec = SceneDecomposition::for_box(scene, b)
        .map_err(|e| Invalid(format!("the scene is not analysable: {e}")))?;
    let mut rest = proofs;
    let mut least: Option<(Exact, Exact)> = None;
    for (a, o) in dec.obstacles.iter().enumerate() {
        let pieces = dec.box_pieces(a);
        let name = &scene.obstacles[o.obstacle].name;
        if rest.len() < pieces.len() {
            return invalid(format!(
                "obstacle {name:?} has {} pieces over the box; the leaf lists {} more proofs",
                pieces.len(),
                rest.len()
            ));
        }
        let (mine, tail) = rest.split_at(pieces.len());
        rest = tail;
        let (margin, lower) = box_margin(&o.decomposition, &pieces, mine, Some(o.obstacle))
            .map_err(|Invalid(e)| Invalid(format!("obstacle {name:?}: {e}")))?;
        least = Some(match least {
            None => (margin, lower),
            Some((m, l)) => (m.min(margin), l.min(lower)),
        });
    }
    if !rest.is_empty() {
        return invalid(format!(
            "the leaf lists {} proofs beyond its pieces",
            rest.len()
        ));
    }
    least.ok_or_else(|| Invalid("no obstacle is in the robot's lane".into()))
}

/// A scene refutation: the point lies in the box, the scene is valid there, the speeds
/// respect each obstacle's bound, and the exact replay collides with the named obstacle.
pub fn check_scene_refutation(
    scene: &Scene,
    b: &ParamBox,
    r: &SceneRefutation,
) -> Result<(), Invalid> {
    let mut at = scene.clone();
    for (a, v) in b.axes.iter().zip(point_in_leaf(b, &r.point)?) {
        a.set_in_scene(&mut at, v).map_err(Invalid)?;
    }
    at.validate("the refuted point")
        .map_err(|e| Invalid(format!("the refuted point's scene is invalid: {e}")))?;
    if r.obstacle_speeds.len() != at.obstacles.len() || r.obstacle >= at.obstacles.len() {
        return invalid("the behaviour lists speeds for another number of obstacles");
    }
    let params = at.params::<Exact>();
    for (i, speeds) in r.obstacle_speeds.iter().enumerate() {
        if let Some(k) = first_outside(speeds, &params.obstacles[i].max_speed) {
            return invalid(format!(
                "the behaviour's speed of obstacle {i} in period {k} is outside [0, W]"
            ));
        }
    }
    let periods = r.obstacle_speeds.iter().map(Vec::len).max().unwrap_or(0);
    let starts: Vec<Exact> = params
        .obstacles
        .iter()
        .map(|o| o.start_min.clone())
        .collect();
    let replay = simulate::replay(&params, &r.obstacle_speeds, &starts, periods, true);
    if !replay.run.outcome.obstacles[r.obstacle].collided {
        return invalid(format!(
            "the behaviour does not collide with obstacle {} at the refuted point",
            r.obstacle
        ));
    }
    Ok(())
}
