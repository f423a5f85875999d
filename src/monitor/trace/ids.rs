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
    pub(super) limit: u32,
    /// The last short id looked up: a trace of one obstacle needs no hashing at all.
    last: Option<(u128, ObstacleId)>,
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
            last: None,
        }
    }

    /// The integer id of `text`, assigning the next one to a new obstacle; `None` when the
    /// table is full.
    #[inline]
    pub fn get_or_insert(&mut self, text: &[u8]) -> Option<ObstacleId> {
        let key = pack(text);
        if let (Some(key), Some((last, id))) = (key, self.last)
            && key == last
        {
            return Some(id);
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
            self.last = Some((key, id));
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
