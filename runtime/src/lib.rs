//! The ncplc runtime: the cyclic scan loop that owns the signal packets, plus the `ncplc` CLI.
//!
//! See ARCHITECTURE.md at the repository root for how the crates fit together.

pub mod cli;
pub mod clock;
pub mod compiled;
pub mod config;
pub mod handshake;
pub mod image;
pub mod io;
pub mod machine;
pub mod machine_facts;
pub mod online;
pub mod program;
pub mod replay;
pub mod retain;
pub mod scheduler;
pub mod sim;
pub mod stats;
pub mod testkit;
pub mod trace;

#[cfg(test)]
#[path = "scheduler_tests.rs"]
mod scheduler_tests;
