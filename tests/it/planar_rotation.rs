//! Issue 36, 5d: rotating a whole planar problem about the origin changes no answer. Each
//! shipped planar problem is turned by an angle whose cosine and sine are decimals (3-4-5,
//! 90°, and 5-12-13's −67.4°), so every rotated coordinate is again an exact decimal and the
//! rotated problem is the same problem in another frame: its path, obstacle starts, start
//! boxes (90° only: a turned box is not a box), fixed directions and regions turn; the stop
//! polygon, the field of view and the danger zone live in the robot's frame and do not.
//! The answers must agree: the verdict, the witness's obstacle, guard and whether it
//! collides, and the bracket on s* to within 10⁻⁶ (the proofs are exact either way; the
//! solver's floats and the decimal grid its optima are rounded to are not turned with the
//! frame).

use safereach::analysis::planar::certify_text;
use safereach::core::planar::AXIS_LENGTH;
use safereach::proof::planar::check::check_planar;

use crate::common::paths::root;

/// A decimal as an integer and a power of ten: x = m · 10^-e.
fn decimal(v: &toml::Value) -> (i128, u32) {
    let text = match v {
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::Float(f) => format!("{f}"),
        other => panic!("not a number: {other}"),
    };
    let (int, frac) = text.split_once('.').unwrap_or((&text, ""));
    let digits = format!("{int}{frac}");
    (digits.parse().unwrap(), frac.len() as u32)
}

/// `m · 10^-e` as a TOML float (exactly that decimal: the reader takes the decimal written).
fn value(m: i128, e: u32) -> toml::Value {
    let sign = if m < 0 { "-" } else { "" };
    let digits = format!("{:0>width$}", m.unsigned_abs(), width = e as usize + 1);
    let (int, frac) = digits.split_at(digits.len() - e as usize);
    let text = if frac.is_empty() {
        format!("{sign}{int}.0")
    } else {
        format!("{sign}{int}.{frac}")
    };
    toml::Value::Float(text.parse().unwrap())
}

/// A rotation by (cos, sin) = (c/d, s/d) with integers c² + s² = d², d a power of 2 and 5's
/// product so that 1/d is a finite decimal.
#[derive(Clone, Copy)]
struct Turn {
    c: i128,
    s: i128,
    d: i128,
}

impl Turn {
    /// The point [x, y] turned.
    fn point(self, p: &toml::Value) -> toml::Value {
        let a = p.as_array().expect("a point");
        let ((x, ex), (y, ey)) = (decimal(&a[0]), decimal(&a[1]));
        let e = ex.max(ey);
        let (x, y) = (x * 10i128.pow(e - ex), y * 10i128.pow(e - ey));
        // 1/d = k · 10^-n exactly.
        let (k, n) = {
            let mut n = 0;
            while (10i128.pow(n)) % self.d != 0 {
                n += 1;
            }
            (10i128.pow(n) / self.d, n)
        };
        let rx = (self.c * x - self.s * y) * k;
        let ry = (self.s * x + self.c * y) * k;
        toml::Value::Array(vec![value(rx, e + n), value(ry, e + n)])
    }

    fn points(self, v: &toml::Value) -> toml::Value {
        toml::Value::Array(
            v.as_array()
                .unwrap()
                .iter()
                .map(|p| self.point(p))
                .collect(),
        )
    }

    fn quarter(self) -> bool {
        self.c == 0
    }
}

/// The problem file `text` turned by `turn` (module docs), as TOML text.
fn turned(text: &str, turn: Turn) -> String {
    let mut doc: toml::Table = text.parse().unwrap();
    let robot = doc["robot"].as_table_mut().unwrap();
    let path = robot.get("path").cloned().unwrap_or_else(|| {
        // The default: the x axis without end.
        robot.insert("path_end".into(), toml::Value::String("continue".into()));
        toml::Value::Array(vec![
            toml::Value::Array(vec![0.into(), 0.into()]),
            toml::Value::Array(vec![AXIS_LENGTH.into(), 0.into()]),
        ])
    });
    robot.insert("path".into(), turn.points(&path));
    for o in doc["obstacle"].as_array_mut().unwrap() {
        let o = o.as_table_mut().unwrap();
        for key in ["start", "direction"] {
            if let Some(p) = o.get(key).cloned() {
                o.insert(key.into(), turn.point(&p));
            }
        }
        if let Some(q) = o.get("region").cloned() {
            o.insert("region".into(), turn.points(&q));
        }
        if let (Some(lo), Some(hi)) = (o.get("start_min").cloned(), o.get("start_max").cloned()) {
            assert!(
                turn.quarter(),
                "a start box turns into a box by quarter turns only"
            );
            // A quarter turn maps the box [lo, hi] to the box of the turned corners.
            let (a, b) = (turn.point(&lo), turn.point(&hi));
            let (a, b) = (a.as_array().unwrap(), b.as_array().unwrap());
            let pick = |i: usize, least: bool| {
                let (u, v) = (a[i].as_float().unwrap(), b[i].as_float().unwrap());
                toml::Value::Float(if least { u.min(v) } else { u.max(v) })
            };
            o.insert(
                "start_min".into(),
                toml::Value::Array(vec![pick(0, true), pick(1, true)]),
            );
            o.insert(
                "start_max".into(),
                toml::Value::Array(vec![pick(0, false), pick(1, false)]),
            );
        }
    }
    toml::to_string(&doc).unwrap()
}

/// The turns every problem is tried under: 3-4-5 (53.1°) and 7-24-25's
/// (−24/25, 7/25) (163.7°). A turn keeps decimals decimal only when its denominator has no
/// prime factor but 2 and 5 (so not 5-12-13 or 8-15-17).
const TURNS: [Turn; 2] = [
    Turn { c: 3, s: 4, d: 5 },
    Turn {
        c: -24,
        s: 7,
        d: 25,
    },
];

/// A quarter turn, the one that keeps start boxes boxes.
const QUARTER: Turn = Turn { c: 0, s: 1, d: 1 };

/// Certifies `name` and its turned copies and holds their answers equal (module docs).
fn answers_do_not_turn(name: &str, turns: &[Turn]) {
    let path = root().join("problems/planar").join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    let (verdict, cert) = certify_text(&text, name, &[]).unwrap();
    for &turn in turns {
        let rotated = turned(&text, turn);
        let shown = format!(
            "{name} turned by ({}/{}, {}/{})",
            turn.c, turn.d, turn.s, turn.d
        );
        let (v, c) = certify_text(&rotated, &shown, &[])
            .unwrap_or_else(|e| panic!("{shown}: {e}\n{rotated}"));
        check_planar(&c).unwrap();
        assert_eq!(v, verdict, "{shown}");
        let near = |a: f64, b: f64| (a - b).abs() <= 1e-6;
        assert!(
            near(c.lower_bound, cert.lower_bound),
            "{shown}: lower bound {} vs {}",
            c.lower_bound,
            cert.lower_bound
        );
        match (c.upper_bound, cert.upper_bound) {
            (Some(a), Some(b)) => assert!(near(a, b), "{shown}: upper bound {a} vs {b}"),
            (a, b) => assert_eq!(a.is_some(), b.is_some(), "{shown}: witness {a:?} vs {b:?}"),
        }
        let w = |c: &safereach::proof::planar::certificate::PlanarCertificate| {
            // Not its brake step: worst behaviours a step apart may tie to within 1e-6.
            c.witness
                .as_ref()
                .map(|w| (w.obstacle.clone(), w.guard.clone(), w.collides))
        };
        assert_eq!(w(&c), w(&cert), "{shown}: the witness differs");
    }
}

#[test]
fn the_seed_in_the_plane_does_not_turn() {
    answers_do_not_turn("seed-in-plane.toml", &TURNS);
}

#[test]
fn the_crossing_car_does_not_turn() {
    answers_do_not_turn("crossing-car.toml", &[TURNS[0], QUARTER]);
}

#[test]
fn the_pedestrian_crossing_does_not_turn() {
    answers_do_not_turn("pedestrian-crossing.toml", &TURNS);
}

#[test]
fn the_overtaking_jogger_does_not_turn() {
    answers_do_not_turn("overtaking.toml", &TURNS);
}

#[test]
fn the_nav2_stop_polygon_does_not_turn() {
    answers_do_not_turn("nav2-stop-polygon.toml", &TURNS);
}
