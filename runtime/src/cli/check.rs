//! `ncplc check`.

use std::process::ExitCode;

/// Arguments of `ncplc check`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Arguments not yet defined.
    #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
    pub rest: Vec<String>,
}

/// Runs `ncplc check`.
pub fn run(_args: Args) -> ExitCode {
    eprintln!("ncplc check: not built yet");
    ExitCode::from(2)
}
