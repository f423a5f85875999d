//! The runtime monitor as a library: simulator and monitor close the loop (no false alarm on
//! thousands of simulations within the premises, the exact first sample of a real violation),
//! every check and fail-safe case on hand-written samples, the trace reader, and no allocation
//! per sample.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use safereach::analysis::{self, Verdict as Proved, analyse};
use safereach::core::model::{Params, Problem};
use safereach::core::num::Exact;
use safereach::core::output::{trace_csv, trace_jsonl};
use safereach::core::semantics::Mode;
use safereach::core::simulate::{self, TraceRow};
use safereach::monitor::trace::{Columns, Decoded, Decoder, Format, parse_f64};
use safereach::monitor::{Check, Detail, Field, Monitor, MonitorError, Sample, Status, Verdict};
use safereach::proof::certificate::Certificate;

use crate::common::monitoring::{sample_events, samples_of, text_events};
use crate::common::paths::load_problem;

// ------------------------------------------------------------------------------------------
// Counting allocations of the current thread (tests run in parallel threads)
// ------------------------------------------------------------------------------------------

struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

fn count() {
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

fn allocations() -> u64 {
    ALLOCATIONS.with(Cell::get)
}

// ------------------------------------------------------------------------------------------
// Problems, certificates, simulated traces
// ------------------------------------------------------------------------------------------

fn certificate(p: &Problem) -> Certificate {
    let a = analyse(p).expect("analyses");
    Certificate::from_analysis(&a)
}

fn certified(p: &Problem) -> Certificate {
    let c = certificate(p);
    assert_eq!(c.verdict, Proved::Certified, "{} is not certified", p.name);
    c
}

fn floats(p: &Problem) -> Params<f64> {
    analysis::params_f64(&p.params::<Exact>())
}

/// The trace of a run with obstacle speed `speed(k)` in period k.
fn rows_of(params: &Params<f64>, speed: impl FnMut(usize) -> f64) -> Vec<TraceRow> {
    let run = simulate::run(params.clone(), speed, simulate::horizon(params), false);
    simulate::trace(params, &run)
}

/// Monte Carlo run `i` (as `simulate` does it).
fn random_rows(params: &Params<f64>, seed: u64, i: usize) -> Vec<TraceRow> {
    rows_of(
        params,
        safereach::analysis::random_speeds(params.W, seed, i),
    )
}

// ------------------------------------------------------------------------------------------
// Simulator and monitor close the loop
// ------------------------------------------------------------------------------------------

/// The problems of the no-false-alarm test: the seed and its variants (latency 0..2, each
/// danger rule, a static obstacle, W at the certified bound W = V_a).
fn within_premises() -> Vec<Problem> {
    vec![
        load_problem("seed.toml", &[]),
        load_problem("seed.toml", &["robot.latency=0"]),
        load_problem("seed.toml", &["robot.latency=2"]),
        load_problem("seed.toml", &["environment.obstacle_speed=0.2"]),
        load_problem(
            "seed.toml",
            &["environment.obstacle_speed=0.2", "robot.latency=2"],
        ),
        load_problem("zero-latency.toml", &[]),
        load_problem("kinematic-rule.toml", &[]),
        load_problem("kinematic-rule.toml", &["environment.obstacle_speed=0.2"]),
        load_problem("area-rule.toml", &[]),
        load_problem("area-rule.toml", &["environment.obstacle_speed=0.2"]),
        load_problem("static-obstacle.toml", &[]),
    ]
}

#[test]
fn simulations_within_the_premises_never_raise_a_violation() {
    const RUNS: usize = 1000;
    let mut traces = 0;
    let mut samples_seen = 0;
    for p in within_premises() {
        let cert = certified(&p);
        // `Monitor::new` re-verifies the certificate (milliseconds); copies are fresh monitors.
        let fresh = Monitor::new(&cert).expect("monitorable");
        let params = floats(&p);
        let w = params.W;
        let mut all: Vec<(String, Vec<TraceRow>)> = (0..RUNS)
            .map(|i| (format!("random run {i}"), random_rows(&params, 7, i)))
            .collect();
        // Extreme behaviours: always at W, alternating 0 and W, and the certificate's own
        // worst case replayed exactly.
        all.push(("always W".into(), rows_of(&params, |_| w)));
        all.push((
            "alternating".into(),
            rows_of(&params, |k| if k % 2 == 0 { w } else { 0.0 }),
        ));
        let witness = cert
            .witness
            .as_ref()
            .expect("a certified problem has a witness");
        all.push(("witness".into(), witness.steps.clone()));
        for (what, rows) in &all {
            for with_speed in [true, false] {
                let mut m = fresh.clone();
                let s = samples_of(rows, with_speed);
                let e = sample_events(&mut m, &s);
                assert!(
                    e.is_empty(),
                    "{} {what} (obstacle_v given: {with_speed}): {:?}",
                    p.name,
                    e.first()
                );
                assert_eq!(m.verdict(), Verdict::Held);
                samples_seen += s.len();
                traces += 1;
            }
        }
        // Through the text formats the simulator writes, on a few runs.
        for (what, rows) in all.iter().step_by(25) {
            let mut m = fresh.clone();
            let e = text_events(&mut m, &trace_csv(rows, "0"), Some(Format::Csv));
            assert!(e.is_empty(), "{} {what} as CSV: {:?}", p.name, e.first());
            let mut m = fresh.clone();
            let e = text_events(&mut m, &trace_jsonl(rows, "0"), None);
            assert!(
                e.is_empty(),
                "{} {what} as JSON Lines: {:?}",
                p.name,
                e.first()
            );
            assert_eq!(m.samples(), rows.len() as u64);
        }
    }
    assert!(traces >= 6000, "{traces} traces");
    assert!(samples_seen > 1_000_000, "{samples_seen} samples");
}

/// The first sample whose `obstacle_v` (the speed over the period before it) exceeds `w`.
fn first_fast_sample(rows: &[TraceRow], w: f64) -> Option<usize> {
    (1..rows.len()).find(|&k| rows[k - 1].obstacle_speed > w)
}

#[test]
fn an_obstacle_faster_than_certified_is_flagged_at_the_first_sample_that_shows_it() {
    // The seed's example: certified for W = 0.2, at run time the obstacle moves up to 0.25.
    let cert = certified(&load_problem(
        "seed.toml",
        &["environment.obstacle_speed=0.2"],
    ));
    let run_time = floats(&load_problem(
        "seed.toml",
        &["environment.obstacle_speed=0.25"],
    ));
    let fresh = Monitor::new(&cert).unwrap();
    let mut flagged = 0;
    for i in 0..300 {
        let rows = random_rows(&run_time, 11, i);
        let expected = first_fast_sample(&rows, 0.2);
        for with_speed in [true, false] {
            let mut m = fresh.clone();
            let e = sample_events(&mut m, &samples_of(&rows, with_speed));
            let Some(k) = expected else {
                assert!(e.is_empty(), "run {i}: {:?}", e.first());
                continue;
            };
            let speed = rows[k - 1].obstacle_speed;
            if !with_speed && speed < 0.2 + 1e-6 {
                // Within the estimate's tolerance of the bound: not a clean test case.
                continue;
            }
            let first = e.first().unwrap_or_else(|| panic!("run {i}: not flagged"));
            assert_eq!(first.check, Check::ObstacleSpeed, "run {i}: {first:?}");
            assert_eq!(
                first.sample, k as u64,
                "run {i} (obstacle_v given: {with_speed})"
            );
            assert_eq!(first.t, Some(rows[k].t));
            assert_eq!(first.obstacle_id, Some(0));
            assert_eq!(first.bound, Some(0.2));
            let observed = first.observed.unwrap();
            if with_speed {
                assert_eq!(observed, speed);
            } else {
                assert!(
                    (observed - speed).abs() < 1e-9,
                    "estimated {observed}, true {speed}"
                );
            }
            assert_eq!(m.first_violation(), Some(first));
            assert_eq!(m.verdict(), Verdict::Violated);
            // Every period faster than W is reported, and nothing else.
            let fast: Vec<u64> = (1..rows.len())
                .filter(|&k| rows[k - 1].obstacle_speed > 0.2)
                .map(|k| k as u64)
                .collect();
            if with_speed {
                let reported: Vec<u64> = e.iter().map(|e| e.sample).collect();
                assert_eq!(reported, fast, "run {i}");
            }
            assert!(e.iter().all(|e| e.check == Check::ObstacleSpeed));
            flagged += 1;
        }
    }
    assert!(flagged > 500, "{flagged}");
}

#[test]
fn certificates_that_cannot_be_monitored_are_refused() {
    let p = load_problem("seed.toml", &[]);
    let cert = certified(&p);
    // Tampered: a premise's bound raised after the fact.
    let mut forged = cert.clone();
    forged.premises[0].bound = 0.3;
    assert!(matches!(
        Monitor::new(&forged),
        Err(MonitorError::Invalid(_))
    ));
    // Tampered and re-signed: the premises no longer follow from the problem.
    forged.digest = forged.compute_digest();
    assert!(matches!(
        Monitor::new(&forged),
        Err(MonitorError::Invalid(_))
    ));
    // A changed problem.
    let mut other = cert.clone();
    other.problem.environment.obstacle_speed = 0.3;
    other.digest = other.compute_digest();
    assert!(matches!(
        Monitor::new(&other),
        Err(MonitorError::Invalid(_))
    ));
    // Valid, but refuted: premises holding would guarantee nothing.
    let refuted = certificate(&load_problem("fast-obstacle.toml", &[]));
    assert_eq!(refuted.verdict, Proved::Refuted);
    let e = Monitor::new(&refuted).unwrap_err();
    assert!(
        matches!(e, MonitorError::NotCertified(Proved::Refuted)),
        "{e}"
    );
    assert!(e.to_string().contains("refuted"), "{e}");
    // The genuine one, with the bounds of its premises.
    let m = Monitor::new(&cert).unwrap();
    let b = m.bounds();
    assert_eq!(
        (b.obstacle_speed, b.braking_deceleration, b.control_period),
        (0.15, 0.05, 0.1)
    );
    assert_eq!(
        (b.latency, b.first_detection_gap, b.observation_noise),
        (1.0, 1.4, 0.0)
    );
}

// ------------------------------------------------------------------------------------------
// Each check on hand-written samples (seed certificate: W 0.15, b 0.05, dt 0.1, L 1, ρ 1.4)
// ------------------------------------------------------------------------------------------

fn seed_monitor() -> Monitor {
    Monitor::new(&certified(&load_problem("seed.toml", &[]))).unwrap()
}

/// A sample of obstacle `id` at `t`, the robot driving at 0.2 m/s from 0 at t = 0.
fn at(t: f64, id: u32, obstacle_x: f64) -> Sample {
    Sample {
        t,
        robot_x: 0.2 * t,
        robot_v: 0.2,
        robot_mode: Some(Mode::Drive),
        obstacle_id: id,
        obstacle_x,
        obstacle_v: None,
        obstacle_t: None,
    }
}

/// The checks of the events of one sample.
fn checks(m: &mut Monitor, s: &Sample) -> Vec<Check> {
    m.observe(s).events.iter().map(|e| e.check).collect()
}

#[test]
fn obstacle_speed_observed_and_estimated() {
    let mut m = seed_monitor();
    let mut s = at(0.0, 0, 10.0);
    s.obstacle_v = Some(0.15);
    assert!(checks(&mut m, &s).is_empty(), "exactly W holds");
    s = at(0.1, 0, 9.9);
    s.obstacle_v = Some(0.150001);
    let o = m.observe(&s);
    assert_eq!(o.verdict, Verdict::Violated);
    let e = o.events[0];
    assert_eq!(
        (e.check, e.observed, e.bound, e.t, e.sample),
        (
            Check::ObstacleSpeed,
            Some(0.150001),
            Some(0.15),
            Some(0.1),
            1
        )
    );
    // Without obstacle_v: 0.016 m in 0.1 s is 0.16 m/s.
    let mut m = seed_monitor();
    assert!(checks(&mut m, &at(0.0, 0, 10.0)).is_empty());
    assert!(
        checks(&mut m, &at(0.1, 0, 9.985)).is_empty(),
        "0.15 m/s holds"
    );
    let o = m.observe(&at(0.2, 0, 9.969));
    assert_eq!(o.events.len(), 1);
    assert_eq!(o.events[0].check, Check::ObstacleSpeed);
    assert!((o.events[0].observed.unwrap() - 0.16).abs() < 1e-12);
    // An obstacle moving away, or standing, is fine.
    assert!(checks(&mut m, &at(0.3, 0, 10.5)).is_empty());
    assert!(checks(&mut m, &at(0.4, 0, 10.5)).is_empty());
}

#[test]
fn braking_deceleration() {
    let mut m = seed_monitor();
    // The robot at x, slowing uniformly from one speed to the next: it moves their mean
    // over the period.
    let brake = |t: f64, x: f64, v: f64| Sample {
        robot_mode: Some(Mode::Brake),
        robot_v: v,
        robot_x: x,
        ..at(t, 0, 1e4)
    };
    let mean = |v0: f64, v1: f64| (v0 + v1) / 2.0 * 0.1;
    // b·dt = 0.005 m/s per period: 0.2 → 0.195 holds, 0.195 → 0.191 does not.
    let x1 = mean(0.2, 0.195);
    let x2 = x1 + mean(0.195, 0.191);
    assert!(checks(&mut m, &brake(0.0, 0.0, 0.2)).is_empty());
    assert!(checks(&mut m, &brake(0.1, x1, 0.195)).is_empty());
    let o = m.observe(&brake(0.2, x2, 0.191));
    assert_eq!(o.events.len(), 1, "{:?}", o.events);
    let e = o.events[0];
    assert_eq!(e.check, Check::BrakingDeceleration);
    assert!((e.observed.unwrap() - 0.04).abs() < 1e-9);
    assert_eq!(e.bound, Some(0.05));
    // Speeding up while braking is a violation too.
    assert_eq!(
        checks(&mut m, &brake(0.3, x2 + mean(0.191, 0.2), 0.2)),
        [Check::BrakingDeceleration]
    );
    // A robot that stops inside the step (0.003 m/s needs 0.06 s, and 0.00009 m) is fine.
    let mut m = seed_monitor();
    let rest = 0.003 * 0.003 / (2.0 * 0.05);
    assert!(checks(&mut m, &brake(0.0, 0.0, 0.003)).is_empty());
    assert!(checks(&mut m, &brake(0.1, rest, 0.0)).is_empty());
    // At rest in brake: nothing to check.
    assert!(checks(&mut m, &brake(0.2, rest, 0.0)).is_empty());
    // Not braking: no check, even if it slows slowly.
    let mut m = seed_monitor();
    assert!(checks(&mut m, &at(0.0, 0, 10.0)).is_empty());
    assert!(
        checks(
            &mut m,
            &Sample {
                robot_v: 0.1999,
                ..at(0.1, 0, 10.0)
            }
        )
        .is_empty()
    );
    assert_eq!(m.checks(Check::BrakingDeceleration), 0);
    // Exactly b, with speeds, positions and times of a long run in floats: no false alarm.
    let mut m = seed_monitor();
    let (mut v, mut x): (f64, f64) = (0.2, 500.0);
    for k in 0..40 {
        let t = 1000.0 + k as f64 * 0.1;
        assert!(checks(&mut m, &brake(t, x, v)).is_empty(), "k = {k}");
        x += v * 0.1 - 0.05 * 0.1 * 0.1 / 2.0;
        v -= 0.05 * 0.1;
    }
}

#[test]
fn control_period() {
    let mut m = seed_monitor();
    assert!(checks(&mut m, &at(0.0, 0, 10.0)).is_empty());
    assert!(checks(&mut m, &at(0.1, 0, 10.0)).is_empty());
    let o = m.observe(&at(0.35, 0, 10.0));
    let e = o.events[0];
    assert_eq!(e.check, Check::ControlPeriod);
    assert!((e.observed.unwrap() - 0.25).abs() < 1e-12);
    assert_eq!(e.bound, Some(0.1));
    // A faster loop is fine.
    assert!(checks(&mut m, &at(0.36, 0, 10.0)).is_empty());
    // Times computed as k·dt, and by repeated addition, over a long run: no false alarm.
    let mut m = seed_monitor();
    let mut summed = 0.0;
    for k in 0..200_000 {
        assert!(
            checks(&mut m, &at(k as f64 * 0.1, 0, 1e4)).is_empty(),
            "k = {k}"
        );
    }
    let mut m2 = seed_monitor();
    for k in 0..200_000 {
        assert!(checks(&mut m2, &at(summed, 0, 1e4)).is_empty(), "k = {k}");
        summed += 0.1;
    }
    assert_eq!(m.checks(Check::ControlPeriod), 199_999);
}

#[test]
fn first_detection_gap() {
    let mut m = seed_monitor();
    // Without robot_mode: what the controller did is not judged here (obstacle 2 inside ρ
    // with the robot driving is a `controller_reaction`, tested on its own).
    let at = |t, id, x| Sample {
        robot_mode: None,
        ..at(t, id, x)
    };
    // Exactly ρ holds, also when the gap is computed from rounded positions.
    assert!(
        checks(
            &mut m,
            &Sample {
                robot_x: 0.3,
                ..at(0.0, 0, 1.7)
            }
        )
        .is_empty()
    );
    assert!(
        checks(
            &mut m,
            &Sample {
                robot_x: 0.3,
                ..at(0.0, 1, 1.7)
            }
        )
        .is_empty()
    );
    let o = m.observe(&Sample {
        robot_x: 0.3,
        ..at(0.0, 2, 1.6)
    });
    let e = o.events[0];
    assert_eq!(
        (e.check, e.obstacle_id),
        (Check::FirstDetectionGap, Some(2))
    );
    assert!((e.observed.unwrap() - 1.3).abs() < 1e-12);
    assert_eq!(e.bound, Some(1.4));
    // Only the first sighting counts: obstacle 0 may then come closer.
    let got = checks(
        &mut m,
        &Sample {
            robot_x: 0.32,
            ..at(0.1, 0, 1.69)
        },
    );
    assert!(got.is_empty(), "{got:?}");
}

#[test]
fn latency_is_checked_when_samples_carry_the_observation_time() {
    let mut m = seed_monitor();
    let seen = |t: f64, obs_t: f64| Sample {
        obstacle_t: Some(obs_t),
        ..at(t, 0, 10.0)
    };
    assert!(checks(&mut m, &seen(0.0, 0.0)).is_empty());
    assert!(
        checks(&mut m, &seen(0.1, 0.0)).is_empty(),
        "one period old: L = 1 holds"
    );
    let o = m.observe(&seen(0.2, 0.05));
    let e = o.events[0];
    assert_eq!(e.check, Check::Latency);
    assert!((e.observed.unwrap() - 1.5).abs() < 1e-9);
    assert_eq!(e.bound, Some(1.0));
    assert_eq!(m.summary().premises[3].status, Status::Violated);
    // Without the column latency is not monitored, and says so.
    let mut m = seed_monitor();
    m.observe(&at(0.0, 0, 10.0));
    let p = &m.summary().premises[3];
    assert_eq!(
        (p.premise, p.status),
        (Check::Latency, Status::NotMonitored)
    );
    assert!(p.reason.as_deref().unwrap().contains("obstacle_t"));
}

#[test]
fn speeds_are_estimated_over_observation_times_when_given() {
    let mut m = seed_monitor();
    let seen = |t: f64, obs_t: f64, x: f64| Sample {
        obstacle_t: Some(obs_t),
        ..at(t, 0, x)
    };
    assert!(checks(&mut m, &seen(0.0, 0.0, 10.0)).is_empty());
    // The same observation again (perception did not update): no estimate from it.
    assert!(checks(&mut m, &seen(0.1, 0.0, 10.0)).is_empty());
    // 0.015 m over 0.1 s of observation time (not 0.2 s of sample time): 0.15 m/s holds…
    assert!(checks(&mut m, &seen(0.2, 0.1, 9.985)).is_empty());
    // …and 0.02 m over the next 0.1 s does not.
    assert_eq!(
        checks(&mut m, &seen(0.3, 0.2, 9.965)),
        [Check::ObstacleSpeed]
    );
}

#[test]
fn interleaved_obstacles_are_tracked_separately() {
    let mut m = seed_monitor();
    // Obstacle 0 slow (0.1 m/s) from 10 m, obstacle 1 fast (0.2 m/s) from 20 m, in either
    // order within an instant; speeds are estimated per obstacle.
    let mut events_by_sample = Vec::new();
    for k in 0..10 {
        let t = k as f64 * 0.1;
        let a = at(t, 0, 10.0 - 0.1 * t);
        let b = at(t, 1, 20.0 - 0.2 * t);
        let order = if k % 2 == 0 { [a, b] } else { [b, a] };
        for s in order {
            for e in m.observe(&s).events {
                events_by_sample.push((k, e.obstacle_id, e.check));
            }
        }
    }
    assert_eq!(events_by_sample.len(), 9);
    assert!(
        events_by_sample
            .iter()
            .all(|&(_, id, c)| id == Some(1) && c == Check::ObstacleSpeed)
    );
    let s = m.summary();
    assert_eq!((s.samples, s.instants, s.obstacles), (20, 10, 2));
    // Obstacle 0 missing at one instant, 10 m away (far outside ρ = 1.4): a track lost for
    // a frame where the controller does not need it is no violation (it used to be a
    // `control_period` one, which commanded a needless brake).
    let mut m = seed_monitor();
    m.observe(&at(0.0, 0, 10.0));
    m.observe(&at(0.0, 1, 20.0));
    m.observe(&at(0.1, 1, 20.0));
    assert!(m.events().is_empty());
    m.observe(&at(0.2, 1, 20.0));
    assert!(m.events().is_empty());
    let o = m.observe(&at(0.2, 0, 10.0));
    assert!(o.events.is_empty(), "{:?}", o.events);
    assert_eq!(m.verdict(), Verdict::Held);
    // A new obstacle appearing inside the reaction radius among known ones.
    let o = m.observe(&at(0.2, 7, 1.0));
    assert_eq!(o.events[0].check, Check::FirstDetectionGap);
    assert_eq!(o.events[0].obstacle_id, Some(7));
}

/// Samples of two interleaved obstacles from a seed run at W = 0.25 m/s (over the certified
/// 0.15), with fail-safe cases mixed in: a non-finite position, time going backwards, an
/// obstacle twice at one instant, an id beyond the table.
fn mixed_samples(i: usize) -> Vec<Sample> {
    let fast = floats(&load_problem(
        "seed.toml",
        &["environment.obstacle_speed=0.25"],
    ));
    let rows = random_rows(&fast, 3, i);
    let mut out = Vec::new();
    for (k, s) in samples_of(&rows, i.is_multiple_of(2))
        .into_iter()
        .enumerate()
    {
        out.push(s);
        out.push(Sample {
            obstacle_id: 1,
            obstacle_x: s.obstacle_x + 2.0,
            ..s
        });
        match k % 41 {
            7 => out.push(Sample {
                obstacle_x: f64::NAN,
                ..s
            }),
            13 => out.push(Sample { t: s.t - 0.05, ..s }),
            19 => out.push(s),
            29 => out.push(Sample {
                obstacle_id: 9,
                ..s
            }),
            _ => {}
        }
    }
    out
}

/// `observe_all` is `observe` one sample at a time: the same events from the same samples,
/// the same verdict and summary, under a single-obstacle and a scene certificate.
#[test]
fn observing_a_block_is_observing_its_samples_one_by_one() {
    let scene = safereach::core::scene::Scene::load(&crate::common::paths::problem_file(
        "scene-oncoming.toml",
    ))
    .expect("scene loads");
    let scene_cert = safereach::proof::scene_certificate::SceneCertificate::from_analysis(
        &safereach::analysis::scene::analyse_scene(&scene).expect("analysed"),
    );
    let fresh = [
        Monitor::with_max_obstacles(&certified(&load_problem("seed.toml", &[])), 4).unwrap(),
        {
            // Ids matched to the scene's obstacles, so that their own bounds apply.
            let mut m = Monitor::for_scene(&scene_cert).expect("a certified scene");
            for (id, o) in scene.obstacles.iter().take(2).enumerate() {
                m.identify(id as u32, &o.name);
            }
            m
        },
    ];
    for i in 0..8 {
        let samples = mixed_samples(i);
        for (j, m) in fresh.iter().enumerate() {
            let mut one = m.clone();
            let mut expected = Vec::new();
            for (k, s) in samples.iter().enumerate() {
                expected.extend(one.observe(s).events.iter().map(|e| (k, *e)));
            }
            let mut block = m.clone();
            let mut got = Vec::new();
            let verdict = block.observe_all(&samples, |k, e| got.push((k, *e)));
            assert!(expected.len() > 4, "run {i}: the trace breaks premises");
            // The first difference, rather than two long lists.
            let differ = got.iter().zip(&expected).position(|(a, b)| a != b);
            assert_eq!(differ, None, "run {i}, monitor {j}: events differ");
            assert_eq!(got.len(), expected.len(), "run {i}, monitor {j}");
            assert_eq!(verdict, one.verdict());
            assert_eq!(block.summary(), one.summary(), "run {i}, monitor {j}");
        }
    }
}

// ------------------------------------------------------------------------------------------
// Fail safe: each case named, reported, and the monitor goes on
// ------------------------------------------------------------------------------------------

#[test]
fn non_finite_numbers() {
    let fields = [
        (
            Field::T,
            Sample {
                t: f64::NAN,
                ..at(0.1, 0, 10.0)
            },
        ),
        (
            Field::RobotX,
            Sample {
                robot_x: f64::INFINITY,
                ..at(0.1, 0, 10.0)
            },
        ),
        (
            Field::RobotV,
            Sample {
                robot_v: f64::NAN,
                ..at(0.1, 0, 10.0)
            },
        ),
        (
            Field::ObstacleX,
            Sample {
                obstacle_x: f64::NEG_INFINITY,
                ..at(0.1, 0, 10.0)
            },
        ),
        (
            Field::ObstacleV,
            Sample {
                obstacle_v: Some(f64::NAN),
                ..at(0.1, 0, 10.0)
            },
        ),
        (
            Field::ObstacleT,
            Sample {
                obstacle_t: Some(f64::INFINITY),
                ..at(0.1, 0, 10.0)
            },
        ),
    ];
    for (field, bad) in fields {
        let mut m = seed_monitor();
        assert!(checks(&mut m, &at(0.0, 0, 10.0)).is_empty());
        let o = m.observe(&bad);
        assert_eq!(o.events.len(), 1, "{field}");
        let e = o.events[0];
        assert_eq!(e.check, Check::NonFinite);
        assert_eq!(e.detail, Some(Detail::NonFinite(field)));
        assert_eq!(e.t, if field == Field::T { None } else { Some(0.1) });
        assert_eq!(o.verdict, Verdict::Violated);
        // Ignored otherwise: the next good sample is checked as if it had not been there.
        assert!(checks(&mut m, &at(0.1, 0, 10.0)).is_empty(), "{field}");
        assert_eq!(m.verdict(), Verdict::Violated, "latched");
        assert_eq!(m.violations(Check::NonFinite), 1);
    }
}

#[test]
fn time_going_backwards() {
    let mut m = seed_monitor();
    m.observe(&at(0.0, 0, 10.0));
    m.observe(&at(0.1, 0, 10.0));
    let o = m.observe(&at(0.05, 0, 10.0));
    let e = o.events[0];
    assert_eq!(
        (e.check, e.observed, e.bound),
        (Check::TimeBackwards, Some(0.05), Some(0.1))
    );
    // Also for another obstacle: instants are the robot's.
    assert_eq!(checks(&mut m, &at(0.05, 1, 10.0)), [Check::TimeBackwards]);
    // The monitor goes on from the last good instant.
    assert!(checks(&mut m, &at(0.2, 0, 10.0)).is_empty());
    assert_eq!(m.summary().instants, 3);
}

#[test]
fn the_same_obstacle_twice_at_one_instant() {
    let mut m = seed_monitor();
    m.observe(&at(0.0, 0, 10.0));
    m.observe(&at(0.0, 1, 12.0));
    assert_eq!(checks(&mut m, &at(0.0, 0, 10.0)), [Check::DuplicateSample]);
    assert!(checks(&mut m, &at(0.1, 0, 10.0)).is_empty());
}

#[test]
fn robot_state_must_agree_within_an_instant() {
    let mut m = seed_monitor();
    m.observe(&at(0.0, 0, 10.0));
    let o = m.observe(&Sample {
        robot_v: 0.1,
        ..at(0.0, 1, 12.0)
    });
    assert_eq!(o.events[0].check, Check::MalformedSample);
    assert_eq!(o.events[0].detail, Some(Detail::RobotStateDiffers));
    let o = m.observe(&Sample {
        robot_mode: Some(Mode::Brake),
        ..at(0.0, 2, 12.0)
    });
    assert_eq!(o.events[0].detail, Some(Detail::RobotStateDiffers));
    // The same state without a mode is consistent.
    assert!(
        checks(
            &mut m,
            &Sample {
                robot_mode: None,
                ..at(0.0, 3, 12.0)
            }
        )
        .is_empty()
    );
}

#[test]
fn obstacle_ids_beyond_a_fixed_table() {
    let cert = certified(&load_problem("seed.toml", &[]));
    let mut m = Monitor::with_max_obstacles(&cert, 2).unwrap();
    assert!(checks(&mut m, &at(0.0, 1, 10.0)).is_empty());
    let o = m.observe(&at(0.0, 2, 10.0));
    assert_eq!(o.events[0].check, Check::MalformedSample);
    assert_eq!(
        o.events[0].detail,
        Some(Detail::ObstacleIdOutOfRange { limit: 2 })
    );
    assert!(checks(&mut m, &at(0.1, 1, 10.0)).is_empty());
}

#[test]
fn unreadable_input_reported_by_the_reader() {
    let mut m = seed_monitor();
    m.observe(&at(0.0, 0, 10.0));
    let o = m.malformed(Some(0.1), Detail::BadMode);
    assert_eq!(o.events.len(), 1);
    let e = o.events[0];
    assert_eq!(
        (e.check, e.t, e.obstacle_id, e.observed),
        (Check::MalformedSample, Some(0.1), None, None)
    );
    assert!(e.to_string().contains("robot_mode"), "{e}");
    assert_eq!(
        m.malformed(None, Detail::NonFinite(Field::T)).events[0].check,
        Check::NonFinite
    );
    assert!(checks(&mut m, &at(0.1, 0, 10.0)).is_empty());
    assert_eq!(m.samples(), 4);
}

#[test]
fn the_verdict_latches_but_every_violation_is_reported() {
    let mut m = seed_monitor();
    let fast = |t: f64| Sample {
        obstacle_v: Some(0.3),
        ..at(t, 0, 10.0)
    };
    // The stated 0.3 m/s is above W, and (the obstacle standing still) disagrees with the
    // positions: two events each time.
    let both = [Check::ObstacleSpeed, Check::ObservationInconsistent];
    assert_eq!(m.observe(&at(0.0, 0, 10.0)).verdict, Verdict::Held);
    assert_eq!(checks(&mut m, &fast(0.1)), both);
    let o = m.observe(&at(0.2, 0, 10.0));
    assert_eq!((o.verdict, o.events.len()), (Verdict::Violated, 0));
    assert_eq!(checks(&mut m, &fast(0.3)), both);
    let s = m.summary();
    assert_eq!(s.violations, 4);
    assert_eq!(s.first_violation.unwrap().t, Some(0.1));
    assert_eq!(s.premises[0].status, Status::Violated);
    assert_eq!(s.premises[0].violations, 2);
}

#[test]
fn several_events_from_one_sample() {
    let mut m = seed_monitor();
    m.observe(&Sample {
        robot_mode: Some(Mode::Brake),
        obstacle_t: Some(0.0),
        ..at(0.0, 0, 10.0)
    });
    let o = m.observe(&Sample {
        robot_mode: Some(Mode::Brake),
        obstacle_t: Some(0.0),
        obstacle_v: Some(1.0),
        ..at(0.5, 0, 10.0)
    });
    let got: Vec<Check> = o.events.iter().map(|e| e.check).collect();
    assert_eq!(
        got,
        [
            Check::ControlPeriod,
            Check::BrakingDeceleration,
            Check::Latency,
            Check::ObstacleSpeed
        ]
    );
}

#[test]
fn summary_names_every_premise_and_why_some_were_not_checked() {
    let mut m = seed_monitor();
    m.observe(&Sample {
        robot_mode: None,
        ..at(0.0, 0, 10.0)
    });
    let s = m.summary();
    let status: Vec<(Check, Status)> = s.premises.iter().map(|p| (p.premise, p.status)).collect();
    assert_eq!(
        status,
        [
            (Check::ObstacleSpeed, Status::NotChecked),
            (Check::BrakingDeceleration, Status::NotMonitored),
            (Check::ControlPeriod, Status::NotChecked),
            (Check::Latency, Status::NotMonitored),
            (Check::FirstDetectionGap, Status::Held),
            (Check::ObservationNoise, Status::NotMonitored),
        ]
    );
    assert!(
        s.premises
            .iter()
            .all(|p| (p.reason.is_some()) == (p.status != Status::Held))
    );
    assert_eq!(s.fail_safe.len(), 4);
    assert_eq!(s.verdict, Verdict::Held);
}

// ------------------------------------------------------------------------------------------
// No allocation per sample
// ------------------------------------------------------------------------------------------

#[test]
fn observing_does_not_allocate() {
    let cert = certified(&load_problem("seed.toml", &[]));
    let mut m = Monitor::with_max_obstacles(&cert, 4).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let before = allocations();
    let mut n_events = 0;
    for k in 0..100_000 {
        let t = k as f64 * 0.1;
        for id in 0..4 {
            let mut s = at(t, id, 1e4 - 0.1 * t);
            if rng.random::<f64>() < 0.01 {
                s.obstacle_v = Some(1.0); // violations too
            }
            n_events += m.observe(&s).events.len();
        }
        if k % 1000 == 0 {
            n_events += m.malformed(None, Detail::BadMode).events.len();
        }
    }
    assert_eq!(allocations() - before, 0);
    assert!(n_events > 1000);
}

#[test]
fn reading_csv_lines_does_not_allocate_per_line() {
    let cert = certified(&load_problem("seed.toml", &[]));
    let mut m = Monitor::new(&cert).unwrap();
    let params = floats(&load_problem("seed.toml", &[]));
    let text = trace_csv(&random_rows(&params, 1, 0), "obstacle-A");
    let lines: Vec<&str> = text.lines().collect();
    let mut decoder = Decoder::new(Some(Format::Csv), None, 16);
    // Header and the first sample (a new obstacle) may allocate.
    for line in &lines[..2] {
        if let Decoded::Sample { sample, .. } = decoder.decode(line.as_bytes()) {
            assert!(m.observe(&sample).events.is_empty());
        }
    }
    let before = allocations();
    for line in &lines[2..] {
        match decoder.decode(line.as_bytes()) {
            Decoded::Sample { sample, .. } => assert!(m.observe(&sample).events.is_empty()),
            other => panic!("{other:?}"),
        }
    }
    assert_eq!(allocations() - before, 0);
}

// ------------------------------------------------------------------------------------------
// The trace reader
// ------------------------------------------------------------------------------------------

fn decode_all(text: &str, format: Option<Format>) -> Vec<Result<(Sample, String), Detail>> {
    let mut d = Decoder::new(format, None, 16);
    let mut out = Vec::new();
    for line in text.split('\n') {
        match d.decode(line.as_bytes()) {
            Decoded::Blank | Decoded::Header => {}
            Decoded::Sample { sample, t_text } => {
                out.push(Ok((sample, String::from_utf8(t_text.to_vec()).unwrap())))
            }
            Decoded::Robot { .. } => out.push(Err(Detail::MissingField(Field::ObstacleId))),
            Decoded::Malformed { detail, .. } => out.push(Err(detail)),
        }
    }
    out
}

#[test]
fn csv_columns_in_any_order_with_optional_ones_absent() {
    let text = "\u{feff}obstacle_x, t ,extra,obstacle_id,robot_v,robot_x\r\n\
                9.5,0.1,whatever,\"ob,1\",0.2,0.02\r\n\
                \r\n\
                9.4,  0.2 ,,\"say \"\"hi\"\"\",0.2,0.04\n";
    let got = decode_all(text, Some(Format::Csv));
    assert_eq!(got.len(), 2);
    let (s, t) = got[0].clone().unwrap();
    assert_eq!(t, "0.1");
    assert_eq!(
        s,
        Sample {
            t: 0.1,
            robot_x: 0.02,
            robot_v: 0.2,
            robot_mode: None,
            obstacle_id: 0,
            obstacle_x: 9.5,
            obstacle_v: None,
            obstacle_t: None,
        }
    );
    let (s, t) = got[1].clone().unwrap();
    assert_eq!((s.obstacle_id, t.as_str()), (1, "0.2"));
    let mut d = Decoder::new(Some(Format::Csv), None, 16);
    for line in text.lines() {
        let _ = d.decode(line.as_bytes());
    }
    assert_eq!(d.ids().name(0), "ob,1");
    assert_eq!(d.ids().name(1), "say \"hi\"");
}

#[test]
fn csv_rows_that_are_not_samples() {
    let header = "t,robot_x,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_v\n";
    let cases = [
        (
            "0.1,0,0.2,drive,a,9\n",
            Detail::FieldCount {
                found: 6,
                expected: 7,
            },
        ),
        (
            "0.1,0,0.2,drive,a,9,0.1,7\n",
            Detail::FieldCount {
                found: 8,
                expected: 7,
            },
        ),
        (
            "0.1,0,fast,drive,a,9,0.1\n",
            Detail::BadNumber(Field::RobotV),
        ),
        ("0.1,0,0.2,flying,a,9,0.1\n", Detail::BadMode),
        (
            "0.1,,0.2,drive,a,9,0.1\n",
            Detail::MissingField(Field::RobotX),
        ),
        (
            "0.1,0,0.2,drive,,9,0.1\n",
            Detail::MissingField(Field::ObstacleId),
        ),
        (
            "0.1,0,0.2,drive,\"a,9,0.1\n",
            Detail::Csv("unterminated quote"),
        ),
    ];
    for (row, detail) in cases {
        let got = decode_all(&format!("{header}{row}"), Some(Format::Csv));
        assert_eq!(got, [Err(detail)], "{row}");
    }
    // Non-finite numbers are read, for the monitor to name them.
    let got = decode_all(&format!("{header}0.1,0,0.2,DRIVE,a,NaN,inf\n"), None);
    let (s, _) = got[0].clone().unwrap();
    assert!(s.obstacle_x.is_nan() && s.obstacle_v == Some(f64::INFINITY));
    assert_eq!(s.robot_mode, Some(Mode::Drive));
    // A header without a required column: reported once, then every line has no header.
    let got = decode_all(
        "t,robot_x,obstacle_id,obstacle_x\n0,0,a,9\n0.1,0,a,9\n",
        None,
    );
    assert_eq!(
        got,
        [
            Err(Detail::MissingColumn(Field::RobotV)),
            Err(Detail::NoHeader),
            Err(Detail::NoHeader)
        ]
    );
    assert_eq!(
        Columns::from_names("t,robot_x,robot_v,obstacle_id,obstacle_x,t"),
        Err(Detail::DuplicateColumn(Field::T))
    );
}

#[test]
fn json_lines() {
    let text = r#"{"t": 0.5, "robot_x": 1, "robot_v": 0.2, "robot_mode": "brake", "obstacle_id": 3, "obstacle_x": 9.5, "obstacle_v": null, "meta": {"a": [1, {"b": "}"}]}}
{"obstacle_id": "3", "t": 0.6, "robot_x": 1.02, "robot_v": 0.195, "obstacle_x": 9.48, "obstacle_t": 0.55}
{"t":0.7,"robot_x":1,"robot_v":0.2,"obstacle_id":"\u00e9\n","obstacle_x":null}
{"t":0.7,"robot_x":1,"robot_v":0.2,"obstacle_id":"x","obstacle_x":NaN}
{"t":0.7,"robot_x":1,"robot_v":0.2,"obstacle_id":"x","obstacle_x":1,"t":0.8}
{"t":0.7,"robot_x":1,"robot_v":0.2,"obstacle_id":"x","obstacle_x":1} trailing
{"t":0.7,"robot_x":1,"robot_v":"0.2","obstacle_id":"x","obstacle_x":1}
{"t":0.7,"robot_x":1,"robot_v":0.2,"obstacle_id":1.5,"obstacle_x":1}
{"t":0.7,"robot_x":1,"obstacle_id":"x","obstacle_x":1}
[1, 2]"#;
    let got = decode_all(text, None);
    assert_eq!(got.len(), 10);
    let (a, t) = got[0].clone().unwrap();
    assert_eq!(t, "0.5");
    assert_eq!(
        (a.t, a.robot_mode, a.obstacle_id, a.obstacle_v),
        (0.5, Some(Mode::Brake), 0, None)
    );
    let (b, _) = got[1].clone().unwrap();
    assert_eq!(
        (b.obstacle_id, b.obstacle_t, b.robot_mode),
        (0, Some(0.55), None)
    );
    let (c, _) = got[2].clone().unwrap();
    assert_eq!(c.obstacle_id, 1);
    assert!(
        c.obstacle_x.is_nan(),
        "null in a required number is non-finite"
    );
    assert!(got[3].clone().unwrap().0.obstacle_x.is_nan());
    assert_eq!(got[4], Err(Detail::DuplicateKey(Field::T)));
    assert_eq!(got[5], Err(Detail::Json("text after the object")));
    assert_eq!(got[6], Err(Detail::BadNumber(Field::RobotV)));
    assert_eq!(got[7], Err(Detail::BadId));
    assert_eq!(got[8], Err(Detail::MissingField(Field::RobotV)));
    assert_eq!(got[9], Err(Detail::Json("expected an object")));
    let mut d = Decoder::new(None, None, 16);
    for line in text.lines() {
        let _ = d.decode(line.as_bytes());
    }
    assert_eq!(d.format(), Some(Format::Jsonl));
    assert_eq!(d.ids().name(1), "é\n");
}

#[test]
fn numbers_parse_exactly_as_the_standard_library_does() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for _ in 0..200_000 {
        let x: f64 = match rng.random_range(0..4) {
            0 => rng.random::<f64>() * 100.0,
            1 => f64::from_bits(rng.random::<u64>()),
            2 => (rng.random_range(-1_000_000i64..1_000_000) as f64) / 1000.0,
            _ => rng.random::<f64>() * 10f64.powi(rng.random_range(-30..30)),
        };
        if !x.is_finite() {
            continue;
        }
        let texts = [
            format!("{x}"),
            format!("{x:e}"),
            format!("{x:.3}"),
            format!("{x:.17}"),
        ];
        for text in texts {
            let std = text.parse::<f64>().unwrap();
            assert_eq!(
                parse_f64(text.as_bytes()).map(f64::to_bits),
                Some(std.to_bits()),
                "{text}"
            );
        }
    }
    // Random short decimals, the fast path's domain, with exponents.
    for _ in 0..200_000 {
        let digits = rng.random_range(1..16);
        let m: u64 = rng.random_range(0..10u64.pow(digits));
        let point = rng.random_range(0..=digits as usize);
        let mut s = format!("{m:0width$}", width = digits as usize);
        s.insert(point, '.');
        if rng.random::<bool>() {
            s = format!("-{s}e{}", rng.random_range(-25..25));
        }
        let std = s.parse::<f64>().ok().map(f64::to_bits);
        assert_eq!(parse_f64(s.as_bytes()).map(f64::to_bits), std, "{s}");
    }
}

#[test]
fn garbage_never_panics_and_is_always_reported() {
    // Random lines built from the bytes that matter to the readers (and some that do not),
    // after a valid CSV header or as JSON Lines; every line is a sample, blank or malformed,
    // and whatever decodes goes through the monitor.
    const ALPHABET: &[u8] = b"0123456789.,-+eE\"{}[]:\\ntrufalsNI \ttobstacle_idxvrm\xff\x00";
    let cert = certified(&load_problem("seed.toml", &[]));
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for format in [Format::Csv, Format::Jsonl] {
        let mut m = Monitor::new(&cert).unwrap();
        let mut d = Decoder::new(Some(format), None, 64);
        if format == Format::Csv {
            let header = b"t,robot_x,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_v";
            assert_eq!(d.decode(header), Decoded::Header);
        }
        let mut reported = 0;
        for _ in 0..100_000 {
            let len = rng.random_range(0..60);
            let mut line: Vec<u8> = (0..len)
                .map(|_| ALPHABET[rng.random_range(0..ALPHABET.len())])
                .collect();
            if format == Format::Jsonl && rng.random::<bool>() {
                line = format!(
                    r#"{{"t":{},"robot_x":0,"robot_v":0,"obstacle_id":{},"obstacle_x":{}}}"#,
                    String::from_utf8_lossy(&line[..len.min(5)]),
                    rng.random_range(0..100),
                    String::from_utf8_lossy(&line[len.min(5)..len.min(9)])
                )
                .into_bytes();
            }
            match d.decode(&line) {
                Decoded::Blank | Decoded::Header => {}
                Decoded::Sample { sample, .. } => {
                    m.observe(&sample);
                    reported += 1;
                }
                Decoded::Robot { sample, .. } => {
                    m.observe_robot(&sample, d.lanes());
                    reported += 1;
                }
                Decoded::Malformed { t, detail, .. } => {
                    assert_eq!(m.malformed(t, detail).events.len(), 1);
                    reported += 1;
                }
            }
        }
        assert_eq!(m.samples(), reported);
        assert!(reported > 90_000, "{reported}");
    }
}
