//! Certified maps of the design space: a box that does not certify is halved, down to a
//! depth, and every leaf ends certified, refuted or undecided ([`RegionMap`]).
//!
//! **Splitting**: the axis widest relative to its range in the whole box is halved. The
//! halves first try the proofs their parent found for the same pieces; a proof that
//! failed over the parent often holds over a half, with no solver call.
//!
//! **Corners first**: every box is analysed at its corners (neighbouring boxes share them,
//! so each is analysed once). A box is tried for a certificate only when every corner
//! certifies, and analysed at its centre only when none does; a box the boundary crosses
//! (corners on both sides) is split at once, carrying its parent's proofs down.
//!
//! **Refuted leaves**: a refuted centre (a colliding behaviour, replayed exactly) makes a
//! box no corner of which certifies a refuted leaf naming that behaviour. The corners are a
//! guard against a leaf straddling the boundary, not a claim: only the centre is checked.

use std::sync::{Arc, Mutex, OnceLock};

use rustc_hash::FxHashMap;

use rayon::prelude::*;

use crate::analysis::planar::PlanarRegion;
use crate::analysis::region::Hints;
use crate::analysis::region_subject::{LeafRefutation, RegionSubject};
use crate::core::budget::{Work, grouped};
use crate::core::model::Problem;
use crate::core::num::f64_at_most;
use crate::core::param_box::ParamBox;
use crate::core::planar::PlanarProblem;
use crate::core::scene::Scene;
use crate::proof::region_map::{
    Coverage, FORMAT, Leaf, LeafVerdict, RegionMap, bounds_of, path_letter, volume_fraction,
};
use crate::proof::verdict::Verdict;

/// How far the search may split.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RegionOptions {
    /// Most splits on the way from the whole box to a leaf.
    pub depth: u32,
    /// An axis narrower than this fraction of its whole range is not split again (0: no
    /// limit but the depth).
    pub min_width: f64,
    /// Budget: the most boxes decided (each its corner analyses, then perhaps a certificate
    /// attempt or a centre analysis); boxes beyond it are left undecided, saying so.
    pub max_boxes: u64,
}

/// The default depth: 14 cuts, 7 per axis of a plane. Boxes the boundary crosses stay
/// undecided at any depth (their corners disagree), so the undecided share of a plane is
/// about its boundary's length times a leaf's width: the seed plane W ∈ [0.1, 0.3] × ρ ∈
/// [1.0, 1.6] keeps 3.25% undecided at 12 cuts and 1.65% at 14, and no placement of 12
/// axis-parallel cuts goes below about 2.2% along its nearly straight boundary. Since boxes
/// the boundary crosses are split without a certificate attempt or a centre analysis, the map
/// at 14 solves about as many programs (1,853) as the map at 12 did before (1,682).
pub const DEFAULT_DEPTH: u32 = 14;

/// The default depth of a planar map: 8 cuts, 4 per axis of a plane. A planar box costs two
/// bound-only planar certifications (about 0.2 s each on the seed in the plane) and a
/// decided leaf stores a whole planar certificate, so planar maps stop coarser: the seed
/// plane W ∈ [0.15, 0.3] × ρ ∈ [1.0, 1.6] takes about 15 s on 2 cores and 11 MB at 8.
pub const PLANAR_DEFAULT_DEPTH: u32 = 8;

impl Default for RegionOptions {
    fn default() -> Self {
        RegionOptions {
            depth: DEFAULT_DEPTH,
            min_width: 0.0,
            max_boxes: Work::Boxes.default_limit(),
        }
    }
}

/// Why a box cannot be mapped.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RegionError {
    /// The problem or the box is one region certificates do not cover.
    #[error("{0}")]
    Refused(String),
}

/// A box waiting to be decided.
struct Task {
    b: ParamBox,
    path: String,
    hints: Hints,
}

/// What the analysis says at points (keyed by their ranged values' bits): neighbouring
/// boxes share corners. Each point is analysed exactly once — a box that needs a corner
/// another thread is analysing waits for its verdict — so the map's count of programs
/// solved does not depend on how the threads met. (A point's analysis runs no rayon jobs,
/// so a waiting worker never picks up a box that needs the corner it waits for.)
#[derive(Default)]
struct Corners(Mutex<FxHashMap<Vec<u64>, Arc<OnceLock<Verdict>>>>);

/// What deciding one box gave: a leaf, or two halves to decide.
enum Decided {
    Leaf(Leaf, usize),
    Split(Task, Task, usize),
}

/// Maps `problem` over `whole` (a valid, point-start problem). `on_decided` is told the
/// fraction of the box each leaf covers as leaves are found (for progress bars).
pub fn map_region(
    problem: &Problem,
    whole: &ParamBox,
    options: &RegionOptions,
    on_decided: &(dyn Fn(f64) + Sync),
) -> Result<RegionMap, RegionError> {
    map_subject(problem, whole, options, on_decided)
}

/// Maps a (valid) `scene` over `whole`, whose axes may be shared parameters or one
/// obstacle's own (`obstacle.<i>.max_speed`, `obstacle.<i>.position`); see
/// [`map_region`].
pub fn map_scene_region(
    scene: &Scene,
    whole: &ParamBox,
    options: &RegionOptions,
    on_decided: &(dyn Fn(f64) + Sync),
) -> Result<RegionMap, RegionError> {
    map_subject(scene, whole, options, on_decided)
}

/// Maps the planar problem file `text` with `overrides` (read as `problem`) over `whole`,
/// whose axes are the keys of Lemma P7 (docs/reductions.md): see [`map_region`].
pub fn map_planar_region(
    text: &str,
    overrides: &[String],
    problem: &PlanarProblem,
    whole: &ParamBox,
    options: &RegionOptions,
    on_decided: &(dyn Fn(f64) + Sync),
) -> Result<RegionMap, RegionError> {
    let subject = PlanarRegion::new(text, overrides, problem);
    map_subject(&subject, whole, options, on_decided)
}

fn map_subject<S: RegionSubject>(
    subject: &S,
    whole: &ParamBox,
    options: &RegionOptions,
    on_decided: &(dyn Fn(f64) + Sync),
) -> Result<RegionMap, RegionError> {
    if let Some(reason) = subject.refusal(whole) {
        return Err(RegionError::Refused(reason));
    }
    let mut level = vec![Task {
        b: whole.clone(),
        path: String::new(),
        hints: Hints::default(),
    }];
    let mut leaves = Vec::new();
    let mut solved = 0;
    let corners = Corners::default();
    let mut boxes: u64 = 0;
    while !level.is_empty() {
        if boxes.saturating_add(level.len() as u64) > options.max_boxes {
            // The whole level is left undecided (not part of it: the map stays a function
            // of the options, not of the order of work).
            let reason = format!(
                "box budget reached: {} boxes decided, {} more would pass the budget of {} \
                 (--max-boxes raises it)",
                grouped(boxes),
                grouped(level.len() as u64),
                grouped(options.max_boxes)
            );
            for task in level {
                on_decided(volume_fraction(whole, &task.b));
                leaves.push(Leaf {
                    path: task.path,
                    bounds: bounds_of(&task.b),
                    verdict: LeafVerdict::Undecided,
                    lower_bound: None,
                    proofs: Vec::new(),
                    refutation: None,
                    scene_refutation: None,
                    planar_certificate: None,
                    reason: Some(reason.clone()),
                });
            }
            break;
        }
        boxes += level.len() as u64;
        let decided: Vec<Decided> = level
            .into_par_iter()
            .map(|task| decide(subject, whole, task, options, &corners, on_decided))
            .collect();
        level = Vec::new();
        for d in decided {
            match d {
                Decided::Leaf(leaf, n) => {
                    solved += n;
                    leaves.push(leaf);
                }
                Decided::Split(low, high, n) => {
                    solved += n;
                    level.push(low);
                    level.push(high);
                }
            }
        }
    }
    leaves.sort_by(|a, b| a.path.cmp(&b.path));
    let mut coverage = Coverage::default();
    for leaf in &leaves {
        let b = crate::proof::region_map::box_at(whole, &leaf.path).expect("paths the search made");
        let share = volume_fraction(whole, &b);
        match leaf.verdict {
            LeafVerdict::Certified => coverage.certified += share,
            LeafVerdict::Refuted => coverage.refuted += share,
            LeafVerdict::Undecided => coverage.undecided += share,
        }
    }
    let mut map = RegionMap {
        format: FORMAT.into(),
        problem: None,
        scene: None,
        planar: None,
        ranges: whole.axes.clone(),
        depth: options.depth,
        leaves,
        coverage,
        programs_solved: solved,
        digest: String::new(),
    };
    subject.record(&mut map);
    map.digest = map.compute_digest();
    Ok(map)
}

/// Decides one box: certified, refuted, split, or (at the depth limit) undecided.
///
/// Its corners are analysed first (each once, shared with the neighbours): a box with a
/// corner that does not certify cannot be certified as a whole, and one with a corner that
/// does is never marked refuted, so a box with both — one the boundary crosses — is split
/// without a certificate attempt or a centre analysis. Along the boundary that is most
/// boxes, and what deeper maps spend their programs on.
fn decide<S: RegionSubject>(
    subject: &S,
    whole: &ParamBox,
    task: Task,
    options: &RegionOptions,
    corners: &Corners,
    on_decided: &(dyn Fn(f64) + Sync),
) -> Decided {
    let mut solved = 0;
    let leaf = |verdict, reason: Option<String>| Leaf {
        path: task.path.clone(),
        bounds: bounds_of(&task.b),
        verdict,
        lower_bound: None,
        proofs: Vec::new(),
        refutation: None,
        scene_refutation: None,
        planar_certificate: None,
        reason,
    };
    let share = volume_fraction(whole, &task.b);
    let sides = corner_sides(subject, &task.b, corners, &mut solved);
    let (hints, reason) = match (&sides.certified, &sides.not_certified) {
        (Some(yes), Some(no)) => (
            task.hints.clone(),
            format!("the boundary crosses it: its corner {yes}, its corner {no}"),
        ),
        (_, None) => match subject.certify_box(&task.b, &task.hints, &mut solved) {
            Ok(cert) => {
                on_decided(share);
                let mut l = leaf(LeafVerdict::Certified, None);
                l.lower_bound = Some(f64_at_most(&cert.lower_bound));
                l.proofs = cert.proofs;
                l.planar_certificate = cert.planar;
                return Decided::Leaf(l, solved);
            }
            Err(nc) => (
                nc.hints,
                format!("{}; every corner is certified", nc.reason),
            ),
        },
        (None, Some(no)) => match subject.refute_centre(&task.b, &mut solved) {
            Ok(r) => {
                on_decided(share);
                let mut l = leaf(LeafVerdict::Refuted, None);
                match r {
                    LeafRefutation::Problem(r) => l.refutation = Some(r),
                    LeafRefutation::Scene(r) => l.scene_refutation = Some(r),
                    LeafRefutation::Planar(c) => l.planar_certificate = Some(c),
                }
                return Decided::Leaf(l, solved);
            }
            Err(note) => (task.hints.clone(), format!("its corner {no}; {note}")),
        },
    };
    if let Some(axis) = split_axis(whole, &task, options)
        && let Some((low, high)) = task.b.split(axis)
    {
        let half = |b, upper| Task {
            b,
            path: format!("{}{}", task.path, path_letter(axis, upper)),
            hints: hints.clone(),
        };
        return Decided::Split(half(low, false), half(high, true), solved);
    }
    on_decided(share);
    Decided::Leaf(leaf(LeafVerdict::Undecided, Some(reason)), solved)
}

/// The axis to halve: the widest relative to its whole range, if the depth and minimum
/// width allow a split.
fn split_axis(whole: &ParamBox, task: &Task, options: &RegionOptions) -> Option<usize> {
    if task.path.chars().count() >= options.depth as usize {
        return None;
    }
    let relative = |i: usize| {
        let (w, a) = (&whole.axes[i], &task.b.axes[i]);
        if w.hi > w.lo {
            (a.hi - a.lo) / (w.hi - w.lo)
        } else {
            0.0
        }
    };
    (0..whole.axes.len())
        .filter(|&i| relative(i) > 0.0 && relative(i) / 2.0 >= options.min_width)
        .max_by(|&i, &j| relative(i).total_cmp(&relative(j)).then(j.cmp(&i)))
}

/// A box's corners by verdict: one that certifies and one that does not (each in words,
/// with its verdict), when there are.
struct CornerSides {
    certified: Option<String>,
    not_certified: Option<String>,
}

/// Analyses the corners of `b` (each point once over the whole search), stopping once both
/// sides are seen. (Only the verdict is needed: no witness is replayed at corners.)
fn corner_sides<S: RegionSubject>(
    subject: &S,
    b: &ParamBox,
    corners: &Corners,
    solved: &mut usize,
) -> CornerSides {
    let mut sides = CornerSides {
        certified: None,
        not_certified: None,
    };
    for mask in subject.corners(b) {
        let values = b.corner_values(mask);
        let key: Vec<u64> = values.iter().map(|v| v.to_bits()).collect();
        let slot = Arc::clone(
            corners
                .0
                .lock()
                .expect("no panics inside")
                .entry(key)
                .or_default(),
        );
        let verdict = *slot.get_or_init(|| {
            let (verdict, n) = subject.verdict_at(b, &values);
            *solved += n;
            verdict
        });
        let side = if verdict == Verdict::Certified {
            &mut sides.certified
        } else {
            &mut sides.not_certified
        };
        if side.is_none() {
            let at: Vec<String> = b
                .axes
                .iter()
                .zip(&values)
                .map(|(a, v)| format!("{} = {v}", a.key()))
                .collect();
            *side = Some(format!("{} is {}", at.join(", "), verdict.as_str()));
        }
        if sides.certified.is_some() && sides.not_certified.is_some() {
            break;
        }
    }
    sides
}
