//! Issue 15's fuzzing findings of unbounded work, as a new user met them: each case is the
//! real binary, and must end promptly — refused with the budget and the flag that raises
//! it (exit 2), or inconclusive with the reason (exit 3) — never a hang, an abort or a
//! silent wrap; outputs never replace what is not a regular file; traces with any line
//! ending are read, and "nothing was checked" is never exit 0.

use std::path::Path;

use crate::common::cli::{safereach, stdout};
use crate::common::paths::{fixture, problem_file, seed_file};
use crate::common::tmp;

/// One row: the arguments (run in `dir`), the exit code, and what the output must say.
struct Row {
    what: &'static str,
    args: Vec<String>,
    code: i32,
    says: Vec<&'static str>,
}

fn row(what: &'static str, args: &[&str], code: i32, says: &[&'static str]) -> Row {
    Row {
        what,
        args: args.iter().map(|a| a.to_string()).collect(),
        code,
        says: says.to_vec(),
    }
}

/// A grid over the seed with `axes` lines and `extra` top-level keys.
fn grid(dir: &Path, name: &str, extra: &str, axes: &[String]) {
    std::fs::write(
        dir.join(name),
        format!(
            "base = \"seed.toml\"\n{extra}\n[axes]\n{}\n",
            axes.join("\n")
        ),
    )
    .unwrap();
}

/// `n` values of an axis, all valid for `key`.
fn axis(key: &str, n: usize) -> String {
    let values: Vec<String> = (1..=n)
        .map(|i| format!("{}", 0.05 + i as f64 / 100_000.0))
        .collect();
    format!("\"{key}\" = [{}]", values.join(", "))
}

fn run_rows(dir: &Path, rows: &[Row]) {
    let mut wrong = Vec::new();
    for r in rows {
        let out = safereach(dir).args(&r.args).output().expect("runs");
        let text = stdout(&out) + &String::from_utf8_lossy(&out.stderr);
        let missing: Vec<_> = r.says.iter().filter(|s| !text.contains(**s)).collect();
        if out.status.code() != Some(r.code) || !missing.is_empty() {
            wrong.push(format!(
                "{} ({:?}): exit {:?}, missing {missing:?}:\n{text}",
                r.what,
                r.args,
                out.status.code()
            ));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn work_past_a_budget_is_refused_or_inconclusive_naming_the_flag() {
    let dir = tmp();
    let d = dir.path();
    std::fs::copy(seed_file(), d.join("seed.toml")).unwrap();
    std::fs::copy(problem_file("area-rule.toml"), d.join("area.toml")).unwrap();
    std::fs::copy(problem_file("scene-oncoming.toml"), d.join("scene.toml")).unwrap();
    let keys = [
        "robot.max_speed",
        "robot.braking",
        "controller.reaction_radius",
        "environment.obstacle_speed",
        "controller.buffer",
        "robot.clearance",
    ];
    // 10^7 and 10^12 cells; 256^4 cells (the abort of 4 GiB); a billion runs per cell.
    let ten = |n: usize, count: usize| -> Vec<String> {
        keys[..count].iter().map(|k| axis(k, n)).collect()
    };
    let mut seven = ten(10, 6);
    seven.push(axis("controller.assumed_obstacle_speed", 10));
    grid(d, "seven.toml", "", &seven);
    grid(d, "twelve.toml", "", &ten(100, 6));
    grid(d, "quad.toml", "", &ten(256, 4));
    grid(d, "runs.toml", "runs = 1000000000", &ten(2, 1));
    run_rows(
        d,
        &[
            row(
                "a radius search whose analyses are long",
                &[
                    "radius",
                    "area.toml",
                    "--set",
                    "robot.control_period=0.000113",
                    "--max-periods",
                    "100000",
                ],
                2,
                &[
                    "analysed control periods",
                    "budget of 100,000",
                    "--max-periods raises it",
                ],
            ),
            row(
                "a scene's radius search past its budget",
                &["radius", "scene.toml", "--max-periods", "1000"],
                2,
                &[
                    "scene analysis",
                    "budget of 1,000",
                    "--max-periods raises it",
                ],
            ),
            row(
                "a scene's speed search past its budget",
                &["max-speed", "scene.toml", "--max-periods", "1000"],
                2,
                &[
                    "scene analysis",
                    "budget of 1,000",
                    "--max-periods raises it",
                ],
            ),
            row(
                "a robot that accelerates for 50,000 periods (36.6 s once)",
                &[
                    "certify",
                    "seed.toml",
                    "--set",
                    "robot.acceleration=0.000394",
                ],
                0,
                &["certified"],
            ),
            row(
                "the largest count of runs",
                &["simulate", "seed.toml", "--runs", "18446744073709551615"],
                2,
                &[
                    "seed.toml: --runs 18446744073709551615",
                    "more simulated control periods than can be counted",
                    "--max-periods raises it",
                ],
            ),
            row(
                "a grid of a billion runs per cell",
                &["sweep", "runs.toml", "--out", "out"],
                2,
                &["runs.toml", "simulated control periods", "--max-periods"],
            ),
            row(
                "a grid of 10^7 cells",
                &["sweep", "seven.toml", "--out", "out"],
                2,
                &["seven.toml", "10,000,000 cells", "--max-cells raises it"],
            ),
            row(
                "a grid of 10^12 cells",
                &["sweep", "twelve.toml", "--out", "out"],
                2,
                &["1,000,000,000,000 cells", "--max-cells"],
            ),
            row(
                "a grid of 256^4 cells",
                &["sweep", "quad.toml", "--out", "out"],
                2,
                &["4,294,967,296 cells", "--max-cells"],
            ),
            row(
                "an exploration over its memory budget",
                &[
                    "explore",
                    "seed.toml",
                    "--set",
                    "robot.latency=999",
                    "--set",
                    "environment.obstacle_speed=0.05",
                    "--max-states",
                    "100000",
                    "--max-memory",
                    "1",
                ],
                3,
                &["memory budget reached", "raise --max-memory"],
            ),
        ],
    );
    assert!(!d.join("out").exists(), "no refused sweep wrote results");
}

#[cfg(unix)]
#[test]
fn endless_or_binary_inputs_are_refused_before_they_fill_the_memory() {
    let dir = tmp();
    let d = dir.path();
    std::fs::copy(fixture("seed.cert.json"), d.join("cert.json")).unwrap();
    std::fs::write(
        d.join("zero-grid.toml"),
        "base = \"/dev/zero\"\n[axes]\n\"robot.max_speed\" = [0.1]\n",
    )
    .unwrap();
    run_rows(
        d,
        &[
            row(
                "a problem file without end",
                &["certify", "/dev/zero"],
                2,
                &["/dev/zero", "larger than 1 MiB"],
            ),
            row(
                "random bytes as a certificate",
                &["check", "/dev/urandom"],
                2,
                &["/dev/urandom", "not UTF-8"],
            ),
            row(
                "a grid whose base has no end",
                &["sweep", "zero-grid.toml", "--out", "out"],
                2,
                &["zero-grid.toml", "/dev/zero", "larger than 1 MiB"],
            ),
            row(
                "a trace without end",
                &["monitor", "--certificate", "cert.json", "/dev/zero"],
                2,
                &[
                    "/dev/zero",
                    "has no end in 64 MiB",
                    "not a line-oriented trace",
                ],
            ),
        ],
    );
}

#[cfg(unix)]
#[test]
fn out_replaces_only_a_regular_file() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tmp();
    let d = dir.path();
    std::fs::copy(seed_file(), d.join("seed.toml")).unwrap();
    std::fs::write(d.join("kept.txt"), "kept").unwrap();
    std::os::unix::fs::symlink("kept.txt", d.join("link.json")).unwrap();
    std::fs::create_dir(d.join("dir.json")).unwrap();
    run_rows(
        d,
        &[
            row(
                "a symbolic link",
                &["certify", "seed.toml", "--out", "link.json"],
                2,
                &["link.json", "a symbolic link, not a regular file"],
            ),
            row(
                "a device",
                &["certify", "seed.toml", "--out", "/dev/null"],
                2,
                &["/dev/null", "a device", "not a regular file"],
            ),
            row(
                "a directory",
                &["certify", "seed.toml", "--out", "dir.json"],
                2,
                &["dir.json", "a directory"],
            ),
            row(
                "a regular file",
                &["certify", "seed.toml", "--out", "kept.txt"],
                0,
                &["certified"],
            ),
        ],
    );
    let link = std::fs::symlink_metadata(d.join("link.json")).unwrap();
    assert!(link.file_type().is_symlink(), "the link is still a link");
    assert!(
        std::fs::metadata("/dev/null")
            .unwrap()
            .file_type()
            .is_char_device()
    );
    assert!(d.join("dir.json").is_dir());
    let written = std::fs::read_to_string(d.join("kept.txt")).unwrap();
    assert!(
        written.contains("\"verdict\""),
        "a regular file is replaced"
    );
}

/// The seed's violating trace with every line end replaced by `end`.
fn with_line_ends(end: &str) -> String {
    let text = std::fs::read_to_string(fixture("seed-w0.25.run.csv")).unwrap();
    text.lines().map(|l| format!("{l}{end}")).collect()
}

#[test]
fn traces_read_alike_with_every_line_ending_and_nothing_checked_is_an_error() {
    let dir = tmp();
    let d = dir.path();
    std::fs::copy(fixture("seed.cert.json"), d.join("cert.json")).unwrap();
    let monitor = |name: &str, text: &[u8]| {
        std::fs::write(d.join(name), text).unwrap();
        let out = safereach(d)
            .args(["monitor", "--certificate", "cert.json", name])
            .output()
            .expect("runs");
        (
            out.status.code(),
            stdout(&out),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let (code, lf, _) = monitor("lf.csv", with_line_ends("\n").as_bytes());
    assert_eq!(code, Some(1), "the trace violates its premises:\n{lf}");
    assert!(lf.contains("315 samples"), "{lf}");
    for (name, end) in [("cr.csv", "\r"), ("crlf.csv", "\r\n"), ("lfcr.csv", "\n\r")] {
        let (c, text, _) = monitor(name, with_line_ends(end).as_bytes());
        assert_eq!(
            (c, text.as_str()),
            (code, lf.as_str()),
            "{name} reads as the LF trace does"
        );
    }
    let header = with_line_ends("\n");
    let header = header.lines().next().unwrap();
    for (name, text) in [
        ("header.csv", format!("{header}\n").into_bytes()),
        ("byte.csv", vec![0xA7]),
        ("empty.csv", Vec::new()),
    ] {
        let (c, out, err) = monitor(name, &text);
        assert_eq!(
            c,
            Some(2),
            "{name}: nothing was checked is not a pass:\n{out}{err}"
        );
        assert!(err.contains("nothing was checked"), "{name}: {err}");
    }
}
