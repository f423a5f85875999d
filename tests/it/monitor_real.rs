//! The monitor on traces like a real robot's (issue 10): observation noise within the
//! certified σ raises nothing, and the same noise against σ = 0 does; observations the model
//! cannot explain (`observation_inconsistent`), a controller that ignores danger
//! (`controller_reaction`), a robot beyond its envelope (`robot_envelope`), a crash
//! (`collision`, even when every premise held); robot-only instants, dropouts outside and
//! inside the reaction area; and the smallest margins.
//!
//! The independent answers are the simulator's: the certified worst-case replay (the seed
//! certificate's witness), the instant its controller braked, the rows where it collided.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use safereach::analysis::analyse;
use safereach::core::model::Sensing;
use safereach::core::semantics::Mode;
use safereach::core::simulate::TraceRow;
use safereach::monitor::{Check, Event, Lanes, Monitor, RobotSample, Sample, Verdict};
use safereach::proof::certificate::Certificate;
use safereach::proof::premise::{Premise, PremiseKind};

use crate::common::monitoring::{sample_events, samples_of};
use crate::common::paths::fixture;

/// The seed's certificate (W = 0.15, ρ = 1.4, latency 1, rule `paper`).
fn seed_certificate() -> Certificate {
    let text = std::fs::read_to_string(fixture("seed.cert.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// The certified worst-case replay: the witness's rows.
fn worst_case(cert: &Certificate) -> Vec<TraceRow> {
    cert.witness.as_ref().expect("a witness").steps.clone()
}

/// The seed certificate's premises with observation noise σ_g and speed noise σ_w.
fn noisy_premises(cert: &Certificate, gap: f64, speed: f64) -> Vec<Premise> {
    let mut premises: Vec<Premise> = cert
        .premises
        .iter()
        .map(|p| match p.name {
            PremiseKind::ObservationNoise => Premise { bound: gap, ..*p },
            _ => *p,
        })
        .collect();
    premises.push(Premise {
        name: PremiseKind::SpeedNoise,
        bound: speed,
    });
    premises
}

/// The samples with every position moved by up to ±σ_g and every stated speed by up to
/// ±σ_w, uniformly (run `seed` of a ChaCha8 stream).
fn with_noise(samples: &[Sample], gap: f64, speed: f64, seed: u64) -> Vec<Sample> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    samples
        .iter()
        .map(|s| Sample {
            obstacle_x: s.obstacle_x + rng.random_range(-gap..=gap),
            obstacle_v: s.obstacle_v.map(|v| v + rng.random_range(-speed..=speed)),
            ..*s
        })
        .collect()
}

/// Issue 10: a run with noise within σ raises nothing — thousands of seeded runs of the
/// certified worst-case replay with uniform noise ≤ σ — and the same noisy traces against
/// the σ = 0 premises do raise (`obstacle_speed` or `observation_inconsistent`).
///
/// The monitor is built from the seed's certificate proved *for* σ_g = 2 mm, σ_w = 0.01 m/s
/// (`[sensing]`), and, as a control, from explicit premises with the same bounds
/// ([`Monitor::for_premises`]).
#[test]
fn noise_within_sigma_raises_nothing_and_without_sigma_it_does() {
    let cert = seed_certificate();
    let clean = samples_of(&worst_case(&cert), true);
    let (gap, speed) = (0.002, 0.01);
    let premises = noisy_premises(&cert, gap, speed);
    let mut problem = cert.problem.clone();
    problem.sensing = Some(Sensing {
        gap_noise: Some(gap),
        speed_noise: Some(speed),
        first_detection_gap: None,
    });
    let proved = Certificate::from_analysis(&analyse(&problem).expect("analyses"));
    assert_eq!(proved.verdict, safereach::analysis::Verdict::Certified);
    let mut raised_without_sigma = 0;
    for seed in 0..2000 {
        let noisy = with_noise(&clean, gap, speed, seed);
        let mut by_proof = Monitor::new(&proved).unwrap();
        let got = sample_events(&mut by_proof, &noisy);
        assert!(got.is_empty(), "run {seed}, noisy certificate: {got:?}");
        let mut m = Monitor::for_premises(&cert.problem, &premises).unwrap();
        let got = sample_events(&mut m, &noisy);
        assert!(got.is_empty(), "run {seed}: {got:?}");
        assert_eq!(m.summary().verdict, Verdict::Held);
        let mut exact = Monitor::new(&cert).unwrap();
        let got = sample_events(&mut exact, &noisy);
        if !got.is_empty() {
            raised_without_sigma += 1;
            // Speeds from noisy positions; (near ρ) noise can also make the robot look late.
            assert!(got.iter().any(|e| matches!(
                e.check,
                Check::ObstacleSpeed | Check::ObservationInconsistent
            )));
        }
    }
    assert_eq!(raised_without_sigma, 2000, "noise is visible at σ = 0");
}

/// The trace: the obstacle jumps from 9.98 m to 5.0 m in 0.1 s while `obstacle_v`
/// says 0.1, and the gap goes to −0.07 m with the robot driving at 0.2 m/s. It used to end
/// "held"; now the jump is `obstacle_speed` and `observation_inconsistent`, and the crash a
/// `collision`.
#[test]
fn an_impossible_jump_and_the_crash_it_hides_are_named() {
    let cert = seed_certificate();
    let mut m = Monitor::new(&cert).unwrap();
    let at = |t: f64, robot_x: f64, obstacle_x: f64| Sample {
        t,
        robot_x,
        robot_v: 0.2,
        robot_mode: Some(Mode::Drive),
        obstacle_id: 0,
        obstacle_x,
        obstacle_v: Some(0.1),
        obstacle_t: None,
    };
    assert!(m.observe(&at(0.0, 4.8, 9.99)).events.is_empty());
    assert!(m.observe(&at(0.1, 4.82, 9.98)).events.is_empty());
    let jump: Vec<Check> = m
        .observe(&at(0.2, 4.84, 5.0))
        .events
        .iter()
        .map(|e| e.check)
        .collect();
    assert_eq!(jump, [Check::ObstacleSpeed, Check::ObservationInconsistent]);
    let o = m.observe(&at(0.3, 4.86, 4.79));
    let collision = o
        .events
        .iter()
        .find(|e| e.check == Check::Collision)
        .unwrap();
    assert!((collision.observed.unwrap() + 0.07).abs() < 1e-9);
    assert_eq!(collision.bound, Some(cert.clearance));
    assert_eq!(m.summary().verdict, Verdict::Violated);
}

/// A crash with every premise holding: the seed problem with the obstacle's true bound
/// above what was certified is not this certificate's case, so instead the certified
/// problem's robot is made to ignore its brake (modes say `drive`, speeds stay at v_max):
/// `collision` is raised at exactly the samples where the robot moves at a gap ≤ clearance.
#[test]
fn a_collision_is_raised_at_exactly_the_moving_samples_within_clearance() {
    let cert = seed_certificate();
    let rows = worst_case(&cert);
    let braked = rows
        .iter()
        .position(|r| r.robot_mode == Mode::Brake)
        .unwrap();
    // From the brake on, the robot drives on at the speed it had, 0.02 m per period.
    let mut crash = samples_of(&rows[..braked], true);
    let last = crash.last().copied().unwrap();
    let mut x = last.robot_x;
    let mut obstacle = last.obstacle_x;
    for k in 1..=120 {
        x += last.robot_v * 0.1;
        obstacle -= 0.15 * 0.1;
        crash.push(Sample {
            t: last.t + 0.1 * k as f64,
            robot_x: x,
            obstacle_x: obstacle,
            obstacle_v: Some(0.15),
            ..last
        });
    }
    let expected: Vec<f64> = crash
        .iter()
        .filter(|s| s.robot_v > 0.0 && s.obstacle_x - s.robot_x <= cert.clearance)
        .map(|s| s.t)
        .collect();
    assert!(!expected.is_empty());
    let mut m = Monitor::new(&cert).unwrap();
    let got = sample_events(&mut m, &crash);
    let collisions: Vec<f64> = got
        .iter()
        .filter(|e| e.check == Check::Collision)
        .map(|e| e.t.unwrap())
        .collect();
    assert_eq!(collisions, expected);
    // Every premise held: the obstacle kept to W, the controller ran every period.
    let s = m.summary();
    assert!(
        s.premises.iter().all(|p| p.violations == 0),
        "{:?}",
        s.premises
    );
}

/// A controller that ignores danger: the worst-case replay with its modes kept at `drive`
/// (and the speed held) after the instant the certified controller braked raises
/// `controller_reaction` at exactly that instant — not earlier — and the obstacle as its
/// cause.
#[test]
fn a_controller_that_ignores_danger_is_flagged_at_the_instant_it_should_have_braked() {
    let cert = seed_certificate();
    let rows = worst_case(&cert);
    let braked = rows
        .iter()
        .position(|r| r.robot_mode == Mode::Brake)
        .unwrap();
    let mut trace = samples_of(&rows, true);
    let v = trace[braked - 1].robot_v;
    for (k, s) in trace.iter_mut().enumerate().skip(braked) {
        s.robot_mode = Some(Mode::Drive);
        s.robot_v = v;
        s.robot_x = trace_x(&rows, braked, k, v);
    }
    let mut m = Monitor::new(&cert).unwrap();
    let got = sample_events(&mut m, &trace);
    let first = got
        .iter()
        .find(|e| e.check == Check::ControllerReaction)
        .expect("flagged");
    assert_eq!(first.t, Some(rows[braked].t));
    assert_eq!(first.obstacle_id, Some(0));
    assert!(
        got.iter()
            .take_while(|e| e.check != Check::ControllerReaction)
            .all(|e| e.t >= Some(rows[braked].t))
    );
    // The replay as certified raises nothing.
    let mut m = Monitor::new(&cert).unwrap();
    assert!(sample_events(&mut m, &samples_of(&rows, true)).is_empty());
}

/// The robot's position when it holds speed `v` from row `from` on.
fn trace_x(rows: &[TraceRow], from: usize, k: usize, v: f64) -> f64 {
    rows[from - 1].robot_position + v * (rows[k].t - rows[from - 1].t)
}

/// `robot_envelope`: a speed above v_max, and an acceleration above a, each flagged with its
/// detail; at v_max and at a exactly, nothing.
#[test]
fn robot_envelope() {
    let cert = seed_certificate();
    let (v_max, a) = (
        cert.problem.robot.max_speed,
        cert.problem.robot.acceleration,
    );
    // The robot where speeding up uniformly from rest to v over t puts it (a robot whose
    // positions agree with its speeds: `robot_motion` is not what is tested here).
    let robot = |t: f64, v: f64| RobotSample {
        t,
        robot_x: v * t / 2.0,
        robot_v: v,
        robot_mode: Some(Mode::Accelerate),
    };
    let mut m = Monitor::new(&cert).unwrap();
    assert!(
        m.observe_robot(&robot(0.0, 0.0), Lanes::UNKNOWN)
            .events
            .is_empty()
    );
    assert!(
        m.observe_robot(&robot(0.1, a * 0.1), Lanes::UNKNOWN)
            .events
            .is_empty()
    );
    let fast = m.observe_robot(&robot(0.2, a * 0.1 + a * 0.15), Lanes::UNKNOWN);
    assert_eq!(fast.events.len(), 1);
    let e = fast.events[0];
    assert_eq!((e.check, e.bound), (Check::RobotEnvelope, Some(a)));
    assert!(e.detail.unwrap().to_string().contains("acceleration"));
    assert_eq!(e.obstacle_id, None);
    // Driving at v_max, then a little faster: it covers v_max·t.
    let driving = |t: f64, v: f64| RobotSample {
        robot_x: v_max * t,
        ..robot(t, v)
    };
    let mut m = Monitor::new(&cert).unwrap();
    assert!(
        m.observe_robot(&driving(0.0, v_max), Lanes::UNKNOWN)
            .events
            .is_empty()
    );
    let e = m
        .observe_robot(&driving(0.1, v_max * 1.01), Lanes::UNKNOWN)
        .events[0];
    assert_eq!((e.check, e.bound), (Check::RobotEnvelope, Some(v_max)));
    assert!(e.detail.unwrap().to_string().contains("speed"));
}

/// Robot-only instants: the worst-case replay with every fifth row's obstacle left out (a
/// robot-only row) raises nothing while the obstacle is outside ρ, and counts every instant.
/// Inside ρ, the same gap is an `observation_dropout`, reported at the first sample of the
/// instant after the one that came without it, with the last gap seen.
#[test]
fn robot_only_instants_and_dropouts_inside_the_area() {
    let cert = seed_certificate();
    let rows = worst_case(&cert);
    let rho = cert.problem.controller.reaction_radius;
    let all = samples_of(&rows, true);
    let outside = |s: &Sample| s.obstacle_x - s.robot_x > rho;
    let mut m = Monitor::new(&cert).unwrap();
    let mut dropped = 0;
    for (k, s) in all.iter().enumerate() {
        let o = if k % 5 == 4 && outside(s) {
            dropped += 1;
            let r = RobotSample {
                t: s.t,
                robot_x: s.robot_x,
                robot_v: s.robot_v,
                robot_mode: s.robot_mode,
            };
            m.observe_robot(&r, Lanes::UNKNOWN).events.to_vec()
        } else {
            m.observe(s).events.to_vec()
        };
        assert!(o.is_empty(), "t={}: {o:?}", s.t);
    }
    assert!(dropped > 50);
    let summary = m.summary();
    assert_eq!(summary.instants, rows.len() as u64);
    assert_eq!(summary.verdict, Verdict::Held);

    // The first sample inside ρ dropped: reported one instant later.
    let inside = all.iter().position(|s| !outside(s)).unwrap();
    let mut m = Monitor::new(&cert).unwrap();
    let mut got = Vec::new();
    for (k, s) in all.iter().enumerate() {
        let events = if k == inside + 1 {
            let r = RobotSample {
                t: s.t,
                robot_x: s.robot_x,
                robot_v: s.robot_v,
                robot_mode: s.robot_mode,
            };
            m.observe_robot(&r, Lanes::UNKNOWN).events.to_vec()
        } else {
            m.observe(s).events.to_vec()
        };
        got.extend(events);
    }
    let dropout: Vec<&Event> = got
        .iter()
        .filter(|e| e.check == Check::ObservationDropout)
        .collect();
    assert_eq!(dropout.len(), 1, "{got:?}");
    let e = dropout[0];
    assert_eq!((e.t, e.obstacle_id), (Some(all[inside + 2].t), Some(0)));
    let last_gap = all[inside].obstacle_x - all[inside].robot_x;
    assert_eq!((e.observed, e.bound), (Some(last_gap), Some(rho)));
}

/// An obstacle reappearing after a dropout must have been able to get there: 3 periods
/// unseen 9 m away, it may come back up to 3·W·dt closer, not more.
#[test]
fn reappearing_after_a_dropout_within_and_beyond_reach() {
    let cert = seed_certificate();
    let w = cert.problem.environment.obstacle_speed;
    let at = |t: f64, obstacle_x: f64| Sample {
        t,
        robot_x: 0.0,
        robot_v: 0.0,
        robot_mode: Some(Mode::Stop),
        obstacle_id: 0,
        obstacle_x,
        obstacle_v: None,
        obstacle_t: None,
    };
    let robot = |t: f64| RobotSample {
        t,
        robot_x: 0.0,
        robot_v: 0.0,
        robot_mode: Some(Mode::Stop),
    };
    for (distance, raised) in [(3.0 * w * 0.1, false), (3.0 * w * 0.1 + 0.01, true)] {
        let mut m = Monitor::new(&cert).unwrap();
        m.observe(&at(0.0, 9.0));
        for t in [0.1, 0.2] {
            assert!(m.observe_robot(&robot(t), Lanes::UNKNOWN).events.is_empty());
        }
        let got: Vec<Check> = m
            .observe(&at(0.3, 9.0 - distance))
            .events
            .iter()
            .map(|e| e.check)
            .collect();
        let expected: &[Check] = if raised { &[Check::ObstacleSpeed] } else { &[] };
        assert_eq!(got, expected, "{distance}");
    }
}

/// The smallest margin of each premise is the least bound − observed over the trace, at the
/// sample that had it: for `obstacle_speed` on the worst-case replay, W − the fastest stated
/// speed, at the first sample that stated it.
#[test]
fn margins_are_the_smallest_slack_and_where() {
    let cert = seed_certificate();
    let trace = samples_of(&worst_case(&cert), true);
    let mut m = Monitor::new(&cert).unwrap();
    sample_events(&mut m, &trace);
    let w = cert.problem.environment.obstacle_speed;
    let fastest = trace
        .iter()
        .filter_map(|s| s.obstacle_v)
        .fold(f64::NEG_INFINITY, f64::max);
    let at = trace
        .iter()
        .find(|s| s.obstacle_v == Some(fastest))
        .unwrap();
    let margin = m.margin(Check::ObstacleSpeed).unwrap();
    // The estimate from positions may come closer than the stated speed by rounding only.
    assert!((margin.slack - (w - fastest)).abs() < 1e-9, "{margin:?}");
    assert!(margin.t >= at.t);
    let s = m.summary();
    let speed = s
        .premises
        .iter()
        .find(|p| p.premise == Check::ObstacleSpeed)
        .unwrap();
    assert_eq!(speed.margin, Some(margin));
    // The closest the robot came while moving: the collision check's margin is the least
    // moving gap, or the gap at which the robot came to rest inside the step into rest, the
    // obstacle approaching at W until then but not nearer than the rest sample shows it
    // (the worst case the witness replays: the certified s*, within its tolerance and the
    // witness's margin).
    let closest = trace
        .iter()
        .filter(|s| s.robot_v > 0.0)
        .map(|s| s.obstacle_x - s.robot_x)
        .fold(f64::INFINITY, f64::min);
    let into_rest = trace
        .windows(2)
        .find(|p| p[0].robot_v > 0.0 && p[1].robot_v == 0.0)
        .expect("the witness brakes to rest");
    let b = cert.problem.robot.plant_braking();
    let (before, after) = (into_rest[0], into_rest[1]);
    let nearest = (before.obstacle_x - w * before.robot_v / b).max(after.obstacle_x);
    let rest = nearest - after.robot_x;
    assert!(rest < closest);
    let collision = m.margin(Check::Collision).unwrap();
    assert!(
        (collision.slack - (rest - cert.clearance)).abs() < 1e-12,
        "{collision:?}"
    );
    assert_eq!(collision.t, into_rest[1].t);
    let tolerance = cert.separation_tolerance + cert.witness.as_ref().unwrap().margin;
    assert!(
        (collision.slack - cert.min_separation.unwrap()).abs() <= tolerance,
        "{collision:?}"
    );
}

/// README's commands: the seed certified for 2 mm / 0.01 m/s of noise, and the noisy
/// example trace monitored against it, holds (exit 0); against the exact certificate it
/// does not (exit 1).
#[test]
fn the_readme_noisy_trace_holds_against_a_certificate_proved_for_its_noise() {
    use crate::common::cli::safereach;
    use crate::common::paths::{root, seed_file};
    let dir = crate::common::tmp();
    let cert = dir.path().join("seed-noisy.json");
    safereach(dir.path())
        .arg("certify")
        .arg(seed_file())
        .args(["--set", "sensing.gap_noise=0.002"])
        .args(["--set", "sensing.speed_noise=0.01"])
        .arg("--out")
        .arg(&cert)
        .assert()
        .code(0);
    let trace = root().join("examples/traces/noisy.csv");
    safereach(dir.path())
        .args(["monitor", "--certificate"])
        .arg(&cert)
        .arg(&trace)
        .assert()
        .code(0);
    safereach(dir.path())
        .args(["monitor", "--certificate"])
        .arg(fixture("seed.cert.json"))
        .arg(&trace)
        .assert()
        .code(1);
}
