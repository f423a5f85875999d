//! The lane axis: positions and velocities in the odometry frame projected on the line the
//! robot drives along, which is the one dimension the certificate's model has.

use super::messages::{Pose, Quaternion, Twist};

/// A point and a unit direction in the plane of the odometry frame: `x` along the lane is
/// `(p − origin) · direction`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneAxis {
    /// Where lane position 0 is (m), in the odometry frame.
    pub origin: [f64; 2],
    /// The unit direction the robot drives in.
    pub direction: [f64; 2],
}

impl LaneAxis {
    /// The axis through `origin` at heading `yaw` (rad, counter-clockwise from the frame's x
    /// axis), as `--lane-axis X,Y,YAW` states it.
    pub fn new(origin: [f64; 2], yaw: f64) -> LaneAxis {
        LaneAxis {
            origin,
            direction: [yaw.cos(), yaw.sin()],
        }
    }

    /// The axis of a robot's first pose: through its position, along its heading. `None`
    /// when the pose has no usable heading (a zero or non-finite quaternion, or a robot
    /// pointing straight up): the lane's direction is then unknown.
    pub fn from_pose(pose: &Pose) -> Option<LaneAxis> {
        let [ex, _] = body_axes(&pose.orientation)?;
        let norm = ex[0].hypot(ex[1]);
        let origin = [pose.position.x, pose.position.y];
        (norm > 1e-9 && origin.iter().all(|v| v.is_finite())).then(|| LaneAxis {
            origin,
            direction: [ex[0] / norm, ex[1] / norm],
        })
    }

    /// A position along the lane (m).
    #[inline]
    pub fn position(&self, p: [f64; 2]) -> f64 {
        (p[0] - self.origin[0]) * self.direction[0] + (p[1] - self.origin[1]) * self.direction[1]
    }

    /// A position in the frame whose origin is the axis's and whose x axis is its direction
    /// (m): along it, and to its left.
    #[inline]
    pub fn local(&self, p: [f64; 2]) -> [f64; 2] {
        let d = [p[0] - self.origin[0], p[1] - self.origin[1]];
        self.rotate(d)
    }

    /// A world-frame vector in that frame.
    #[inline]
    pub fn rotate(&self, v: [f64; 2]) -> [f64; 2] {
        let [c, s] = self.direction;
        [v[0] * c + v[1] * s, v[1] * c - v[0] * s]
    }

    /// A world-frame velocity's component along the lane (m/s).
    #[inline]
    pub fn along(&self, v: [f64; 2]) -> f64 {
        v[0] * self.direction[0] + v[1] * self.direction[1]
    }
}

/// The planar velocity of a body, in the pose's frame, from a twist in the body frame (as
/// `nav_msgs/Odometry` and Autoware's tracked objects give it). `None` when the orientation
/// is not a rotation (zero or non-finite): the velocity's direction is then unknown.
#[inline]
pub fn world_velocity(pose: &Pose, twist: &Twist) -> Option<[f64; 2]> {
    let [ex, ey] = body_axes(&pose.orientation)?;
    let (vx, vy) = (twist.linear.x, twist.linear.y);
    Some([vx * ex[0] + vy * ey[0], vx * ex[1] + vy * ey[1]])
}

/// The body's x and y axes in the pose's frame (their planar parts): the first two columns
/// of the rotation matrix of `q`, which need not be normalised.
#[inline]
fn body_axes(q: &Quaternion) -> Option<[[f64; 2]; 2]> {
    let n2 = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
    if !(n2 > 0.0 && n2.is_finite()) {
        return None;
    }
    let s = 2.0 / n2;
    let ex = [
        1.0 - s * (q.y * q.y + q.z * q.z),
        s * (q.x * q.y + q.w * q.z),
    ];
    let ey = [
        s * (q.x * q.y - q.w * q.z),
        1.0 - s * (q.x * q.x + q.z * q.z),
    ];
    Some([ex, ey])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::monitor::bag::messages::Vector3;

    fn pose(x: f64, y: f64, yaw: f64) -> Pose {
        let h = yaw / 2.0;
        Pose {
            position: Vector3 { x, y, z: 0.0 },
            orientation: Quaternion {
                x: 0.0,
                y: 0.0,
                z: h.sin(),
                w: h.cos(),
            },
        }
    }

    fn twist(vx: f64, vy: f64) -> Twist {
        let zero = Vector3 {
            x: 0.0,
            y: 0.0,
            z: 0.0,
        };
        Twist {
            linear: Vector3 {
                x: vx,
                y: vy,
                z: 0.0,
            },
            angular: zero,
        }
    }

    #[test]
    fn the_identity_pose_reads_positions_and_speeds_exactly() {
        let axis = LaneAxis::from_pose(&pose(0.0, 0.0, 0.0)).unwrap();
        assert_eq!(axis.direction, [1.0, 0.0]);
        // Exact: the seed's traces go through a bag bit for bit.
        for x in [0.1, 2.1, 9.7, 1e-300, 123.456] {
            assert_eq!(axis.position([x, 0.0]), x);
            let v = world_velocity(&pose(x, 0.0, 0.0), &twist(x, 0.0)).unwrap();
            assert_eq!(axis.along(v), x);
        }
    }

    #[test]
    fn a_rotated_lane_projects_like_the_closed_form() {
        // A lane at 30° through (1, 2): a point 5 m along it and 1 m to its left.
        let yaw = 30f64.to_radians();
        let axis = LaneAxis::from_pose(&pose(1.0, 2.0, yaw)).unwrap();
        let (c, s) = (yaw.cos(), yaw.sin());
        let p = [1.0 + 5.0 * c - s, 2.0 + 5.0 * s + c];
        assert!((axis.position(p) - 5.0).abs() < 1e-12);
        // An oncoming obstacle facing back down the lane at 0.25 m/s forward speed.
        let v = world_velocity(
            &pose(p[0], p[1], yaw + std::f64::consts::PI),
            &twist(0.25, 0.0),
        );
        assert!((axis.along(v.unwrap()) + 0.25).abs() < 1e-12);
        // Sideways body motion contributes nothing along the lane.
        let v = world_velocity(&pose(0.0, 0.0, yaw), &twist(0.0, 3.0)).unwrap();
        assert!(axis.along(v).abs() < 1e-12);
        // The same axis stated by hand.
        let given = LaneAxis::new([1.0, 2.0], yaw);
        assert!((given.position(p) - 5.0).abs() < 1e-12);
    }

    #[test]
    fn a_zero_quaternion_has_no_direction() {
        let mut p = pose(0.0, 0.0, 0.0);
        p.orientation.w = 0.0;
        assert!(LaneAxis::from_pose(&p).is_none());
        assert!(world_velocity(&p, &twist(1.0, 0.0)).is_none());
        p.orientation.w = f64::NAN;
        assert!(world_velocity(&p, &twist(1.0, 0.0)).is_none());
    }
}
