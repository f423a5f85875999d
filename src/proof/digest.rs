//! The digest every certificate and region map carries: SHA-256 (hex) of its compact JSON
//! with the digest field empty, so an edit after the fact is named as such by `check`.

use serde::Serialize;
use sha2::{Digest, Sha256};

/// SHA-256 (hex) of `value` serialised as compact JSON.
pub fn json_sha256(value: &impl Serialize) -> String {
    let text = serde_json::to_string(value).expect("certificates serialise");
    let hash = Sha256::digest(text.as_bytes());
    hash.iter().map(|b| format!("{b:02x}")).collect()
}
