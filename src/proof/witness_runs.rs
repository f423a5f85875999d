//! A witness as runs rather than periods: the obstacle's speeds as constant-speed segments
//! and the robot's modes as mode segments, so a certificate's witness grows with how often
//! the behaviour changes, not with the horizon (a robot at 1 kHz keeps a worst case of a
//! few segments over half a million periods).
//!
//! In memory a witness keeps one speed per period (the replay reads them as constant runs); the
//! certificate file stores [`SpeedSegment`]s, read back with their order, contiguity and total
//! length checked ([`speeds_from_segments`]), so a file cannot ask for more periods than a
//! problem's horizon may have.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::core::semantics::Mode;

/// Most periods a witness file may describe. Validation keeps each part of a problem's
/// horizon (reaching top speed, covering the initial gap, stopping) within 10⁶ periods, so a
/// real witness stays below a few million; this bounds what a forged segment can make a
/// reader allocate (80 MB of speeds, one `f64` a period in memory). The replay itself leaps
/// over quiescent stretches ([`crate::core::semantics::World::leap`]), so it is not what this
/// guards.
pub const MAX_WITNESS_PERIODS: usize = 10_000_000;

/// The obstacle's speed held over `length` control periods from period `start`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedSegment {
    /// First period (from 0).
    pub start: usize,
    /// Number of periods (at least 1).
    pub length: usize,
    /// Speed towards the robot (m/s).
    pub speed: f64,
}

pub use crate::core::simulate::ModeSegment;

/// Per-period speeds as maximal constant segments (equal neighbours bit for bit merge).
pub fn speed_segments(speeds: &[f64]) -> Vec<SpeedSegment> {
    let mut out: Vec<SpeedSegment> = Vec::new();
    for (k, &s) in speeds.iter().enumerate() {
        match out.last_mut() {
            Some(last) if last.speed.to_bits() == s.to_bits() => last.length += 1,
            _ => out.push(SpeedSegment {
                start: k,
                length: 1,
                speed: s,
            }),
        }
    }
    out
}

/// Per-period speeds from segments, which must start at 0, follow each other without gap or
/// overlap, each be at least one period long, and in all stay within
/// [`MAX_WITNESS_PERIODS`].
pub fn speeds_from_segments(segments: &[SpeedSegment]) -> Result<Vec<f64>, String> {
    let mut next = 0usize;
    for (i, s) in segments.iter().enumerate() {
        if s.start != next {
            return Err(format!(
                "obstacle_speeds[{i}] starts at period {}, not {next} (segments follow each \
                 other from period 0)",
                s.start
            ));
        }
        if s.length == 0 {
            return Err(format!("obstacle_speeds[{i}] is empty (length 0)"));
        }
        next = next
            .checked_add(s.length)
            .filter(|&n| n <= MAX_WITNESS_PERIODS)
            .ok_or_else(|| {
                format!(
                    "obstacle_speeds[{i}] reaches past {MAX_WITNESS_PERIODS} periods, more than \
                     any problem's witness"
                )
            })?;
    }
    let mut speeds = Vec::with_capacity(next);
    for s in segments {
        speeds.extend(std::iter::repeat_n(s.speed, s.length));
    }
    Ok(speeds)
}

/// The robot's modes per period (its mode at each period's start, as a replay's records or
/// rows give it) as maximal segments.
pub fn mode_segments(modes: impl IntoIterator<Item = Mode>) -> Vec<ModeSegment> {
    let mut out: Vec<ModeSegment> = Vec::new();
    for (k, mode) in modes.into_iter().enumerate() {
        match out.last_mut() {
            Some(last) if last.mode == mode => last.length += 1,
            _ => out.push(ModeSegment {
                start: k,
                length: 1,
                mode,
            }),
        }
    }
    out
}

/// Serde for a witness's per-period speeds stored as [`SpeedSegment`]s.
pub mod as_segments {
    use super::*;

    /// Writes the speeds as segments.
    pub fn serialize<S: Serializer>(speeds: &[f64], s: S) -> Result<S::Ok, S::Error> {
        speed_segments(speeds).serialize(s)
    }

    /// Reads segments back into per-period speeds (checked: [`speeds_from_segments`]).
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
        let segments = Vec::<SpeedSegment>::deserialize(d)?;
        speeds_from_segments(&segments).map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segments_round_trip_and_merge_equal_neighbours() {
        let speeds = [0.0, 0.0, 0.2, 0.2, 0.2, 0.1, 0.0];
        let segs = speed_segments(&speeds);
        assert_eq!(segs.len(), 4);
        assert_eq!(
            segs[1],
            SpeedSegment {
                start: 2,
                length: 3,
                speed: 0.2
            }
        );
        assert_eq!(speeds_from_segments(&segs).unwrap(), speeds);
        assert!(speed_segments(&[]).is_empty());
        assert_eq!(speeds_from_segments(&[]).unwrap(), Vec::<f64>::new());
    }

    #[test]
    fn gaps_overlaps_empty_and_endless_segments_are_refused() {
        let seg = |start, length| SpeedSegment {
            start,
            length,
            speed: 0.1,
        };
        assert!(
            speeds_from_segments(&[seg(1, 2)])
                .unwrap_err()
                .contains("not 0")
        );
        assert!(speeds_from_segments(&[seg(0, 2), seg(3, 1)]).is_err());
        assert!(speeds_from_segments(&[seg(0, 2), seg(1, 1)]).is_err());
        assert!(
            speeds_from_segments(&[seg(0, 0)])
                .unwrap_err()
                .contains("length 0")
        );
        let e = speeds_from_segments(&[seg(0, usize::MAX)]).unwrap_err();
        assert!(e.contains("more than any problem's witness"), "{e}");
        let e = speeds_from_segments(&[seg(0, MAX_WITNESS_PERIODS), seg(MAX_WITNESS_PERIODS, 1)])
            .unwrap_err();
        assert!(e.contains("obstacle_speeds[1]"), "{e}");
    }
}
