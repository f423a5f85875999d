//! What the explorer keeps of one observation still to come: what the environment can make
//! the guard do with it. With sensing noise each observation's error is the environment's
//! choice, and the only thing an error changes is whether that observation's guard fires
//! (docs/semantics.md §12), so an observation is *quiet-able*, *fire-able*, or both; the
//! module docs of `explore` prove that these two choices are exact. With occlusion, a
//! hidden obstacle's observations are also tagged with whether they may be its first
//! sighting (a true gap ≥ d_det).

use crate::core::model::Params;
use crate::core::num::Exact;
use crate::core::semantics::danger_distance;

/// What the guard can do on one observation, for every robot speed it may be acted on at
/// (see the module docs, 3).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(super) enum Seen {
    /// It can only stay quiet (also: no observation at all).
    Quiet,
    /// It can only fire (if the robot still accelerates or drives then).
    Fires,
    /// The error decides: it can stay quiet and it can fire.
    Either,
    /// It depends on the robot's speed when it is acted on: the true gap and what the
    /// speed measured with it can be made to look like are kept exactly.
    Near {
        /// The true gap observed.
        gap: Exact,
        /// The measured speed's possibilities.
        speed: SpeedSeen,
    },
}

impl Seen {
    /// The verdict that allows exactly `(fire, quiet)` (not both false: an observation
    /// always makes the guard do something).
    fn fixed(fire: bool, quiet: bool) -> Seen {
        match (fire, quiet) {
            (true, true) => Seen::Either,
            (true, false) => Seen::Fires,
            _ => Seen::Quiet,
        }
    }
}

/// What the obstacle speed measured for one period can be made to look like, against V_a
/// (with the wrong-assumption guard off it never counts as fast).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) struct SpeedSeen {
    /// Some error shows it above V_a.
    pub(super) fast: bool,
    /// Some error shows it at or below V_a.
    pub(super) slow: bool,
}

impl SpeedSeen {
    /// The speed seen before any period has ended: exactly 0, never fast (V_a ≥ 0).
    pub(super) const NONE_YET: SpeedSeen = SpeedSeen {
        fast: false,
        slow: true,
    };

    /// A period at speed `w`, measured within ±σ_w.
    pub(super) fn of(p: &Params<Exact>, w: &Exact) -> SpeedSeen {
        if !p.wrong_assumption_brake {
            return Self::NONE_YET;
        }
        SpeedSeen {
            fast: w.clone() + p.sigma_w.clone() > p.V_a,
            slow: w.clone() - p.sigma_w.clone() <= p.V_a,
        }
    }
}

/// Occlusion: may an observation be the hidden obstacle's first sighting?
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Sight {
    /// No observation at that step (before L).
    Nothing,
    /// Its true gap is ≥ d_det: the obstacle may be first seen there.
    Far,
    /// Its true gap is < d_det: too late for a first sighting (gaps never grow, so every
    /// later one is too).
    Close,
}

impl Sight {
    /// The tag of an observation of true gap `gap`.
    pub(super) fn of(p: &Params<Exact>, gap: &Exact) -> Sight {
        match &p.d_det {
            Some(d) if gap < d => Sight::Close,
            _ => Sight::Far,
        }
    }
}

/// One observation still to come: its verdict, and (while the obstacle is hidden) its tag.
#[derive(Clone, Debug)]
pub(super) struct Pending {
    pub(super) seen: Seen,
    pub(super) sight: Sight,
}

/// `(fire, quiet)`: whether some error makes the guard fire, and whether some error keeps
/// it quiet, on an observation of true gap `gap` and a measured speed `speed`, for a robot
/// whose danger distance is `danger` (None: infinite, the `area` rule). The observed gap
/// ranges over [g − σ_g, g + σ_g]; the guard fires on o in (0, ρ] with o ≤ d_coll or a
/// speed seen above V_a (docs/semantics.md §5, §12).
pub(super) fn choices(
    p: &Params<Exact>,
    gap: &Exact,
    speed: SpeedSeen,
    danger: Option<&Exact>,
) -> (bool, bool) {
    let sg = &p.sigma_g;
    let (low, high) = (gap.clone() - sg.clone(), gap.clone() + sg.clone());
    let theta = match danger {
        Some(d) if *d < p.rho => d.clone(),
        _ => p.rho.clone(),
    };
    // Some observed gap in (0, limit]?
    let hits = |limit: &Exact| high > Exact::ZERO && low <= *limit && *limit > Exact::ZERO;
    let fire = if speed.fast {
        hits(&p.rho)
    } else {
        hits(&theta)
    };
    // Seen as passed (≤ 0), or beyond what fires: θ if the speed can look slow, else ρ.
    let beyond = if speed.slow { &theta } else { &p.rho };
    let quiet = low <= Exact::ZERO || high > *beyond;
    (fire, quiet)
}

/// The verdict of an observation of true gap `gap` with measured speed `speed`, by a robot
/// whose speed is `v` now and will not fall, nor pass v_max (danger distance `top`), before
/// it is acted on: fixed when it is the same at v and at v_max (fire-ability only grows
/// with the speed and quiet-ability only shrinks, so then it is the same in between).
pub(super) fn classify(
    p: &Params<Exact>,
    gap: &Exact,
    speed: SpeedSeen,
    v: &Exact,
    top: Option<&Exact>,
) -> Seen {
    let now = choices(p, gap, speed, danger_distance(p, v).as_ref());
    let last = choices(p, gap, speed, top);
    if now == last {
        Seen::fixed(now.0, now.1)
    } else {
        Seen::Near {
            gap: gap.clone(),
            speed,
        }
    }
}

/// `(fire, quiet)` of a pending verdict for a robot at speed `v`.
pub(super) fn resolve(p: &Params<Exact>, seen: &Seen, v: &Exact) -> (bool, bool) {
    match seen {
        Seen::Quiet => (false, true),
        Seen::Fires => (true, false),
        Seen::Either => (true, true),
        Seen::Near { gap, speed } => choices(p, gap, *speed, danger_distance(p, v).as_ref()),
    }
}

/// Whether the current true gap can be seen inside the reaction area (−σ_g < g ≤ ρ + σ_g):
/// only then can the speed measured with it matter.
pub(super) fn may_be_in_area(p: &Params<Exact>, gap: &Exact) -> bool {
    gap.clone() + p.sigma_g.clone() > Exact::ZERO && gap.clone() - p.sigma_g.clone() <= p.rho
}
