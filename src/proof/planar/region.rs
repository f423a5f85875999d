//! Region maps of planar problems (docs/reductions.md Lemma P7): a box over the reaction
//! radius, the assumed speed, the buffer, the clearance and each obstacle's speed bound is
//! certified by one planar certificate at its *weak corner* — each axis at the end that
//! makes the relaxation's feasible sets largest — and refuted by a planar certificate with a
//! replayed collision at a point of it.
//!
//! What a map stores of the problem is its file's text and overrides; every leaf's
//! certificate must be that text with those overrides and one more per axis, at the leaf's
//! weak corner (certified) or at a point of the leaf (refuted). `check` rebuilds those
//! overrides itself, so a certificate for any other point is rejected.

use serde::{Deserialize, Serialize};

use crate::core::num::exact_decimal;
use crate::core::param_box::{Axis, End, ParamBox};
use crate::core::parameter::Parameter;
use crate::core::planar::PlanarProblem;
use crate::proof::check::Invalid;
use crate::proof::verdict::Verdict;

use super::certificate::PlanarCertificate;
use super::check::check_planar;

/// The planar problem a map is of: its file's text and overrides, as read.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct PlanarSource {
    /// The problem's name.
    pub name: String,
    /// The clearance (m) at the map's base values (the file with its overrides).
    pub clearance: f64,
    /// The problem file's text.
    pub problem_toml: String,
    /// The `--set` overrides every point of the map has, in order (each axis adds one more).
    pub overrides: Vec<String>,
}

/// The end of `axis` whose relaxation contains every other point's (Lemma P7): the lower
/// end of the reaction radius, the assumed speed and the buffer (smaller sure-fire sets),
/// the upper end of an obstacle's speed bound (larger reachable sets) and of the clearance
/// (a higher goal); the reason, in the user's terms, when the key is not one the lemma
/// covers.
pub fn weak_end(axis: &Axis) -> Result<End, String> {
    match (axis.parameter, axis.obstacle) {
        (Parameter::ReactionRadius | Parameter::AssumedObstacleSpeed | Parameter::Buffer, None) => {
            Ok(End::Low)
        }
        (Parameter::Clearance, None) | (Parameter::ObstacleSpeed, Some(_)) => Ok(End::High),
        _ => Err(format!(
            "{}: a planar map ranges controller.reaction_radius, \
             controller.assumed_obstacle_speed, controller.buffer, robot.clearance and \
             obstacle.<i>.max_speed (the keys whose relaxation is largest at one end: \
             docs/reductions.md Lemma P7)",
            axis.key()
        )),
    }
}

/// The value of each axis of `b` at its weak corner, in axis order.
pub fn weak_corner(b: &ParamBox) -> Result<Vec<f64>, String> {
    b.axes
        .iter()
        .map(|a| {
            Ok(match weak_end(a)? {
                End::Low => a.lo,
                End::High => a.hi,
            })
        })
        .collect()
}

/// The overrides of the point where each axis of `b` takes its value in `values`: the
/// source's, then one `key=value` per axis (the value as it prints, which reads back as
/// the decimal the box means).
pub fn point_overrides(source: &PlanarSource, b: &ParamBox, values: &[f64]) -> Vec<String> {
    let mut sets = source.overrides.clone();
    sets.extend(
        b.axes
            .iter()
            .zip(values)
            .map(|(a, v)| format!("{}={v}", a.key())),
    );
    sets
}

/// The origin planar maps read their problem text as, in errors.
pub const ORIGIN: &str = "the map's problem";

/// Why a planar map over `whole` is not one Lemma P7 covers (None: it is): a key it does
/// not cover, an obstacle past the last, or a corner where the problem does not read.
pub fn planar_refusal(source: &PlanarSource, whole: &ParamBox) -> Option<String> {
    if let Some(reason) = crate::proof::region_check::shape_refusal(whole) {
        return Some(reason);
    }
    for a in &whole.axes {
        if let Err(reason) = weak_end(a) {
            return Some(reason);
        }
    }
    // Every key here is a number with an interval of valid values, so validity at every
    // corner is validity everywhere in the box.
    let n = whole.axes.len();
    for mask in 0..(1u32 << n) {
        let values = whole.corner_values(mask);
        let sets = point_overrides(source, whole, &values);
        if let Err(e) =
            PlanarProblem::from_toml_str_with_overrides(&source.problem_toml, ORIGIN, &sets)
        {
            return Some(format!(
                "the problem does not read at a corner of the box: {e}"
            ));
        }
    }
    None
}

fn invalid<T>(msg: impl Into<String>) -> Result<T, Invalid> {
    Err(Invalid(msg.into()))
}

/// A leaf's certificate must be for the map's problem at the point `values` of `b`, verify,
/// and give `verdict`.
fn check_at(
    source: &PlanarSource,
    b: &ParamBox,
    values: &[f64],
    cert: &PlanarCertificate,
    verdict: Verdict,
) -> Result<(), Invalid> {
    if cert.problem_toml != source.problem_toml {
        return invalid("its certificate is for another problem text than the map's");
    }
    if cert.overrides != point_overrides(source, b, values) {
        return invalid(format!(
            "its certificate's overrides are {:?}, expected {:?}",
            cert.overrides,
            point_overrides(source, b, values)
        ));
    }
    check_planar(cert).map_err(|Invalid(e)| Invalid(format!("its certificate: {e}")))?;
    if cert.verdict != verdict {
        return invalid(format!(
            "its certificate is {}, not {}",
            cert.verdict.as_str(),
            verdict.as_str()
        ));
    }
    Ok(())
}

/// A certified leaf `b`: its certificate is at the leaf's weak corner and certified, and
/// the stated lower bound is the certificate's. By Lemma P7 that bound holds at every
/// point of `b`.
pub fn check_certified_leaf(
    source: &PlanarSource,
    b: &ParamBox,
    cert: &PlanarCertificate,
    stated_lower: Option<f64>,
) -> Result<(), Invalid> {
    let values = weak_corner(b).map_err(Invalid)?;
    check_at(source, b, &values, cert, Verdict::Certified)?;
    if stated_lower != Some(cert.lower_bound) {
        return invalid(format!(
            "stated lower bound {stated_lower:?}, its certificate proves {}",
            cert.lower_bound
        ));
    }
    Ok(())
}

/// A refuted leaf `b`: its certificate is at a point of the leaf (every axis's value
/// between the leaf's ends, exactly) and refuted by a replayed collision.
pub fn check_refuted_leaf(
    source: &PlanarSource,
    b: &ParamBox,
    cert: &PlanarCertificate,
) -> Result<(), Invalid> {
    let n = source.overrides.len();
    if cert.overrides.len() != n + b.axes.len() {
        return invalid("its certificate does not set exactly the ranged keys");
    }
    let values = b
        .axes
        .iter()
        .zip(&cert.overrides[n..])
        .map(|(a, set)| {
            let key = a.key();
            let Some(v) = set
                .strip_prefix(key.as_str())
                .and_then(|s| s.strip_prefix('='))
                .and_then(|s| s.parse::<f64>().ok())
            else {
                return invalid(format!(
                    "its certificate's override {set:?} does not set {key}"
                ));
            };
            let exact = exact_decimal(v);
            if exact < a.lo_exact() || exact > a.hi_exact() {
                return invalid(format!("its point's {key} = {v} lies outside the leaf"));
            }
            Ok(v)
        })
        .collect::<Result<Vec<f64>, Invalid>>()?;
    check_at(source, b, &values, cert, Verdict::Refuted)
}

/// The map's stated name and clearance must be its problem's.
pub fn check_source(source: &PlanarSource) -> Result<(), Invalid> {
    let problem = PlanarProblem::from_toml_str_with_overrides(
        &source.problem_toml,
        ORIGIN,
        &source.overrides,
    )
    .map_err(|e| Invalid(format!("the map's planar problem does not read: {e}")))?;
    if problem.name != source.name {
        return invalid(format!(
            "the map names its problem {:?}; its text names it {:?}",
            source.name, problem.name
        ));
    }
    let clearance = problem.params().motion.clearance.to_f64().value();
    if clearance != source.clearance {
        return invalid(format!(
            "the map states clearance {}; its problem's is {clearance}",
            source.clearance
        ));
    }
    Ok(())
}
