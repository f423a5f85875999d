//! Textual obstacle ids mapped to the monitor's dense integer ids (0, 1, 2, … in order of
//! first appearance), so a trace may name obstacles as it likes while the monitor keeps one
//! small record per obstacle in a table.

use rustc_hash::FxHashMap;

use crate::monitor::ObstacleId;

/// Textual obstacle ids mapped to the monitor's dense integer ids (0, 1, 2, … in order of
/// first appearance). Allocates once per new obstacle, never per sample.
///
/// Ids of up to 15 bytes — the usual case — are looked up as one 128-bit integer (the bytes
/// and the length), so a lookup is a hash of two words and an integer comparison.
#[derive(Clone, Debug)]
pub struct Ids {
    short: FxHashMap<u128, ObstacleId>,
    long: FxHashMap<Box<[u8]>, ObstacleId>,
    names: Vec<String>,
    pub(crate) limit: u32,
    /// Short ids looked up lately, by [`slot`]: a trace of a few obstacles, interleaved or
    /// not, needs no hashing at all. An entry is a packed id (or [`NO_KEY`]) and its number.
    recent: [(u128, ObstacleId); RECENT],
}

/// Entries of [`Ids`]'s cache of recent short ids.
const RECENT: usize = 16;

/// A key no short id packs to (its length byte is above 15).
const NO_KEY: u128 = u128::MAX;

/// The cache entry of a packed short id: a multiplicative hash of its two halves, so that
/// ids differing in any byte (`0`, `1`, … or `car_1`, `car_2`, …) tend to take different
/// entries.
#[inline]
fn slot(key: u128) -> usize {
    let folded = (key as u64) ^ ((key >> 64) as u64);
    let folded = folded ^ (folded >> 32);
    (folded.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 60) as usize % RECENT
}

/// A short id as one integer: its bytes, then its length in the top byte. (Built in
/// registers: writing bytes to memory and reading them back as one word stalls the CPU.)
#[inline]
fn pack(text: &[u8]) -> Option<u128> {
    if text.len() > 15 {
        return None;
    }
    let mut key = (text.len() as u128) << 120;
    for (k, &b) in text.iter().enumerate() {
        key |= u128::from(b) << (8 * k);
    }
    Some(key)
}

impl Ids {
    /// An empty table for at most `limit` obstacles.
    pub fn new(limit: u32) -> Ids {
        Ids {
            short: FxHashMap::default(),
            long: FxHashMap::default(),
            names: Vec::new(),
            limit,
            recent: [(NO_KEY, 0); RECENT],
        }
    }

    /// The integer id of `text`, assigning the next one to a new obstacle; `None` when the
    /// table is full.
    #[inline]
    pub fn get_or_insert(&mut self, text: &[u8]) -> Option<ObstacleId> {
        let key = pack(text);
        if let Some(key) = key {
            let (cached, id) = self.recent[slot(key)];
            if cached == key {
                return Some(id);
            }
        }
        let found = match key {
            Some(key) => self.short.get(&key).copied(),
            None => self.long.get(text).copied(),
        };
        let id = match found {
            Some(id) => id,
            None => {
                if self.names.len() >= self.limit as usize {
                    return None;
                }
                let id = self.names.len() as ObstacleId;
                match key {
                    Some(key) => {
                        self.short.insert(key, id);
                    }
                    None => {
                        self.long.insert(text.into(), id);
                    }
                }
                self.names.push(String::from_utf8_lossy(text).into_owned());
                id
            }
        };
        if let Some(key) = key {
            self.recent[slot(key)] = (key, id);
        }
        Some(id)
    }

    /// The text of integer id `id` (empty if unknown).
    pub fn name(&self, id: ObstacleId) -> &str {
        self.names.get(id as usize).map_or("", String::as_str)
    }

    /// Number of distinct obstacles.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// Whether no obstacle has been seen.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }
}
