//! The conventions every subcommand shares: exit codes, where output goes, colour, SIGPIPE, and
//! how paths are shown.
//!
//! **stdout** carries what a command was asked to produce (the `--dump` model, `--emit` IR, a
//! plan's blocks, trace text, `--stats`); **stderr** carries diagnostics (human or `--format
//! json`), progress and summaries. Exit codes: [`OK`], [`PROBLEMS`], [`USAGE`].

use std::process::ExitCode;
use std::sync::OnceLock;
use std::time::Instant;

/// Exit code: success.
pub const OK: u8 = 0;
/// Exit code: the input has problems (diagnostics with errors, a replay that diverges, a run
/// that tripped its safe state).
pub const PROBLEMS: u8 = 1;
/// Exit code: a usage or environment error (bad arguments, a missing machine directory or file,
/// an unwritable output).
pub const USAGE: u8 = 2;

/// The exit-code table shown at the end of `--help`.
pub const EXIT_CODES_HELP: &str = "Exit codes: 0 ok; 1 problems found in the input (the errors check, build, nc check/plan and trace report; a diverging replay; a tripped run); 2 usage or environment error (bad arguments, missing machine directory or file), and a run or replay that refuses to start (its machine, PLC program, part program or trace has errors: check, build and nc check list them with exit 1).\nOutput: results (--dump, --emit, plan blocks, trace text, --stats) on stdout; diagnostics (any --format), progress and summaries on stderr.";

pub use runtime::render::{
    Color, colored, colorize, relocate, render_diagnostics, render_diagnostics_capped,
    render_diagnostics_capped_with, user_path,
};

static STARTED: OnceLock<Instant> = OnceLock::new();

/// Records the process start and the colour choice; called first thing by `cli::main`.
pub fn init(color: Color) {
    STARTED.get_or_init(Instant::now);
    runtime::render::set_color(color);
}

/// When the command line started being handled (for the start-to-first-tick figure).
pub fn started() -> Instant {
    *STARTED.get_or_init(Instant::now)
}

/// Reports a usage or environment error on stderr and returns [`USAGE`].
pub fn usage_error(message: impl std::fmt::Display) -> ExitCode {
    eprintln!("{message}");
    ExitCode::from(USAGE)
}

/// Lets a write to a closed pipe end the process quietly (as `cat` does: killed by SIGPIPE, exit
/// status 141 in a shell) instead of a panic in `println!`. Not for `run`, whose fieldbus sockets
/// must never kill the controller.
pub fn quiet_sigpipe() {
    // SAFETY: restoring the default disposition of one signal; no handler runs.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}
