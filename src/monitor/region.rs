//! Monitoring against a region map: one box of parameters certified at once.
//!
//! A map's certified leaf (or its whole box, when every leaf is certified) proves safety at
//! every point of the box. The monitor checks a trace against **one** of those points: the
//! one whose premises ask least of the world and whose controller asks least of the robot,
//! so that a trace that any certified point's monitor would pass is passed here too.
//!
//! - The environment's bounds take the box's **upper** ends: W, σ_g, σ_w (an obstacle as
//!   fast as W_hi, or a reading σ_hi off, is within the premises of the point with those
//!   ends), and the clearance too (the proof gives s* > clearance at every point, so at the
//!   largest: a gap at or below it is a `collision` event).
//! - The controller's reaction radius ρ and buffer take the **lower** ends: the danger the
//!   robot must react to is the least any certified controller of the box reacts to (a
//!   robot that brakes earlier is braking without being asked, which no monitor flags).
//! - The start and the first sighting take the **lower** ends: g0 and d_det (an obstacle
//!   first seen at a smaller gap is within the premises of the point with the lower d_det).
//! - The assumed bound V_a has no end that asks least (the wrong-assumption guard fires less
//!   often at the upper end, the kinematic danger distance is shorter at the lower), so a
//!   ranged V_a must be named: the value the robot's controller runs with.
//!
//! A planar map is monitored through its certificates instead
//! ([`planar_region_certificate`]): the weak corner's (Lemma P7).
//!
//! Any ranged controller parameter may be named that way ([`RegionPoint::controller`]); the
//! value must lie in the box. The point picked lies in a certified box, so the monitor is
//! exactly the one of a point certificate there, and `check` has verified the map first.

use super::check::Bounds;
use super::{Monitor, MonitorError, Rule};
use crate::core::param_box::{Axis, ParamBox};
use crate::core::parameter::Parameter;
use crate::proof::planar::certificate::PlanarCertificate;
use crate::proof::planar::region::weak_corner;
use crate::proof::premise::premises;
use crate::proof::region_check::check_map;
use crate::proof::region_map::{LeafVerdict, RegionMap, box_at};

/// Which box of a map, and which controller, the monitor checks against.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RegionPoint {
    /// A certified leaf, by its path in the map; `None`: the whole box, which must then be
    /// certified leaf by leaf.
    pub leaf: Option<String>,
    /// The values the robot's controller uses for ranged controller parameters (ρ, V_a,
    /// buffer); the others take the ends the module docs give.
    pub controller: Vec<(Parameter, f64)>,
}

/// Whether the parameter is one of the controller's (the robot chooses it, the world does
/// not).
fn is_controller(p: Parameter) -> bool {
    matches!(
        p,
        Parameter::ReactionRadius | Parameter::AssumedObstacleSpeed | Parameter::Buffer
    )
}

fn refuse<T>(reason: String) -> Result<T, MonitorError> {
    Err(MonitorError::Region(reason))
}

/// The box the monitor is for: the leaf named, or the whole box.
fn chosen_box(map: &RegionMap, leaf: Option<&str>) -> Result<ParamBox, MonitorError> {
    let Some(path) = leaf else {
        if map.all_certified() {
            return Ok(map.whole());
        }
        let certified = map
            .leaves
            .iter()
            .filter(|l| l.verdict == LeafVerdict::Certified)
            .count();
        return refuse(format!(
            "the map certifies {certified} of its {} leaves, not the whole box: name a \
             certified leaf by its path (--leaf PATH)",
            map.leaves.len()
        ));
    };
    let Some(found) = map.leaves.iter().find(|l| l.path == path) else {
        return refuse(format!("the map has no leaf with path {path:?}"));
    };
    if found.verdict != LeafVerdict::Certified {
        return refuse(format!(
            "leaf {path:?} is {}, not certified",
            found.verdict.as_str()
        ));
    }
    let mut b = map.whole();
    for a in &mut b.axes {
        let [lo, hi] = found.bounds[&a.key()];
        (a.lo, a.hi) = (lo, hi);
    }
    Ok(b)
}

/// The value axis `a` takes at the point the monitor checks against (see the module docs).
fn chosen_value(a: &Axis, at: &RegionPoint) -> Result<f64, MonitorError> {
    let named = at
        .controller
        .iter()
        .find(|(p, _)| a.obstacle.is_none() && *p == a.parameter);
    Ok(match (a.parameter, named) {
        (_, Some((_, v))) => *v,
        (
            Parameter::ReactionRadius
            | Parameter::Buffer
            | Parameter::InitialGap
            | Parameter::FirstDetectionGap,
            _,
        ) => a.lo,
        (Parameter::AssumedObstacleSpeed, None) if a.lo < a.hi => {
            return refuse(format!(
                "the box ranges {} over [{}, {}]: name the value the robot's controller runs \
                 with",
                a.key(),
                a.lo,
                a.hi
            ));
        }
        _ => a.hi,
    })
}

impl Monitor {
    /// A monitor for a region map (see the module docs): [`check_map`] runs first, then the
    /// point of the box `at` names is picked. Errors name what is missing or out of the box.
    pub fn for_region(map: &RegionMap, at: &RegionPoint) -> Result<Monitor, MonitorError> {
        check_map(map)?;
        let b = chosen_box(map, at.leaf.as_deref())?;
        for (p, v) in &at.controller {
            let Some(a) = b.axis(*p) else {
                return refuse(format!("{} is not ranged in the map", p.key()));
            };
            if !is_controller(*p) {
                return refuse(format!(
                    "only the controller's parameters can be named (controller.reaction_radius, \
                     controller.assumed_obstacle_speed, controller.buffer); the monitor takes \
                     the box's {} end of {}",
                    if matches!(p, Parameter::InitialGap | Parameter::FirstDetectionGap) {
                        "lower"
                    } else {
                        "upper"
                    },
                    p.key()
                ));
            }
            if !(a.lo <= *v && *v <= a.hi) {
                return refuse(format!(
                    "{}={v} lies outside the box's [{}, {}]",
                    p.key(),
                    a.lo,
                    a.hi
                ));
            }
        }
        if let Some(scene) = &map.scene {
            let mut point = scene.clone();
            for a in &b.axes {
                a.set_in_scene(&mut point, chosen_value(a, at)?)
                    .map_err(MonitorError::Region)?;
            }
            return Monitor::for_certified_scene(&point);
        }
        let Some(mapped) = &map.problem else {
            return refuse("the map names neither a problem nor a scene".into());
        };
        let mut problem = mapped.clone();
        for a in &b.axes {
            a.parameter.set_in(&mut problem, chosen_value(a, at)?);
        }
        let bounds = Bounds::from_premises(&premises(&problem))?;
        Ok(Self::with_bounds(
            bounds,
            Rule::of_problem(&problem),
            None,
            super::DEFAULT_MAX_OBSTACLES,
            0,
        ))
    }
}

/// The planar certificate a monitor checks a planar map against: for the leaf named (or
/// the whole box, certified leaf by leaf), the certificate of the certified leaf that holds
/// the box's weak corner — ρ and the buffer at their lower ends (the least danger any
/// certified controller of the box reacts to), the clearance and speed bounds at their
/// upper ends (the premises that ask least of the world). By docs/reductions.md Lemma P7
/// that corner's proof covers the box. A ranged V_a is refused: its lower end makes the
/// wrong-assumption guard fire most often, which a controller running the upper end would
/// be flagged for.
pub fn planar_region_certificate(
    map: &RegionMap,
    leaf: Option<&str>,
) -> Result<PlanarCertificate, MonitorError> {
    check_map(map)?;
    let b = chosen_box(map, leaf)?;
    if b.axis(Parameter::AssumedObstacleSpeed).is_some() {
        return refuse(
            "the map ranges controller.assumed_obstacle_speed, which has no end that asks \
             least of a planar controller; monitor against a planar certificate at the \
             value the robot runs with"
                .into(),
        );
    }
    let weak = weak_corner(&b).map_err(MonitorError::Region)?;
    let whole = map.whole();
    let holder = map.leaves.iter().find(|l| {
        l.verdict == LeafVerdict::Certified
            && box_at(&whole, &l.path).and_then(|lb| weak_corner(&lb).ok()) == Some(weak.clone())
    });
    match holder.and_then(|l| l.planar_certificate.as_deref()) {
        Some(cert) => Ok(cert.clone()),
        None => refuse("no certified leaf holds the box's weak corner".into()),
    }
}
