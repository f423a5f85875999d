//! Subcommands that live in files of their own (the older ones are still in `main.rs`).

pub mod explore;
pub mod monitor;
pub mod radius;
pub mod sweep;
