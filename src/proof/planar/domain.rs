//! What one obstacle's lower bound must cover (docs/reductions.md Lemmas P2, P5, P6): every
//! moving instant under every brake step, as finitely many *pieces*, each a time interval
//! with the anchor observation that bounds it; and a piece's sub-interval and arc as a
//! [`Leaf`].
//!
//! - `Pre(m)`: the instants of step m before any brake, shared by every brake step T > m
//!   and by "never": the robot is on its drive profile, and step k = m is an anchor for
//!   all of them (k < T) when m ≥ L.
//! - `Post(T)`: the instants from T·dt to the rest instant τ_T when the robot brakes at T,
//!   anchored by step T − 1 (when T − 1 ≥ L).
//!
//! Beyond a *horizon* step H no piece is needed: when the path ends, no brake step lies
//! beyond the destination guard's; otherwise Lemma P6(3)'s outrun rule finds H from the
//! last segment (the robot outruns everything the obstacle can reach, or leaves its
//! bounded region), decided in rationals.

use crate::core::num::Exact;
use crate::core::planar::{DangerZone, PlanarObstacle, PlanarParams, Start};
use crate::core::plane::point::Point;
use crate::core::semantics::danger_distance;

use super::cover::{Arc, HalfPlane, line_sides, outside_polygon, outside_view};
use super::leaf::{Leaf, Travel};
use super::trajectory::{BrakeTrajectory, DriveProfile};

/// Which instants a piece covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PieceKind {
    /// Step m on the drive profile, before any brake.
    Pre(usize),
    /// From the brake step T to the rest instant.
    Post(usize),
}

/// The anchor of a piece: the sure-fire set about the robot's centre at the observed
/// instant that the obstacle's centre was outside of (Lemma P1), as a disc and half-planes.
#[derive(Clone, Debug, PartialEq)]
pub struct Anchor {
    /// The anchor step k.
    pub step: usize,
    /// The observed instant's index j = k − L.
    pub instant: usize,
    /// The robot's centre at j·dt.
    pub centre: Point,
    /// The sure-fire disc's radius: the least of θ_k + r − σ_p (disc zone), the range and
    /// d_det + r, each less D; > 0. None: no disc bounds the set (a polygon zone, no range,
    /// no occlusion).
    pub radius: Option<Exact>,
    /// Half-planes that, with the disc's outside, cover the set's outside: beyond the
    /// view's rays, beyond the zone polygon's edges.
    pub outside: Vec<HalfPlane>,
}

/// One piece: a time interval and its anchor (None: only the reachable set bounds it).
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    /// Which instants.
    pub kind: PieceKind,
    /// The brake step of the robot's motion on this piece (None: the drive profile).
    pub brake: Option<usize>,
    /// The first instant.
    pub from: Exact,
    /// The last instant (closed: the rest instant is included, which only lowers bounds).
    pub to: Exact,
    /// The anchor, if any.
    pub anchor: Option<Anchor>,
}

/// Which convex set of a piece's cover a leaf is in (Lemma P3).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum CoverPiece {
    /// The piece has no anchor, or its sure-fire disc misses every feasible centre.
    Whole,
    /// One side of the disc along the line a fixed-direction obstacle from a point moves
    /// on (P3(3), exact): 0 ahead along the direction, 1 behind.
    Side(usize),
    /// An arc of directions from the disc's centre (P3(2), refinable).
    Arc(Arc),
    /// Beyond the anchor's outside half-plane of this index (the view's, the zone's).
    Outside(usize),
}

/// Why an obstacle's pieces cannot be listed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum DomainError {
    /// A setting the planar bound does not cover yet (the setting's name).
    Unsupported(&'static str),
    /// The path has no end and the obstacle can keep up with the robot in an unbounded
    /// region: finitely many pieces do not cover it yet (Lemma P6(2)'s tail).
    Unbounded,
}

/// One obstacle's bound problem: its pieces, and how to make a leaf of each.
pub struct ObstacleDomain<'a> {
    params: &'a PlanarParams,
    obstacle: &'a PlanarObstacle,
    profile: DriveProfile,
    /// r_R + r_i + the path's drift.
    pub radii: Exact,
    /// The pieces, in time order of their first instant.
    pub pieces: Vec<Piece>,
}

impl<'a> ObstacleDomain<'a> {
    /// The pieces of obstacle `index` that can bring its separation to `goal` or below.
    /// `goal` (usually the clearance, or the best witness's separation) only sets the
    /// horizon: instants past it are proved above `goal` by the outrun rule.
    pub fn new(
        params: &'a PlanarParams,
        index: usize,
        goal: &Exact,
        step_limit: usize,
    ) -> Result<Self, DomainError> {
        let obstacle = &params.obstacles[index];
        let goal_len = params.path_ends.then(|| params.path.length());
        let mut profile = DriveProfile::new(params.motion.clone(), goal_len);
        let radii = &params.robot_radius + &obstacle.radius + params.path.drift();
        let horizon = horizon(params, obstacle, &mut profile, &radii, goal, step_limit)?;
        let mut domain = ObstacleDomain {
            params,
            obstacle,
            profile,
            radii,
            pieces: Vec::new(),
        };
        domain.list(horizon);
        Ok(domain)
    }

    /// Every piece up to the horizon: Pre(m) for m < H, Post(T) for T ≤ min(H, the
    /// destination step).
    fn list(&mut self, horizon: Horizon) {
        let dt = self.params.motion.dt.clone();
        let l = self.params.motion.L;
        let last_brake = horizon.last_brake;
        for m in 0..horizon.steps {
            let anchor = (m >= l).then(|| self.anchor(m)).flatten();
            if last_brake.is_some_and(|t| m >= t) {
                break; // the destination guard has braked the robot by then
            }
            let from = Exact::from(m) * &dt;
            let to = Exact::from(m + 1) * &dt;
            self.pieces.push(Piece {
                kind: PieceKind::Pre(m),
                brake: None,
                from,
                to,
                anchor,
            });
        }
        let brakes = last_brake.map_or(horizon.steps, |t| t.min(horizon.steps));
        for t in 0..=brakes {
            let trajectory = BrakeTrajectory::new(&mut self.profile, Some(t));
            let from = Exact::from(t) * &dt;
            let rest = trajectory.rest.clone().expect("a braking robot rests");
            if rest <= from {
                continue; // at rest already: no moving instant
            }
            let anchor = (t > l).then(|| self.anchor(t - 1)).flatten();
            self.pieces.push(Piece {
                kind: PieceKind::Post(t),
                brake: Some(t),
                from,
                to: rest,
                anchor,
            });
        }
    }

    /// The sure-fire set of step k (Lemma P1) as the disc and half-planes whose outsides
    /// cover its outside; None when the set is empty (the anchor constrains nothing).
    ///
    /// The analysed path is within D of the file's (§13), so the robot centre used here is
    /// within D of the true one: every radius about it is taken D smaller.
    fn anchor(&mut self, k: usize) -> Option<Anchor> {
        let p = &self.params.motion;
        let l = p.L;
        let j = k - l;
        let v = self.profile.start(k).speed.clone();
        let theta = match danger_distance(p, &v) {
            Some(d) if d < p.rho => d,
            _ => p.rho.clone(),
        };
        let s = &self.params.sensing;
        let drift = self.params.path.drift().clone();
        let rims = &self.params.robot_radius + &self.obstacle.radius;
        let mut caps: Vec<Exact> = Vec::new();
        if matches!(self.params.zone, DangerZone::Disc) {
            caps.push(theta + &rims - &s.position_noise - &drift);
        }
        if let Some(range) = &s.range {
            caps.push(range - &drift);
        }
        if let Some(d) = &s.first_detection {
            caps.push(d + &rims - &drift);
        }
        let radius = caps.into_iter().reduce(|a, b| if b < a { b } else { a });
        if radius.as_ref().is_some_and(|r| *r <= Exact::ZERO) {
            return None;
        }
        let drive = BrakeTrajectory::new(&mut self.profile, None);
        let at = Exact::from(j) * &p.dt;
        let centre = drive.centre_at(&mut self.profile, &self.params.path, &at);
        let position = drive.state_at(&mut self.profile, &at).position;
        let heading = self.params.path.heading_at(&position).clone();
        let mut outside = Vec::new();
        if let DangerZone::Polygon(zone) = &self.params.zone {
            // The seen disc meets Z whatever the noise when the centre is in Z shrunk by
            // σ_p − r_i (if positive) and by D.
            let mut inset = &s.position_noise - &self.obstacle.radius;
            if inset < Exact::ZERO {
                inset = Exact::ZERO;
            }
            inset += &drift;
            outside.extend(outside_polygon(zone, &inset, &centre, &heading));
        }
        if let Some(c) = &s.view_cos_half {
            outside.extend(outside_view(&centre, heading.unit(), c));
        }
        if radius.is_none() && outside.is_empty() {
            return None;
        }
        Some(Anchor {
            step: k,
            instant: j,
            centre,
            radius,
            outside,
        })
    }

    /// The cover sets a piece starts with: its anchor disc's two sides on a fixed
    /// direction's line, or four quarter arcs, and one set per outside half-plane; the
    /// whole plane without an anchor.
    pub fn initial_covers(&self, piece: &Piece) -> Vec<CoverPiece> {
        let Some(anchor) = &piece.anchor else {
            return vec![CoverPiece::Whole];
        };
        let mut covers = Vec::new();
        if let Some(radius) = &anchor.radius {
            match (&self.obstacle.direction, &self.obstacle.start) {
                (Some(d), Start::At(p)) => match line_sides(p, d.unit(), &anchor.centre, radius) {
                    Some(_) => covers.extend([CoverPiece::Side(0), CoverPiece::Side(1)]),
                    // The line misses the disc: every feasible centre is outside it.
                    None => return vec![CoverPiece::Whole],
                },
                _ => covers.extend(Arc::quarters().into_iter().map(CoverPiece::Arc)),
            }
        }
        covers.extend((0..anchor.outside.len()).map(CoverPiece::Outside));
        covers
    }

    /// s(t₂) − s(t₁) for the robot's motion on piece `index`: the chord loss of Lemma P4.
    pub fn arc_length_gain(&mut self, index: usize, t1: &Exact, t2: &Exact) -> Exact {
        let trajectory = BrakeTrajectory::new(&mut self.profile, self.pieces[index].brake);
        let s1 = trajectory.state_at(&mut self.profile, t1).position;
        trajectory.state_at(&mut self.profile, t2).position - s1
    }

    /// The leaf of `piece` on the sub-interval [t1, t2] ⊆ [piece.from, piece.to], in the
    /// cover set `cover` of its anchor.
    pub fn leaf(&mut self, piece: &Piece, t1: &Exact, t2: &Exact, cover: &CoverPiece) -> Leaf {
        let dt = self.params.motion.dt.clone();
        let trajectory = BrakeTrajectory::new(&mut self.profile, piece.brake);
        let s1 = trajectory.state_at(&mut self.profile, t1).position;
        let s2 = trajectory.state_at(&mut self.profile, t2).position;
        let target = self.params.path.point_at(&s1);
        let chord = s2 - s1;
        let w = &self.obstacle.max_speed;
        // Where the obstacle can get in the times [lo, hi] after (or, negative, before) a
        // known centre: within W·max|t| (free), or w·d with w·t, w ∈ [0, W] (fixed).
        let travel = |lo: Exact, hi: Exact| -> Travel {
            let zero = Exact::ZERO;
            match &self.obstacle.direction {
                None => {
                    let far = if -lo.clone() > hi { -lo } else { hi };
                    Travel::Free(w * &far)
                }
                Some(d) => Travel::Along {
                    direction: d.unit().clone(),
                    lo: if lo < zero { w * &lo } else { zero.clone() },
                    hi: if hi > zero { w * &hi } else { zero },
                },
            }
        };
        let (to_anchor, to_instant, (cover, sector)) = match &piece.anchor {
            Some(a) => {
                let at = Exact::from(a.instant) * &dt;
                let (cover, sector): (Vec<HalfPlane>, Vec<HalfPlane>) = match cover {
                    CoverPiece::Whole => (Vec::new(), Vec::new()),
                    CoverPiece::Outside(i) => (vec![a.outside[*i].clone()], Vec::new()),
                    CoverPiece::Arc(arc) => match &a.radius {
                        // The sector's two rays hold its centres in their closure only;
                        // the third half-plane holds them strictly (Lemma P3(2)).
                        Some(r) => {
                            let [after_a, before_b, beyond] = arc.half_planes(&a.centre, r);
                            (vec![beyond], vec![after_a, before_b])
                        }
                        None => (Vec::new(), Vec::new()),
                    },
                    CoverPiece::Side(side) => {
                        let side = match (&self.obstacle.direction, &self.obstacle.start, &a.radius)
                        {
                            (Some(d), Start::At(p), Some(r)) => {
                                line_sides(p, d.unit(), &a.centre, r)
                                    .map(|sides| vec![sides[*side].clone()])
                                    .unwrap_or_default()
                            }
                            _ => Vec::new(),
                        };
                        (side, Vec::new())
                    }
                };
                (
                    travel(Exact::ZERO, at.clone()),
                    travel(t1 - &at, t2 - &at),
                    (cover, sector),
                )
            }
            None => (
                travel(Exact::ZERO, t2.clone()),
                travel(Exact::ZERO, Exact::ZERO),
                (Vec::new(), Vec::new()),
            ),
        };
        Leaf {
            target,
            start: self.obstacle.start.clone(),
            to_anchor,
            to_instant,
            region: self.obstacle.region.clone(),
            cover,
            sector,
            constant: -(&self.radii + &chord),
        }
    }
}

/// How far the pieces go.
struct Horizon {
    /// Pre(m) for m below this; Post(T) for T up to it.
    steps: usize,
    /// The destination guard's step, when the path ends.
    last_brake: Option<usize>,
}

/// The horizon of Lemma P6: the destination step when the path ends, else the first step
/// H from which the outrun rule proves every later instant, braking or not, above `goal`.
fn horizon(
    params: &PlanarParams,
    obstacle: &PlanarObstacle,
    profile: &mut DriveProfile,
    radii: &Exact,
    goal: &Exact,
    step_limit: usize,
) -> Result<Horizon, DomainError> {
    if params.path_ends {
        let last = profile
            .destination_step(step_limit)
            .ok_or(DomainError::Unbounded)?;
        return Ok(Horizon {
            steps: last,
            last_brake: Some(last),
        });
    }
    let p = params.motion.clone();
    let last = params.path.segments().last().expect("a path has a segment");
    let u = last.direction.unit().clone();
    // The farthest along u the obstacle can start, and (bounded region) ever be.
    let corners: Vec<Point> = match &obstacle.start {
        Start::At(q) => vec![q.clone()],
        Start::Box { min, max } => vec![
            min.clone(),
            max.clone(),
            Point::new(min.x.clone(), max.y.clone()),
            Point::new(max.x.clone(), min.y.clone()),
        ],
    };
    let reach_front = max_dot(&u, &corners);
    let region_front = obstacle.region.as_ref().map(|q| max_dot(&u, q.vertices()));
    // How fast the obstacle can advance along u: W, or W·(u·d)⁺ along a fixed direction.
    let w = match &obstacle.direction {
        None => obstacle.max_speed.clone(),
        Some(d) => {
            let along = u.dot(d.unit());
            if along > Exact::ZERO {
                &obstacle.max_speed * &along
            } else {
                Exact::ZERO
            }
        }
    };
    let w = &w;
    let brake_time = &p.v_max / &p.b_min;
    for h in 0..=step_limit {
        let s = profile.start(h).clone();
        if s.speed < p.v_max || s.position < last.arc_start {
            continue;
        }
        let at = Exact::from(h) * &p.dt;
        let ahead = u.dot(&params.path.point_at(&s.position));
        // Braking at any T ≥ h or driving on: the robot is at least this far along u at
        // every later instant, and the obstacle at most its start's front plus w·t.
        let outrun = &ahead - &reach_front - w * &(&at + &brake_time) - radii;
        let outrun_ok = *w < p.v_max && outrun > *goal;
        let left = region_front
            .as_ref()
            .is_some_and(|front| &ahead - front - radii > *goal);
        if outrun_ok || left {
            return Ok(Horizon {
                steps: h,
                last_brake: None,
            });
        }
    }
    Err(DomainError::Unbounded)
}

fn max_dot(u: &Point, points: &[Point]) -> Exact {
    points
        .iter()
        .map(|q| u.dot(q))
        .reduce(|a, b| if a > b { a } else { b })
        .expect("at least one point")
}
