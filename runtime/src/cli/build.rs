//! `ncplc build`.

use std::process::ExitCode;

/// Arguments of `ncplc build`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Arguments not yet defined.
    #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
    pub rest: Vec<String>,
}

/// Runs `ncplc build`.
pub fn run(_args: Args) -> ExitCode {
    eprintln!("ncplc build: not built yet");
    ExitCode::from(2)
}
