//! Region maps of a planar problem (docs/reductions.md Lemma P7): what the map search asks
//! of a planar problem. A box is certified by the bound alone at its weak corner (every
//! axis at the end whose relaxation contains the others'), and a box that the boundary
//! does not cross is refuted by a full planar `certify` at its centre that replays a
//! collision. Only the weak and the strong corner are analysed per box: if the weak corner
//! certifies, the whole box does; if the strong corner does not, no corner would be
//! certified by a relaxation that contains the strong corner's.

use std::sync::{Arc, Mutex, OnceLock};

use rustc_hash::FxHashMap;

use crate::analysis::region::{BoxCertificate, Hints, NotCertified};
use crate::analysis::region_subject::{LeafRefutation, RegionSubject};
use crate::core::num::Exact;
use crate::core::param_box::{End, ParamBox};
use crate::core::planar::PlanarProblem;
use crate::proof::planar::certificate::PlanarCertificate;
use crate::proof::planar::region::{
    ORIGIN, PlanarSource, planar_refusal, point_overrides, weak_end,
};
use crate::proof::region_map::RegionMap;
use crate::proof::verdict::Verdict;

use super::boundary::{Work, answer_text};
use super::certify::PlanarVerdict;

/// A bound-only answer at one point: its verdict, and its certificate and exact lower
/// bound when certified (the only answers a leaf keeps).
type PointAnswer = (Verdict, Option<(Box<PlanarCertificate>, Exact)>, usize);

/// A planar problem as a region map's subject.
pub struct PlanarRegion {
    source: PlanarSource,
    /// Bound-only answers by point (the ranged values' bits): neighbouring boxes share
    /// corners, and a certified leaf takes its weak corner's certificate from here.
    points: Mutex<FxHashMap<Vec<u64>, Arc<OnceLock<PointAnswer>>>>,
}

impl PlanarRegion {
    /// The planar problem file `text` with `overrides` (its `--set`s), already read as
    /// `problem`.
    pub fn new(text: &str, overrides: &[String], problem: &PlanarProblem) -> Self {
        PlanarRegion {
            source: PlanarSource {
                name: problem.name.clone(),
                clearance: problem.params().motion.clearance.to_f64().value(),
                problem_toml: text.to_string(),
                overrides: overrides.to_vec(),
            },
            points: Mutex::default(),
        }
    }

    /// The bound-only answer where each axis of `b` takes its value in `values`, computed
    /// once per point.
    fn at(&self, b: &ParamBox, values: &[f64]) -> Arc<OnceLock<PointAnswer>> {
        let key: Vec<u64> = values.iter().map(|v| v.to_bits()).collect();
        let slot = Arc::clone(
            self.points
                .lock()
                .expect("no panics inside")
                .entry(key)
                .or_default(),
        );
        slot.get_or_init(|| {
            let sets = point_overrides(&self.source, b, values);
            match answer_text(&self.source.problem_toml, ORIGIN, &sets, Work::BoundOnly) {
                Ok((PlanarVerdict::Certified, cert, lower)) => {
                    let programs = cert.programs;
                    (Verdict::Certified, Some((Box::new(cert), lower)), programs)
                }
                Ok((_, cert, _)) => (Verdict::Inconclusive, None, cert.programs),
                Err(_) => (Verdict::Inconclusive, None, 0),
            }
        });
        slot
    }

    /// The mask of `b`'s weak corner (bit i: axis i at its upper end).
    fn weak_mask(b: &ParamBox) -> u32 {
        b.axes
            .iter()
            .enumerate()
            .filter(|(_, a)| weak_end(a) == Ok(End::High))
            .map(|(i, _)| 1u32 << i)
            .sum()
    }
}

impl RegionSubject for PlanarRegion {
    fn refusal(&self, whole: &ParamBox) -> Option<String> {
        planar_refusal(&self.source, whole)
    }

    fn corners(&self, b: &ParamBox) -> Vec<u32> {
        let weak = Self::weak_mask(b);
        let strong = !weak & ((1u32 << b.axes.len()) - 1);
        vec![weak, strong]
    }

    fn certify_box(
        &self,
        b: &ParamBox,
        _hints: &Hints,
        _solved: &mut usize,
    ) -> Result<BoxCertificate, NotCertified> {
        // The weak corner was analysed as a corner: its programs are counted there.
        let slot = self.at(b, &b.corner_values(Self::weak_mask(b)));
        let (_, found, _) = slot.get().expect("computed by `at`");
        match found {
            Some((cert, lower)) => Ok(BoxCertificate {
                proofs: Vec::new(),
                lower_bound: lower.clone(),
                planar: Some(cert.clone()),
            }),
            None => Err(NotCertified {
                reason: "its weak corner is not certified".into(),
                hints: Hints::default(),
            }),
        }
    }

    fn verdict_at(&self, b: &ParamBox, values: &[f64]) -> (Verdict, usize) {
        let slot = self.at(b, values);
        let (verdict, _, programs) = slot.get().expect("computed by `at`");
        (*verdict, *programs)
    }

    fn refute_centre(&self, b: &ParamBox, solved: &mut usize) -> Result<LeafRefutation, String> {
        let centre: Vec<f64> = (0..b.axes.len()).map(|i| b.middle(i)).collect();
        let sets = point_overrides(&self.source, b, &centre);
        let (verdict, cert, _) =
            answer_text(&self.source.problem_toml, ORIGIN, &sets, Work::Certify)
                .map_err(|e| format!("its centre could not be analysed ({e})"))?;
        *solved += cert.programs;
        match verdict {
            PlanarVerdict::Refuted => Ok(LeafRefutation::Planar(Box::new(cert))),
            PlanarVerdict::Certified => Err("its centre is certified".into()),
            PlanarVerdict::Inconclusive => Err("its centre is inconclusive".into()),
        }
    }

    fn record(&self, map: &mut RegionMap) {
        map.planar = Some(self.source.clone());
    }
}
