//! The ncplc scan runtime: the cyclic loop that owns the signal packets and the program's image.
//!
//! See ARCHITECTURE.md at the repository root for how the crates fit together. Above this crate
//! `sim` simulates the machine, `controller` assembles a running controller, and the `ncplc` binary
//! parses arguments and prints; below it `trace` holds the trace formats.
//!
//! | module | concept |
//! |---|---|
//! | [`image`] | the flat process image (packets, then the compiler's areas) |
//! | [`program`] | what the runtime needs from a program: [`program::Logic`], [`program::ProgramMeta`] |
//! | [`compiled`] | the compiler's interpreter and JIT behind those traits; state migration |
//! | [`scheduler`] | the tick loop: latch, scan, publish; overruns, safe state, swaps, retain |
//! | [`clock`] | real time (absolute deadlines, SCHED_FIFO) and virtual time |
//! | [`stats`] | scan-time and wake-latency histograms |
//! | [`replay`] | replaying a trace and comparing outputs |
//! | [`idle_skip`], [`output_watch`] | the replay's exact jumps over idle ticks and its lean output diff |
//! | [`retain`] | atomic, checksummed retained data (PGCFIL OLD, MUSPE) |
//! | [`atomic_file`] | every file ncplc replaces: temporary file, sync, rename |
//! | [`online`] | watching the source, background compile, swap at a tick boundary |
//! | [`force`] | the HMI's write-once and force table, applied by the scheduler |
//! | [`config`], [`machine_facts`] | machine settings for a run, from the validated characterization |
//! | [`process_map`] | the interface map against the machine's processes (NBP>1 roles) |
//! | [`render`] | diagnostics rendered (coloured as the CLI chose) and paths as the user sees them |
//! | [`testkit`] | hand-written programs for tests |
//!
//! **Invariants:** the scan never allocates, prints or waits on I/O; the image is the only state
//! of a running program (engines keep none). This crate depends on `trace` and the compiler side,
//! never on `sim`, `controller` or the CLI.

pub mod atomic_file;
pub mod clock;
pub mod compiled;
pub mod config;
pub mod force;
pub mod idle_skip;
pub mod image;
pub mod machine_facts;
pub mod online;
pub mod output_watch;
pub mod process_map;
pub mod program;
pub mod render;
pub mod replay;
pub mod retain;
pub mod scheduler;
pub mod stats;
pub mod testkit;

#[cfg(test)]
mod replay_skip_tests;
