//! Wall-clock medians shared by the bench binaries (speed is measured in benches, never in
//! tests).

use std::time::{Duration, Instant};

/// Median time per call of `f` over `rounds` calls.
pub fn median(rounds: usize, mut f: impl FnMut()) -> Duration {
    let mut times: Vec<Duration> = (0..rounds)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed()
        })
        .collect();
    times.sort();
    times[rounds / 2]
}
