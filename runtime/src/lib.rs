//! The ncplc runtime: the cyclic scan loop that owns the signal packets, plus the `ncplc` CLI.
//!
//! See ARCHITECTURE.md at the repository root for how the crates fit together.
//!
//! | module | concept |
//! |---|---|
//! | [`image`] | the flat process image (packets, then the compiler's areas) |
//! | [`program`] | what the runtime needs from a program: [`program::Logic`], [`program::ProgramMeta`] |
//! | [`compiled`] | the compiler's interpreter and JIT behind those traits; state migration |
//! | [`scheduler`] | the tick loop: latch, scan, publish; overruns, safe state, swaps, retain |
//! | [`clock`] | real time (absolute deadlines, SCHED_FIFO) and virtual time |
//! | [`stats`] | scan-time and wake-latency histograms |
//! | [`trace`] | trace records, text and binary forms, recorder, comparison |
//! | [`replay`] | replaying a trace and comparing outputs |
//! | [`idle_skip`], [`output_watch`] | the replay's exact jumps over idle ticks and its lean output diff |
//! | [`retain`] | atomic, checksummed retained data (PGCFIL OLD, MUSPE) |
//! | [`online`] | watching the source, background compile, swap at a tick boundary |
//! | [`handshake`], [`sim`] | the simulated CNC (M/S/T handshake) and machine |
//! | [`io`] | choosing the I/O (`sim`, `modbus`, `canopen`) |
//! | [`config`], [`machine`], [`machine_facts`] | machine settings for a run |
//! | [`process_map`] | the interface map against the machine's processes (NBP>1 roles) |

pub mod atomic_file;
pub mod cli;
pub mod clock;
pub mod compiled;
pub mod config;
pub mod force;
pub mod hmi_link;
pub mod idle_skip;
pub use cnc::handshake;
pub mod image;
pub mod io;
pub mod machine;
pub mod machine_facts;
pub mod online;
pub mod output_watch;
pub mod plot;
pub mod process_map;
pub mod program;
pub mod replay;
pub mod retain;
pub mod scheduler;
pub mod sim;
pub mod stats;
pub mod testkit;
pub mod trace;

#[cfg(test)]
mod replay_skip_tests;
#[cfg(test)]
#[path = "scheduler_tests.rs"]
mod scheduler_tests;
