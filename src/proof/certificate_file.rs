//! A certificate file of any kind, told apart by its `format` tag: a single-obstacle
//! [`Certificate`], a [`SceneCertificate`], a [`SearchCertificate`] or a
//! [`PlanarCertificate`].

use serde::Deserialize;

use crate::proof::json_read::from_json;

#[cfg(doc)]
use crate::proof::certificate::FORMAT;
use crate::proof::certificate::{CheckReport, Invalid, check};
use crate::proof::planar::certificate::{PLANAR_FORMAT, PlanarCertificate};
use crate::proof::planar::check::check_planar;
use crate::proof::scene_certificate::{SCENE_FORMAT, SceneCertificate};
use crate::proof::scene_check::check_scene;
use crate::proof::search_certificate::{SEARCH_FORMAT, SearchCertificate};
use crate::proof::search_check::check_search;
use crate::proof::verdict::Verdict;

pub use crate::proof::certificate::Certificate;

/// A certificate of either kind.
#[derive(Clone, Debug, PartialEq)]
pub enum CertificateFile {
    /// One obstacle in the robot's lane (`safereach-certificate/3`).
    Single(Box<Certificate>),
    /// A scene (`safereach-scene-certificate/5`).
    Scene(Box<SceneCertificate>),
    /// A scene decided by the run search (`safereach-scene-search-certificate/4`).
    Search(Box<SearchCertificate>),
    /// A planar problem (`safereach-planar-certificate/1`).
    Planar(Box<PlanarCertificate>),
}

/// Format tags of earlier versions: their files lack fields today's check needs.
const EARLIER_FORMATS: &[&str] = &[
    "safereach-certificate/1",
    "safereach-certificate/2",
    "safereach-scene-certificate/1",
    "safereach-scene-certificate/2",
    "safereach-scene-certificate/3",
    "safereach-scene-certificate/4",
    "safereach-scene-search-certificate/1",
    "safereach-scene-search-certificate/2",
    "safereach-scene-search-certificate/3",
];

/// Only the format tag, to choose the reader.
#[derive(Deserialize)]
struct Tag {
    format: String,
}

/// Whether `text` is a region map (`safereach region --out`, tag
/// [`region_map::FORMAT`](crate::proof::region_map::FORMAT)), which [`CertificateFile`] does
/// not read: `check` and `monitor` read it as a
/// [`RegionMap`](crate::proof::region_map::RegionMap).
pub fn is_region_map(text: &str) -> bool {
    from_json::<Tag>(text).is_ok_and(|t| t.format == crate::proof::region_map::FORMAT)
}

impl CertificateFile {
    /// Parses certificate JSON of either kind (strictly: unknown fields are refused, and a
    /// certificate of an earlier format is named as such).
    pub fn from_json(text: &str) -> Result<Self, serde_json::Error> {
        // A certificate is a JSON object. Anything else would be named by the reader's own
        // type ("expected struct Tag"), and an array would be read field by field.
        if let Some(c) = text.trim_start().chars().next()
            && c != '{'
        {
            let shown = if c.is_alphanumeric() || c.is_ascii_punctuation() {
                format!("`{c}`")
            } else {
                format!("U+{:04X}", u32::from(c))
            };
            return Err(<serde_json::Error as serde::de::Error>::custom(format!(
                "a certificate is a JSON object ({{ ... }}); this text starts with {shown}"
            )));
        }
        let tag: Tag = from_json(text)?;
        if EARLIER_FORMATS.contains(&tag.format.as_str()) {
            return Err(<serde_json::Error as serde::de::Error>::custom(format!(
                "its format {:?} was written by an earlier safereach (before certificates \
                 pinned s*, or stored witnesses period by period); certify the problem again",
                tag.format
            )));
        }
        if tag.format == PLANAR_FORMAT {
            return Ok(CertificateFile::Planar(Box::new(from_json(text)?)));
        }
        if tag.format == SEARCH_FORMAT {
            return Ok(CertificateFile::Search(Box::new(from_json(text)?)));
        }
        if tag.format == SCENE_FORMAT {
            Ok(CertificateFile::Scene(Box::new(from_json(text)?)))
        } else {
            // Any other tag is read as a single-obstacle certificate, whose check names a
            // wrong format (it accepts only [`FORMAT`]).
            Ok(CertificateFile::Single(Box::new(from_json(text)?)))
        }
    }

    /// Re-verifies it without the solver.
    pub fn check(&self) -> Result<CheckReport, Invalid> {
        match self {
            CertificateFile::Single(c) => check(c),
            CertificateFile::Scene(c) => check_scene(c),
            CertificateFile::Search(c) => check_search(c),
            CertificateFile::Planar(c) => check_planar(c),
        }
    }

    /// The stated verdict.
    pub fn verdict(&self) -> Verdict {
        match self {
            CertificateFile::Single(c) => c.verdict,
            CertificateFile::Scene(c) => c.verdict,
            CertificateFile::Search(c) => c.verdict,
            CertificateFile::Planar(c) => c.verdict,
        }
    }

    /// The certificate as pretty JSON with a final newline.
    pub fn to_json(&self) -> String {
        let text = match self {
            CertificateFile::Single(c) => serde_json::to_string_pretty(c),
            CertificateFile::Scene(c) => serde_json::to_string_pretty(c),
            CertificateFile::Search(c) => serde_json::to_string_pretty(c),
            CertificateFile::Planar(c) => serde_json::to_string_pretty(c),
        };
        text.expect("certificates serialise") + "\n"
    }
}
