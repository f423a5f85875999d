//! A witness as runs rather than periods: the obstacle's speeds as constant-speed segments
//! and the robot's modes as mode segments, so a certificate's witness grows with how often
//! the behaviour changes, not with the horizon (a robot at 1 kHz keeps a worst case of a
//! few segments over half a million periods).
//!
//! In memory and in the certificate file a witness keeps its speeds as [`SpeedSegment`]s
//! ([`Speeds`]), read back with their order, contiguity and total length checked
//! ([`speeds_from_segments`]), so a file cannot ask for more periods than a problem's horizon
//! may have.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::core::semantics::Mode;

/// Most periods a witness file may describe. Validation keeps each part of a problem's
/// horizon (reaching top speed, covering the initial gap, stopping) within 10⁶ periods, so a
/// real witness stays below a few million. Speeds are kept as segments and the replay leaps
/// over quiescent stretches ([`crate::core::semantics::World::leap`]), but a forged witness
/// can still make the replay step period by period where no leap applies (a robot cruising
/// on past an obstacle seen passed), and a per-period list (`to_vec`, `speeds_from_segments`)
/// allocates 8 bytes a period: this bounds both.
pub const MAX_WITNESS_PERIODS: usize = 10_000_000;

pub use crate::core::simulate::{ModeSegment, SpeedSegment};

/// A witness's obstacle speeds, one per period, kept as maximal constant segments (equal
/// neighbours bit for bit merged), contiguous from period 0: memory and work grow with how
/// often the speed changes, not with the horizon. Equal as the per-period lists are.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Speeds {
    segments: Vec<SpeedSegment>,
}

impl Speeds {
    /// The speeds of a per-period list.
    pub fn from_periods(speeds: &[f64]) -> Self {
        Speeds {
            segments: speed_segments(speeds),
        }
    }

    /// Speeds from segments, checked as [`speeds_from_segments`] checks them (equal
    /// neighbours are merged).
    pub fn from_segments(segments: &[SpeedSegment]) -> Result<Self, String> {
        check_segments(segments)?;
        let mut out = Speeds::default();
        for s in segments {
            out.extend(s.speed, s.length);
        }
        Ok(out)
    }

    /// The segments.
    pub fn segments(&self) -> &[SpeedSegment] {
        &self.segments
    }

    /// Number of periods.
    pub fn len(&self) -> usize {
        self.segments.last().map_or(0, |s| s.start + s.length)
    }

    /// Whether there is no period.
    pub fn is_empty(&self) -> bool {
        self.segments.is_empty()
    }

    /// The speed in period `k`.
    pub fn get(&self, k: usize) -> Option<f64> {
        let i = self.segments.partition_point(|s| s.start + s.length <= k);
        self.segments.get(i).map(|s| s.speed)
    }

    /// One speed per period.
    pub fn to_vec(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.len());
        for s in &self.segments {
            out.extend(std::iter::repeat_n(s.speed, s.length));
        }
        out
    }

    /// Appends `length` periods at `speed`.
    pub fn extend(&mut self, speed: f64, length: usize) {
        if length == 0 {
            return;
        }
        let start = self.len();
        match self.segments.last_mut() {
            Some(last) if last.speed.to_bits() == speed.to_bits() => last.length += length,
            _ => self.segments.push(SpeedSegment {
                start,
                length,
                speed,
            }),
        }
    }

    /// Cuts the list to its first `n` periods, or extends it to `n` with `tail`.
    pub fn resize(&mut self, n: usize, tail: f64) {
        let len = self.len();
        if n >= len {
            self.extend(tail, n - len);
            return;
        }
        let keep = self.segments.partition_point(|s| s.start < n);
        self.segments.truncate(keep);
        if let Some(last) = self.segments.last_mut() {
            last.length = n - last.start;
        }
    }
}

impl Serialize for Speeds {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.segments.serialize(s)
    }
}

#[cfg(feature = "schema")]
impl schemars::JsonSchema for Speeds {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "Speeds".into()
    }

    fn json_schema(generator: &mut schemars::SchemaGenerator) -> schemars::Schema {
        // Written as its segments.
        <Vec<SpeedSegment>>::json_schema(generator)
    }
}

impl<'de> Deserialize<'de> for Speeds {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let segments = Vec::<SpeedSegment>::deserialize(d)?;
        Speeds::from_segments(&segments).map_err(serde::de::Error::custom)
    }
}

/// Per-period values as maximal runs `(start, length, value)` of neighbours `same` calls
/// equal: what every kind of witness segment is made from.
pub(crate) fn runs<T>(
    values: impl IntoIterator<Item = T>,
    same: impl Fn(&T, &T) -> bool,
) -> Vec<(usize, usize, T)> {
    let mut out: Vec<(usize, usize, T)> = Vec::new();
    for (k, v) in values.into_iter().enumerate() {
        match out.last_mut() {
            Some(last) if same(&last.2, &v) => last.1 += 1,
            _ => out.push((k, 1, v)),
        }
    }
    out
}

/// Per-period speeds as maximal constant segments (equal neighbours bit for bit merge).
pub fn speed_segments(speeds: &[f64]) -> Vec<SpeedSegment> {
    runs(speeds.iter().copied(), |a, b| a.to_bits() == b.to_bits())
        .into_iter()
        .map(|(start, length, speed)| SpeedSegment {
            start,
            length,
            speed,
        })
        .collect()
}

/// Per-period speeds from segments, which must start at 0, follow each other without gap or
/// overlap, each be at least one period long, and in all stay within
/// [`MAX_WITNESS_PERIODS`].
pub fn speeds_from_segments(segments: &[SpeedSegment]) -> Result<Vec<f64>, String> {
    let next = check_segments(segments)?;
    let mut speeds = Vec::with_capacity(next);
    for s in segments {
        speeds.extend(std::iter::repeat_n(s.speed, s.length));
    }
    Ok(speeds)
}

/// The checks of [`speeds_from_segments`]; the number of periods.
fn check_segments(segments: &[SpeedSegment]) -> Result<usize, String> {
    check_runs(segments.iter().map(|s| (s.start, s.length)))
}

/// The checks of [`speeds_from_segments`] on segments given as (start, length), float or
/// exact ([`crate::proof::exact_speed_runs`]); the number of periods.
pub(crate) fn check_runs(runs: impl Iterator<Item = (usize, usize)>) -> Result<usize, String> {
    let mut next = 0usize;
    for (i, (start, length)) in runs.enumerate() {
        if start != next {
            return Err(format!(
                "obstacle_speeds[{i}] starts at period {start}, not {next} (segments follow \
                 each other from period 0)"
            ));
        }
        if length == 0 {
            return Err(format!("obstacle_speeds[{i}] is empty (length 0)"));
        }
        next = next
            .checked_add(length)
            .filter(|&n| n <= MAX_WITNESS_PERIODS)
            .ok_or_else(|| {
                format!(
                    "obstacle_speeds[{i}] reaches past {MAX_WITNESS_PERIODS} periods, more than \
                     any problem's witness"
                )
            })?;
    }
    Ok(next)
}

/// The robot's modes per period (its mode at each period's start, as a replay's records or
/// rows give it) as maximal segments.
pub fn mode_segments(modes: impl IntoIterator<Item = Mode>) -> Vec<ModeSegment> {
    runs(modes, |a, b| a == b)
        .into_iter()
        .map(|(start, length, mode)| ModeSegment {
            start,
            length,
            mode,
        })
        .collect()
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

    /// Speeds kept as segments behave as the per-period list: length, lookup, resizing,
    /// equality whatever the segments a file split them into.
    #[test]
    fn speeds_as_segments_are_the_per_period_list() {
        let list = [0.0, 0.0, 0.2, 0.2, 0.2, 0.1, 0.0];
        let s = Speeds::from_periods(&list);
        assert_eq!(s.len(), 7);
        assert_eq!(s.to_vec(), list);
        assert!((0..7).all(|k| s.get(k) == Some(list[k])) && s.get(7).is_none());
        for n in 0..10 {
            let mut r = s.clone();
            r.resize(n, 0.3);
            let mut v = list.to_vec();
            v.resize(n, 0.3);
            assert_eq!(r, Speeds::from_periods(&v), "{n}");
            assert_eq!(r.len(), n);
        }
        let split = [
            SpeedSegment {
                start: 0,
                length: 2,
                speed: 0.1,
            },
            SpeedSegment {
                start: 2,
                length: 3,
                speed: 0.1,
            },
        ];
        assert_eq!(
            Speeds::from_segments(&split).unwrap(),
            Speeds::from_periods(&[0.1; 5])
        );
        assert!(Speeds::from_segments(&split[1..]).is_err());
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
