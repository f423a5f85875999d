//! The human-readable answer of a search certificate (a scene with lane changes or
//! position ranges): the verdict, s* exactly, the worst case told as what the robot did
//! (its lane changes and why it braked), and s* per obstacle.

use safereach::core::semantics::BrakeReason;
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
            "{x:.6} m (exactly {})",
            cert.min_separation_exact.as_deref().unwrap_or("?")
        ),
        (None, _) => "+inf (the robot never moves in an obstacle's lane)".to_string(),
    };
    s += &format!("  worst-case minimum separation s* = {sep}\n");
    if let Some(lb) = cert.lower_bound {
        s += &format!(
            "  rigorous lower bound {lb:.9} m vs clearance {} m\n",
            cert.clearance
        );
    }
    if let Some(w) = &cert.witness {
        let dt = scene.robot.control_period;
        let name = &scene.obstacles[w.obstacle].name;
        let mut story: Vec<String> = w
            .lane_changes
            .iter()
            .map(|c| {
                format!(
                    "changes from lane {} to lane {} at t = {:.3} s",
                    c.from,
                    c.to,
                    c.step as f64 * dt
                )
            })
            .collect();
        story.push(match w.brake {
            Some((k, reason)) => format!(
                "brakes at t = {:.3} s ({})",
                k as f64 * dt,
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
                format!("separation {:.6} m", w.separation.unwrap_or(f64::NAN))
            }
        );
    }
    s += "  per obstacle:\n";
    for o in &cert.obstacles {
        let sep = match (o.min_separation, o.unbounded) {
            (_, true) => "-inf".to_string(),
            (Some(x), _) => format!("{x:.6} m"),
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
    s += "  premises:\n";
    for p in &cert.premises {
        s += &format!(
            "    {:<21} {} {} {}\n",
            p.name,
            p.description(),
            p.bound,
            p.unit()
        );
    }
    s
}
