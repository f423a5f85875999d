//! Fixtures the semantics' tests share (and the witness schedule's): one parameter set, a
//! small deterministic generator and random parameter sets.

use crate::core::model::{Params, Problem};
use crate::core::num::Exact;

/// One parameter set: the kinematic rule, latency 2, the wrong-assumption guard on.
pub(super) fn params() -> Params<Exact> {
    Problem::from_toml_str(
        "name = \"t\"\n[robot]\nmax_speed = 0.8\nacceleration = 0.3\nbraking = 0.5\ncontrol_period = 0.1\n\
         latency = 2\nclearance = 0.0\n[controller]\nassumed_obstacle_speed = 0.2\nreaction_radius = 1.4\n\
         danger_rule = \"kinematic\"\nbuffer = 0.1\nwrong_assumption_brake = true\n[environment]\n\
         obstacle_speed = 0.3\ninitial_gap = 3.0\n",
        "test",
    )
    .expect("valid")
    .params()
}

/// A small deterministic generator (tests need no reproducibility beyond a fixed seed).
pub(crate) struct Lcg(pub(crate) u64);

impl Lcg {
    pub(crate) fn below(&mut self, n: u64) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 33) % n
    }
    pub(crate) fn pick<T: Copy>(&mut self, xs: &[T]) -> T {
        xs[self.below(xs.len() as u64) as usize]
    }
}

/// Parameters across rules, latencies, speeds, radii, noise, occlusion, weaker brakes
/// and start speeds.
pub(crate) fn random_params(rng: &mut Lcg) -> Params<crate::core::rational::Rational> {
    let rule = rng.pick(&["paper", "kinematic", "area"]);
    let latency = rng.below(4);
    let dt = rng.pick(&[0.1, 0.05, 0.01, 0.25]);
    let w = rng.pick(&[0.15, 0.3, 0.25, 0.6]);
    let rho = rng.pick(&[1.4, 0.9, 1.6, 0.5]);
    let mut sensing = String::new();
    if rng.below(2) == 1 {
        sensing += &format!(
            "gap_noise = {}\nspeed_noise = {}\n",
            rng.pick(&[0.002, 0.05, 0.0]),
            rng.pick(&[0.01, 0.0, 0.1])
        );
    }
    if rng.below(3) == 0 {
        sensing += &format!("first_detection_gap = {}\n", rng.pick(&[0.4, 1.2, 2.0]));
    }
    let sensing = if sensing.is_empty() {
        sensing
    } else {
        format!("[sensing]\n{sensing}")
    };
    let v0 = rng.pick(&[0.0, 0.1, 0.8]);
    let b_min = rng.pick(&[0.5, 0.35]);
    let text = format!(
        "name = \"t\"\n[robot]\nmax_speed = 0.8\nacceleration = 0.3\nbraking = 0.5\n\
         braking_min = {b_min}\ninitial_speed = {v0}\ncontrol_period = {dt}\n\
         latency = {latency}\nclearance = {}\n[controller]\nassumed_obstacle_speed = 0.2\n\
         reaction_radius = {rho}\ndanger_rule = \"{rule}\"\nbuffer = 0.1\n\
         wrong_assumption_brake = {}\n[environment]\nobstacle_speed = {w}\n\
         initial_gap = {}\n{sensing}",
        rng.pick(&[0.0, 0.05]),
        rng.below(2) == 1,
        rng.pick(&[3.0, 2.5, 8.0, 30.0]),
    );
    Problem::from_toml_str(&text, "test")
        .expect("valid")
        .params()
}
