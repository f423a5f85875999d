//! The problem's named parameters, and numbers that are affine in them.
//!
//! W, ρ, V_a, the buffer, the initial gap, the clearance, the noise bounds and d_det enter a
//! piece's program only through right-hand sides, variable bounds and the objective's
//! constant — never through its matrix. A [`ParamAffine`] carries such a number together with its exact partial
//! derivatives in those parameters, so that a bound proved by fixed dual multipliers is an
//! exact affine function of them (`radius` reads its Newton slope from it; a region
//! certificate minimises it over a box).
//!
//! Parameters that shape the robot's own motion (v_max, a, b, dt, L) are not named here:
//! they decide the schedule itself and stay points.

use std::cmp::Ordering;
use std::ops::{Add, Div, Mul, Neg, Sub};

use serde::{Deserialize, Serialize};

use crate::core::model::{Params, Position, Problem, Sensing};
use crate::core::num::{Exact, Scalar, exact_decimal};

/// The value of a parameter the problem does not set (d_det: no obstacle is hidden). No
/// affine number depends on it then.
static UNSET: Exact = Exact::ZERO;

/// A parameter that programs depend on affinely.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum Parameter {
    /// W, `environment.obstacle_speed` (m/s).
    ObstacleSpeed,
    /// ρ, `controller.reaction_radius` (m).
    ReactionRadius,
    /// V_a, `controller.assumed_obstacle_speed` (m/s).
    AssumedObstacleSpeed,
    /// The danger rule's buffer, `controller.buffer` (m).
    Buffer,
    /// g0, `environment.initial_gap` (m).
    InitialGap,
    /// `robot.clearance` (m); enters only the margin s* − clearance.
    Clearance,
    /// σ_g, `sensing.gap_noise` (m).
    GapNoise,
    /// σ_w, `sensing.speed_noise` (m/s).
    SpeedNoise,
    /// d_det, `sensing.first_detection_gap` (m): enters only the first sighting's row
    /// `g ≥ d_det`.
    FirstDetectionGap,
}

impl Parameter {
    /// Every parameter, in a fixed order.
    pub const ALL: [Parameter; 9] = [
        Parameter::ObstacleSpeed,
        Parameter::ReactionRadius,
        Parameter::AssumedObstacleSpeed,
        Parameter::Buffer,
        Parameter::InitialGap,
        Parameter::Clearance,
        Parameter::GapNoise,
        Parameter::SpeedNoise,
        Parameter::FirstDetectionGap,
    ];

    /// The problem-file key that sets it.
    pub fn key(self) -> &'static str {
        match self {
            Parameter::ObstacleSpeed => "environment.obstacle_speed",
            Parameter::ReactionRadius => "controller.reaction_radius",
            Parameter::AssumedObstacleSpeed => "controller.assumed_obstacle_speed",
            Parameter::Buffer => "controller.buffer",
            Parameter::InitialGap => "environment.initial_gap",
            Parameter::Clearance => "robot.clearance",
            Parameter::GapNoise => "sensing.gap_noise",
            Parameter::SpeedNoise => "sensing.speed_noise",
            Parameter::FirstDetectionGap => "sensing.first_detection_gap",
        }
    }

    /// The parameter a problem-file key sets, if it is one.
    pub fn from_key(key: &str) -> Option<Parameter> {
        Parameter::ALL.into_iter().find(|p| p.key() == key)
    }

    /// Its unit, for messages and plots.
    pub fn unit(self) -> &'static str {
        match self {
            Parameter::ObstacleSpeed | Parameter::AssumedObstacleSpeed | Parameter::SpeedNoise => {
                "m/s"
            }
            _ => "m",
        }
    }

    /// Its symbol, for plots.
    pub fn symbol(self) -> &'static str {
        match self {
            Parameter::ObstacleSpeed => "W",
            Parameter::ReactionRadius => "ρ",
            Parameter::AssumedObstacleSpeed => "V_a",
            Parameter::Buffer => "buffer",
            Parameter::InitialGap => "g0",
            Parameter::Clearance => "clearance",
            Parameter::GapNoise => "σ_g",
            Parameter::SpeedNoise => "σ_w",
            Parameter::FirstDetectionGap => "d_det",
        }
    }

    /// Sets it in exact problem numbers (the initial gap: both ends, a point problem).
    pub fn set(self, p: &mut Params<Exact>, value: Exact) {
        match self {
            Parameter::ObstacleSpeed => p.W = value,
            Parameter::ReactionRadius => p.rho = value,
            Parameter::AssumedObstacleSpeed => p.V_a = value,
            Parameter::Buffer => p.buffer = value,
            Parameter::InitialGap => {
                p.g0_max = value.clone();
                p.g0 = value;
            }
            Parameter::Clearance => p.clearance = value,
            Parameter::GapNoise => p.sigma_g = value,
            Parameter::SpeedNoise => p.sigma_w = value,
            Parameter::FirstDetectionGap => p.d_det = Some(value),
        }
    }

    /// Its value in a problem file (the initial gap's nearest end).
    pub fn get_in(self, problem: &Problem) -> f64 {
        match self {
            Parameter::ObstacleSpeed => problem.environment.obstacle_speed,
            Parameter::ReactionRadius => problem.controller.reaction_radius,
            Parameter::AssumedObstacleSpeed => problem.controller.assumed_obstacle_speed,
            Parameter::Buffer => problem.controller.buffer,
            Parameter::InitialGap => problem.environment.initial_gap.min(),
            Parameter::Clearance => problem.robot.clearance,
            Parameter::GapNoise => problem.gap_noise(),
            Parameter::SpeedNoise => problem.speed_noise(),
            // (Unset: no obstacle is hidden; 0 lies in no box, since d_det > 0.)
            Parameter::FirstDetectionGap => problem.first_detection_gap().unwrap_or(0.0),
        }
    }

    /// Sets it in a problem file (the initial gap becomes a point).
    pub fn set_in(self, problem: &mut Problem, value: f64) {
        match self {
            Parameter::ObstacleSpeed => problem.environment.obstacle_speed = value,
            Parameter::ReactionRadius => problem.controller.reaction_radius = value,
            Parameter::AssumedObstacleSpeed => problem.controller.assumed_obstacle_speed = value,
            Parameter::Buffer => problem.controller.buffer = value,
            Parameter::InitialGap => problem.environment.initial_gap = Position::At(value),
            Parameter::Clearance => problem.robot.clearance = value,
            Parameter::GapNoise => {
                problem
                    .sensing
                    .get_or_insert_with(Sensing::default)
                    .gap_noise = Some(value);
            }
            Parameter::SpeedNoise => {
                problem
                    .sensing
                    .get_or_insert_with(Sensing::default)
                    .speed_noise = Some(value);
            }
            Parameter::FirstDetectionGap => {
                problem
                    .sensing
                    .get_or_insert_with(Sensing::default)
                    .first_detection_gap = Some(value);
            }
        }
    }

    /// Its value in a problem's exact numbers.
    pub fn value(self, p: &Params<Exact>) -> &Exact {
        match self {
            Parameter::ObstacleSpeed => &p.W,
            Parameter::ReactionRadius => &p.rho,
            Parameter::AssumedObstacleSpeed => &p.V_a,
            Parameter::Buffer => &p.buffer,
            Parameter::InitialGap => &p.g0,
            Parameter::Clearance => &p.clearance,
            Parameter::GapNoise => &p.sigma_g,
            Parameter::SpeedNoise => &p.sigma_w,
            Parameter::FirstDetectionGap => p.d_det.as_ref().unwrap_or(&UNSET),
        }
    }
}

/// An exact number at the problem's parameters, with its exact partial derivatives in the
/// named [`Parameter`]s: `value = constant + Σ coef_p · p` where the form is affine.
///
/// Comparisons look at `value` only. Products are affine only when one factor is a
/// constant; the program builder never forms another (a parameter times a parameter would
/// be a modelling error, and is caught by an assertion).
#[derive(Clone, Debug, PartialEq)]
pub struct ParamAffine {
    /// The value at the problem's parameters.
    pub value: Exact,
    /// ∂value/∂p for each parameter p it depends on, sorted by parameter, none zero.
    coef: Vec<(Parameter, Exact)>,
}

impl ParamAffine {
    /// A number that depends on no parameter.
    pub fn constant(value: Exact) -> Self {
        ParamAffine {
            value,
            coef: Vec::new(),
        }
    }

    /// The parameter `p` itself, at the value it has in `params`.
    pub fn parameter(p: Parameter, params: &Params<Exact>) -> Self {
        ParamAffine {
            value: p.value(params).clone(),
            coef: vec![(p, Exact::ONE)],
        }
    }

    /// ∂value/∂p (zero when it does not depend on p).
    pub fn slope(&self, p: Parameter) -> Exact {
        self.coef
            .iter()
            .find(|(q, _)| *q == p)
            .map_or(Exact::ZERO, |(_, c)| c.clone())
    }

    /// Whether it depends on no parameter.
    pub fn is_constant(&self) -> bool {
        self.coef.is_empty()
    }

    /// The parameters it depends on, with their coefficients.
    pub fn terms(&self) -> &[(Parameter, Exact)] {
        &self.coef
    }

    /// Its value when the parameters move from `base` to `at` (both exact problem numbers).
    pub fn value_at(&self, base: &Params<Exact>, at: &Params<Exact>) -> Exact {
        let mut v = self.value.clone();
        for (p, c) in &self.coef {
            v += c * &(p.value(at) - p.value(base));
        }
        v
    }

    /// `self · k` for an exact constant k.
    pub fn scaled(&self, k: &Exact) -> Self {
        if *k == Exact::ZERO {
            return Self::constant(Exact::ZERO);
        }
        ParamAffine {
            value: &self.value * k,
            coef: self.coef.iter().map(|(p, c)| (*p, c * k)).collect(),
        }
    }

    fn combine(self, other: &Self, sign: i8) -> Self {
        let value = if sign > 0 {
            self.value + &other.value
        } else {
            self.value - &other.value
        };
        if other.coef.is_empty() {
            return ParamAffine {
                value,
                coef: self.coef,
            };
        }
        let mut coef = self.coef;
        for (p, c) in &other.coef {
            let c = if sign > 0 { c.clone() } else { -c.clone() };
            match coef.binary_search_by(|(q, _)| q.cmp(p)) {
                Ok(i) => {
                    coef[i].1 += c;
                    if coef[i].1 == Exact::ZERO {
                        coef.remove(i);
                    }
                }
                Err(i) => coef.insert(i, (*p, c)),
            }
        }
        ParamAffine { value, coef }
    }
}

impl From<Exact> for ParamAffine {
    fn from(value: Exact) -> Self {
        ParamAffine::constant(value)
    }
}

impl PartialOrd for ParamAffine {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        self.value.partial_cmp(&other.value)
    }
}

impl Add for ParamAffine {
    type Output = ParamAffine;
    fn add(self, rhs: Self) -> Self {
        self.combine(&rhs, 1)
    }
}

impl Sub for ParamAffine {
    type Output = ParamAffine;
    fn sub(self, rhs: Self) -> Self {
        self.combine(&rhs, -1)
    }
}

impl Neg for ParamAffine {
    type Output = ParamAffine;
    fn neg(self) -> Self {
        self.scaled(&-Exact::ONE)
    }
}

impl Mul for ParamAffine {
    type Output = ParamAffine;
    fn mul(self, rhs: Self) -> Self {
        if rhs.is_constant() {
            self.scaled(&rhs.value)
        } else {
            assert!(
                self.is_constant(),
                "a product of two parameters is not affine in them"
            );
            rhs.scaled(&self.value)
        }
    }
}

impl Div for ParamAffine {
    type Output = ParamAffine;
    fn div(self, rhs: Self) -> Self {
        assert!(rhs.is_constant(), "division by a parameter is not affine");
        self.scaled(&(Exact::ONE / rhs.value))
    }
}

/// The semantics' own formulas (e.g. the danger distance) evaluate over affine numbers
/// too, so a threshold's dependence on V_a and the buffer comes from the one formula.
impl Scalar for ParamAffine {
    fn zero() -> Self {
        Self::constant(Exact::ZERO)
    }
    fn int(i: i64) -> Self {
        Self::constant(Exact::from(i))
    }
    fn decimal(x: f64) -> Self {
        Self::constant(exact_decimal(x))
    }
    fn as_f64(&self) -> f64 {
        self.value.as_f64()
    }
}

/// A problem's numbers with the named parameters symbolic and everything else constant.
pub fn symbolic(p: &Params<Exact>) -> Params<ParamAffine> {
    let c = |x: &Exact| ParamAffine::constant(x.clone());
    let s = |q: Parameter| ParamAffine::parameter(q, p);
    Params {
        v_max: c(&p.v_max),
        a: c(&p.a),
        b: c(&p.b),
        b_min: c(&p.b_min),
        v0: c(&p.v0),
        dt: c(&p.dt),
        L: p.L,
        clearance: s(Parameter::Clearance),
        V_a: s(Parameter::AssumedObstacleSpeed),
        rho: s(Parameter::ReactionRadius),
        rule: p.rule,
        buffer: s(Parameter::Buffer),
        wrong_assumption_brake: p.wrong_assumption_brake,
        W: s(Parameter::ObstacleSpeed),
        g0: s(Parameter::InitialGap),
        // The far end of a range is not a named parameter yet (issue 11 names it).
        g0_max: if p.gap_is_range() {
            c(&p.g0_max)
        } else {
            s(Parameter::InitialGap)
        },
        sigma_g: s(Parameter::GapNoise),
        sigma_w: s(Parameter::SpeedNoise),
        d_det: p.d_det.as_ref().map(|_| s(Parameter::FirstDetectionGap)),
        k: p.k.map(&c),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::semantics::danger_distance;

    fn q(n: i64, d: i64) -> Exact {
        Exact::from(n) / Exact::from(d)
    }

    #[test]
    fn sums_merge_and_cancel_coefficients() {
        let a = ParamAffine {
            value: q(3, 1),
            coef: vec![(Parameter::ObstacleSpeed, q(2, 1))],
        };
        let b = ParamAffine {
            value: q(1, 2),
            coef: vec![
                (Parameter::ObstacleSpeed, q(2, 1)),
                (Parameter::Buffer, q(1, 3)),
            ],
        };
        let d = a.clone() - b.clone();
        assert_eq!(d.value, q(5, 2));
        assert_eq!(d.slope(Parameter::ObstacleSpeed), Exact::ZERO);
        assert_eq!(d.terms(), &[(Parameter::Buffer, q(-1, 3))]);
        let s = a + b;
        assert_eq!(s.slope(Parameter::ObstacleSpeed), q(4, 1));
        assert_eq!(s.slope(Parameter::Buffer), q(1, 3));
    }

    #[test]
    fn danger_distance_is_affine_in_assumed_speed_and_buffer() {
        // Paper rule: d = v·v/b + V_a·v/b + buffer, so ∂d/∂V_a = v/b and ∂d/∂buffer = 1.
        let problem = crate::core::model::Problem::shipped_seed();
        let p: Params<Exact> = problem.params();
        let sym = symbolic(&p);
        let v = p.v_max.clone();
        let d = danger_distance(&sym, &ParamAffine::constant(v.clone())).expect("finite rule");
        let exact = danger_distance(&p, &v).expect("finite rule");
        assert_eq!(d.value, exact);
        assert_eq!(d.slope(Parameter::AssumedObstacleSpeed), &v / &p.b);
        assert_eq!(d.slope(Parameter::Buffer), Exact::ONE);
        assert_eq!(d.slope(Parameter::ObstacleSpeed), Exact::ZERO);
        // Moving V_a by 1/10 moves d by exactly (v/b)/10.
        let mut moved = p.clone();
        moved.V_a = &p.V_a + q(1, 10);
        let at = danger_distance(&moved, &v).expect("finite rule");
        assert_eq!(d.value_at(&p, &moved), at);
    }

    #[test]
    #[should_panic(expected = "not affine")]
    fn a_product_of_parameters_is_refused() {
        let p = q(1, 1);
        let a = ParamAffine {
            value: p.clone(),
            coef: vec![(Parameter::ObstacleSpeed, p.clone())],
        };
        let _ = a.clone() * a;
    }
}
