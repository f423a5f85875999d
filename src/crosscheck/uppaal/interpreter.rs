//! The interpreter: the exported network's transitions under UPPAAL's semantics for this
//! network (committed locations first, binary synchronisations with the sender's update
//! before the receiver's; the clock only spaces `decide` and `advance` one time unit apart,
//! so it is left out), and the breadth-first search over them ([`crate::crosscheck::bfs`],
//! the explorer's search) that answers what UPPAAL would answer for the safety query.

use super::machine::{Frame, Machine};
use super::syntax::{Dir, Edge, Kind, Network};
use super::{UppaalError, UppaalModel};
use crate::core::num::Exact;
use crate::crosscheck::bfs::{self, Successors};
use crate::crosscheck::explore::{ExploreVerdict, Options};

/// A state of the network: one location per template, then every variable.
type NetState = (Vec<usize>, Vec<i64>);

/// A queued state: the network state and the periods (`advance` synchronisations) on the
/// path that first reached it.
type Queued = (NetState, usize);

/// The successors of a network state (UPPAAL's action transitions; see the module docs on
/// clocks), each with whether it ends a period (an `advance` synchronisation).
fn successors(
    net: &Network,
    m: &Machine<'_>,
    state: &NetState,
) -> Result<Vec<(NetState, bool)>, UppaalError> {
    let committed: Vec<bool> = net
        .templates
        .iter()
        .zip(&state.0)
        .map(|(t, &l)| t.locations[l].kind == Kind::Committed)
        .collect();
    let mut out = Vec::new();
    internal_steps(net, m, state, &committed, &mut out)?;
    synchronisations(net, m, state, &committed, &mut out)?;
    Ok(out)
}

/// The edges without a synchronisation that can fire (only committed processes' edges while
/// some process is in a committed location).
fn internal_steps(
    net: &Network,
    m: &Machine<'_>,
    (locs, vars): &NetState,
    committed: &[bool],
    out: &mut Vec<(NetState, bool)>,
) -> Result<(), UppaalError> {
    let any_committed = committed.iter().any(|c| *c);
    for (ti, t) in net.templates.iter().enumerate() {
        if any_committed && !committed[ti] {
            continue;
        }
        for e in t
            .edges
            .iter()
            .filter(|e| e.source == locs[ti] && e.sync.is_none())
        {
            let mut vars = vars.clone();
            let mut frame = Frame::new();
            if m.truth(&e.guard, &frame, &mut vars)? {
                m.update(e, &mut frame, &mut vars)?;
                let mut locs = locs.clone();
                locs[ti] = e.target;
                out.push(((locs, vars), false));
            }
        }
    }
    Ok(())
}

/// The binary synchronisations that can fire: a sender's edge (for every value of its
/// `select`) with each receiver's edge on the same channel; the sender's update runs first,
/// then the receiver's.
fn synchronisations(
    net: &Network,
    m: &Machine<'_>,
    state: &NetState,
    committed: &[bool],
    out: &mut Vec<(NetState, bool)>,
) -> Result<(), UppaalError> {
    let any_committed = committed.iter().any(|c| *c);
    let locs = &state.0;
    for (si, st) in net.templates.iter().enumerate() {
        for se in st.edges.iter().filter(|e| e.source == locs[si]) {
            let Some((chan, Dir::Send)) = se.sync else {
                continue;
            };
            let choices = match se.select {
                Some((name, _, hi)) => (0..=hi).map(|v| vec![(name, v)]).collect(),
                None => vec![Frame::new()],
            };
            for choice in choices {
                for (ri, rt) in net.templates.iter().enumerate() {
                    if ri == si || (any_committed && !committed[si] && !committed[ri]) {
                        continue;
                    }
                    for re in rt
                        .edges
                        .iter()
                        .filter(|e| e.source == locs[ri] && e.sync == Some((chan, Dir::Receive)))
                    {
                        let sender = (si, se, choice.clone());
                        if let Some(next) = handshake(m, state, sender, (ri, re))? {
                            out.push((next, chan == "advance"));
                        }
                    }
                }
            }
        }
    }
    Ok(())
}

/// The state after the sender `(process, edge, select choice)` and the receiver `(process,
/// edge)` synchronise, if both guards hold.
fn handshake(
    m: &Machine<'_>,
    (locs, vars): &NetState,
    (si, se, mut sframe): (usize, &Edge, Frame),
    (ri, re): (usize, &Edge),
) -> Result<Option<NetState>, UppaalError> {
    let mut vars = vars.clone();
    if !m.truth(&se.guard, &sframe, &mut vars)? || !m.truth(&re.guard, &Frame::new(), &mut vars)? {
        return Ok(None);
    }
    m.update(se, &mut sframe, &mut vars)?;
    m.update(re, &mut Frame::new(), &mut vars)?;
    let mut locs = locs.clone();
    locs[si] = se.target;
    locs[ri] = re.target;
    Ok(Some((locs, vars)))
}

/// What the interpreter found in the exported network.
#[derive(Clone, Debug, PartialEq)]
pub struct GridExploration {
    /// `collision` iff a reachable state violates the query; `safe` iff none does and the
    /// search completed; else `inconclusive`.
    pub verdict: ExploreVerdict,
    /// Every reachable state was visited.
    pub complete: bool,
    /// Distinct network states (locations and all variables).
    pub states: usize,
    /// Least `restGap` over reachable states where the robot rested (grid units).
    pub min_separation_grid: Option<i64>,
    /// The same in metres, exactly.
    pub min_separation: Option<Exact>,
    /// Periods (`advance` synchronisations) on a shortest path to a violating state.
    pub collision_period: Option<usize>,
}

/// What the search watches on the network's states, in the order they are expanded.
struct Watch {
    /// Where `rested` and `restGap` are stored in the variable vector.
    rested: usize,
    rest_gap: usize,
    min_rest: Option<i64>,
    collision_period: Option<usize>,
}

/// Explores every reachable state of an exported network breadth first, by interpreting its
/// declarations, functions and edges (the data the XML is printed from).
pub fn explore_grid(
    model: &UppaalModel,
    options: &Options,
) -> Result<GridExploration, UppaalError> {
    if options.max_states == 0 {
        return Err(UppaalError::Options(
            "--max-states must be at least 1".into(),
        ));
    }
    let net = &model.network;
    let m = Machine::new(net);
    let mut watch = Watch {
        rested: m.offset("rested"),
        rest_gap: m.offset("restGap"),
        min_rest: None,
        collision_period: None,
    };
    let init: NetState = (
        net.templates.iter().map(|t| t.init).collect(),
        m.initial_vars().to_vec(),
    );
    let reached = bfs::search(
        [(init.clone(), (init, 0))],
        options.max_states,
        |_, q, next| expand(net, &m, &mut watch, q, next),
    )?;
    let verdict = if watch.collision_period.is_some() {
        ExploreVerdict::Collision
    } else if reached.complete {
        ExploreVerdict::Safe
    } else {
        ExploreVerdict::Inconclusive
    };
    let d = Exact::from(model.grid.scale.clone());
    Ok(GridExploration {
        verdict,
        complete: reached.complete,
        states: reached.states,
        min_separation_grid: watch.min_rest,
        min_separation: watch.min_rest.map(|g| Exact::from(g) / d),
        collision_period: watch.collision_period,
    })
}

/// Watches the state `(state, periods)` (a violation, the gap at rest), then offers its
/// successors to the search in order.
fn expand(
    net: &Network,
    m: &Machine<'_>,
    watch: &mut Watch,
    (state, periods): &Queued,
    next: &mut Successors<'_, Queued, NetState, ()>,
) -> Result<(), UppaalError> {
    let mut vars = state.1.clone();
    if m.eval(&net.violation, &Frame::new(), &mut vars)? != 0 && watch.collision_period.is_none() {
        watch.collision_period = Some(*periods);
    }
    if vars[watch.rested] != 0 {
        let rest_gap = vars[watch.rest_gap];
        watch.min_rest = Some(watch.min_rest.map_or(rest_gap, |x| x.min(rest_gap)));
    }
    for (succ, advanced) in successors(net, m, state)? {
        let periods = periods + usize::from(advanced);
        if next.offer((), succ, |s| (s.clone(), periods)).is_break() {
            break;
        }
    }
    Ok(())
}
