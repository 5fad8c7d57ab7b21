//! `ncplc trace`.

use std::process::ExitCode;

/// Arguments of `ncplc trace`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Arguments not yet defined.
    #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
    pub rest: Vec<String>,
}

/// Runs `ncplc trace`.
pub fn run(_args: Args) -> ExitCode {
    eprintln!("ncplc trace: not built yet");
    ExitCode::from(2)
}
