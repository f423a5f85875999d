//! The integration tests, as one binary: one link of the crate and the test harness instead
//! of one per file, and one place for the scaffolding they share ([`common`]: the problem
//! builder, the command runner, paths and fixtures, temporary directories).
//!
//! Each module is one former test file and keeps its tests' names, so
//! `cargo test --release --test it monitor::` runs what `--test monitor` used to. The slow
//! oracle (`tests/brute_force.rs`) stays a binary of its own; `tests/lean` holds the tests
//! that run without the solver (`--no-default-features`).

mod common;

mod analysis;
mod bad_input;
mod bad_input_cli;
mod bag_writer;
mod bounded_work_cli;
mod certificate;
mod cli;
mod explore;
mod explore_noise;
mod fixtures;
mod fuzz_findings;
/// The fuzz targets' properties (fuzz/src/), shared with [`fuzz_findings`].
#[path = "../../fuzz/src/lib.rs"]
mod fuzz_properties;
mod init_cli;
mod monitor;
mod monitor_bag;
mod monitor_cli;
mod monitor_motion;
mod monitor_real;
mod monitor_region;
mod monitor_scene;
mod noise;
mod pinning;
mod planar_bound;
mod planar_boundary_cli;
mod planar_certify_cli;
mod planar_check_cli;
mod planar_embedding;
mod planar_input;
mod planar_keymaera;
mod planar_monitor;
mod planar_monitor_cli;
mod planar_oracle;
mod planar_region;
mod planar_replay;
mod planar_rotation;
mod planar_sweep;
mod plane_geometry;
mod plane_path;
mod polynomial;
mod radius;
mod region;
mod region_statement;
mod report_slices;
mod scene_analysis;
mod scene_cli;
mod scene_explore;
mod scene_input;
mod scene_region;
mod scene_search;
mod scene_sensing;
mod scene_uppaal;
mod schemas;
mod simulate_within_certificate;
mod slurm_cluster;
mod sweep;
mod sweep_report;
mod sweep_shards_cli;
mod uncertainty;
mod uppaal;
