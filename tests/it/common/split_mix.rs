//! A small deterministic generator (SplitMix64) for tests that draw cases: the same cases on
//! every machine, no dependency. Shared by the `it` binary and `tests/brute_force_scenes.rs`
//! (through `#[path]`); each adds the draws it needs in its own `impl SplitMix` block.

/// SplitMix64's state.
pub struct SplitMix(pub u64);

impl SplitMix {
    /// The next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}
