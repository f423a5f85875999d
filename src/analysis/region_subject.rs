//! What a region map is drawn over — a problem, or a scene — and the four things the map
//! search asks of it: whether it covers the box, a box certificate, a point's verdict
//! (corners) and a colliding behaviour at a box's centre.

use std::collections::BTreeMap;

use crate::analysis::analyse::{Options, WitnessPolicy, analyse_with};
use crate::analysis::region::{BoxCertificate, Hints, NotCertified, certify_box};
use crate::core::model::Problem;
use crate::core::param_box::ParamBox;
use crate::proof::planar::certificate::PlanarCertificate;
use crate::proof::region_check::refusal;
use crate::proof::region_map::{Refutation, RegionMap, SceneRefutation};
use crate::proof::verdict::Verdict;

/// A refuted leaf's evidence.
#[derive(Clone, Debug)]
pub enum LeafRefutation {
    /// At a point of a problem map.
    Problem(Refutation),
    /// At a point of a scene map.
    Scene(SceneRefutation),
    /// At a point of a planar map: its refuted certificate.
    Planar(Box<PlanarCertificate>),
}

/// What region maps can be drawn over.
pub trait RegionSubject: Sync {
    /// Why region certificates do not cover it over `whole` (None: they do).
    fn refusal(&self, whole: &ParamBox) -> Option<String>;

    /// Tries to certify every point of `b`, trying `hints` before the solver.
    fn certify_box(
        &self,
        b: &ParamBox,
        hints: &Hints,
        solved: &mut usize,
    ) -> Result<BoxCertificate, NotCertified>;

    /// The corners of `b` whose verdicts decide how it is searched, each as a mask (bit i
    /// set: axis i at its upper end), in the order they are analysed: every corner, unless
    /// the subject knows fewer suffice.
    fn corners(&self, b: &ParamBox) -> Vec<u32> {
        (0..(1u32 << b.axes.len())).collect()
    }

    /// The verdict where each axis of `b` takes its value in `values` (no witness is
    /// replayed), and the programs solved.
    fn verdict_at(&self, b: &ParamBox, values: &[f64]) -> (Verdict, usize);

    /// A colliding behaviour at the centre of `b`, or a note on what the centre is.
    fn refute_centre(&self, b: &ParamBox, solved: &mut usize) -> Result<LeafRefutation, String>;

    /// Records in the map what was mapped.
    fn record(&self, map: &mut RegionMap);
}

impl RegionSubject for Problem {
    fn refusal(&self, whole: &ParamBox) -> Option<String> {
        refusal(self, whole)
    }

    fn certify_box(
        &self,
        b: &ParamBox,
        hints: &Hints,
        solved: &mut usize,
    ) -> Result<BoxCertificate, NotCertified> {
        certify_box(self, b, hints, solved)
    }

    fn verdict_at(&self, b: &ParamBox, values: &[f64]) -> (Verdict, usize) {
        let mut p = self.clone();
        for (a, &v) in b.axes.iter().zip(values) {
            a.parameter.set_in(&mut p, v);
        }
        let options = Options {
            witness: WitnessPolicy::Never,
        };
        match analyse_with(&p, options) {
            Ok(a) => (a.verdict, a.programs_solved),
            Err(_) => (Verdict::Inconclusive, 0),
        }
    }

    fn refute_centre(&self, b: &ParamBox, solved: &mut usize) -> Result<LeafRefutation, String> {
        let point = b.center_problem(self);
        let options = Options {
            witness: WitnessPolicy::ToRefute,
        };
        let a = analyse_with(&point, options)
            .map_err(|e| format!("its centre could not be analysed ({e})"))?;
        *solved += a.programs_solved;
        match (a.verdict, a.witness) {
            (Verdict::Refuted, Some(w)) => Ok(LeafRefutation::Problem(Refutation {
                point: b
                    .axes
                    .iter()
                    .map(|x| (x.key(), x.parameter.get_in(&point)))
                    .collect::<BTreeMap<_, _>>(),
                piece: w.piece,
                shift: w.shift,
                obstacle_speeds: w.obstacle_speeds.to_vec(),
            })),
            (Verdict::Certified, _) => Err("its centre is certified".into()),
            _ => Err("its centre is inconclusive".into()),
        }
    }

    fn record(&self, map: &mut RegionMap) {
        map.problem = Some(self.clone());
    }
}
