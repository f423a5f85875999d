use safereach::model::Problem;
fn main() {
    let p = Problem::load(std::path::Path::new("problems/seed.toml")).unwrap();
    let a = safereach::analysis::analyse(&p).unwrap();
    let w = a.witness.unwrap();
    let ex = p.params::<safereach::num::Exact>();
    for _ in 0..50 { std::hint::black_box(safereach::simulate::replay_exact(&ex, &w.obstacle_speeds, w.obstacle_speeds.len(), false)); }
}
