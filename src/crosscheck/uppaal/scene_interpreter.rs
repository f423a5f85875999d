//! The scene network run by the interpreter ([`super::interpreter`]'s search, UPPAAL's
//! semantics for the same data): the verdict of the safety query, the periods on a shortest
//! path to a violation, and per obstacle the least separation share over every reachable
//! state — what the scene explorer reports for the same finite model.

use super::interpreter::search_network;
use super::machine::Frame;
use super::{SceneUppaalModel, UppaalError};
use crate::core::num::Exact;
use crate::crosscheck::explore::{ExploreVerdict, Options};

/// What the interpreter found in a scene's exported network.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneGridExploration {
    /// `collision` iff a reachable state violates the query; `safe` iff none does and the
    /// search completed; else `inconclusive`.
    pub verdict: ExploreVerdict,
    /// Every reachable state was visited.
    pub complete: bool,
    /// Distinct network states.
    pub states: usize,
    /// Periods on a shortest path to a violating state.
    pub collision_period: Option<usize>,
    /// Per obstacle: the least separation share over reachable states (grid units; None:
    /// the robot never moved in its lane). The network stops at a violation, so after a
    /// collision this covers only the behaviours up to it.
    pub min_separation_grid: Vec<Option<i64>>,
    /// The same in metres, exactly.
    pub min_separation: Vec<Option<Exact>>,
}

/// Explores every reachable state of a scene's exported network breadth first, by
/// interpreting its declarations, functions and edges (the data the XML is printed from).
pub fn explore_scene_grid(
    model: &SceneUppaalModel,
    options: &Options,
) -> Result<SceneGridExploration, UppaalError> {
    let net = &model.network;
    let n = model.grid.obstacles.len();
    let mut least: Vec<Option<i64>> = vec![None; n];
    let mut collision_period = None;
    let mut slots: Option<(usize, usize)> = None;
    let reached = search_network(net, options.max_states, |m, vars, periods| {
        let (share, sep) = *slots.get_or_insert_with(|| (m.offset("share"), m.offset("sep")));
        if collision_period.is_none() && m.eval(&net.violation, &Frame::new(), vars)? != 0 {
            collision_period = Some(periods);
        }
        for (i, low) in least.iter_mut().enumerate() {
            if vars[share + i] != 0 {
                let s = vars[sep + i];
                *low = Some(low.map_or(s, |x| x.min(s)));
            }
        }
        Ok(())
    })?;
    let verdict = if collision_period.is_some() {
        ExploreVerdict::Collision
    } else if reached.complete {
        ExploreVerdict::Safe
    } else {
        ExploreVerdict::Inconclusive
    };
    let d = Exact::from(model.grid.scale.clone());
    Ok(SceneGridExploration {
        verdict,
        complete: reached.complete,
        states: reached.states,
        collision_period,
        min_separation: least
            .iter()
            .map(|g| g.map(|g| Exact::from(g) / d.clone()))
            .collect(),
        min_separation_grid: least,
    })
}
