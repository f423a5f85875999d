//! The human-readable answer of a search certificate (a scene with lane changes or
//! position ranges): the verdict, s* exactly, the worst case told as what the robot did
//! (its lane changes and why it braked), and s* per obstacle.

use safereach::core::semantics::BrakeReason;
use safereach::core::show::{up, value};

use super::certify::{lower_bound_text, premises_text};
use safereach::proof::search_certificate::SearchCertificate;

/// The summary `certify` prints for a search certificate.
pub fn search_summary(cert: &SearchCertificate) -> String {
    let scene = &cert.scene;
    let mut s = format!("{}: {}\n", scene.name, cert.verdict.as_str());
    let sep = match (&cert.min_separation, cert.never_stops) {
        (_, true) => {
            "-inf (the robot can drive on for ever in the lane of an obstacle ahead)".to_string()
        }
        (Some(x), _) => format!(
            "{} m (exactly {})",
            value(*x),
            cert.min_separation_exact.as_deref().unwrap_or("?")
        ),
        (None, _) => "+inf (the robot never moves in an obstacle's lane)".to_string(),
    };
    s += &format!("  worst-case minimum separation s* = {sep}\n");
    if cert.lower_bound.is_some() {
        s += &lower_bound_text(cert.lower_bound, cert.clearance);
    }
    if let Some(w) = &cert.witness {
        let dt = scene.robot.control_period;
        let name = &scene.obstacles[w.obstacle].name;
        let mut story: Vec<String> = w
            .lane_changes
            .iter()
            .map(|c| {
                format!(
                    "changes from lane {} to lane {} at t = {} s",
                    c.from,
                    c.to,
                    value(c.step as f64 * dt)
                )
            })
            .collect();
        story.push(match w.brake {
            Some((k, reason)) => format!(
                "brakes at t = {} s ({})",
                value(k as f64 * dt),
                match reason {
                    BrakeReason::CollisionDanger => "collision danger",
                    BrakeReason::WrongAssumption => "an obstacle seen faster than V_a",
                    BrakeReason::Destination => "its destination",
                }
            ),
            None => "never brakes".to_string(),
        });
        s += &format!(
            "  worst case: obstacle \"{name}\" in lane {}; the robot {}; {}\n",
            w.lane,
            story.join(", then "),
            if w.collides {
                "collides".to_string()
            } else {
                match w.separation {
                    Some(r) => format!("separation {} m", up(r, 9)),
                    None => "separation -inf".to_string(),
                }
            }
        );
    }
    s += "  per obstacle:\n";
    for o in &cert.obstacles {
        let sep = match (o.min_separation, o.unbounded) {
            (_, true) => "-inf".to_string(),
            (Some(x), _) => format!("{} m", value(x)),
            (None, _) => "+inf (never in its lane while moving)".to_string(),
        };
        s += &format!(
            "    {:<16} lane {:<3} s* {}\n",
            format!("\"{}\"", o.name),
            o.lane,
            sep
        );
    }
    s += &format!(
        "  runs searched: {} ({} step starts), exactly, without a solver\n",
        cert.runs, cert.nodes
    );
    s += &premises_text(&cert.premises);
    s
}
