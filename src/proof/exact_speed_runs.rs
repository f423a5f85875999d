//! A run-search witness's speeds as exact constant-speed segments.
//!
//! The run search's worst cases sit on guard thresholds such as V_a, which a float would
//! cross, so its witness writes speeds as exact numbers ("p/q"). Like a problem witness's
//! [`Speeds`](crate::proof::witness_runs::Speeds) they are kept as maximal segments
//! `{start, length, speed}`, so the file grows with how often a speed changes, not with the
//! horizon; read back, the segments are checked as float segments are (contiguous from
//! period 0, non-empty, within
//! [`MAX_WITNESS_PERIODS`](crate::proof::witness_runs::MAX_WITNESS_PERIODS) in all).

use serde::{Deserialize, Serialize};

use crate::core::num::Exact;
use crate::proof::witness_runs::{check_runs, runs};

/// An obstacle's exact speed over `length` control periods from period `start`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct ExactSpeedSegment {
    /// First period (from 0).
    pub start: usize,
    /// Number of periods (at least 1).
    pub length: usize,
    /// Speed towards the robot (m/s), exact ("p/q" or an integer).
    pub speed: String,
}

/// Per-period exact speeds as maximal segments (equal neighbours merge).
pub fn exact_speed_segments(speeds: &[Exact]) -> Vec<ExactSpeedSegment> {
    runs(speeds, |a, b| a == b)
        .into_iter()
        .map(|(start, length, speed)| ExactSpeedSegment {
            start,
            length,
            speed: speed.to_string(),
        })
        .collect()
}

/// Per-period exact speeds from segments, each speed read by `read` (which refuses what is
/// not a number the caller accepts). The segments must start at 0, follow each other
/// without gap or overlap, each be at least one period long and in all stay within
/// [`MAX_WITNESS_PERIODS`](crate::proof::witness_runs::MAX_WITNESS_PERIODS).
pub fn exact_speeds_from_segments(
    segments: &[ExactSpeedSegment],
    read: impl Fn(&str) -> Option<Exact>,
) -> Result<Vec<Exact>, String> {
    let periods = check_runs(segments.iter().map(|s| (s.start, s.length)))?;
    let mut speeds = Vec::with_capacity(periods);
    for (i, s) in segments.iter().enumerate() {
        let speed = read(&s.speed).ok_or_else(|| {
            format!(
                "segment {i} (from period {}): {:?} is not an exact speed in [0, W]",
                s.start, s.speed
            )
        })?;
        speeds.extend(std::iter::repeat_n(speed, s.length));
    }
    Ok(speeds)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::proof::search_certificate::exact_from_text;
    use crate::proof::witness_runs::MAX_WITNESS_PERIODS;

    #[test]
    fn exact_segments_round_trip_and_refuse_gaps_and_bad_numbers() {
        let e = |t: &str| exact_from_text(t).unwrap();
        let speeds = [e("0"), e("0"), e("1/5"), e("1/5"), e("3/20"), e("0")];
        let segs = exact_speed_segments(&speeds);
        assert_eq!(segs.len(), 4);
        assert_eq!(
            (segs[1].start, segs[1].length, segs[1].speed.as_str()),
            (2, 2, "1/5")
        );
        let back = exact_speeds_from_segments(&segs, exact_from_text).unwrap();
        assert_eq!(back, speeds);
        assert!(exact_speed_segments(&[]).is_empty());

        let mut gap = segs.clone();
        gap[2].start += 1;
        assert!(exact_speeds_from_segments(&gap, exact_from_text).is_err());
        let mut empty = segs.clone();
        empty[3].length = 0;
        assert!(exact_speeds_from_segments(&empty, exact_from_text).is_err());
        let mut word = segs.clone();
        word[1].speed = "fast".into();
        let err = exact_speeds_from_segments(&word, exact_from_text).unwrap_err();
        assert!(err.contains("from period 2"), "{err}");
        let huge = [ExactSpeedSegment {
            start: 0,
            length: MAX_WITNESS_PERIODS + 1,
            speed: "0".into(),
        }];
        assert!(exact_speeds_from_segments(&huge, exact_from_text).is_err());
    }
}
