//! Sweeps on a cluster: the batch scheduler runs the shards (nothing here distributes work).
//! `slurm` writes and submits a sweep as a Slurm array job plus a merge job; each shard reads
//! its index from the scheduler's environment (`core::shard::Shard::from_scheduler`).

pub mod slurm;
