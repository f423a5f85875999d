use safereach::analysis::{Options, WitnessPolicy, analyse_with};
use safereach::model::Problem;
fn main() {
    let p = Problem::load(std::path::Path::new("problems/seed.toml")).unwrap();
    for _ in 0..200 {
        std::hint::black_box(analyse_with(&p, Options { witness: WitnessPolicy::ToRefute }).unwrap());
    }
}
