//! A scene's answer from whichever exact engine decides it: the schedule analyser
//! ([`analyse_scene`], with LP proofs) when the scene has no lane changes and no position
//! ranges, else the run search ([`certify_by_search`]).

use crate::analysis::scene::{SceneAnalysis, SceneAnalysisError, analyse_scene};
use crate::analysis::scene_worst::SceneWorstCase;
use crate::core::num::f64_at_most;
use crate::core::scene::Scene;
use crate::proof::certificate_file::CertificateFile;
use crate::proof::scene_certificate::SceneCertificate;
use crate::proof::scene_schedule::SceneDecomposition;
use crate::proof::search_certificate::{
    SearchCertificate, certify_by_search, certify_by_search_with_steps,
};
use crate::proof::verdict::Verdict;

/// A scene's answer.
#[derive(Clone, Debug)]
pub enum SceneAnswer {
    /// From the schedule analyser; the flag: its certificate keeps the witness's rows.
    Schedule(Box<SceneAnalysis>, bool),
    /// From the run search (lane changes, position ranges).
    Search(Box<SearchCertificate>),
}

impl SceneAnswer {
    /// Decides a (validated) scene with the engine that covers it; the certificate's
    /// witness has no rows per period.
    pub fn of(scene: &Scene) -> Result<SceneAnswer, SceneAnalysisError> {
        Self::deciding(scene, false)
    }

    /// [`Self::of`] with the witness's rows per period in the certificate (`--steps`).
    pub fn of_with_steps(scene: &Scene) -> Result<SceneAnswer, SceneAnalysisError> {
        Self::deciding(scene, true)
    }

    fn deciding(scene: &Scene, steps: bool) -> Result<SceneAnswer, SceneAnalysisError> {
        if SceneDecomposition::decides(scene).is_ok() {
            return Ok(SceneAnswer::Schedule(
                Box::new(analyse_scene(scene)?),
                steps,
            ));
        }
        let certify = match steps {
            true => certify_by_search_with_steps,
            false => certify_by_search,
        };
        let cert = certify(scene).map_err(|e| SceneAnalysisError::Search(e.to_string()))?;
        Ok(SceneAnswer::Search(Box::new(cert)))
    }

    /// The scene answered.
    pub fn scene(&self) -> &Scene {
        match self {
            SceneAnswer::Schedule(a, _) => &a.scene,
            SceneAnswer::Search(c) => &c.scene,
        }
    }

    /// The verdict.
    pub fn verdict(&self) -> Verdict {
        match self {
            SceneAnswer::Schedule(a, _) => a.verdict,
            SceneAnswer::Search(c) => c.verdict,
        }
    }

    /// s* (None: −∞, or nothing measured, or not realised).
    pub fn min_separation(&self) -> Option<f64> {
        match self {
            SceneAnswer::Schedule(a, _) => a.min_separation,
            SceneAnswer::Search(c) => c.min_separation,
        }
    }

    /// s* = −∞.
    pub fn never_stops(&self) -> bool {
        match self {
            SceneAnswer::Schedule(a, _) => a.never_stops,
            SceneAnswer::Search(c) => c.never_stops,
        }
    }

    /// The rigorous lower bound, rounded down.
    pub fn lower_bound(&self) -> Option<f64> {
        match self {
            SceneAnswer::Schedule(a, _) => a.lower_bound.as_ref().map(f64_at_most),
            SceneAnswer::Search(c) => c.lower_bound,
        }
    }

    /// Pieces proved (schedule) or runs searched.
    pub fn cases(&self) -> usize {
        match self {
            SceneAnswer::Schedule(a, _) => a
                .obstacles
                .iter()
                .map(|o| o.own.len() + o.bystanders.len())
                .sum(),
            SceneAnswer::Search(c) => c.runs,
        }
    }

    /// Linear programs solved (none for the search).
    pub fn programs(&self) -> usize {
        match self {
            SceneAnswer::Schedule(a, _) => a.programs_solved,
            SceneAnswer::Search(_) => 0,
        }
    }

    /// The worst case in words.
    pub fn worst_case(&self) -> Option<SceneWorstCase> {
        match self {
            SceneAnswer::Schedule(a, _) => SceneWorstCase::of_analysis(a),
            SceneAnswer::Search(c) => SceneWorstCase::of_search(c),
        }
    }

    /// Its certificate (the witness's rows per period as the answer was asked for).
    pub fn certificate(&self) -> CertificateFile {
        match self {
            SceneAnswer::Schedule(a, false) => {
                CertificateFile::Scene(Box::new(SceneCertificate::from_analysis(a)))
            }
            SceneAnswer::Schedule(a, true) => {
                CertificateFile::Scene(Box::new(SceneCertificate::from_analysis_with_steps(a)))
            }
            SceneAnswer::Search(c) => CertificateFile::Search(c.clone()),
        }
    }
}
