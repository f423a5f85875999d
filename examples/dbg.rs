use safereach::model::Problem;
fn main() {
    let p = Problem::load(std::path::Path::new(&std::env::args().nth(1).unwrap())).unwrap();
    let a = safereach::analysis::analyse(&p).unwrap();
    let w = a.witness.as_ref().unwrap();
    let ex = p.params::<safereach::num::Exact>();
    let run =
        safereach::simulate::replay_exact(&ex, &w.obstacle_speeds, w.obstacle_speeds.len(), false);
    println!(
        "speeds {} records {} steps {} piece {:?} sep {:?} stopped_at_end {:?}",
        w.obstacle_speeds.len(),
        run.records.len(),
        w.steps.len(),
        w.piece,
        w.separation,
        run.records
            .last()
            .map(|r| (r.k, r.robot.mode, r.motion.end.mode))
    );
}
