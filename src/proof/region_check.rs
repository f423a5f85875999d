//! Checking region maps without the solver, in exact rationals.
//!
//! [`check_map`] trusts none of the map's numbers:
//! 1. the format tag and the digest (an edit after the fact is named as such);
//! 2. the problem is valid at every corner of the box, and the box is one region
//!    certificates cover ([`refusal`]);
//! 3. the leaves' paths are the ends of binary splits that cover the box exactly once, and
//!    each leaf's `box` is the box its path leads to;
//! 4. each certified leaf's pieces are rebuilt for its box, its proofs must list exactly
//!    those pieces, and each proof's affine bound, least at a vertex, must exceed the
//!    clearance everywhere in the leaf (emptiness proofs must hold at every vertex);
//! 5. each refuted leaf's point lies in the leaf and its behaviour, replayed exactly at that
//!    point, collides;
//! 6. the stated coverage follows from the leaves.
//!
//! A planar map's leaves carry planar certificates instead, checked by
//! [`crate::proof::planar::region`] (at the weak corner: Lemma P7).

use std::collections::BTreeMap;

use crate::core::model::Problem;
use crate::core::num::{Exact, f64_at_most};
use crate::core::param_box::ParamBox;
use crate::core::parameter::{ParamAffine, Parameter};
use crate::core::scene::Scene;
use crate::core::simulate;
use crate::proof::check::{Invalid, shown};
use crate::proof::planar::region::{self as planar_region, PlanarSource};
use crate::proof::program::{Program, ProofKind};
use crate::proof::region_map::{
    BoxProof, Coverage, FORMAT, Leaf, LeafVerdict, Refutation, RegionMap, bounds_of, box_at,
    path_step, volume_fraction,
};
use crate::proof::scene_region_check::{check_scene_refutation, scene_box_margin, scene_refusal};
use crate::proof::schedule::{Decomposition, Piece};
use crate::proof::verdict::aim;

/// Most ranged parameters a map may have (its corners are all validated).
pub const MAX_AXES: usize = 8;

/// What a valid map establishes.
#[derive(Clone, Debug, PartialEq)]
pub struct MapReport {
    /// Leaves checked.
    pub leaves: usize,
    /// Fractions of the box by verdict.
    pub coverage: Coverage,
    /// Every leaf is certified: the whole box is.
    pub all_certified: bool,
}

fn invalid<T>(msg: impl Into<String>) -> Result<T, Invalid> {
    Err(Invalid(msg.into()))
}

/// Why `whole` is no box a map can have, whatever it maps (None: it can be): no axis, too
/// many, or a malformed one.
pub(crate) fn shape_refusal(whole: &ParamBox) -> Option<String> {
    if whole.axes.is_empty() {
        return Some("no parameter is ranged".into());
    }
    if whole.axes.len() > MAX_AXES {
        return Some(format!(
            "at most {MAX_AXES} parameters can be ranged at once"
        ));
    }
    ParamBox::new(whole.axes.clone()).err()
}

/// Why region certificates do not cover `problem` over `whole` (None: they do).
pub fn refusal(problem: &Problem, whole: &ParamBox) -> Option<String> {
    if let Some(reason) = shape_refusal(whole) {
        return Some(reason);
    }
    if let Some(a) = whole.axes.iter().find(|a| a.obstacle.is_some()) {
        return Some(format!(
            "{}: a problem has one obstacle; range environment.obstacle_speed or \
             environment.initial_gap (or map the problem as a scene)",
            a.key()
        ));
    }
    if problem.environment.initial_gap.is_range() && whole.axis(Parameter::InitialGap).is_none() {
        return Some(
            "environment.initial_gap is a range, which region certificates do not cover yet; \
             range it with --range environment.initial_gap=LO..HI instead"
                .into(),
        );
    }
    let hidden = problem.first_detection_gap().is_some()
        || whole.axis(Parameter::FirstDetectionGap).is_some();
    if hidden {
        let dec = Decomposition::for_box(problem, whole);
        if dec.wrong_assumption_active() {
            return Some(
                "sensing.first_detection_gap with a wrong-assumption guard active somewhere in \
                 the box is not covered by region certificates yet (certify analyses each \
                 point)"
                    .into(),
            );
        }
    }
    // Every constraint on these keys is an interval, so validity at every corner is validity
    // everywhere in the box.
    let n = whole.axes.len();
    for mask in 0..(1u32 << n) {
        let mut p = problem.clone();
        for (i, a) in whole.axes.iter().enumerate() {
            let v = if mask >> i & 1 == 1 { a.hi } else { a.lo };
            a.parameter.set_in(&mut p, v);
        }
        if let Err(e) = p.validate("the box's corner") {
            return Some(format!(
                "the problem is invalid at a corner of the box: {e}"
            ));
        }
    }
    None
}

/// Re-verifies a map (see the module docs for what is checked).
pub fn check_map(map: &RegionMap) -> Result<MapReport, Invalid> {
    if map.format != FORMAT {
        return invalid(format!("format is {:?}, expected {FORMAT:?}", map.format));
    }
    if map.compute_digest() != map.digest {
        return invalid("digest mismatch: the map was edited after it was written");
    }
    let subject = match (&map.problem, &map.scene, &map.planar) {
        (Some(p), None, None) => {
            p.validate("map problem")
                .map_err(|e| Invalid(format!("the map's problem is invalid: {e}")))?;
            Mapped::Problem(p)
        }
        (None, Some(s), None) => {
            s.validate("map scene")
                .map_err(|e| Invalid(format!("the map's scene is invalid: {e}")))?;
            Mapped::Scene(s)
        }
        (None, None, Some(q)) => {
            planar_region::check_source(q)?;
            Mapped::Planar(q)
        }
        _ => return invalid("a map names exactly one of a problem, a scene and a planar problem"),
    };
    let whole = map.whole();
    let refused = match subject {
        Mapped::Problem(p) => refusal(p, &whole),
        Mapped::Scene(s) => scene_refusal(s, &whole),
        Mapped::Planar(q) => planar_region::planar_refusal(q, &whole),
    };
    if let Some(reason) = refused {
        return invalid(format!(
            "the map's box is not one region certificates cover: {reason}"
        ));
    }
    check_partition(&map.leaves, map.depth)?;
    let mut coverage = Coverage::default();
    for leaf in &map.leaves {
        let Some(b) = box_at(&whole, &leaf.path) else {
            return invalid(format!("leaf {:?}: the path leads to no box", leaf.path));
        };
        if leaf.bounds != bounds_of(&b) {
            return invalid(format!(
                "leaf {:?}: its box is not the one its path leads to",
                leaf.path
            ));
        }
        check_leaf(subject, &b, leaf)
            .map_err(|Invalid(e)| Invalid(format!("leaf {:?}: {e}", leaf.path)))?;
        let share = volume_fraction(&whole, &b);
        match leaf.verdict {
            LeafVerdict::Certified => coverage.certified += share,
            LeafVerdict::Refuted => coverage.refuted += share,
            LeafVerdict::Undecided => coverage.undecided += share,
        }
    }
    let near = |a: f64, b: f64| (a - b).abs() <= 1e-9;
    if !(near(coverage.certified, map.coverage.certified)
        && near(coverage.refuted, map.coverage.refuted)
        && near(coverage.undecided, map.coverage.undecided))
    {
        return invalid("the stated coverage does not follow from the leaves");
    }
    Ok(MapReport {
        leaves: map.leaves.len(),
        coverage,
        all_certified: map.all_certified(),
    })
}

/// The paths must be the leaves of one binary split tree (each inner node split along one
/// axis into both halves), no deeper than `depth`.
fn check_partition(leaves: &[Leaf], depth: u32) -> Result<(), Invalid> {
    if leaves.is_empty() {
        return invalid("the map has no leaves");
    }
    if let Some(l) = leaves
        .iter()
        .find(|l| l.path.chars().count() > depth as usize)
    {
        return invalid(format!("leaf {:?} is deeper than the map's depth", l.path));
    }
    let mut paths: Vec<&str> = leaves.iter().map(|l| l.path.as_str()).collect();
    paths.sort_unstable();
    if paths.windows(2).any(|w| w[0] == w[1]) {
        return invalid("two leaves have the same path");
    }
    fn covers(paths: &[&str], at: usize) -> Result<(), String> {
        if let [only] = paths
            && only.len() == at
        {
            return Ok(());
        }
        let mut low = Vec::new();
        let mut high = Vec::new();
        let mut axis = None;
        for p in paths {
            let Some(c) = p[at..].chars().next() else {
                return Err(format!("leaf {p:?} lies inside another leaf"));
            };
            let Some((a, upper)) = path_step(c) else {
                return Err(format!("leaf {p:?}: {c:?} names no split"));
            };
            if *axis.get_or_insert(a) != a {
                return Err(format!("leaves under {:?} split different axes", &p[..at]));
            }
            if upper { high.push(*p) } else { low.push(*p) }
        }
        if low.is_empty() || high.is_empty() {
            return Err(format!(
                "the leaves do not cover the box: a half under {:?} has none",
                &paths[0][..at]
            ));
        }
        covers(&low, at + 1)?;
        covers(&high, at + 1)
    }
    covers(&paths, 0).map_err(Invalid)
}

/// What a map is of.
#[derive(Clone, Copy)]
enum Mapped<'a> {
    Problem(&'a Problem),
    Scene(&'a Scene),
    Planar(&'a PlanarSource),
}

/// One leaf's evidence.
fn check_leaf(subject: Mapped, b: &ParamBox, leaf: &Leaf) -> Result<(), Invalid> {
    if let Mapped::Planar(q) = subject {
        return check_planar_leaf(q, b, leaf);
    }
    if leaf.planar_certificate.is_some() {
        return invalid("a leaf of a map that is not planar carries a planar certificate");
    }
    let refuted = leaf.refutation.is_some() || leaf.scene_refutation.is_some();
    match leaf.verdict {
        LeafVerdict::Certified => {
            if refuted {
                return invalid("a certified leaf carries a refutation");
            }
            let (margin, lower) = match subject {
                Mapped::Problem(p) => {
                    let dec = Decomposition::for_box(p, b);
                    box_margin(&dec, &dec.pieces, &leaf.proofs, None)?
                }
                Mapped::Scene(s) => scene_box_margin(s, b, &leaf.proofs)?,
                Mapped::Planar(_) => unreachable!("planar leaves are checked above"),
            };
            if margin <= Exact::ZERO {
                return invalid("the proofs do not keep s* above the clearance everywhere");
            }
            check_stated_lower(leaf.lower_bound, &lower)
        }
        LeafVerdict::Refuted => {
            if !leaf.proofs.is_empty() || leaf.lower_bound.is_some() {
                return invalid("a refuted leaf carries proofs");
            }
            match (subject, &leaf.refutation, &leaf.scene_refutation) {
                (Mapped::Problem(p), Some(r), None) => check_refutation(p, b, r),
                (Mapped::Scene(s), None, Some(r)) => check_scene_refutation(s, b, r),
                _ => invalid("a refuted leaf names no colliding point of what the map is of"),
            }
        }
        LeafVerdict::Undecided => {
            if !leaf.proofs.is_empty() || refuted || leaf.lower_bound.is_some() {
                return invalid("an undecided leaf carries evidence for a verdict");
            }
            Ok(())
        }
    }
}

/// One planar leaf's evidence: a certificate at its weak corner (certified) or at a
/// colliding point of it (refuted), and nothing of the line's.
fn check_planar_leaf(source: &PlanarSource, b: &ParamBox, leaf: &Leaf) -> Result<(), Invalid> {
    if !leaf.proofs.is_empty() || leaf.refutation.is_some() || leaf.scene_refutation.is_some() {
        return invalid("a planar leaf carries the line's proofs or refutations");
    }
    match (leaf.verdict, &leaf.planar_certificate) {
        (LeafVerdict::Certified, Some(c)) => {
            planar_region::check_certified_leaf(source, b, c, leaf.lower_bound)
        }
        (LeafVerdict::Refuted, Some(c)) => {
            if leaf.lower_bound.is_some() {
                return invalid("a refuted leaf states a lower bound");
            }
            planar_region::check_refuted_leaf(source, b, c)
        }
        (LeafVerdict::Undecided, None) if leaf.lower_bound.is_none() => Ok(()),
        (LeafVerdict::Undecided, _) => invalid("an undecided leaf carries evidence for a verdict"),
        (_, None) => invalid("a decided planar leaf carries no certificate"),
    }
}

/// The least margin s* − clearance over the box that the proofs establish, and the least
/// lower bound on s*; an error when a proof is malformed, for another piece or obstacle,
/// or does not prove what it says. Proofs must list `pieces` (of the box decomposition
/// `dec`, of scene obstacle `obstacle` in a scene) in order.
pub fn box_margin(
    dec: &Decomposition,
    pieces: &[Piece],
    proofs: &[BoxProof],
    obstacle: Option<usize>,
) -> Result<(Exact, Exact), Invalid> {
    if proofs.len() != pieces.len() {
        return invalid(format!(
            "the box has {} pieces; the leaf lists {} proofs",
            pieces.len(),
            proofs.len()
        ));
    }
    if let Some(p) = proofs.iter().find(|p| p.obstacle != obstacle) {
        return invalid(format!(
            "a proof is tagged with obstacle {}, expected {}",
            shown_index(p.obstacle),
            shown_index(obstacle)
        ));
    }
    let b = dec.region().expect("a box decomposition");
    let clearance = ParamAffine::parameter(Parameter::Clearance, &dec.params);
    let mut margin: Option<Exact> = None;
    let mut lower: Option<Exact> = None;
    for (i, (proof, piece)) in proofs.iter().zip(pieces).enumerate() {
        if proof.piece != *piece {
            return invalid(format!(
                "proof {i} is for {}, but piece {i} is {}",
                describe(&proof.piece),
                describe(piece)
            ));
        }
        let program = dec.program(piece);
        match box_proof_value(
            b,
            &dec.params,
            &program,
            piece,
            &proof.kind,
            &proof.multipliers,
        ) {
            Err(reason) => return invalid(format!("proof {i} ({}): {reason}", describe(piece))),
            Ok(None) => {
                if proof.bound.is_some() {
                    return invalid(format!("proof {i}: an emptiness proof states a bound"));
                }
            }
            Ok(Some(bound)) => {
                let least = b.min_of(&bound, &dec.params);
                if proof.bound != Some(f64_at_most(&least)) {
                    return invalid(format!(
                        "proof {i}: stated bound {}, the multipliers prove {}",
                        shown(proof.bound),
                        f64_at_most(&least)
                    ));
                }
                let m = b.min_of(&(bound - clearance.clone()), &dec.params);
                if margin.as_ref().is_none_or(|x| m < *x) {
                    margin = Some(m);
                }
                if lower.as_ref().is_none_or(|x| least < *x) {
                    lower = Some(least);
                }
            }
        }
    }
    // Every piece empty: no behaviour comes nearer than the start.
    let start = ParamAffine::parameter(Parameter::InitialGap, &dec.params);
    let margin = margin.unwrap_or_else(|| b.min_of(&(start.clone() - clearance), &dec.params));
    let lower = lower.unwrap_or_else(|| b.min_of(&start, &dec.params));
    Ok((margin, lower))
}

/// What multipliers prove about a piece's box program at every point of the box `b` (the
/// program taken at `at`, its centre): `Some(bound)`, affine in the ranged parameters, or
/// `None` when they prove it empty everywhere; the reason when they prove neither.
pub fn box_proof_value(
    b: &ParamBox,
    at: &crate::core::model::Params<Exact>,
    program: &Program,
    piece: &Piece,
    kind: &ProofKind,
    z: &[f64],
) -> Result<Option<ParamAffine>, String> {
    match kind {
        ProofKind::Bound => {
            if !piece.has_objective() {
                return Err("a pass-through piece needs an emptiness proof".into());
            }
            program
                .bound_affine(z, true)
                .map(Some)
                .ok_or_else(|| "the multipliers are malformed".into())
        }
        ProofKind::Infeasible => {
            let farkas = program
                .bound_affine(z, false)
                .ok_or_else(|| "the multipliers are malformed".to_string())?;
            let least = b.min_of(&farkas, at);
            // Zero proves the strict system empty only with weight on a strict row.
            let strict_weight = program
                .rows
                .iter()
                .zip(z)
                .any(|(row, &zi)| row.strict && zi > 0.0);
            if least > Exact::ZERO || (least == Exact::ZERO && strict_weight) {
                Ok(None)
            } else {
                Err("the multipliers do not prove the piece empty at every point".into())
            }
        }
    }
}

/// A refuted point's value of each axis of `b`, in axis order, when the point gives exactly
/// the ranged keys and lies in the leaf `b`.
pub(crate) fn point_in_leaf(
    b: &ParamBox,
    point: &BTreeMap<String, f64>,
) -> Result<Vec<f64>, Invalid> {
    let mut keys: Vec<String> = b.axes.iter().map(|a| a.key()).collect();
    keys.sort_unstable();
    if point.keys().ne(keys.iter()) {
        return invalid("the refuted point does not give exactly the ranged keys");
    }
    b.axes
        .iter()
        .map(|a| {
            let v = point[&a.key()];
            if a.lo <= v && v <= a.hi {
                Ok(v)
            } else {
                invalid(format!(
                    "the refuted point's {} = {v} lies outside the leaf",
                    a.key()
                ))
            }
        })
        .collect()
}

/// The stated lower bound of a certified leaf must be what its proofs give.
fn check_stated_lower(stated: Option<f64>, lower: &Exact) -> Result<(), Invalid> {
    if stated != Some(f64_at_most(lower)) {
        return invalid(format!(
            "stated lower bound {}, the proofs give {}",
            shown(stated),
            f64_at_most(lower)
        ));
    }
    Ok(())
}

/// A refutation: the point lies in the box and the behaviour collides there, exactly.
fn check_refutation(problem: &Problem, b: &ParamBox, r: &Refutation) -> Result<(), Invalid> {
    let mut at = problem.clone();
    for (a, v) in b.axes.iter().zip(point_in_leaf(b, &r.point)?) {
        a.parameter.set_in(&mut at, v);
    }
    at.validate("the refuted point")
        .map_err(|e| Invalid(format!("the refuted point's problem is invalid: {e}")))?;
    let params = at.params::<Exact>();
    if let Some(k) = crate::proof::check::first_outside(&r.obstacle_speeds, &params.W) {
        return invalid(format!(
            "the behaviour's speed in period {k} is outside [0, W]"
        ));
    }
    let replay = simulate::replay_reacting_at(
        &params,
        &r.obstacle_speeds,
        aim(&r.piece, r.shift, None),
        r.obstacle_speeds.len(),
        true,
    );
    if !replay.collided() {
        return invalid("the behaviour does not collide at the refuted point");
    }
    Ok(())
}

fn shown_index(i: Option<usize>) -> String {
    i.map_or_else(|| "none".into(), |i| i.to_string())
}

/// A piece in words, for messages.
pub fn describe(p: &Piece) -> String {
    let ending = match p.ending {
        crate::proof::schedule::Ending::Danger => "danger",
        crate::proof::schedule::Ending::WrongAssumption => "wrong assumption",
        crate::proof::schedule::Ending::PassThrough => "pass-through",
        crate::proof::schedule::Ending::Bystander => "bystander",
    };
    let mut s = format!("brake step {}, {ending}", p.brake);
    if let Some(e) = p.entry {
        s += &format!(", entry {}{}", e, if p.early { " or earlier" } else { "" });
    }
    if p.merged {
        s += ", with its later shifts";
    }
    if p.detected {
        s += ", first seen then";
    }
    s
}

/// A box in words, for messages: `key = lo..hi, …`.
pub fn describe_box(b: &ParamBox) -> String {
    b.axes
        .iter()
        .map(|a| format!("{} = {}..{}", a.key(), a.lo, a.hi))
        .collect::<Vec<_>>()
        .join(", ")
}
