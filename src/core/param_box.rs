//! A box of parameter values: each ranged [`Parameter`] between two ends, every other number
//! of the problem fixed. Region certificates make one claim about every point of a box.
//!
//! Ends are floats read as the decimals they print as (`0.15` is exactly 15/100), so a box
//! written to JSON reads back as the same exact box. Splitting cuts an axis at its
//! [`ParamBox::middle`] — the shortest decimal in the middle third, which both halves share,
//! so the halves cover the box exactly, without gap or overlap beyond the shared face. Short
//! decimals keep the exact arithmetic of deep boxes fast (halving 0.1 adds a digit each
//! time; the middle third adds one every few splits).

use serde::{Deserialize, Serialize};

use crate::core::model::{Params, Position, Problem};
use crate::core::num::{Exact, exact_decimal};
use crate::core::parameter::{ParamAffine, Parameter};
use crate::core::scene::Scene;

/// A scene obstacle's own rangeable keys (`obstacle.<i>.<key>`) and the parameter each is
/// for that obstacle.
const OBSTACLE_KEYS: [(Parameter, &str); 2] = [
    (Parameter::ObstacleSpeed, "max_speed"),
    (Parameter::InitialGap, "position"),
];

/// One ranged parameter: every value in `[lo, hi]`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct Axis {
    /// The parameter.
    pub parameter: Parameter,
    /// Lower end.
    pub lo: f64,
    /// Upper end (≥ lo).
    pub hi: f64,
    /// In a scene, the obstacle (0-based index) whose own number this is: W_i
    /// (`obstacle.<i>.max_speed`, `parameter` = obstacle_speed) or its start
    /// (`obstacle.<i>.position`, `parameter` = initial_gap). Absent: a number every obstacle
    /// shares (or a problem's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub obstacle: Option<usize>,
}

impl Axis {
    /// A problem's (or a scene's shared) parameter between two ends.
    pub fn new(parameter: Parameter, lo: f64, hi: f64) -> Self {
        Axis {
            parameter,
            lo,
            hi,
            obstacle: None,
        }
    }

    /// The axis a range key names between `lo` and `hi`: a named parameter's key
    /// (`controller.reaction_radius`) or, in a scene, an obstacle's own
    /// (`obstacle.<i>.max_speed`, `obstacle.<i>.position`); the reason when the key cannot be
    /// ranged, in the user's terms.
    pub fn for_key(key: &str, lo: f64, hi: f64) -> Result<Axis, String> {
        if let Some(rest) = key.strip_prefix("obstacle.") {
            let (index, field) = rest.split_once('.').unwrap_or((rest, ""));
            let Ok(i) = index.parse::<usize>() else {
                return Err(format!(
                    "{key}: expected obstacle.<index>.<key> with a 0-based index"
                ));
            };
            let Some(&(parameter, _)) = OBSTACLE_KEYS.iter().find(|(_, f)| *f == field) else {
                return Err(format!(
                    "{key}: an obstacle's rangeable keys are max_speed and position"
                ));
            };
            return Ok(Axis {
                obstacle: Some(i),
                ..Axis::new(parameter, lo, hi)
            });
        }
        match Parameter::from_key(key) {
            Some(parameter) => Ok(Axis::new(parameter, lo, hi)),
            None => {
                let known: Vec<&str> = Parameter::ALL.iter().map(|p| p.key()).collect();
                Err(format!(
                    "{key} cannot be ranged: only parameters that enter the programs' \
                     right-hand sides and bounds can ({}, and in a scene \
                     obstacle.<i>.max_speed and obstacle.<i>.position); the robot's own numbers \
                     (max_speed, acceleration, braking, control_period, latency) decide the \
                     schedule itself",
                    known.join(", ")
                ))
            }
        }
    }

    /// The key that sets it: the parameter's, or a scene obstacle's
    /// (`obstacle.0.max_speed`, `obstacle.0.position`).
    pub fn key(&self) -> String {
        let field = OBSTACLE_KEYS.iter().find(|(p, _)| *p == self.parameter);
        match (self.obstacle, field) {
            (Some(i), Some((_, f))) => format!("obstacle.{i}.{f}"),
            (Some(i), None) => format!("obstacle.{i}.{}", self.parameter.key()),
            (None, _) => self.parameter.key().to_string(),
        }
    }

    /// Sets it to `value` in a scene; the reason when a scene has no such number (an
    /// obstacle past the last, or a key only problems have).
    pub fn set_in_scene(&self, scene: &mut Scene, value: f64) -> Result<(), String> {
        match (self.obstacle, self.parameter) {
            (Some(i), p) => {
                let Some(o) = scene.obstacles.get_mut(i) else {
                    return Err(format!(
                        "{}: the scene has {} obstacles (indices from 0)",
                        self.key(),
                        scene.obstacles.len()
                    ));
                };
                match p {
                    Parameter::ObstacleSpeed => o.max_speed = value,
                    Parameter::InitialGap => o.position = Position::At(value),
                    _ => return Err(format!("{}: not an obstacle's key", self.key())),
                }
            }
            (None, Parameter::ReactionRadius) => scene.controller.reaction_radius = value,
            (None, Parameter::AssumedObstacleSpeed) => {
                scene.controller.assumed_obstacle_speed = value;
            }
            (None, Parameter::Buffer) => scene.controller.buffer = value,
            (None, Parameter::Clearance) => scene.robot.clearance = value,
            (None, Parameter::ObstacleSpeed | Parameter::InitialGap) => {
                return Err(format!(
                    "{}: a scene's obstacles each have their own (range \
                     obstacle.<i>.max_speed or obstacle.<i>.position)",
                    self.key()
                ));
            }
            (None, _) => {
                return Err(format!(
                    "{}: scenes with [sensing] are not covered by region certificates",
                    self.key()
                ));
            }
        }
        Ok(())
    }

    /// Exact lower end.
    pub fn lo_exact(&self) -> Exact {
        exact_decimal(self.lo)
    }

    /// Exact upper end.
    pub fn hi_exact(&self) -> Exact {
        exact_decimal(self.hi)
    }
}

/// Which end of an axis a corner takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    /// The lower end.
    Low,
    /// The upper end.
    High,
}

/// A box of parameter values (distinct parameters, finite ends, lo ≤ hi).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct ParamBox {
    /// The ranged parameters, in the order the user gave them.
    pub axes: Vec<Axis>,
}

impl ParamBox {
    /// The value of each axis at the corner `mask` names (bit i set: axis i at its upper
    /// end), in axis order.
    pub fn corner_values(&self, mask: u32) -> Vec<f64> {
        self.axes
            .iter()
            .enumerate()
            .map(|(i, a)| if mask >> i & 1 == 1 { a.hi } else { a.lo })
            .collect()
    }

    /// A box from its axes; the reason when two axes name one parameter, an end is not
    /// finite, or an axis is reversed.
    pub fn new(axes: Vec<Axis>) -> Result<Self, String> {
        for (i, a) in axes.iter().enumerate() {
            if !(a.lo.is_finite() && a.hi.is_finite()) {
                return Err(format!("{}: the ends must be finite numbers", a.key()));
            }
            if a.lo > a.hi {
                return Err(format!(
                    "{}: the range {}..{} is reversed (lower end first)",
                    a.key(),
                    a.lo,
                    a.hi
                ));
            }
            if axes[..i]
                .iter()
                .any(|b| (b.parameter, b.obstacle) == (a.parameter, a.obstacle))
            {
                return Err(format!("{} is ranged twice", a.key()));
            }
        }
        Ok(ParamBox { axes })
    }

    /// The axis of `p`, if it is ranged (in a scene's box, a shared parameter's).
    pub fn axis(&self, p: Parameter) -> Option<&Axis> {
        self.axes
            .iter()
            .find(|a| a.parameter == p && a.obstacle.is_none())
    }

    /// A scene box as it bears on obstacle `i`: its own axes (W_i, its start) as the
    /// problem's, and the shared ones — less V_a for a static obstacle, whose danger rule
    /// assumes speed 0 whatever V_a is.
    pub fn for_obstacle(&self, i: usize, is_static: bool) -> ParamBox {
        let axes = self
            .axes
            .iter()
            .filter(|a| a.obstacle.is_none_or(|j| j == i))
            .filter(|a| !(is_static && a.parameter == Parameter::AssumedObstacleSpeed))
            .map(|a| Axis {
                obstacle: None,
                ..*a
            })
            .collect();
        ParamBox { axes }
    }

    /// The problem's numbers at the box's centre: each axis at its [`ParamBox::middle`].
    pub fn center(&self, base: &Params<Exact>) -> Params<Exact> {
        let mut p = base.clone();
        for (i, a) in self.axes.iter().enumerate() {
            a.parameter.set(&mut p, exact_decimal(self.middle(i)));
        }
        p
    }

    /// The shortest decimal in the middle third of axis `i` (nearest its midpoint among
    /// those as short); the lower end for an axis without width.
    pub fn middle(&self, i: usize) -> f64 {
        let a = &self.axes[i];
        if a.hi <= a.lo {
            return a.lo;
        }
        let third = (a.hi - a.lo) / 3.0;
        let (from, to) = (a.lo + third, a.hi - third);
        let mid = a.lo + (a.hi - a.lo) / 2.0;
        for digits in 0..=17 {
            // The float nearest the decimal: its shortest form is that decimal.
            if let Ok(m) = format!("{mid:.digits$}").parse::<f64>()
                && from <= m
                && m <= to
                && a.lo < m
                && m < a.hi
            {
                return m;
            }
        }
        mid
    }

    /// The problem's numbers at the corner that takes, on each ranged axis, the end `pick`
    /// names (unranged parameters keep their values).
    pub fn corner(&self, base: &Params<Exact>, pick: impl Fn(Parameter) -> End) -> Params<Exact> {
        let mut p = base.clone();
        for a in &self.axes {
            let v = match pick(a.parameter) {
                End::Low => a.lo_exact(),
                End::High => a.hi_exact(),
            };
            a.parameter.set(&mut p, v);
        }
        p
    }

    /// The least value over the box of an affine number whose value is taken at `at` (a
    /// point of the box): an affine function is least at a vertex, taken axis by axis.
    pub fn min_of(&self, f: &ParamAffine, at: &Params<Exact>) -> Exact {
        self.extreme(f, at, false)
    }

    /// The greatest value over the box of an affine number taken at `at`.
    pub fn max_of(&self, f: &ParamAffine, at: &Params<Exact>) -> Exact {
        self.extreme(f, at, true)
    }

    fn extreme(&self, f: &ParamAffine, at: &Params<Exact>, greatest: bool) -> Exact {
        let mut v = f.value.clone();
        for (p, c) in f.terms() {
            let here = p.value(at);
            let Some(a) = self.axis(*p) else { continue };
            let (lo, hi) = (c * &(a.lo_exact() - here), c * &(a.hi_exact() - here));
            v += if (lo > hi) == greatest { lo } else { hi };
        }
        v
    }

    /// Whether the problem's value of every ranged parameter lies in the box.
    pub fn contains(&self, problem: &Problem) -> bool {
        self.axes.iter().all(|a| {
            let v = a.parameter.get_in(problem);
            a.lo <= v && v <= a.hi
        })
    }

    /// The two parts of the box along axis `i`, cut at its [`ParamBox::middle`], which both
    /// share. None when the axis cannot be cut any more (no float strictly between its ends).
    pub fn split(&self, i: usize) -> Option<(ParamBox, ParamBox)> {
        let a = self.axes[i];
        let mid = self.middle(i);
        if !(a.lo < mid && mid < a.hi) {
            return None;
        }
        let (mut low, mut high) = (self.clone(), self.clone());
        low.axes[i].hi = mid;
        high.axes[i].lo = mid;
        Some((low, high))
    }

    /// The box's centre ([`ParamBox::center`]) as a problem file.
    pub fn center_problem(&self, base: &Problem) -> Problem {
        let mut p = base.clone();
        for (i, a) in self.axes.iter().enumerate() {
            a.parameter.set_in(&mut p, self.middle(i));
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::parameter::symbolic;

    fn seed_box() -> ParamBox {
        ParamBox::new(vec![
            Axis::new(Parameter::ObstacleSpeed, 0.1, 0.3),
            Axis::new(Parameter::ReactionRadius, 1.0, 1.6),
        ])
        .expect("a valid box")
    }

    #[test]
    fn extremes_of_an_affine_number_sit_at_vertices() {
        // f = 2·W − 3·ρ + buffer, taken at the centre (W = 0.2, ρ = 1.3): least at
        // (W, ρ) = (0.1, 1.6), greatest at (0.3, 1.0); the buffer is not ranged.
        let b = seed_box();
        let base = Problem::shipped_seed().params::<Exact>();
        let at = b.center(&base);
        let s = symbolic(&at);
        let f = s.W.scaled(&Exact::from(2)) - s.rho.scaled(&Exact::from(3)) + s.buffer.clone();
        let value = |w: f64, r: f64| {
            exact_decimal(w) * Exact::from(2) - exact_decimal(r) * Exact::from(3) + &base.buffer
        };
        assert_eq!(b.min_of(&f, &at), value(0.1, 1.6));
        assert_eq!(b.max_of(&f, &at), value(0.3, 1.0));
    }

    #[test]
    fn middles_are_short_decimals_in_the_middle_third() {
        let b = seed_box();
        assert_eq!(b.middle(0), 0.2);
        assert_eq!(b.middle(1), 1.3);
        let narrow =
            ParamBox::new(vec![Axis::new(Parameter::ObstacleSpeed, 0.1, 0.15)]).expect("valid");
        // 0.125 is the midpoint; 0.12 is shorter and in the middle third.
        assert_eq!(narrow.middle(0), 0.12);
        // Deep splits stay short: twenty cuts add far fewer than twenty digits.
        let mut deep = narrow;
        for k in 0..20 {
            let (low, high) = deep.split(0).expect("splittable");
            deep = if k % 2 == 0 { low } else { high };
            let a = deep.axes[0];
            assert!(a.lo < a.hi);
            let third = (a.hi - a.lo) / 3.0;
            let m = deep.middle(0);
            assert!(a.lo + third <= m && m <= a.hi - third);
        }
        assert!(
            format!("{}", deep.axes[0].hi).len() <= 14,
            "{:?}",
            deep.axes[0]
        );
    }

    #[test]
    fn halves_share_their_face_and_cover_the_box() {
        let b = seed_box();
        let (low, high) = b.split(0).expect("splittable");
        assert_eq!(low.axes[0].lo, 0.1);
        assert_eq!(low.axes[0].hi, high.axes[0].lo);
        assert_eq!(high.axes[0].hi, 0.3);
        assert_eq!(low.axes[1], b.axes[1]);
        assert_eq!(exact_decimal(low.axes[0].hi), exact_decimal(0.2));
        let point =
            ParamBox::new(vec![Axis::new(Parameter::Buffer, 0.1, 0.1)]).expect("a point is a box");
        assert!(point.split(0).is_none());
    }

    #[test]
    fn malformed_boxes_are_refused_with_the_key() {
        let axis = |lo, hi| Axis::new(Parameter::ReactionRadius, lo, hi);
        let err = ParamBox::new(vec![axis(1.6, 1.0)]).unwrap_err();
        assert!(err.contains("controller.reaction_radius") && err.contains("reversed"));
        let err = ParamBox::new(vec![axis(1.0, 1.6), axis(1.0, 1.2)]).unwrap_err();
        assert!(err.contains("twice"));
        assert!(ParamBox::new(vec![axis(f64::NAN, 1.0)]).is_err());
    }
}
