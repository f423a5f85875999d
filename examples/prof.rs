use safereach::model::Problem;
use safereach::schedule::Decomposition;
use std::time::Instant;
fn main() {
    let p = Problem::load(std::path::Path::new("problems/seed.toml")).unwrap();
    let a = safereach::analysis::analyse(&p).unwrap();
    let n = 200;
    let t = Instant::now();
    for _ in 0..n {
        std::hint::black_box(Decomposition::new(&p));
    }
    println!("decomp {:?}", t.elapsed() / n);
    let d = Decomposition::new(&p);
    let t = Instant::now();
    for _ in 0..n {
        for pc in &d.pieces {
            std::hint::black_box(d.program(pc));
        }
    }
    println!("programs {:?}", t.elapsed() / n);
    let prog = d.program(&d.pieces[0]);
    let t = Instant::now();
    for _ in 0..n {
        std::hint::black_box(safereach::lp::solve(&prog, 0.0));
    }
    println!("lp {:?}", t.elapsed() / n);
    let w = a.witness.unwrap();
    let ex = p.params::<safereach::num::Exact>();
    let t = Instant::now();
    for _ in 0..n {
        std::hint::black_box(safereach::simulate::replay_exact(
            &ex,
            &w.obstacle_speeds,
            w.obstacle_speeds.len(),
            false,
        ));
    }
    println!("replay {:?}", t.elapsed() / n);
    let r =
        safereach::simulate::replay_exact(&ex, &w.obstacle_speeds, w.obstacle_speeds.len(), false);
    let t = Instant::now();
    for _ in 0..n {
        std::hint::black_box(safereach::simulate::trace(&ex, &r));
    }
    println!("trace {:?}", t.elapsed() / n);
    let t = Instant::now();
    for _ in 0..n {
        std::hint::black_box(p.params::<safereach::num::Exact>());
    }
    println!("params {:?}", t.elapsed() / n);
}
