//! # safereach
//!
//! Proves or refutes that a mobile robot is *passively safe* against an obstacle coming
//! towards it along its lane, and keeps the proof honest at run time.
//!
//! **Passive safety** (Macek et al. 2008): the robot never collides while it is moving.
//! With gap g(t) = obstacle position − robot position and robot speed v(t),
//!
//! > for every obstacle behaviour with speeds in [0, W] and every instant t:
//! > v(t) > 0 ⇒ g(t) > clearance.
//!
//! **The triple.** A problem fixes the assumed bound V_a (what the controller believes
//! about obstacles), the real bound W (what the environment does) and the reaction radius ρ
//! (the robot reacts to obstacles it sees at a gap in (0, ρ]). The controller brakes on
//! *collision danger* (observed gap ≤ d_coll(v)) or, optionally, on a *wrong assumption*
//! (an obstacle in the area seen faster than V_a). `docs/semantics.md` in the repository is
//! the exact semantics; [`core::semantics`] implements it once for every engine.
//!
//! **Verdicts** are three-valued:
//! - `certified`: a lower bound on the worst-case minimum separation s*, re-verified in exact
//!   rational arithmetic without the solver ([`check`]), exceeds the clearance;
//! - `refuted`: a concrete obstacle behaviour, replayed exactly through the semantics,
//!   collides;
//! - `inconclusive`: neither (the boundary, within numerical tolerance). Never a false
//!   `certified`.
//!
//! The analyser (`analysis`, feature `solver`) splits all behaviours into finitely many
//! *pieces* by the robot's discrete schedule ([`proof::schedule`]); each piece is a tiny
//! conic program ([`proof::program`]) solved by Clarabel, whose dual multipliers become the
//! certificate.
//!
//! # Layers
//!
//! Each layer imports only the ones above it in this list:
//! - [`core`]: numbers, exact rationals, the problem model, the semantics, the simulator;
//! - [`proof`]: programs with typed cones and parameter-affine data, exact bounds, the
//!   certificate format and [`check`] — no solver;
//! - `analysis` (feature `solver`, on by default): Clarabel, witnesses, radius, sweeps,
//!   reports;
//! - `cluster` (feature `solver`): sweeps as Slurm array jobs;
//! - [`monitor`]: premise checks over live traces — no solver;
//! - [`crosscheck`]: the exhaustive explorer and the UPPAAL export.
//!
//! With `default-features = false` the crate builds the model, the semantics, the
//! certificate check and the monitor only, with none of the solver's or the command line's
//! dependencies: what a robot embeds.
//!
//! The items below are the facade most users need; the layers hold the rest.

//! ```
//! # #[cfg(not(feature = "solver"))] fn main() {}
//! # #[cfg(feature = "solver")]
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! use safereach::{Certificate, Problem, Verdict, analyse, check};
//!
//! let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/problems/seed.toml"))?;
//! let problem = Problem::from_toml_str(&text, "seed.toml")?;
//! let analysis = analyse(&problem)?;
//! assert_eq!(analysis.verdict, Verdict::Certified);
//! // The certificate is re-verified in exact arithmetic, without the solver.
//! let certificate = Certificate::from_analysis(&analysis);
//! assert_eq!(check(&certificate)?.verdict, Verdict::Certified);
//! # Ok(())
//! # }
//! ```

#![forbid(unsafe_code)]
#![deny(missing_docs)]

#[cfg(feature = "solver")]
pub mod analysis;
#[cfg(feature = "solver")]
pub mod cluster;
pub mod core;
pub mod crosscheck;
pub mod monitor;
pub mod proof;

pub use crate::core::model::{Problem, ProblemError};
pub use crate::core::parameter::{ParamAffine, Parameter};
pub use crate::monitor::Monitor;
pub use crate::proof::certificate::{Certificate, CheckReport, Invalid, Premise, check};
pub use crate::proof::verdict::{Verdict, Witness};

#[cfg(feature = "solver")]
pub use crate::analysis::radius::{Boundary, max_speed, safe_radius};
#[cfg(feature = "solver")]
pub use crate::analysis::{Analysis, AnalysisError, Options, WitnessPolicy, analyse, analyse_with};
