//! Occlusion's exact shortcuts: far cells and quiet cells of an obstacle shown only where
//! no guard reads it are dominated, a hidden obstacle every error would show beyond ρ is as
//! if unread, and a leaf settles the obstacles still hidden.

use crate::core::rational::Rational;
use crate::core::scene::SceneParams;
use crate::proof::scene_search::cells::Cell;
use crate::proof::scene_search::interval::Interval;
use crate::proof::scene_search::sense::{Sense, Sight};

use super::{Child, Node, Profile, Reachable};

/// Whether `cell` shows the obstacle beyond ρ, where no guard reads it (as if hidden), and
/// every truth it allows is showable (ρ − σ_g ≥ d_det; never without occlusion).
///
/// An obstacle first shown in such a cell at read m and read only in such cells since
/// (`far_only`) needs nothing from the run that the lineage hiding it at m and showing it
/// first at the next read does not also allow: hidden at m asks a true gap ≥ d_det, which
/// the far cell implies, and showing it first later asks a true gap ≥ d_det at an
/// observation where the far cell is read again. The commands are the same, so a
/// `far_only` obstacle's far cell at its next read is dominated and left out: exact for
/// s* (every behaviour left out is in a run kept, with the same robot motion), and it keeps
/// a hidden obstacle from starting a new lineage of runs at every read.
pub(super) fn far_cell(p: &SceneParams<Rational>, sense: &Sense, cell: &Cell) -> bool {
    let Some(d) = &sense.d_det else {
        return false;
    };
    let beyond_rho = cell.gap.hi.is_none()
        && cell
            .gap
            .lo
            .as_ref()
            .is_some_and(|lo| lo.at >= p.robot.rho && !(lo.at == p.robot.rho && lo.closed));
    beyond_rho && *d <= p.robot.rho.clone() - sense.sigma_g.clone()
}

/// Quiet cells (`cells::quiet`: the guards read them as nothing) generalise far cells,
/// with a split. Let an obstacle be first shown at read m′ and read only in quiet cells
/// since (`far_only`), and let a behaviour B of that lineage read it at read m + 1 in a
/// quiet cell Q′ with a true gap ≥ d_det there. Then the behaviour B′ with the same motion
/// that hides it through read m and first shows it at m + 1 in Q′ is a behaviour of the
/// sibling lineage hidden at m′: its first sighting has a true gap ≥ d_det, every hidden
/// read before has one too (gaps never grow), and every command is B's (B's reads were
/// quiet, B′'s unseen). From m + 1 on the two are the same. So the lineage keeps of Q′
/// only the truths below d_det (for a far cell, whose truths are all showable, nothing:
/// `far_cell`), exactly for s*; a hidden obstacle inside a large ρ then starts new runs
/// only where showing it changes a command.
pub(super) fn undominated(
    mut r: Reachable,
    n: usize,
    seen_at: &Rational,
    sense: &Sense,
) -> Option<Reachable> {
    r.chain = r
        .chain
        .constrain(n, &sense.undetectable(seen_at), &Interval::all())?;
    Some(r)
}

/// Whether obstacle i is still hidden at read n while every error would show it beyond ρ
/// (a true gap > ρ + σ_g whatever it did): showing it then could not change any command,
/// and it is showable (ρ + σ_g ≥ d_det), so the read is as if unread and its sight stays
/// undecided (see [`super::super::sense`]). Exact, and it keeps far hidden obstacles from
/// splitting the run at every read of a near one.
pub(super) fn hidden_and_far(
    p: &SceneParams<Rational>,
    sense: &Sense,
    node: &Node,
    i: usize,
    n: usize,
    seen_at: &Rational,
) -> bool {
    let Sight::Hidden { .. } = node.sights[i] else {
        return false;
    };
    let chain = &node.chains[i];
    let far = p.robot.rho.clone() + sense.sigma_g.clone() + seen_at.clone();
    let showable = sense
        .d_det
        .as_ref()
        .is_some_and(|d| *d <= p.robot.rho.clone() + sense.sigma_g.clone());
    showable && n >= chain.last_step() && chain.reach_at(n).lo.is_some_and(|lo| lo.at > far)
}

/// At a leaf reached at step k: every obstacle still undecided was first shown at its
/// first undecided observation or is hidden through k, and either needs a true gap ≥ d_det
/// at that observation (see [`super::super::sense`]). False when some obstacle cannot.
pub(super) fn settle_hidden(
    p: &SceneParams<Rational>,
    sense: &Sense,
    profile: &mut Profile,
    k: usize,
    child: &mut Child,
) -> bool {
    let now = k.saturating_sub(p.robot.L);
    for i in 0..child.chains.len() {
        let Sight::Hidden { since } = child.sights[i] else {
            continue;
        };
        if since > now {
            continue;
        }
        let at = profile.at(p, since).position.clone();
        match child.chains[i].constrain(since, &sense.detectable(&at), &Interval::all()) {
            Some(chain) => child.chains[i] = chain,
            None => return false,
        }
    }
    true
}
