//! The planar monitor fed by the trace reader ([`Decoder`]): a decoded line's sample and the
//! decoder's planar cells make a [`PlanarSample`], its obstacle matched by the name the trace
//! gives it — the one way the command line, Python and the fuzz targets feed a text trace.

use super::{PlanarMonitor, PlanarRobotSample, PlanarSample};
use crate::monitor::trace::Decoder;
use crate::monitor::{Detail, Field, Outcome, RobotSample, Sample};

impl PlanarMonitor {
    /// Checks a decoded sample with the planar cells `decoder` read with it; a row without
    /// `robot_y` or `obstacle_y`, or with one velocity component only, is a malformed sample.
    pub fn observe_decoded(&mut self, decoder: &Decoder, s: &Sample) -> Outcome<'_> {
        let cells = decoder.plane();
        let (robot_y, obstacle_y) = match (cells.robot_y, cells.obstacle_y) {
            (Some(r), Some(o)) => (r, o),
            (None, _) => return self.missing(s.t, Field::RobotY),
            (_, None) => return self.missing(s.t, Field::ObstacleY),
        };
        let obstacle_velocity = match (cells.obstacle_vx, cells.obstacle_vy) {
            (Some(x), Some(y)) => Some((x, y)),
            (None, None) => None,
            (Some(_), None) => return self.missing(s.t, Field::ObstacleVy),
            (None, Some(_)) => return self.missing(s.t, Field::ObstacleVx),
        };
        self.identify_once(s.obstacle_id, decoder.ids().name(s.obstacle_id));
        self.observe(&PlanarSample {
            t: s.t,
            robot_x: s.robot_x,
            robot_y,
            robot_v: s.robot_v,
            robot_mode: s.robot_mode,
            obstacle_id: s.obstacle_id,
            obstacle_x: s.obstacle_x,
            obstacle_y,
            obstacle_velocity,
        })
    }

    /// Checks a decoded robot-only sample (`robot_y` from `decoder`'s planar cells; missing,
    /// a malformed sample).
    pub fn observe_decoded_robot(&mut self, decoder: &Decoder, r: &RobotSample) -> Outcome<'_> {
        let Some(robot_y) = decoder.plane().robot_y else {
            return self.missing(r.t, Field::RobotY);
        };
        self.observe_robot(&PlanarRobotSample {
            t: r.t,
            robot_x: r.robot_x,
            robot_y,
            robot_v: r.robot_v,
            robot_mode: r.robot_mode,
        })
    }

    /// The sample at `t` lacks `field`: a malformed sample.
    fn missing(&mut self, t: f64, field: Field) -> Outcome<'_> {
        self.malformed(Some(t), Detail::MissingField(field))
    }
}
