//! Planar certificates (docs/semantics.md §13.5, docs/reductions.md §11): a planar
//! problem's answer in a form `check` re-verifies without the solver.
//!
//! A certificate holds the problem file's text (and its `--set` overrides), the verdict,
//! the witness as exact rationals, and per bound run — a goal and, per obstacle, one
//! [`LeafProof`] per leaf of the refinement. [`check_planar`](super::check::check_planar)
//! trusts none of the numbers: it reads the problem again, rebuilds every obstacle's pieces
//! from it and the run's goal, requires the leaves to tile every piece exactly
//! ([`super::tiling`]), rebuilds each leaf's second-order cone program and recomputes its
//! bound from the stored multipliers in exact rationals, replays the witness exactly, and
//! derives the verdict from what it recomputed.

use serde::{Deserialize, Serialize};

use crate::proof::verdict::Verdict;

/// The format tag written into every planar certificate.
pub const PLANAR_FORMAT: &str = "safereach-planar-certificate/1";

/// One leaf's proof.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct LeafProof {
    /// The piece's index in the obstacle's pieces (time order).
    pub piece: usize,
    /// The index of the piece's initial cover set the leaf refines.
    pub cover: usize,
    /// The halvings from that set to the leaf (`"t1a0"`; `""`: the set itself).
    pub splits: String,
    /// The leaf holds no behaviour: `multipliers` are a Farkas proof (with strict rows
    /// strict), or, when there are none, one row no point of the variables' box meets.
    pub empty: bool,
    /// The dual multipliers, one per row of the leaf's program (none: the solver gave no
    /// usable answer, and the bound is the floor −(r_R + r_i + D)).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub multipliers: Vec<f64>,
    /// The proved bound rounded down (null for an empty leaf): the greater of what the
    /// multipliers prove and the floor.
    pub bound: Option<f64>,
}

/// One obstacle's leaves in one bound run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct ObstacleLeaves {
    /// Its name (checked against the problem).
    pub name: String,
    /// The least bound over its leaves, rounded down (null: every leaf is empty).
    pub lower_bound: Option<f64>,
    /// Its leaves, by piece, cover set and splits.
    pub leaves: Vec<LeafProof>,
}

/// One bound run: every instant up to the horizon its goal sets is in some leaf, and every
/// instant past it is above the goal (Lemma P6).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct BoundRun {
    /// The goal, exact (`"n/d"`).
    pub goal: String,
    /// At most this many steps were searched for the horizon.
    pub step_limit: usize,
    /// What the run proves: min(least leaf bound, goal), rounded down.
    pub claim: f64,
    /// One entry per obstacle, in the problem's order.
    pub obstacles: Vec<ObstacleLeaves>,
}

/// One obstacle's part of the witness, exact.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct ObstacleMotion {
    /// Its name.
    pub name: String,
    /// Its centre at t = 0 (m, exact `"n/d"`).
    pub start: [String; 2],
    /// Its velocity in each step from step 0 (m/s, exact); it stands still past the list.
    pub velocities: Vec<[String; 2]>,
    /// The error of each step's seen centre (m, exact); 0 past the list.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub position_errors: Vec<[String; 2]>,
    /// The error of each step's seen velocity (m/s, exact); 0 past the list.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub velocity_errors: Vec<[String; 2]>,
    /// It stays unseen as long as occlusion allows.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub hide: bool,
}

/// The least replayed behaviour, exact.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct PlanarWitness {
    /// The obstacle that comes closest.
    pub obstacle: String,
    /// When it is closest (s, rounded).
    pub closest_at: f64,
    /// Its least separation from above, exact (`"n/d"`): s* is at most this.
    pub separation: String,
    /// The replay reaches the clearance.
    pub collides: bool,
    /// The step the robot brakes at (null: it never brakes in the replay).
    pub brake_step: Option<usize>,
    /// The guard that fired then (`danger (name)`, `wrong assumption (name)`,
    /// `destination`).
    pub guard: Option<String>,
    /// When the robot rests (s, rounded; null: it does not in the replay).
    pub rest: Option<f64>,
    /// Control periods replayed.
    pub steps: usize,
    /// Every obstacle's motion, in the problem's order.
    pub obstacles: Vec<ObstacleMotion>,
}

/// The planar certificate file (and `certify --json` output for planar problems).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct PlanarCertificate {
    /// Always [`PLANAR_FORMAT`].
    pub format: String,
    /// The problem's name.
    pub problem: String,
    /// The verdict.
    pub verdict: Verdict,
    /// The clearance (m).
    pub clearance: f64,
    /// s* ≥ this (m, proved; rounded down): the greatest claim of the runs.
    pub lower_bound: f64,
    /// The same, exact (`"n/d"`).
    pub lower_bound_exact: String,
    /// s* ≤ this: the witness's separation (m, rounded up; null: no witness).
    pub upper_bound: Option<f64>,
    /// s* to within `separation_tolerance` (m), when the bracket is that narrow (else null).
    pub min_separation: Option<f64>,
    /// How wide the bracket may be for `min_separation` to be stated (m).
    pub separation_tolerance: f64,
    /// Second-order cone programs handed to the solver.
    pub programs: usize,
    /// Some run spent its budget (the bound is sound but may be loose).
    pub budget_exhausted: bool,
    /// Leaves the solver could not bound (their bound is the floor).
    pub unsolved_leaves: usize,
    /// The least replayed behaviour.
    pub witness: Option<PlanarWitness>,
    /// The problem file's text, as read.
    pub problem_toml: String,
    /// The `--set` overrides applied to it, in order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub overrides: Vec<String>,
    /// The bound runs (the clearance's; then, when a witness was found above it, one
    /// towards the witness).
    pub runs: Vec<BoundRun>,
    /// SHA-256 (hex) of this certificate serialised with an empty digest.
    pub digest: String,
}

impl PlanarCertificate {
    /// SHA-256 of the certificate with an empty digest field.
    pub fn compute_digest(&self) -> String {
        let mut copy = self.clone();
        copy.digest.clear();
        crate::proof::digest::json_sha256(&copy)
    }

    /// Leaves over every run and obstacle.
    pub fn leaves(&self) -> usize {
        self.runs
            .iter()
            .flat_map(|r| &r.obstacles)
            .map(|o| o.leaves.len())
            .sum()
    }
}
