//! Issue 15's table of bad input, as a new user met it: each case is the real binary on a
//! bad flag or file, and must exit 2 with the flag or file, the dotted key and the reason in
//! the user's terms — never serde's or Rust's words ("invalid type", "expected f64", "not a
//! TOML value", "recursion limit", debug structures), never a 309-digit number, and never a
//! `--set` the user did not type.

use std::path::Path;

use crate::common::cli::{safereach, stdout};
use crate::common::forgery::resign;
use crate::common::paths::{fixture, seed_file};
use crate::common::tmp;
use safereach::proof::certificate::Certificate;

/// Words that are not the user's.
const FOREIGN: &[&str] = &[
    "invalid type",
    "expected f64",
    "expected u32",
    "not a TOML value",
    "invalid boolean",
    "string values must be quoted",
    "recursion limit",
    "stream did not contain valid UTF-8",
    "Some(",
    "Piece {",
    "0000000000000000000000",
];

/// One row: the arguments (run in `dir`), the exit code, and what the message must say.
struct Row {
    what: &'static str,
    args: Vec<String>,
    code: i32,
    says: Vec<String>,
    /// The message must not mention `--set` (the user typed none).
    no_set: bool,
}

fn row(what: &'static str, args: &[&str], says: &[&str]) -> Row {
    Row {
        what,
        args: args.iter().map(|a| a.to_string()).collect(),
        code: 2,
        says: says.iter().map(|s| s.to_string()).collect(),
        no_set: !args.contains(&"--set"),
    }
}

/// The seed problem with `from` replaced by `to`, written to `dir/name`.
fn edited_seed(dir: &Path, name: &str, from: &str, to: &[u8]) {
    let text = std::fs::read(seed_file()).unwrap();
    let at = text
        .windows(from.len())
        .position(|w| w == from.as_bytes())
        .unwrap_or_else(|| panic!("{from:?} is in the seed"));
    let mut out = text[..at].to_vec();
    out.extend_from_slice(to);
    out.extend_from_slice(&text[at + from.len()..]);
    std::fs::write(dir.join(name), out).unwrap();
}

#[test]
fn every_bad_input_of_issue_15_is_answered_in_the_users_terms() {
    let dir = tmp();
    let d = dir.path();
    std::fs::copy(seed_file(), d.join("seed.toml")).unwrap();
    edited_seed(
        d,
        "typed.toml",
        "max_speed = 0.2 ",
        b"max_speed = \"fast\" ",
    );
    // An invalid byte in the name, 11th character of its line.
    edited_seed(d, "utf8.toml", "name = \"seed\"", b"name = \"se\xffed\"");
    let seed_text = std::fs::read_to_string(seed_file()).unwrap();
    let name_line = seed_text
        .lines()
        .position(|l| l.starts_with("name = \"seed\""))
        .unwrap()
        + 1;
    let utf8_place = format!("line {name_line}, column 11");
    std::fs::write(
        d.join("deep.toml"),
        format!("{} = 1\n", vec!["a"; 5000].join(".")),
    )
    .unwrap();
    let grid = |name: &str, axes: &str| {
        std::fs::write(
            d.join(name),
            format!("base = \"seed.toml\"\n[axes]\n{axes}\n"),
        )
        .unwrap();
    };
    grid("misspelt.toml", "\"robot.maxspeed\" = [0.1]");
    grid(
        "spaced.toml",
        "\" robot.max_speed\" = [0.1, 0.2]\n\"robot.max_speed\" = [0.1, 0.2]",
    );
    let values: Vec<String> = (1..=256)
        .map(|i| format!("{}", i as f64 / 1000.0))
        .collect();
    let huge: Vec<String> = [
        "robot.max_speed",
        "robot.acceleration",
        "robot.braking",
        "robot.clearance",
        "controller.reaction_radius",
        "controller.buffer",
        "environment.obstacle_speed",
        "controller.assumed_obstacle_speed",
    ]
    .iter()
    .map(|k| format!("\"{k}\" = [{}]", values.join(", ")))
    .collect();
    grid("huge.toml", &huge.join("\n"));
    // A trace without its header.
    std::fs::copy(fixture("seed.cert.json"), d.join("cert.json")).unwrap();
    let trace = std::fs::read_to_string(fixture("seed-w0.25.run.csv")).unwrap();
    let body: Vec<&str> = trace.lines().skip(1).take(5).collect();
    std::fs::write(d.join("noheader.csv"), body.join("\n") + "\n").unwrap();
    // A forged certificate: proofs swapped, re-signed.
    let mut forged: Certificate =
        serde_json::from_str(&std::fs::read_to_string(fixture("seed.cert.json")).unwrap()).unwrap();
    forged.proofs.swap(0, 1);
    resign(&mut forged);
    std::fs::write(
        d.join("forged.json"),
        serde_json::to_string(&forged).unwrap(),
    )
    .unwrap();

    // A certificate whose field has the wrong JSON type.
    let mut typed: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(fixture("seed.cert.json")).unwrap()).unwrap();
    typed["problem"]["robot"]["max_speed"] = serde_json::json!([1]);
    std::fs::write(d.join("typed-cert.json"), typed.to_string()).unwrap();
    let mut rows = vec![
        row(
            "a word for a number",
            &["certify", "seed.toml", "--set", "robot.max_speed=fast"],
            &[
                "--set robot.max_speed=fast",
                "robot.max_speed",
                "expected a number in m/s",
            ],
        ),
        row(
            "yes for a flag",
            &[
                "certify",
                "seed.toml",
                "--set",
                "controller.wrong_assumption_brake=yes",
            ],
            &[
                "controller.wrong_assumption_brake",
                "expected true or false, got `yes`",
            ],
        ),
        row(
            "a wrong type in the file",
            &["certify", "typed.toml"],
            &[
                "typed.toml: robot.max_speed = \"fast\"",
                "expected a number in m/s, got the text \"fast\"",
                "typed.toml:",
            ],
        ),
        row(
            "a speed beyond range",
            &["radius", "seed.toml", "--speeds", "1e308"],
            &[
                "--speeds 1e308",
                "environment.obstacle_speed",
                "out of range",
            ],
        ),
        row(
            "nan as a speed",
            &["radius", "seed.toml", "--speeds", "nan"],
            &["--speeds nan", "not a finite number"],
        ),
        row(
            "an empty element of a list",
            &["radius", "seed.toml", "--speeds", "0.1,,0.2"],
            &["--speeds 0.1,,0.2", "element 2 is empty"],
        ),
        row(
            "an empty element of explore's list",
            &["explore", "seed.toml", "--speeds", "0,,0.15"],
            &["--speeds 0,,0.15", "element 2 is empty"],
        ),
        row(
            "a misspelt key in a grid file",
            &["sweep", "misspelt.toml", "--out", "out"],
            &["misspelt.toml", "axes.\"robot.maxspeed\"", "unknown key"],
        ),
        row(
            "a grid axis with a leading space",
            &["sweep", "spaced.toml", "--out", "out"],
            &["spaced.toml", "\" robot.max_speed\"", "space"],
        ),
        row(
            "a grid whose cells cannot be counted",
            &["sweep", "huge.toml", "--out", "out"],
            &["huge.toml", "more cells than can be counted"],
        ),
        row(
            "a 5000-part dotted key",
            &["certify", "deep.toml"],
            &["deep.toml", "line 1", "nested too deeply"],
        ),
        row(
            "invalid UTF-8",
            &["certify", "utf8.toml"],
            &["utf8.toml", "not UTF-8", &utf8_place],
        ),
        row(
            "a certificate field of the wrong JSON type",
            &["check", "typed-cert.json"],
            &[
                "typed-cert.json: not a safereach certificate",
                "problem.robot.max_speed: expected a number, got a list",
            ],
        ),
        row(
            "a CSV without its header",
            &["monitor", "--certificate", "cert.json", "noheader.csv"],
            &["--columns", "nothing was checked"],
        ),
    ];
    rows.push(Row {
        code: 1,
        ..row(
            "a re-signed certificate with its proofs swapped",
            &["check", "forged.json"],
            &[
                "forged.json: INVALID",
                "but piece 0 of the problem is braking on danger at step",
            ],
        )
    });
    let mut wrong = Vec::new();
    for r in &rows {
        let out = safereach(d).args(&r.args).output().expect("runs");
        let text = stdout(&out) + &String::from_utf8_lossy(&out.stderr);
        let code = out.status.code();
        let missing: Vec<&String> = r
            .says
            .iter()
            .filter(|s| !text.contains(s.as_str()))
            .collect();
        let foreign: Vec<&&str> = FOREIGN.iter().filter(|s| text.contains(**s)).collect();
        let set = r.no_set && text.contains("--set");
        if code != Some(r.code) || !missing.is_empty() || !foreign.is_empty() || set {
            wrong.push(format!(
                "{} ({:?}): exit {code:?}, missing {missing:?}, foreign {foreign:?}, --set {set}:\n{text}",
                r.what, r.args
            ));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}
