//! Region maps: one problem, a box of parameter values split into leaves, and for each leaf
//! a verdict with its evidence — the format `safereach region` writes and `check` verifies.
//!
//! A **certified** leaf carries one proof per piece of its box decomposition
//! ([`Decomposition::for_box`](crate::proof::schedule::Decomposition::for_box)): dual
//! multipliers whose exact bound is affine in the ranged parameters and, least at a vertex,
//! exceeds the clearance at every point of the leaf. A **refuted** leaf names a point in it
//! and a colliding behaviour there, replayed exactly (a claim about that point; the search
//! marks a leaf refuted only when none of its corners certifies, as a guard against leaves that
//! straddle the boundary, but only the named point is a checked claim). An **undecided**
//! leaf says why. Leaves are the ends of binary splits (each leaf's `path`), so together
//! they cover the box exactly once.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::core::model::Problem;
use crate::core::param_box::{Axis, ParamBox};
use crate::core::scene::Scene;
use crate::proof::planar::certificate::PlanarCertificate;
use crate::proof::planar::region::PlanarSource;
use crate::proof::program::ProofKind;
use crate::proof::schedule::Piece;

/// The format tag written into every region map.
pub const FORMAT: &str = "safereach-region-map/1";

/// A leaf's verdict.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum LeafVerdict {
    /// s* exceeds the clearance at every point of the leaf (proved).
    Certified,
    /// A named point of the leaf has a colliding behaviour (replayed exactly).
    Refuted,
    /// Neither, at the depth the search was allowed.
    Undecided,
}

impl LeafVerdict {
    /// The verdict's name.
    pub fn as_str(self) -> &'static str {
        match self {
            LeafVerdict::Certified => "certified",
            LeafVerdict::Refuted => "refuted",
            LeafVerdict::Undecided => "undecided",
        }
    }
}

/// One piece's proof over a leaf.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct BoxProof {
    /// In a scene map, the obstacle (scene index) the piece is of.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub obstacle: Option<usize>,
    /// The piece.
    pub piece: Piece,
    /// A lower bound on the piece's separation, or its emptiness.
    pub kind: ProofKind,
    /// One multiplier per row of the piece's box program.
    pub multipliers: Vec<f64>,
    /// For a bound: its least value over the leaf (m), rounded down.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bound: Option<f64>,
}

/// A colliding behaviour at one point of a leaf.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct Refutation {
    /// The point: each ranged key's value.
    pub point: BTreeMap<String, f64>,
    /// The piece the behaviour comes from (it fixes what the environment aims at).
    pub piece: Piece,
    /// For a merged piece, the whole steps it is shifted by.
    pub shift: usize,
    /// The obstacle's speed in each control period, up to the collision.
    pub obstacle_speeds: Vec<f64>,
}

/// A colliding behaviour at one point of a scene map's leaf.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct SceneRefutation {
    /// The point: each ranged key's value.
    pub point: BTreeMap<String, f64>,
    /// Scene index of the obstacle the robot collides with.
    pub obstacle: usize,
    /// Speeds per obstacle (scene order) per period, up to the collision.
    pub obstacle_speeds: Vec<Vec<f64>>,
}

/// One leaf of the map.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct Leaf {
    /// The splits that lead to it from the whole box: one letter per split, `a` + the axis
    /// index, lower case for the lower half and upper case for the upper half ("" for the
    /// whole box; "aB": axis 0's lower half, then axis 1's upper half).
    pub path: String,
    /// Each ranged key mapped to `[lo, hi]`.
    #[serde(rename = "box")]
    pub bounds: BTreeMap<String, [f64; 2]>,
    /// The verdict.
    pub verdict: LeafVerdict,
    /// Certified: the least lower bound on s* over the leaf (m), rounded down.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lower_bound: Option<f64>,
    /// Certified: one proof per piece of the leaf's decomposition, in its order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub proofs: Vec<BoxProof>,
    /// Refuted: the colliding point.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refutation: Option<Refutation>,
    /// Refuted, in a scene map: the colliding point.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene_refutation: Option<SceneRefutation>,
    /// In a planar map: a certified leaf's certificate at its weak corner, or a refuted
    /// leaf's at its colliding point (docs/reductions.md Lemma P7).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub planar_certificate: Option<Box<PlanarCertificate>>,
    /// Undecided (or a remark): why.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

/// How much of the box each verdict covers, as fractions of its volume (over the axes that
/// have width).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct Coverage {
    /// Certified fraction.
    pub certified: f64,
    /// Refuted fraction.
    pub refuted: f64,
    /// Undecided fraction.
    pub undecided: f64,
}

/// The map file (`safereach region --out`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct RegionMap {
    /// Always [`FORMAT`].
    pub format: String,
    /// The problem mapped (a problem map); its values of the ranged keys are replaced by
    /// the box.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub problem: Option<Problem>,
    /// The scene mapped (a scene map, instead of `problem`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene: Option<Scene>,
    /// The planar problem mapped (a planar map, instead of `problem` and `scene`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub planar: Option<PlanarSource>,
    /// The whole box, axes in the order given.
    pub ranges: Vec<Axis>,
    /// Most splits on the way to a leaf the search allowed.
    pub depth: u32,
    /// The leaves, in path order.
    pub leaves: Vec<Leaf>,
    /// Fractions of the box by verdict.
    pub coverage: Coverage,
    /// Linear programs handed to the solver.
    pub programs_solved: usize,
    /// SHA-256 (hex) of this map serialised with an empty digest.
    pub digest: String,
}

impl RegionMap {
    /// SHA-256 of the map with an empty digest field.
    pub fn compute_digest(&self) -> String {
        let mut copy = self.clone();
        copy.digest.clear();
        crate::proof::digest::json_sha256(&copy)
    }

    /// The whole box.
    pub fn whole(&self) -> ParamBox {
        ParamBox {
            axes: self.ranges.clone(),
        }
    }

    /// The mapped problem's or scene's name.
    pub fn name(&self) -> &str {
        match (&self.problem, &self.scene, &self.planar) {
            (Some(p), _, _) => &p.name,
            (None, Some(s), _) => &s.name,
            (None, None, Some(q)) => &q.name,
            (None, None, None) => "",
        }
    }

    /// The clearance (m) of the mapped problem or scene, at the map's base values.
    pub fn clearance(&self) -> f64 {
        match (&self.problem, &self.scene, &self.planar) {
            (Some(p), _, _) => p.robot.clearance,
            (None, Some(s), _) => s.robot.clearance,
            (None, None, Some(q)) => q.clearance,
            (None, None, None) => 0.0,
        }
    }

    /// The map's verdict for the whole box: certified iff every leaf is.
    pub fn all_certified(&self) -> bool {
        self.leaves
            .iter()
            .all(|l| l.verdict == LeafVerdict::Certified)
    }
}

/// The box a path leads to from `whole` (None: a letter names no axis, or an axis cannot
/// be halved there).
pub fn box_at(whole: &ParamBox, path: &str) -> Option<ParamBox> {
    let mut b = whole.clone();
    for c in path.chars() {
        let (axis, upper) = path_step(c)?;
        if axis >= b.axes.len() {
            return None;
        }
        let (low, high) = b.split(axis)?;
        b = if upper { high } else { low };
    }
    Some(b)
}

/// The axis and half a path letter names.
pub fn path_step(c: char) -> Option<(usize, bool)> {
    if c.is_ascii_lowercase() {
        Some((c as usize - 'a' as usize, false))
    } else if c.is_ascii_uppercase() {
        Some((c as usize - 'A' as usize, true))
    } else {
        None
    }
}

/// The path letter for a split of `axis` (< 26), taking the upper half or not.
pub fn path_letter(axis: usize, upper: bool) -> char {
    let base = if upper { b'A' } else { b'a' };
    char::from(base + u8::try_from(axis).expect("fewer than 26 axes"))
}

/// A box's ends keyed by parameter key (a leaf's `box`).
pub fn bounds_of(b: &ParamBox) -> BTreeMap<String, [f64; 2]> {
    b.axes.iter().map(|a| (a.key(), [a.lo, a.hi])).collect()
}

/// The fraction of `whole`'s volume that `part` takes, over the axes of `whole` with width.
pub fn volume_fraction(whole: &ParamBox, part: &ParamBox) -> f64 {
    whole
        .axes
        .iter()
        .zip(&part.axes)
        .filter(|(w, _)| w.hi > w.lo)
        .map(|(w, p)| (p.hi - p.lo) / (w.hi - w.lo))
        .product()
}
