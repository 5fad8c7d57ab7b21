//! `ncplc replay`.

use std::process::ExitCode;

/// Arguments of `ncplc replay`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Arguments not yet defined.
    #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
    pub rest: Vec<String>,
}

/// Runs `ncplc replay`.
pub fn run(_args: Args) -> ExitCode {
    eprintln!("ncplc replay: not built yet");
    ExitCode::from(2)
}
