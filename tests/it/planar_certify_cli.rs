//! `safereach certify` on shipped planar problems, held to independent answers: the seed
//! embedded in the plane has the line's s* (0.33 m, docs/semantics.md §13.7) inside a
//! bracket of at most 1e-9; the crossing car's refutation is a witness whose replayed
//! separation is at or below the clearance, and the bracket holds it.

use std::path::PathBuf;

use crate::common::cli::safereach;
use crate::common::rational;

fn problem(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("problems/planar/{name}.toml"))
}

fn certify(name: &str, code: i32) -> serde_json::Value {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let out = safereach(dir.path())
        .arg("certify")
        .arg(problem(name))
        .arg("--json")
        .assert()
        .code(code)
        .get_output()
        .stdout
        .clone();
    serde_json::from_slice(&out).expect("certify --json prints JSON")
}

#[test]
fn the_seed_in_the_plane_is_certified_with_the_lines_s_star_bracketed_to_1e_6() {
    let r = certify("seed-in-plane", 0);
    assert_eq!(r["verdict"], "certified");
    let lower = r["lower_bound"].as_f64().expect("a lower bound");
    let upper = r["upper_bound"].as_f64().expect("a witness");
    // The line's s* for the seed (problems/seed.toml, analysed in tests/it/analysis.rs).
    let line = 0.33;
    assert!(
        lower <= line + 1e-12 && line <= upper + 1e-12,
        "[{lower}, {upper}]"
    );
    assert!(upper - lower <= 1e-9 + 1e-12, "[{lower}, {upper}]");
    assert_eq!(r["witness"]["obstacle"], "oncoming");
}

#[test]
fn the_crossing_car_is_refuted_by_a_colliding_witness() {
    let r = certify("crossing-car", 1);
    assert_eq!(r["verdict"], "refuted");
    let lower = r["lower_bound"].as_f64().expect("a lower bound");
    let upper = r["upper_bound"].as_f64().expect("a witness");
    assert!(
        upper <= 0.0,
        "the witness's separation {upper} reaches the clearance 0"
    );
    assert!(lower <= upper, "[{lower}, {upper}]");
    // The discs (0.3 m and 1 m) overlap at most fully: no separation below -(1.3).
    assert!(lower >= -1.3 - 1e-9, "{lower}");
    let car = &r["witness"]["obstacles"][0];
    assert_eq!(car["name"], "car");
    // Exact rationals as text ("n/d").
    let rational = |v: &serde_json::Value| rational(v.as_str().expect("a rational's text"));
    for v in car["velocities"].as_array().expect("velocities") {
        let (vx, vy) = (rational(&v[0]), rational(&v[1]));
        assert!(vx.abs() < 1e-12 && (0.0..=10.0 + 1e-9).contains(&vy), "{v}");
    }
}

#[test]
fn simulate_runs_random_planar_runs_and_names_the_closest() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let out = safereach(dir.path())
        .arg("simulate")
        .arg(problem("crossing-car"))
        .args(["--runs", "5", "--json"])
        .assert()
        .code(0)
        .get_output()
        .stdout
        .clone();
    let r: serde_json::Value = serde_json::from_slice(&out).expect("JSON");
    assert_eq!(r["runs"], 5);
    assert_eq!(r["collisions"], 0);
    assert_eq!(r["closest_obstacle"], "car");
    // A random run is a behaviour: never below the proved bound of certify.
    let least = r["least_separation"].as_f64().expect("a closest run");
    assert!(least >= -1.208413535, "{least}");
}
