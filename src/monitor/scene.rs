//! Monitoring against a scene certificate: what the certificate's scene assumed of each of
//! its obstacles (lane, speed bound W_i, static or not), and which trace obstacle is which.
//!
//! A scene certificate's `premises` state the scene's largest moving bound as W; each
//! obstacle's own bound is in its scene. The monitor checks a trace obstacle whose id equals
//! an obstacle's name ([`Monitor::identify`]) against that obstacle's own W_i and lane (a
//! static one must not move at all, beyond what observation noise allows), and any other
//! tracked object against the largest moving bound, in any lane. Safety itself
//! (`collision`) is checked for every obstacle in a lane the robot occupies.

use super::check::Bounds;
use super::lanes::Lanes;
use super::trace::{Decoder, Ids};
use super::{Monitor, MonitorError, ObstacleId, Outcome, Rule, Sample, Track, require_certified};
use crate::core::scene::Scene;
use crate::proof::certificate_file::CertificateFile;
use crate::proof::check::CheckReport;
use crate::proof::premise::Premise;
use crate::proof::scene_certificate::{SceneCertificate, scene_premises};
use crate::proof::scene_check::check_scene;
use crate::proof::search_certificate::SearchCertificate;
use crate::proof::search_check::check_search;

/// What a scene certificate assumed of one of its obstacles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CertifiedObstacle {
    /// Its lane.
    pub(crate) lane: i32,
    /// W_i (m/s).
    pub(crate) max_speed: f64,
    /// Static: it does not move.
    pub(crate) is_static: bool,
}

/// A scene certificate's assumptions, per obstacle in scene order.
#[derive(Clone, Debug)]
pub(crate) struct SceneAssumptions {
    /// The obstacles' names: trace obstacle ids are matched to them.
    pub(crate) names: Vec<String>,
    /// What was assumed of each.
    pub(crate) obstacles: Vec<CertifiedObstacle>,
    /// Premise violations so far by samples of each.
    pub(crate) violations: Vec<u64>,
}

impl SceneAssumptions {
    /// The assumptions of `cert`'s scene, each bound usable (finite, not negative).
    fn of(scene: &Scene) -> Result<SceneAssumptions, MonitorError> {
        let usable = |name: &'static str, bound: f64| {
            if bound.is_finite() && bound >= 0.0 {
                Ok(bound)
            } else {
                Err(MonitorError::BadBound { name, bound })
            }
        };
        let obstacles = scene
            .obstacles
            .iter()
            .map(|o| {
                Ok(CertifiedObstacle {
                    lane: o.lane,
                    max_speed: usable("obstacle_speed", o.max_speed)?,
                    is_static: o.is_static,
                })
            })
            .collect::<Result<Vec<_>, MonitorError>>()?;
        Ok(SceneAssumptions {
            names: scene.obstacles.iter().map(|o| o.name.clone()).collect(),
            violations: vec![0; obstacles.len()],
            obstacles,
        })
    }
}

impl Monitor {
    /// A monitor for a scene certificate: runs
    /// [`check_scene`], requires the verdict
    /// `certified`, reads the bounds from the premises (W is the scene's largest moving
    /// bound) and each obstacle's lane and W_i from the scene. Trace obstacles are matched to
    /// the scene's by name with [`Monitor::identify`] (or [`Monitor::observe_decoded`]);
    /// ids as for [`Monitor::new`].
    pub fn for_scene(cert: &SceneCertificate) -> Result<Monitor, MonitorError> {
        Self::build_scene(cert, super::DEFAULT_MAX_OBSTACLES, 0)
    }

    /// [`Monitor::for_scene`] with the obstacle table allocated once, as
    /// [`Monitor::with_max_obstacles`].
    pub fn for_scene_with_max_obstacles(
        cert: &SceneCertificate,
        max_obstacles: u32,
    ) -> Result<Monitor, MonitorError> {
        Self::build_scene(cert, max_obstacles, max_obstacles as usize)
    }

    /// A monitor for a certificate of either kind: [`Monitor::new`] or
    /// [`Monitor::for_scene`].
    pub fn for_certificate_file(cert: &CertificateFile) -> Result<Monitor, MonitorError> {
        match cert {
            CertificateFile::Single(c) => Monitor::new(c),
            CertificateFile::Scene(c) => Monitor::for_scene(c),
            CertificateFile::Search(c) => Monitor::for_search(c),
            CertificateFile::Planar(_) => Err(MonitorError::Planar),
        }
    }

    /// [`Monitor::for_certificate_file`] with the obstacle table allocated once, as
    /// [`Monitor::with_max_obstacles`].
    pub fn for_certificate_file_with_max_obstacles(
        cert: &CertificateFile,
        max_obstacles: u32,
    ) -> Result<Monitor, MonitorError> {
        match cert {
            CertificateFile::Single(c) => Monitor::with_max_obstacles(c, max_obstacles),
            CertificateFile::Scene(c) => Monitor::for_scene_with_max_obstacles(c, max_obstacles),
            CertificateFile::Search(c) => Self::build_from(
                check_search(c)?,
                &c.premises,
                &c.scene,
                c.clearance,
                max_obstacles,
                max_obstacles as usize,
            ),
            CertificateFile::Planar(_) => Err(MonitorError::Planar),
        }
    }

    /// A monitor for a search certificate (a scene with lane changes or position ranges),
    /// as [`Monitor::for_scene`]: [`check_search`] runs first.
    pub fn for_search(cert: &SearchCertificate) -> Result<Monitor, MonitorError> {
        Self::build_from(
            check_search(cert)?,
            &cert.premises,
            &cert.scene,
            cert.clearance,
            super::DEFAULT_MAX_OBSTACLES,
            0,
        )
    }

    fn build_scene(
        cert: &SceneCertificate,
        max_obstacles: u32,
        reserve: usize,
    ) -> Result<Monitor, MonitorError> {
        Self::build_from(
            check_scene(cert)?,
            &cert.premises,
            &cert.scene,
            cert.clearance,
            max_obstacles,
            reserve,
        )
    }

    /// A monitor for a scene proved certified by other means (a point of a certified box
    /// of a scene region map): its premises are the scene's own ([`scene_premises`]).
    pub(crate) fn for_certified_scene(scene: &Scene) -> Result<Monitor, MonitorError> {
        Self::build_certified(
            &scene_premises(scene),
            scene,
            scene.robot.clearance,
            super::DEFAULT_MAX_OBSTACLES,
            0,
        )
    }

    fn build_from(
        report: CheckReport,
        premises: &[Premise],
        scene: &Scene,
        clearance: f64,
        max_obstacles: u32,
        reserve: usize,
    ) -> Result<Monitor, MonitorError> {
        require_certified(report.verdict)?;
        Self::build_certified(premises, scene, clearance, max_obstacles, reserve)
    }

    fn build_certified(
        premises: &[Premise],
        scene: &Scene,
        clearance: f64,
        max_obstacles: u32,
        reserve: usize,
    ) -> Result<Monitor, MonitorError> {
        let bounds = Bounds::from_premises(premises)?;
        if !(clearance.is_finite() && clearance >= 0.0) {
            return Err(MonitorError::BadBound {
                name: "clearance",
                bound: clearance,
            });
        }
        let params = scene.params::<f64>();
        let rule = Rule {
            moving: params.robot,
            fixed: params.static_robot,
            clearance,
        };
        let assumptions = SceneAssumptions::of(scene)?;
        Ok(Self::with_bounds(
            bounds,
            rule,
            Some(assumptions),
            max_obstacles,
            reserve,
        ))
    }

    /// Whether this monitors a scene certificate.
    pub fn is_scene(&self) -> bool {
        self.scene.is_some()
    }

    /// Matches trace obstacle `id` to the scene obstacle named `name` (exactly, as the trace
    /// writes it): its samples are then checked against that obstacle's W_i and lane. Returns
    /// the obstacle's index in the scene, or `None` when no obstacle has that name, the
    /// certificate is not a scene's, or `id` is beyond the table. An id never matched is a
    /// tracked object the scene does not name, checked against the largest moving bound.
    ///
    /// Call it before the obstacle's first sample (earlier samples were checked as
    /// unmatched). Allocates only to grow the table, as a new largest id does in
    /// [`Monitor::observe`].
    pub fn identify(&mut self, id: ObstacleId, name: &str) -> Option<usize> {
        let found = self.scene.as_ref()?.names.iter().position(|n| n == name);
        if id >= self.max_obstacles {
            return None;
        }
        let idx = id as usize;
        if idx >= self.obstacles.len() {
            self.obstacles.resize(idx + 1, Track::default());
        }
        let track = &mut self.obstacles[idx];
        track.named = true;
        track.certified = found.and_then(|i| std::num::NonZeroU32::new(i as u32 + 1));
        found
    }

    /// [`Monitor::observe_in_lanes`] for a sample `decoder` just read: under a scene
    /// certificate a new obstacle id is first matched by its text ([`Monitor::identify`]),
    /// and the sample's lanes are the decoder's ([`Decoder::lanes`]). The way to feed a text
    /// trace.
    pub fn observe_decoded(&mut self, decoder: &Decoder, s: &Sample) -> Outcome<'_> {
        self.observe_named(decoder.ids(), s, decoder.lanes())
    }

    /// [`Monitor::observe_in_lanes`] for a sample whose obstacle `ids` names: under a scene
    /// certificate a new obstacle id is first matched by its name ([`Monitor::identify`]).
    /// The way to feed any reader that names obstacles (a text trace, a bag).
    pub fn observe_named(&mut self, ids: &Ids, s: &Sample, lanes: Lanes) -> Outcome<'_> {
        if self.scene.is_some() {
            let named = self
                .obstacles
                .get(s.obstacle_id as usize)
                .is_some_and(|t| t.named);
            if !named {
                self.identify(s.obstacle_id, ids.name(s.obstacle_id));
            }
        }
        self.observe_in_lanes(s, lanes)
    }

    /// What the scene assumed of the obstacle `track` was matched to.
    #[inline]
    pub(crate) fn certified(&self, track: &Track) -> Option<CertifiedObstacle> {
        let scene = self.scene.as_ref()?;
        scene.obstacles.get(track.certified_index()?).copied()
    }

    /// Counts a premise violation against the scene obstacle `id` was matched to, if any.
    pub(crate) fn count_for_certified(&mut self, id: Option<ObstacleId>) {
        let Some(scene) = self.scene.as_mut() else {
            return;
        };
        let matched = id
            .and_then(|id| self.obstacles.get(id as usize))
            .and_then(Track::certified_index);
        if let Some(count) = matched.and_then(|i| scene.violations.get_mut(i)) {
            *count += 1;
        }
    }
}
