//! The robot's state: its automaton location ([`Mode`]) and where it is at an instant
//! ([`RobotState`]).

use serde::{Deserialize, Serialize};

use crate::core::model::Params;
use crate::core::num::Scalar;

/// The robot's automaton location (the seed's robot template).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// Before t = 0.
    Idle,
    /// Speeding up at a until v_max.
    Accelerate,
    /// Cruising at v_max.
    Drive,
    /// Slowing at b (the plant: b_min) until at rest; latched.
    Brake,
    /// At rest after braking; final.
    Stop,
}

impl Mode {
    /// Name as written in traces.
    pub fn as_str(self) -> &'static str {
        match self {
            Mode::Idle => "idle",
            Mode::Accelerate => "accelerate",
            Mode::Drive => "drive",
            Mode::Brake => "brake",
            Mode::Stop => "stop",
        }
    }

    /// Every mode, in the automaton's order.
    pub const ALL: [Mode; 5] = [
        Mode::Idle,
        Mode::Accelerate,
        Mode::Drive,
        Mode::Brake,
        Mode::Stop,
    ];

    /// The mode a trace names, in any ASCII case (`drive`, `Brake`, ...).
    pub fn from_name(text: &[u8]) -> Option<Mode> {
        Mode::ALL
            .into_iter()
            .find(|m| m.as_str().as_bytes().eq_ignore_ascii_case(text))
    }
}

/// The robot's state at an instant.
#[derive(Clone, Debug, PartialEq)]
pub struct RobotState<N> {
    /// Position along the lane (m).
    pub position: N,
    /// Speed (m/s).
    pub speed: N,
    /// Automaton location.
    pub mode: Mode,
}

impl<N: Scalar> RobotState<N> {
    /// The robot at t = 0: at position 0 with speed v0, in Drive if v0 = v_max, else in
    /// Accelerate (a robot at rest leaves Idle at t = 0).
    pub fn initial(p: &Params<N>) -> Self {
        let mode = if p.v0 >= p.v_max {
            Mode::Drive
        } else {
            Mode::Accelerate
        };
        RobotState {
            position: N::zero(),
            speed: p.v0.clone(),
            mode,
        }
    }
}
