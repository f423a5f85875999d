//! Sharded sweeps from the command line: shards read from the scheduler's environment, merges
//! byte for byte equal to the unsharded sweep, stale results refused by `report --from`, and
//! `sweep --slurm` submitting through a stand-in `sbatch` whose scripts, run the way Slurm
//! runs them, give the unsharded output. (The real cluster: `slurm_cluster.rs`.)

use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};

use crate::common::cli::{safereach, stdout};
use crate::common::paths::root;
use crate::common::tmp;

const SCHEDULER_VARS: [&str; 7] = [
    "SLURM_ARRAY_JOB_ID",
    "SLURM_ARRAY_TASK_ID",
    "SLURM_ARRAY_TASK_COUNT",
    "SLURM_ARRAY_TASK_MIN",
    "SLURM_ARRAY_TASK_MAX",
    "SLURM_ARRAY_TASK_STEP",
    "JOB_COMPLETION_INDEX",
];

/// `safereach` in `dir` with no scheduler variables inherited.
fn plain(dir: &Path) -> assert_cmd::Command {
    let mut cmd = safereach(dir);
    for v in SCHEDULER_VARS {
        cmd.env_remove(v);
    }
    cmd
}

/// A copy of the seed grid and its base problem in `dir` (so tests can edit them).
fn grid_copy(dir: &Path) -> PathBuf {
    for f in ["seed-grid.toml", "seed.toml"] {
        std::fs::copy(root().join("problems").join(f), dir.join(f)).unwrap();
    }
    dir.join("seed-grid.toml")
}

/// The unsharded sweep's output files (JSON Lines, CSV) of the grid in `dir`.
fn unsharded(dir: &Path, runs: &str) -> (Vec<u8>, Vec<u8>) {
    let out = dir.join("unsharded");
    plain(dir)
        .args(["sweep", "seed-grid.toml", "--runs", runs, "--out"])
        .arg(&out)
        .assert()
        .success();
    (
        std::fs::read(out.join("seed-grid.jsonl")).unwrap(),
        std::fs::read(out.join("seed-grid.csv")).unwrap(),
    )
}

#[test]
fn shard_auto_reads_slurm_and_kubernetes_and_refuses_what_it_cannot_map() {
    let dir = tmp();
    grid_copy(dir.path());
    // --array=1-9:4, task 5: shard 1 of 3.
    let out = plain(dir.path())
        .args(["sweep", "seed-grid.toml", "--shard", "auto", "--out", "s"])
        .envs([
            ("SLURM_ARRAY_JOB_ID", "77"),
            ("SLURM_ARRAY_TASK_ID", "5"),
            ("SLURM_ARRAY_TASK_COUNT", "3"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
            ("SLURM_ARRAY_TASK_MAX", "9"),
            ("SLURM_ARRAY_TASK_STEP", "4"),
        ])
        .assert()
        .success()
        .get_output()
        .clone();
    assert!(
        stdout(&out).contains("shard 1/3 (Slurm array job 77, task 5)"),
        "{}",
        stdout(&out)
    );
    let written = std::fs::read_to_string(dir.path().join("s/seed-grid.shard-1-of-3.jsonl"))
        .expect("the shard's output");
    let cells: Vec<u64> = written
        .lines()
        .skip(1)
        .map(|l| {
            serde_json::from_str::<serde_json::Value>(l).unwrap()["cell"]
                .as_u64()
                .unwrap()
        })
        .collect();
    assert_eq!(cells, [1, 4, 7, 10, 13]);
    // A Kubernetes Indexed Job's pod, with the count from --shards.
    plain(dir.path())
        .args([
            "sweep",
            "seed-grid.toml",
            "--shard",
            "auto",
            "--shards",
            "2",
            "--out",
            "k",
        ])
        .env("JOB_COMPLETION_INDEX", "1")
        .assert()
        .success();
    assert!(dir.path().join("k/seed-grid.shard-1-of-2.jsonl").is_file());
    // Refusals, exit 2 with the reason.
    let refused = |envs: &[(&str, &str)], extra: &[&str], needle: &str| {
        let out = plain(dir.path())
            .args(["sweep", "seed-grid.toml", "--shard", "auto", "--out", "x"])
            .args(extra)
            .envs(envs.iter().copied())
            .assert()
            .code(2)
            .get_output()
            .clone();
        let err = String::from_utf8(out.stderr).unwrap();
        assert!(err.contains(needle), "{envs:?} {extra:?}: {err}");
    };
    refused(&[], &[], "neither SLURM_ARRAY_TASK_ID");
    refused(&[("JOB_COMPLETION_INDEX", "0")], &[], "needs --shards N");
    let sparse = [
        ("SLURM_ARRAY_TASK_ID", "3"),
        ("SLURM_ARRAY_TASK_COUNT", "3"),
        ("SLURM_ARRAY_TASK_MIN", "0"),
        ("SLURM_ARRAY_TASK_MAX", "7"),
        ("SLURM_ARRAY_TASK_STEP", "1"),
    ];
    refused(&sparse, &[], "sparse array");
    let four = [
        ("SLURM_ARRAY_TASK_ID", "3"),
        ("SLURM_ARRAY_TASK_COUNT", "4"),
        ("SLURM_ARRAY_TASK_MIN", "0"),
        ("SLURM_ARRAY_TASK_MAX", "3"),
        ("SLURM_ARRAY_TASK_STEP", "1"),
    ];
    refused(
        &four,
        &["--shards", "8"],
        "--shards 8 but the Slurm array has 4 tasks",
    );
    assert!(
        !dir.path().join("x").exists(),
        "nothing written on a refusal"
    );
}

#[test]
fn merge_writes_the_unsharded_output_byte_for_byte() {
    let dir = tmp();
    grid_copy(dir.path());
    let (jsonl, csv) = unsharded(dir.path(), "10");
    for i in 0..3 {
        plain(dir.path())
            .args(["sweep", "seed-grid.toml", "--runs", "10", "--out", "shards"])
            .args(["--shard", &format!("{i}/3")])
            .assert()
            .success();
    }
    plain(dir.path())
        .args([
            "merge",
            "seed-grid.toml",
            "--from",
            "shards",
            "--out",
            "merged",
        ])
        .assert()
        .success();
    assert!(std::fs::read(dir.path().join("merged/seed-grid.jsonl")).unwrap() == jsonl);
    assert!(std::fs::read(dir.path().join("merged/seed-grid.csv")).unwrap() == csv);
}

/// The stale cases, through `report --from`: a changed axis and a changed base
/// problem are refused (exit 2, the shard file and the change named); `--from A B` and
/// `--from A --from B` both read two directories.
#[test]
fn report_refuses_stale_results_and_reads_several_directories() {
    let dir = tmp();
    let grid = grid_copy(dir.path());
    for (i, place) in [(0, "A"), (1, "B")] {
        plain(dir.path())
            .args(["sweep", "seed-grid.toml", "--out", place])
            .args(["--shard", &format!("{i}/2")])
            .assert()
            .success();
    }
    let report = |from: &[&str]| {
        let mut cmd = plain(dir.path());
        cmd.args(["report", "seed-grid.toml"])
            .args(from)
            .args(["--out", "rep"]);
        cmd.assert()
    };
    let grid_text = std::fs::read_to_string(&grid).unwrap();
    std::fs::write(
        &grid,
        grid_text
            .replace("[0.2]", "[0.3]")
            .replace("0.25, 0.3]", "0.25, 0.5]"),
    )
    .unwrap();
    let err = String::from_utf8(
        report(&["--from", "A", "B"])
            .code(2)
            .get_output()
            .stderr
            .clone(),
    )
    .unwrap();
    assert!(
        err.contains("A/seed-grid.shard-0-of-2.jsonl: not a result of seed-grid.toml")
            && err.contains("axis controller.assumed_obstacle_speed was [0.2], is now [0.3]")
            && err.contains("axis environment.obstacle_speed was [0.15,0.2,0.25,0.3], is now [0.15,0.2,0.25,0.5]"),
        "{err}"
    );
    std::fs::write(&grid, &grid_text).unwrap();
    let base = std::fs::read_to_string(dir.path().join("seed.toml")).unwrap();
    std::fs::write(
        dir.path().join("seed.toml"),
        base.replace("braking = 0.05", "braking = 0.02"),
    )
    .unwrap();
    report(&["--from", "A", "--from", "B"])
        .code(2)
        .stderr(predicates::str::contains(
            "the base problem has changed since: robot.braking was 0.05, is now 0.02",
        ));
    assert!(
        !dir.path().join("rep/seed-grid.md").exists(),
        "no report of stale results"
    );
    // An unsharded output is held to the same record.
    plain(dir.path())
        .args(["sweep", "seed-grid.toml", "--out", "W"])
        .assert()
        .success();
    std::fs::write(dir.path().join("seed.toml"), &base).unwrap();
    report(&["--from", "W"])
        .code(2)
        .stderr(predicates::str::contains(
            "W/seed-grid.jsonl: not a result of seed-grid.toml as it is now: the base problem has \
         changed since: robot.braking was 0.02, is now 0.05",
        ));
    report(&["--from", "A", "B"]).success();
    let one_flag = std::fs::read(dir.path().join("rep/seed-grid.md")).unwrap();
    report(&["--from", "A", "--from", "B"]).success();
    assert!(std::fs::read(dir.path().join("rep/seed-grid.md")).unwrap() == one_flag);
    // Only one of the two shards: refused, naming the missing one.
    report(&["--from", "A"])
        .code(2)
        .stderr(predicates::str::contains(
            "shard 1/2 of grid seed-grid is missing",
        ));
}

#[test]
fn slurm_dry_run_prints_both_jobs_and_writes_nothing() {
    let dir = tmp();
    grid_copy(dir.path());
    let out = slurm_sweep(dir.path(), "res", "4")
        .args([
            "--sbatch-arg=--partition=debug",
            "--sbatch-arg",
            "--time=10",
        ])
        .arg("--dry-run")
        .assert()
        .success()
        .get_output()
        .clone();
    let text = stdout(&out);
    for needle in [
        "#SBATCH --array=0-3",
        "#SBATCH --partition=debug",
        "#SBATCH --time=10",
        "--shard auto --shards 4 --runs 100 --seed 2016",
        " merge ",
        "--dependency=afterok:<array job> --kill-on-invalid-dep=yes",
    ] {
        assert!(text.contains(needle), "{needle}: {text}");
    }
    assert!(!dir.path().join("res").exists());
    // Bad settings: exit 2 with the flag named.
    plain(dir.path())
        .args([
            "sweep",
            "seed-grid.toml",
            "--out",
            "res",
            "--slurm",
            "--dry-run",
        ])
        .assert()
        .code(2)
        .stderr(predicates::str::contains("--shards"));
    slurm_sweep(dir.path(), "my res", "2")
        .arg("--dry-run")
        .assert()
        .code(2)
        .stderr(predicates::str::contains("white space"));
}

/// `safereach sweep seed-grid.toml --out OUT --slurm --shards N` in `dir`.
fn slurm_sweep(dir: &Path, out: &str, shards: &str) -> assert_cmd::Command {
    let mut cmd = plain(dir);
    cmd.args([
        "sweep",
        "seed-grid.toml",
        "--out",
        out,
        "--slurm",
        "--shards",
        shards,
    ]);
    cmd
}

/// A stand-in `sbatch` on PATH: records its arguments, prints job ids 100, 101, …, or
/// refuses when `refuse` is set.
fn stand_in_sbatch(bin: &Path, refuse: bool) {
    std::fs::create_dir_all(bin).unwrap();
    let script = if refuse {
        "#!/bin/sh\necho 'sbatch: error: invalid partition specified: gpu' >&2\nexit 1\n"
            .to_string()
    } else {
        format!(
            "#!/bin/sh\nlog={0}/calls\nn=$(( $(cat {0}/calls 2>/dev/null | wc -l) + 100 ))\n\
             echo \"$*\" >> \"$log\"\necho \"$n;ci\"\n",
            bin.display()
        )
    };
    let path = bin.join("sbatch");
    std::fs::write(&path, script).unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    let scancel = bin.join("scancel");
    std::fs::write(&scancel, "#!/bin/sh\nexit 0\n").unwrap();
    std::fs::set_permissions(&scancel, std::fs::Permissions::from_mode(0o755)).unwrap();
}

fn path_with(bin: &Path) -> String {
    format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    )
}

/// `sweep --slurm` submits the array job, then the merge job with `afterok` on it; its
/// scripts, run as Slurm runs them (each task with its array variables, then the merge),
/// write exactly the unsharded sweep's output.
#[test]
fn slurm_submission_scripts_run_as_slurm_runs_them_give_the_unsharded_output() {
    let dir = tmp();
    grid_copy(dir.path());
    let (jsonl, csv) = unsharded(dir.path(), "20");
    let bin = dir.path().join("bin");
    stand_in_sbatch(&bin, false);
    let out = plain(dir.path())
        .env("PATH", path_with(&bin))
        .args(["sweep", "seed-grid.toml", "--runs", "20", "--out", "res"])
        .args(["--slurm", "--shards", "4"])
        .assert()
        .success()
        .get_output()
        .clone();
    let said = stdout(&out);
    assert!(
        said.contains("submitted array job 100 (4 shards of 16 cells) and merge job 101"),
        "{said}"
    );
    let calls = std::fs::read_to_string(bin.join("calls")).unwrap();
    let calls: Vec<&str> = calls.lines().collect();
    let res = dir.path().join("res").canonicalize().unwrap();
    let array = res.join("slurm/seed-grid.array.sh");
    let merge = res.join("slurm/seed-grid.merge.sh");
    assert_eq!(
        calls,
        [
            format!("--parsable {}", array.display()),
            format!(
                "--parsable --dependency=afterok:100 --kill-on-invalid-dep=yes {}",
                merge.display()
            )
        ]
    );
    for task in 0..4 {
        let status = std::process::Command::new("bash")
            .arg(&array)
            .current_dir(dir.path())
            .envs([
                ("SLURM_ARRAY_JOB_ID", "100".to_string()),
                ("SLURM_ARRAY_TASK_ID", task.to_string()),
                ("SLURM_ARRAY_TASK_COUNT", "4".into()),
                ("SLURM_ARRAY_TASK_MIN", "0".into()),
                ("SLURM_ARRAY_TASK_MAX", "3".into()),
                ("SLURM_ARRAY_TASK_STEP", "1".into()),
            ])
            .status()
            .unwrap();
        assert!(status.success(), "task {task}");
    }
    let status = std::process::Command::new("bash")
        .arg(&merge)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .status()
        .unwrap();
    assert!(status.success());
    assert!(std::fs::read(res.join("seed-grid.jsonl")).unwrap() == jsonl);
    assert!(std::fs::read(res.join("seed-grid.csv")).unwrap() == csv);
    // A second submission into the same directory would mix runs: refused.
    slurm_sweep(dir.path(), "res", "4")
        .env("PATH", path_with(&bin))
        .assert()
        .code(2)
        .stderr(predicates::str::contains(
            "already holds results of grid seed-grid",
        ));
    // sbatch refusing the job: exit 2 with sbatch's reason.
    let refusing = dir.path().join("bin-refusing");
    stand_in_sbatch(&refusing, true);
    slurm_sweep(dir.path(), "res2", "2")
        .env("PATH", path_with(&refusing))
        .assert()
        .code(2)
        .stderr(predicates::str::contains("invalid partition specified"));
}
