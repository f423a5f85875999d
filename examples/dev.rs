use safereach::model::Problem;
fn main() {
    let path = std::env::args().nth(1).unwrap();
    let mut p: Problem = toml::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    for kv in std::env::args().skip(2) {
        let (k, v) = kv.split_once('=').unwrap();
        let v: f64 = v.parse().unwrap();
        match k {
            "W" => p.environment.obstacle_speed = v,
            "rho" => p.controller.reaction_radius = v,
            "L" => p.robot.latency = v as u32,
            "g0" => p.environment.initial_gap = v,
            _ => panic!(),
        }
    }
    let t = std::time::Instant::now();
    let a = safereach::analysis::analyse(&p).unwrap();
    let el = t.elapsed();
    println!(
        "verdict {:?} s*={:?} lb={:?} never={} solved={} pieces={} time={:?}",
        a.verdict,
        a.min_separation,
        a.lower_bound.as_ref().map(|x| x.to_f64().value()),
        a.never_stops,
        a.programs_solved,
        a.outcomes.len(),
        el
    );
    println!(
        "first_brake {} last_brake {} cruise {}",
        a.decomposition.first_brake, a.decomposition.last_brake, a.decomposition.cruise_from
    );
    for o in &a.outcomes {
        println!(
            "{:?} {:?}",
            o.piece,
            match &o.result {
                safereach::analysis::PieceResult::Proved {
                    kind,
                    bound,
                    optimum,
                    ..
                } => format!(
                    "{kind:?} {:.9} {:?}",
                    bound.to_f64().value(),
                    optimum.as_ref().map(|o| o.0)
                ),
                r => format!("{r:?}"),
            }
        );
    }
    if let Some(w) = &a.witness {
        println!(
            "witness collides={} sep={:?} shift={} steps={}",
            w.collides,
            w.separation,
            w.shift,
            w.steps.len()
        );
        for s in w.steps.iter().rev().take(20).rev() {
            println!("  {:?}", s);
        }
    }
}
