//! What observation noise and occlusion (docs/semantics.md §12) do to the run search.
//!
//! **Noise.** The robot is shown an obstacle's gap within ±σ_g of the true one and its
//! speed within ±σ_w, each error the environment's choice per observation. The controller
//! still tells apart only the cells of what it is shown, so the search branches on the
//! shown cells as before; a shown cell C constrains the truth only to C widened by σ
//! (some error lands in C iff the truth is within σ of it). Errors are independent across
//! observations, so the widened constraints are exactly what a run asks of the obstacle.
//!
//! **Occlusion.** An obstacle may be hidden (shown nothing) for a prefix of its
//! observations; the first that shows it shows a true gap ≥ d_det, and while the robot
//! still drives a hidden obstacle must stay showable: its observation at the step shows a
//! true gap ≥ d_det (else it would never be detected in time, which the premise rules out;
//! the explorer's `Lost` states). Hidden or shown matters only where an observation is
//! read, so the search decides it lazily ([`Sight`]): at a read, *hidden* asks a true gap
//! ≥ d_det now, and *shown* asks it at the first unread observation since the last read
//! (the obstacle could have been first shown at any of them, and true gaps never grow, so
//! the earliest is the weakest); at a leaf a still-undecided obstacle asks the same.

use crate::core::num::Scalar;
use crate::core::rational::Rational;
use crate::core::scene::SceneParams;

use super::interval::{End, Interval};

/// Whether an obstacle has been shown yet, as far as the run has read it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sight {
    /// Shown from the observation of the gap at step `from`·dt on (0 without occlusion).
    Shown {
        /// The observation step of its first sighting.
        from: usize,
        /// Every read since then showed it beyond ρ, where no guard reads it (see
        /// `tree::occlusion::far_cell`: its next far read is dominated).
        far_only: bool,
    },
    /// Hidden at every read observation before step `since` (observation steps: the gap at
    /// `since`·dt), and not read since.
    Hidden {
        /// The first observation step not yet decided.
        since: usize,
    },
}

/// The sensing premises in the search's numbers.
#[derive(Clone, Debug)]
pub struct Sense {
    /// σ_g.
    pub sigma_g: Rational,
    /// σ_w.
    pub sigma_w: Rational,
    /// d_det (None: every obstacle is shown from the start).
    pub d_det: Option<Rational>,
}

impl Sense {
    /// The scene's sensing premises.
    pub fn of(p: &SceneParams<Rational>) -> Sense {
        Sense {
            sigma_g: p.robot.sigma_g.clone(),
            sigma_w: p.robot.sigma_w.clone(),
            d_det: p.robot.d_det.clone(),
        }
    }

    /// Whether any observation can be off.
    pub fn noisy(&self) -> bool {
        self.sigma_g > Rational::zero() || self.sigma_w > Rational::zero()
    }

    /// How every obstacle starts: hidden with occlusion, else shown.
    pub fn initial(&self) -> Sight {
        match self.d_det {
            Some(_) => Sight::Hidden { since: 0 },
            None => Sight::Shown {
                from: 0,
                far_only: false,
            },
        }
    }

    /// True positions X(n) that some error shows in the gap cell `gap` to a robot at
    /// `robot_at`.
    pub fn positions(&self, gap: &Interval, robot_at: &Rational) -> Interval {
        widened(gap, &self.sigma_g).shifted(robot_at)
    }

    /// True speeds that some error shows in the speed cell `speed`.
    pub fn speeds(&self, speed: &Interval) -> Interval {
        widened(speed, &self.sigma_w)
    }

    /// True positions at which a robot at `robot_at` may first be shown the obstacle:
    /// x ≥ robot_at + d_det (everything without occlusion).
    pub fn detectable(&self, robot_at: &Rational) -> Interval {
        match &self.d_det {
            Some(d) => Interval {
                lo: Some(End::closed(robot_at.clone() + d.clone())),
                hi: None,
            },
            None => Interval::all(),
        }
    }
}

impl Sense {
    /// True positions at which a robot at `robot_at` could not be shown the obstacle for
    /// the first time: x < robot_at + d_det (nothing without occlusion).
    pub fn undetectable(&self, robot_at: &Rational) -> Interval {
        match &self.d_det {
            Some(d) => Interval {
                lo: None,
                hi: Some(End::open(robot_at.clone() + d.clone())),
            },
            None => Interval {
                lo: Some(End::open(Rational::zero())),
                hi: Some(End::open(Rational::zero())),
            },
        }
    }
}

/// `x` widened by σ on both sides (its ends keep their kind).
fn widened(x: &Interval, sigma: &Rational) -> Interval {
    if *sigma == Rational::zero() {
        return x.clone();
    }
    x.plus(&Interval::closed(-sigma.clone(), sigma.clone()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn r(n: i64, d: i64) -> Rational {
        Rational::int(n) / Rational::int(d)
    }

    /// A truth within σ of a cell can be shown in it, one farther cannot.
    #[test]
    fn widening_keeps_exactly_the_truths_an_error_can_show_in_the_cell() {
        let sense = Sense {
            sigma_g: r(1, 10),
            sigma_w: Rational::zero(),
            d_det: None,
        };
        let cell = Interval {
            lo: Some(End::open(r(1, 1))),
            hi: Some(End::closed(r(2, 1))),
        };
        // Shown in (1, 2] from a robot at 5: true positions (5.9, 7.1].
        let truths = sense.positions(&cell, &r(5, 1));
        assert!(!truths.contains(&r(59, 10)), "5.9 is shown at 1.0 at best");
        assert!(truths.contains(&r(591, 100)), "5.91 can be shown at 1.01");
        assert!(truths.contains(&r(71, 10)), "7.1 can be shown at 2.0");
        assert!(
            !truths.contains(&r(711, 100)),
            "7.11 is shown at 2.01 at best"
        );
    }
}
