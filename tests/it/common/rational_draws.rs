//! Draws of small integers and rationals from [`SplitMix`], for the exact-arithmetic tests
//! (the plane's geometry, polynomials) that pick their cases at random.

use dashu_ratio::RBig;
use safereach::core::num::Exact;

use super::split_mix::SplitMix;

impl SplitMix {
    /// An integer in [lo, hi].
    pub fn int(&mut self, lo: i64, hi: i64) -> i64 {
        lo + (self.next() % (hi - lo + 1) as u64) as i64
    }
    /// A rational with denominator 1..=8 and value in about [−lim, lim].
    pub fn rational(&mut self, lim: i64) -> Exact {
        let den = self.int(1, 8);
        RBig::from(self.int(-lim * den, lim * den)) / RBig::from(den)
    }
}
