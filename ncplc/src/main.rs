//! The `ncplc` command-line tool: one subcommand per job, each in its own module under `cli/`.

use std::process::ExitCode;

use clap::Parser;

/// mimalloc instead of the system allocator: the PLC compiler's front end and cranelift allocate many
/// small objects, and with glibc malloc the 10,000-statement compile took 175 ms instead of 89 ms
/// (README, benchmarks). The scan itself does not allocate.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> ExitCode {
    ncplc::cli::main(ncplc::cli::Cli::parse())
}
