//! The bottom layer: numbers, exact rationals, the problem model and the one semantics every
//! engine runs. Nothing here knows about programs, solvers, certificates or monitors.

pub mod budget;
pub mod grid;
pub mod model;
pub mod num;
pub mod output;
pub mod param_box;
pub mod parameter;
pub mod planar;
pub mod plane;
pub mod polynomial;
pub mod rational;
pub mod scene;
pub mod semantics;
pub mod shard;
pub mod show;
pub mod simulate;
pub mod sweep_provenance;
pub mod template;
pub mod text_file;
