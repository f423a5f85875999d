//! Region maps of scenes: a box over shared parameters (ρ, V_a, buffer, clearance) and
//! each obstacle's own (`obstacle.<i>.max_speed`, `obstacle.<i>.position`), certified with
//! one proof per piece of [`SceneDecomposition::for_box`] for every obstacle of the robot's
//! lane, and refuted at a centre by the scene analyser's colliding witness.

use crate::analysis::region::{BoxCertificate, Hints, NotCertified, certify_obstacle};
use crate::analysis::region_subject::{LeafRefutation, RegionSubject};
use crate::analysis::scene::analyse_scene;
use crate::core::num::Exact;
use crate::core::param_box::ParamBox;
use crate::core::scene::Scene;
use crate::proof::region_map::{RegionMap, SceneRefutation};
use crate::proof::scene_region_check::{check_scene_refutation, scene_refusal};
use crate::proof::scene_schedule::SceneDecomposition;
use crate::proof::verdict::Verdict;

/// Tries to certify `scene` (covered over `b`: [`scene_refusal`]) at every point of `b`.
pub fn certify_scene_box(
    scene: &Scene,
    b: &ParamBox,
    hints: &Hints,
    solved: &mut usize,
) -> Result<BoxCertificate, NotCertified> {
    let mut found = Hints::default();
    let dec = SceneDecomposition::for_box(scene, b).map_err(|e| NotCertified {
        reason: e.0,
        hints: Hints::default(),
    })?;
    let mut proofs = Vec::new();
    let mut lower: Option<Exact> = None;
    for (a, o) in dec.obstacles.iter().enumerate() {
        let pieces = dec.box_pieces(a);
        let d = &o.decomposition;
        match certify_obstacle(d, &pieces, Some(o.obstacle), hints, &mut found, solved) {
            Ok((p, l)) => {
                proofs.extend(p);
                if lower.as_ref().is_none_or(|x| l < *x) {
                    lower = Some(l);
                }
            }
            Err(reason) => {
                return Err(NotCertified {
                    reason: format!("obstacle {:?}: {reason}", scene.obstacles[o.obstacle].name),
                    hints: found,
                });
            }
        }
    }
    Ok(BoxCertificate {
        proofs,
        lower_bound: lower.expect("a covered scene has an obstacle in the robot's lane"),
        planar: None,
    })
}

/// The scene where each axis of `b` takes its value in `values`.
fn scene_at(scene: &Scene, b: &ParamBox, values: &[f64]) -> Scene {
    let mut s = scene.clone();
    for (a, &v) in b.axes.iter().zip(values) {
        a.set_in_scene(&mut s, v).expect("a covered box");
    }
    s
}

impl RegionSubject for Scene {
    fn refusal(&self, whole: &ParamBox) -> Option<String> {
        scene_refusal(self, whole)
    }

    fn certify_box(
        &self,
        b: &ParamBox,
        hints: &Hints,
        solved: &mut usize,
    ) -> Result<BoxCertificate, NotCertified> {
        certify_scene_box(self, b, hints, solved)
    }

    fn verdict_at(&self, b: &ParamBox, values: &[f64]) -> (Verdict, usize) {
        match analyse_scene(&scene_at(self, b, values)) {
            Ok(a) => (a.verdict, a.programs_solved),
            Err(_) => (Verdict::Inconclusive, 0),
        }
    }

    fn refute_centre(&self, b: &ParamBox, solved: &mut usize) -> Result<LeafRefutation, String> {
        let values: Vec<f64> = (0..b.axes.len()).map(|i| b.middle(i)).collect();
        let a = analyse_scene(&scene_at(self, b, &values))
            .map_err(|e| format!("its centre could not be analysed ({e})"))?;
        *solved += a.programs_solved;
        match (a.verdict, a.witness) {
            (Verdict::Refuted, Some(w)) => {
                let r = SceneRefutation {
                    point: b.axes.iter().map(|x| x.key()).zip(values).collect(),
                    obstacle: w.obstacle,
                    obstacle_speeds: w.obstacle_speeds.iter().map(|s| s.to_vec()).collect(),
                };
                // What `check` will ask of it (a witness may collide with another obstacle
                // than the one whose separation it pins).
                check_scene_refutation(self, b, &r)
                    .map_err(|e| format!("its centre's witness is no refutation here ({})", e.0))?;
                Ok(LeafRefutation::Scene(r))
            }
            (Verdict::Certified, _) => Err("its centre is certified".into()),
            _ => Err("its centre is inconclusive".into()),
        }
    }

    fn record(&self, map: &mut RegionMap) {
        map.scene = Some(self.clone());
    }
}
