//! The monitor and the robot's own motion (issue 37, items 1 and 2).
//!
//! 1. The robot's displacement between instants must be one its speeds and mode allow: a
//!    robot whose `robot_x` advances while it reports speed 0 (in `stop`, or without a mode)
//!    or moves farther or less far than its speeds allow is a `robot_motion` violation, and the
//!    collision check uses the positions the trace shows, not its claim to stand.
//! 2. Between two samples the separation can fall below the clearance even when neither
//!    sample shows it while moving: a robot that comes to rest within the period at a gap
//!    below the clearance collided while still moving. The monitor checks the period with the
//!    worst motion the premises allow: the robot braking at exactly b from its speed at the
//!    period's start, the obstacle approaching at up to W.
//!
//! The independent answers are closed forms: the kinematics of constant acceleration
//! (docs/semantics.md §2) and the rest gap of a robot braking at b (§6), checked case by case
//! and on a grid against the monitor.

use safereach::core::semantics::Mode;
use safereach::monitor::trace::Format;
use safereach::monitor::{Check, Event, Monitor, Sample};
use safereach::proof::certificate::Certificate;

use crate::common::monitoring::{sample_events, text_events};
use crate::common::paths::fixture;

/// The seed's certificate: W 0.15 m/s, b 0.05 m/s², dt 0.1 s, L 1, ρ 1.4 m, v_max 0.2 m/s,
/// a 0.1 m/s², clearance 0.
fn seed_certificate() -> Certificate {
    let text = std::fs::read_to_string(fixture("seed.cert.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

fn seed_monitor() -> Monitor {
    Monitor::new(&seed_certificate()).unwrap()
}

/// The check named `name` (by name, so that a build without it fails the test, not its
/// compilation).
fn named(name: &str) -> Check {
    Check::from_name(name).unwrap_or_else(|| panic!("the monitor has no check `{name}`"))
}

/// The events of check `name`.
fn of<'a>(events: &'a [Event], name: &str) -> Vec<&'a Event> {
    let check = named(name);
    events.iter().filter(|e| e.check == check).collect()
}

/// A sample of obstacle 0.
fn sample(t: f64, x: f64, v: f64, mode: Option<Mode>, obstacle_x: f64) -> Sample {
    Sample {
        t,
        robot_x: x,
        robot_v: v,
        robot_mode: mode,
        obstacle_id: 0,
        obstacle_x,
        obstacle_v: None,
        obstacle_t: None,
    }
}

/// Item 1, the trace: the robot reports speed 0 in mode `stop` while its position
/// advances 0.05 m every period, through a standing obstacle first seen at 1.525 m. Each
/// period is a `robot_motion` violation (observed the displacement, bound 0: a robot in
/// `stop` does not move), and every sample at which the robot, having moved, is at or past
/// the obstacle is a `collision` — exactly the samples whose gap is ≤ 0.
#[test]
fn a_robot_that_moves_while_claiming_to_stand_is_flagged_and_its_crash_seen() {
    let obstacle = 1.525;
    let xs: Vec<f64> = (0..=40).map(|k| 0.05 * k as f64).collect();
    let trace: Vec<Sample> = xs
        .iter()
        .enumerate()
        .map(|(k, &x)| sample(k as f64 / 10.0, x, 0.0, Some(Mode::Stop), obstacle))
        .collect();
    let mut m = seed_monitor();
    let events = sample_events(&mut m, &trace);
    let motion = of(&events, "robot_motion");
    assert_eq!(motion.len(), 40, "{events:?}");
    for (k, e) in (1..).zip(&motion) {
        assert_eq!(e.t, Some(trace[k].t));
        assert!((e.observed.unwrap() - (xs[k] - xs[k - 1])).abs() < 1e-12);
        assert_eq!(e.bound, Some(0.0));
        assert!(e.detail.unwrap().to_string().contains("stop"), "{e}");
    }
    let crashed: Vec<Option<f64>> = of(&events, "collision").iter().map(|e| e.t).collect();
    let expected: Vec<Option<f64>> = trace
        .iter()
        .skip(1)
        .filter(|s| s.obstacle_x - s.robot_x <= 0.0)
        .map(|s| Some(s.t))
        .collect();
    assert!(!expected.is_empty());
    assert_eq!(crashed, expected);
    // Without a mode, speed 0 at both ends allows at most a·Δt²/2 (accelerate, then stop at
    // once): 0.05 m is far beyond it.
    let unmoded: Vec<Sample> = trace
        .iter()
        .map(|s| Sample {
            robot_mode: None,
            ..*s
        })
        .collect();
    let mut m = seed_monitor();
    let events = sample_events(&mut m, &unmoded);
    let motion = of(&events, "robot_motion");
    assert_eq!(motion.len(), 40);
    assert!((motion[0].bound.unwrap() - 0.1 * 0.1 * 0.1 / 2.0).abs() < 1e-15);
    assert_eq!(of(&events, "collision").len(), expected.len());
}

/// The one `robot_motion` event of a two-sample trace whose robot drives at `v` from `x0` to
/// `x1`, and its text.
fn motion_event(x0: f64, x1: f64, v: f64) -> (Event, String) {
    let trace = [
        sample(0.0, x0, v, Some(Mode::Drive), 10.0),
        sample(0.1, x1, v, Some(Mode::Drive), 10.0),
    ];
    let mut m = seed_monitor();
    let events = sample_events(&mut m, &trace);
    let e = of(&events, "robot_motion");
    assert_eq!(e.len(), 1, "{events:?}");
    (*e[0], e[0].to_string())
}

/// Item 1, both ways: farther than the speeds allow (0.5 m/s shown by the positions while
/// `drive` at 0.1 m/s reports; the most is ∫ min(v₀ + a·s, v_max) ds = 0.0105 m), and less
/// far (positions that stand still while the robot reports 0.2 m/s; the least is
/// v₁·Δt − a·Δt²/2 = 0.0195 m). A robot that moves as its speeds say raises nothing.
#[test]
fn a_displacement_beyond_or_short_of_what_the_speeds_allow_is_flagged() {
    let (far, text) = motion_event(0.0, 0.05, 0.1);
    assert!((far.observed.unwrap() - 0.05).abs() < 1e-15);
    assert!((far.bound.unwrap() - (0.1 * 0.1 + 0.1 * 0.01 / 2.0)).abs() < 1e-15);
    assert!(text.contains(" > bound"), "{text}");
    let (short, text) = motion_event(3.0, 3.0, 0.2);
    assert_eq!(short.observed, Some(0.0));
    assert!((short.bound.unwrap() - (0.2 * 0.1 - 0.1 * 0.01 / 2.0)).abs() < 1e-15);
    assert!(text.contains(" < bound"), "{text}");

    // As the model moves: accelerating at a, driving, braking at b into rest inside a period.
    let (a, b, dt) = (0.1, 0.05, 0.1);
    let moving = [
        sample(0.0, 0.0, 0.15, Some(Mode::Accelerate), 10.0),
        sample(
            dt,
            0.15 * dt + a * dt * dt / 2.0,
            0.16,
            Some(Mode::Brake),
            10.0,
        ),
    ];
    let mut m = seed_monitor();
    assert!(sample_events(&mut m, &moving).is_empty());
    let x0 = moving[1].robot_x;
    let braking = [
        sample(dt, x0, 0.16, Some(Mode::Brake), 10.0),
        sample(
            2.0 * dt,
            x0 + 0.16 * dt - b * dt * dt / 2.0,
            0.155,
            Some(Mode::Brake),
            10.0,
        ),
    ];
    let mut m = seed_monitor();
    assert!(sample_events(&mut m, &braking).is_empty());
    let stopping = [
        sample(0.0, 1.0, 0.003, Some(Mode::Brake), 10.0),
        sample(
            dt,
            1.0 + 0.003 * 0.003 / (2.0 * b),
            0.0,
            Some(Mode::Stop),
            10.0,
        ),
    ];
    let mut m = seed_monitor();
    assert!(sample_events(&mut m, &stopping).is_empty());
}

/// Item 2, the numbers as a whole trace, read as CSV: the robot drives at v_max, then
/// slows at exactly b to rest; at v = 0.005 m/s the gap is +0.01 m, and at the rest sample
/// one period later −0.005 m. Braking from 0.005 m/s at b takes exactly one period, so the
/// robot was moving until that sample: a collision, reported there (observed the gap at rest,
/// the worst separation the period allows). The obstacle's last step is 0.1475 m/s ≤ W, and
/// every premise holds. With the rest gap +0.005 m instead, nothing is raised.
#[test]
fn a_collision_between_the_last_moving_sample_and_the_rest_sample_is_reported() {
    for modes in [false, true] {
        for rest_gap in [-0.005, 0.005] {
            let csv = rest_trace(modes, rest_gap);
            let mut m = seed_monitor();
            let events = text_events(&mut m, &csv, Some(Format::Csv));
            let crashes = of(&events, "collision");
            if rest_gap < 0.0 {
                assert_eq!(crashes.len(), 1, "modes {modes}: {events:?}");
                assert_eq!(crashes[0].t, Some(9.0));
                assert!((crashes[0].observed.unwrap() - rest_gap).abs() < 1e-12);
            } else {
                assert!(crashes.is_empty(), "modes {modes}: {events:?}");
            }
            // The trace is physically consistent, and within the premises.
            let others: Vec<&Event> = events
                .iter()
                .filter(|e| e.check != named("collision"))
                .filter(|e| !(modes && e.check == Check::ControllerReaction))
                .collect();
            assert!(others.is_empty(), "modes {modes}: {others:?}");
        }
    }
}

/// The rest trace of [`a_collision_between_the_last_moving_sample_and_the_rest_sample_is_reported`]:
/// 50 periods at 0.2 m/s from 0, then 40 periods braking at b = 0.05 (v = 0.005 at t = 8.9,
/// rest at t = 9.0 at x = 1.4), the obstacle standing at 1.40975 (gap 0.01 at t = 8.9) and
/// at 1.4 + `rest_gap` from t = 9.0, then moving on at W. With `modes`, the modes `drive`,
/// `brake` and `stop` (the controller is then late: the obstacle is in danger from the
/// second sample on).
fn rest_trace(modes: bool, rest_gap: f64) -> String {
    let mut csv = String::from(if modes {
        "t,robot_x,robot_v,robot_mode,obstacle_id,obstacle_x\n"
    } else {
        "t,robot_x,robot_v,obstacle_id,obstacle_x\n"
    });
    for k in 0..=93u32 {
        let t = f64::from(k) / 10.0;
        let (x, v, mode) = if k <= 50 {
            (
                0.02 * f64::from(k),
                0.2,
                if k < 50 { "drive" } else { "brake" },
            )
        } else if k < 90 {
            let j = f64::from(k - 50);
            (1.0 + 0.02 * j - 0.00025 * j * j, 0.2 - 0.005 * j, "brake")
        } else {
            (1.4, 0.0, "stop")
        };
        let y = if k < 90 {
            1.40975
        } else {
            1.4 + rest_gap - 0.015 * f64::from(k - 90)
        };
        if modes {
            csv += &format!("{t:?},{x:?},{v:?},{mode},0,{y:?}\n");
        } else {
            csv += &format!("{t:?},{x:?},{v:?},0,{y:?}\n");
        }
    }
    csv
}

/// Item 2, within the period: a robot braking at b from v₀ ≤ b·Δt rests at τ = t₀ + v₀/b,
/// and while it moves the obstacle may approach at up to W. The monitor reports a collision
/// exactly when the worst the premises allow collides: the robot moving until τ and the
/// obstacle at W until then (or where the next sample shows it, if that is nearer), a rest gap
/// of max(g₁, g₀ − W·v₀/b − v₀²/(2b)) < 0. Checked against that closed form on a grid of
/// speeds, gaps and true obstacle speeds; every case where the true run (obstacle at its
/// constant w) collides is among those reported.
#[test]
fn within_a_period_the_worst_motion_the_premises_allow_is_checked() {
    let (w_max, b, dt) = (0.15, 0.05, 0.1);
    let mut reported = 0;
    let mut hit_at_rest_without_collision = 0;
    for i in 1..=10 {
        let v0 = b * dt * f64::from(i) / 10.0;
        let rest = v0 * v0 / (2.0 * b);
        let tau = v0 / b;
        for j in 1..=40 {
            let g0 = 0.0005 * f64::from(j);
            for k in 0..=6 {
                let w = w_max * f64::from(k) / 6.0;
                let g1 = g0 - w * dt - rest;
                let worst = g1.max(g0 - w_max * tau - rest);
                if worst.abs() < 1e-9 {
                    continue;
                }
                let trace = [
                    sample(0.0, 0.0, v0, Some(Mode::Brake), g0),
                    sample(dt, rest, 0.0, Some(Mode::Stop), g0 - w * dt),
                ];
                let mut m = seed_monitor();
                m.observe(&trace[0]);
                let events = m.observe(&trace[1]).events.to_vec();
                let crash = of(&events, "collision");
                let case = format!("v0 {v0}, g0 {g0}, w {w}: {events:?}");
                assert_eq!(crash.len(), usize::from(worst < 0.0), "{case}");
                if let Some(e) = crash.first() {
                    assert!((e.observed.unwrap() - worst).abs() < 1e-12, "{case}");
                    reported += 1;
                }
                let truly = g0 - w * tau - rest;
                assert!(truly >= 0.0 || !crash.is_empty(), "missed: {case}");
                if g1 < 0.0 && crash.is_empty() {
                    hit_at_rest_without_collision += 1;
                }
                assert!(of(&events, "robot_motion").is_empty(), "{case}");
            }
        }
    }
    assert!(reported > 100, "{reported}");
    // A robot that is reached only after it stopped did not collide.
    assert!(
        hit_at_rest_without_collision > 100,
        "{hit_at_rest_without_collision}"
    );
}
