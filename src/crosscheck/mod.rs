//! Independent engines that hold the analyser to account: the exhaustive explorer over
//! finite speed sets, and the UPPAAL export with its interpreter.

mod bfs;
pub mod explore;
pub mod uppaal;
