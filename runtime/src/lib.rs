//! The ncplc runtime: the cyclic scan loop that owns the signal packets, plus the `ncplc` CLI.
//!
//! See ARCHITECTURE.md at the repository root for how the crates fit together.

pub mod cli;
