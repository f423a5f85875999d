//! The interpreter: the exported network's transitions under UPPAAL's semantics for this
//! network (committed locations first, binary synchronisations with the sender's update
//! before the receiver's; the clock only spaces `decide` and `advance` one time unit apart,
//! so it is left out), and the breadth-first search over them ([`crate::crosscheck::bfs`],
//! the explorer's search) that answers what UPPAAL would answer for the safety query.

use super::machine::{Frame, Machine};
use super::syntax::{Dir, Edge, Kind, Network, Template};
use super::{UppaalError, UppaalModel};
use crate::core::num::Exact;
use crate::crosscheck::bfs::{self, Successors};
use crate::crosscheck::explore::{ExploreVerdict, Options};

/// A state of the network: one location per process, then every variable.
pub(super) type NetState = (Vec<usize>, Vec<i64>);

/// A queued state: the network state and the periods on the path that first reached it.
type Queued = (NetState, usize);

/// A process: an instance of a template, with its parameter's value bound (if it has one).
struct Process<'n> {
    template: &'n Template,
    frame: Frame,
}

/// The processes of a network: each template once, or once per value of its parameter, in
/// the order of the `system` line.
fn processes(net: &Network) -> Vec<Process<'_>> {
    let mut out = Vec::new();
    for t in &net.templates {
        match t.param {
            None => out.push(Process {
                template: t,
                frame: Frame::new(),
            }),
            Some(p) => out.extend((0..p.count).map(|id| Process {
                template: t,
                frame: vec![(p.name, id as i64)],
            })),
        }
    }
    out
}

/// The frames of an edge of a process: its parameter, and each value of its `select`.
fn choices(process: &Process<'_>, e: &Edge) -> Vec<Frame> {
    match e.select {
        Some((name, _, hi)) => (0..=hi)
            .map(|v| {
                let mut f = process.frame.clone();
                f.push((name, v));
                f
            })
            .collect(),
        None => vec![process.frame.clone()],
    }
}

/// The successors of a network state (UPPAAL's action transitions; see the module docs on
/// clocks), each with whether it ends a period: a transition that resets the clock (the
/// clock counts the period).
fn successors(
    procs: &[Process<'_>],
    m: &Machine<'_>,
    state: &NetState,
) -> Result<Vec<(NetState, bool)>, UppaalError> {
    let committed: Vec<bool> = procs
        .iter()
        .zip(&state.0)
        .map(|(p, &l)| p.template.locations[l].kind == Kind::Committed)
        .collect();
    let mut out = Vec::new();
    internal_steps(procs, m, state, &committed, &mut out)?;
    synchronisations(procs, m, state, &committed, &mut out)?;
    Ok(out)
}

/// The edges without a synchronisation that can fire (only committed processes' edges while
/// some process is in a committed location).
fn internal_steps(
    procs: &[Process<'_>],
    m: &Machine<'_>,
    (locs, vars): &NetState,
    committed: &[bool],
    out: &mut Vec<(NetState, bool)>,
) -> Result<(), UppaalError> {
    let any_committed = committed.iter().any(|c| *c);
    for (pi, p) in procs.iter().enumerate() {
        if any_committed && !committed[pi] {
            continue;
        }
        for e in p
            .template
            .edges
            .iter()
            .filter(|e| e.source == locs[pi] && e.sync.is_none())
        {
            for mut frame in choices(p, e) {
                let mut vars = vars.clone();
                if m.truth(&e.guard, &frame, &mut vars)? {
                    m.update(e, &mut frame, &mut vars)?;
                    let mut locs = locs.clone();
                    locs[pi] = e.target;
                    out.push(((locs, vars), e.clock_reset.is_some()));
                }
            }
        }
    }
    Ok(())
}

/// The binary synchronisations that can fire: a sender's edge (for every value of its
/// `select`) with each receiver's edge on the same channel (for every value of its); the sender's update runs first,
/// then the receiver's.
fn synchronisations(
    procs: &[Process<'_>],
    m: &Machine<'_>,
    state: &NetState,
    committed: &[bool],
    out: &mut Vec<(NetState, bool)>,
) -> Result<(), UppaalError> {
    let any_committed = committed.iter().any(|c| *c);
    let locs = &state.0;
    for (si, sp) in procs.iter().enumerate() {
        for se in sp.template.edges.iter().filter(|e| e.source == locs[si]) {
            let Some((chan, Dir::Send)) = se.sync else {
                continue;
            };
            for choice in choices(sp, se) {
                for (ri, rp) in procs.iter().enumerate() {
                    if ri == si || (any_committed && !committed[si] && !committed[ri]) {
                        continue;
                    }
                    for re in
                        rp.template.edges.iter().filter(|e| {
                            e.source == locs[ri] && e.sync == Some((chan, Dir::Receive))
                        })
                    {
                        // The receiver's edge may select too (the observation error).
                        for rchoice in choices(rp, re) {
                            let sender = (si, se, choice.clone());
                            if let Some(next) = handshake(m, state, sender, (ri, re, &rchoice))? {
                                let ends = se.clock_reset.is_some() || re.clock_reset.is_some();
                                out.push((next, ends));
                            }
                        }
                    }
                }
            }
        }
    }
    Ok(())
}

/// The state after the sender `(process, edge, frame)` and the receiver `(process, edge,
/// frame)` synchronise, if both guards hold.
fn handshake(
    m: &Machine<'_>,
    (locs, vars): &NetState,
    (si, se, mut sframe): (usize, &Edge, Frame),
    (ri, re, rframe): (usize, &Edge, &Frame),
) -> Result<Option<NetState>, UppaalError> {
    let mut vars = vars.clone();
    let mut rframe = rframe.clone();
    if !m.truth(&se.guard, &sframe, &mut vars)? || !m.truth(&re.guard, &rframe, &mut vars)? {
        return Ok(None);
    }
    m.update(se, &mut sframe, &mut vars)?;
    m.update(re, &mut rframe, &mut vars)?;
    let mut locs = locs.clone();
    locs[si] = se.target;
    locs[ri] = re.target;
    Ok(Some((locs, vars)))
}

/// What a search over a network reached.
pub(super) struct Searched {
    /// Every reachable state was visited.
    pub complete: bool,
    /// Distinct network states.
    pub states: usize,
}

/// Explores every reachable state of `net` breadth first (up to `max_states`), calling
/// `watch` on each state's variables, with the periods on the path that first reached it,
/// in the order the states are expanded.
pub(super) fn search_network(
    net: &Network,
    max_states: usize,
    mut watch: impl FnMut(&Machine<'_>, &mut [i64], usize) -> Result<(), UppaalError>,
) -> Result<Searched, UppaalError> {
    if max_states == 0 {
        return Err(UppaalError::Options(
            "--max-states must be at least 1".into(),
        ));
    }
    let m = Machine::new(net);
    let procs = processes(net);
    let init: NetState = (
        procs.iter().map(|p| p.template.init).collect(),
        m.initial_vars().to_vec(),
    );
    let reached = bfs::search(
        [(init.clone(), (init, 0))],
        max_states,
        |_, (state, periods): &Queued, next: &mut Successors<'_, Queued, NetState, ()>| {
            let mut vars = state.1.clone();
            watch(&m, &mut vars, *periods)?;
            for (succ, advanced) in successors(&procs, &m, state)? {
                let periods = periods + usize::from(advanced);
                if next.offer((), succ, |s| (s.clone(), periods)).is_break() {
                    break;
                }
            }
            Ok::<(), UppaalError>(())
        },
    )?;
    Ok(Searched {
        complete: reached.complete,
        states: reached.states,
    })
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

/// Explores every reachable state of an exported network breadth first, by interpreting its
/// declarations, functions and edges (the data the XML is printed from).
pub fn explore_grid(
    model: &UppaalModel,
    options: &Options,
) -> Result<GridExploration, UppaalError> {
    let net = &model.network;
    let m = Machine::new(net);
    let (rested, rest_gap) = (m.offset("rested"), m.offset("restGap"));
    let mut min_rest: Option<i64> = None;
    let mut collision_period = None;
    let reached = search_network(net, options.max_states, |m, vars, periods| {
        if m.eval(&net.violation, &Frame::new(), vars)? != 0 && collision_period.is_none() {
            collision_period = Some(periods);
        }
        if vars[rested] != 0 {
            let g = vars[rest_gap];
            min_rest = Some(min_rest.map_or(g, |x| x.min(g)));
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
    Ok(GridExploration {
        verdict,
        complete: reached.complete,
        states: reached.states,
        min_separation_grid: min_rest,
        min_separation: min_rest.map(|g| Exact::from(g) / d),
        collision_period,
    })
}
