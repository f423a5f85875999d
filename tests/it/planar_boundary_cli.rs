//! `radius` and `max-speed` on a planar problem, held to the line's engines: the seed
//! embedded in the plane (docs/semantics.md §13.7) must put the boundary where the line's
//! exact searches on problems/seed.toml do, within the planar search's resolution (10⁻³),
//! and the certificate of the claimed value must pass `check`.

use std::path::PathBuf;

use serde_json::Value;

use crate::common::cli::safereach;
use crate::common::tmp;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn json(dir: &std::path::Path, args: &[&str], code: i32) -> Value {
    let out = safereach(dir)
        .args(args)
        .assert()
        .code(code)
        .get_output()
        .clone();
    serde_json::from_slice(&out.stdout).expect("JSON")
}

#[test]
fn the_planar_safe_radius_of_the_seed_is_the_lines() {
    let dir = tmp();
    let seed = root().join("problems/seed.toml");
    let planar = root().join("problems/planar/seed-in-plane.toml");
    let line = json(dir.path(), &["radius", seed.to_str().unwrap(), "--json"], 0);
    let line = line["safe_radius"]
        .as_f64()
        .expect("the line's safe radius");
    let certs = dir.path().join("certs");
    let r = json(
        dir.path(),
        &[
            "radius",
            planar.to_str().unwrap(),
            "--json",
            "--certificates",
            certs.to_str().unwrap(),
        ],
        0,
    );
    let value = r["value"].as_f64().expect("a certified radius");
    let below = r["uncertified"]["value"]
        .as_f64()
        .expect("an uncertified probe");
    assert_eq!(r["certified"]["verdict"], "certified");
    // Certified at or above the line's boundary, uncertified at or below it, 10⁻³ apart.
    assert!(
        line <= value + 1e-9 && below <= line + 1e-9,
        "{below} < {line} <= {value}"
    );
    assert!(value - below <= 1e-3 + 1e-12, "{below}..{value}");
    safereach(dir.path())
        .arg("check")
        .arg(certs.join("radius-Wfile.json"))
        .args(["--require", "certified"])
        .assert()
        .code(0);
}

#[test]
fn the_planar_max_speed_of_the_seed_is_the_lines() {
    let dir = tmp();
    let seed = root().join("problems/seed.toml");
    let planar = root().join("problems/planar/seed-in-plane.toml");
    let line = json(
        dir.path(),
        &["max-speed", seed.to_str().unwrap(), "--json"],
        0,
    );
    let line = line["max_obstacle_speed"]
        .as_f64()
        .expect("the line's max speed");
    let cert = dir.path().join("cert.json");
    let r = json(
        dir.path(),
        &[
            "max-speed",
            planar.to_str().unwrap(),
            "--json",
            "--out",
            cert.to_str().unwrap(),
        ],
        0,
    );
    let value = r["value"].as_f64().expect("a certified speed");
    let above = r["uncertified"]["value"]
        .as_f64()
        .expect("an uncertified probe");
    assert!(
        value <= line + 1e-9 && line <= above + 1e-9,
        "{value} <= {line} < {above}"
    );
    assert!(above - value <= 1e-3 + 1e-12, "{value}..{above}");
    safereach(dir.path())
        .arg("check")
        .arg(&cert)
        .args(["--require", "certified"])
        .assert()
        .code(0);
    // What the planar searches refuse, named: region statements, an unknown obstacle.
    for args in [
        vec!["max-speed", planar.to_str().unwrap(), "--region"],
        vec!["radius", planar.to_str().unwrap(), "--region"],
        vec![
            "max-speed",
            planar.to_str().unwrap(),
            "--obstacle",
            "nobody",
        ],
    ] {
        let out = safereach(dir.path())
            .args(&args)
            .assert()
            .code(2)
            .get_output()
            .clone();
        let err = String::from_utf8_lossy(&out.stderr).to_string();
        assert!(
            err.contains("--region") || err.contains("nobody"),
            "{args:?}: {err}"
        );
    }
}
