//! `safereach init`, `completions` and `man`: the templates certify as written (and with
//! their defaults spelled out, to the same answer), existing files are never overwritten by
//! accident, and completions and man pages cover every subcommand `--help` lists.

use std::fs;

use safereach::core::template;

use crate::common::cli::{files, safereach, stdout};
use crate::common::tmp;

/// The subcommands `safereach --help` lists (without `help`).
fn subcommands() -> Vec<String> {
    let help = stdout(
        &safereach(&std::env::temp_dir())
            .arg("--help")
            .output()
            .unwrap(),
    );
    let commands = help
        .split("Commands:")
        .nth(1)
        .expect("--help lists commands")
        .split("\n\n")
        .next()
        .unwrap();
    let names: Vec<String> = commands
        .lines()
        .filter_map(|l| l.split_whitespace().next())
        .filter(|name| *name != "help")
        .map(str::to_string)
        .collect();
    assert!(names.len() >= 15, "{names:?}");
    names
}

/// `certify FILE`'s verdict and s* lines (exit 0 asserted: certified).
fn certified(dir: &std::path::Path, file: &str) -> Vec<String> {
    let out = safereach(dir)
        .args(["certify", file, "--out", &format!("{file}.cert.json")])
        .assert()
        .code(0)
        .get_output()
        .clone();
    let text = stdout(&out);
    assert!(
        text.lines().next().unwrap().ends_with(": certified"),
        "{text}"
    );
    safereach(dir)
        .args(["check", &format!("{file}.cert.json")])
        .assert()
        .code(0);
    text.lines()
        .filter(|l| l.contains("certified") || l.contains("s* ="))
        .map(str::to_string)
        .collect()
}

#[test]
fn each_template_certifies_as_written_and_with_its_defaults_spelled_out() {
    let dir = tmp();
    for (flag, default, text) in [
        (None, "problem.toml", template::PROBLEM),
        (Some("--scene"), "scene.toml", template::SCENE),
    ] {
        let out = safereach(dir.path())
            .arg("init")
            .args(flag)
            .assert()
            .code(0)
            .get_output()
            .clone();
        assert!(stdout(&out).contains(&format!("safereach certify {default}")));
        assert_eq!(fs::read_to_string(dir.path().join(default)).unwrap(), text);
        let as_written = certified(dir.path(), default);

        let spelled = format!("defaults-{default}");
        fs::write(dir.path().join(&spelled), template::uncommented(text, true)).unwrap();
        assert_ne!(
            template::uncommented(text, true),
            text,
            "some default is commented"
        );
        assert_eq!(certified(dir.path(), &spelled), as_written, "{default}");
    }
}

#[test]
fn init_never_overwrites_without_force_and_writes_to_stdout_on_dash() {
    let dir = tmp();
    let path = dir.path().join("mine.toml");
    fs::write(&path, "name = \"mine\"\n").unwrap();
    let out = safereach(dir.path())
        .args(["init", "mine.toml"])
        .assert()
        .code(2)
        .get_output()
        .clone();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        err.contains("mine.toml") && err.contains("--force"),
        "{err}"
    );
    assert_eq!(fs::read_to_string(&path).unwrap(), "name = \"mine\"\n");

    safereach(dir.path())
        .args(["init", "--scene", "--force", "mine.toml"])
        .assert()
        .code(0);
    assert_eq!(fs::read_to_string(&path).unwrap(), template::SCENE);

    let out = safereach(dir.path())
        .args(["init", "-"])
        .assert()
        .code(0)
        .get_output()
        .clone();
    assert_eq!(stdout(&out), template::PROBLEM);
    assert_eq!(files(dir.path()).len(), 1, "nothing else written");

    let missing = dir.path().join("no/such/dir/p.toml");
    let out = safereach(dir.path())
        .arg("init")
        .arg(&missing)
        .assert()
        .code(2)
        .get_output()
        .clone();
    assert!(String::from_utf8_lossy(&out.stderr).contains("no/such/dir"));
}

#[test]
fn completions_name_every_subcommand_in_each_shell() {
    let dir = tmp();
    let commands = subcommands();
    for shell in ["bash", "zsh", "fish"] {
        let out = safereach(dir.path())
            .args(["completions", shell])
            .assert()
            .code(0)
            .get_output()
            .clone();
        let script = stdout(&out);
        for command in &commands {
            assert!(
                script.contains(command.as_str()),
                "{shell}: {command} missing"
            );
        }
        // Flags of a subcommand are completed too.
        assert!(
            script.contains("reaction-radius") || script.contains("certificate"),
            "{shell}"
        );
    }
    let out = safereach(dir.path())
        .args(["completions", "tcsh"])
        .assert()
        .code(2)
        .get_output()
        .clone();
    assert!(String::from_utf8_lossy(&out.stderr).contains("tcsh"));
}

#[test]
fn man_prints_the_main_page_and_writes_one_per_subcommand() {
    let dir = tmp();
    let out = safereach(dir.path())
        .arg("man")
        .assert()
        .code(0)
        .get_output()
        .clone();
    let page = stdout(&out);
    assert!(
        page.starts_with(".ie") || page.contains(".TH safereach"),
        "{}",
        &page[..200]
    );
    safereach(dir.path())
        .args(["man", "--out", "pages"])
        .assert()
        .code(0);
    let pages = files(&dir.path().join("pages"));
    for command in subcommands() {
        assert!(
            pages.contains(&format!("safereach-{command}.1")),
            "{command}: {pages:?}"
        );
    }
    assert!(pages.contains("safereach.1"));
    let certify = fs::read_to_string(dir.path().join("pages/safereach-certify.1")).unwrap();
    assert!(
        certify.contains("safereach certify"),
        "the synopsis names the command"
    );
}
