//! `ncplc run`.

use std::process::ExitCode;

/// Arguments of `ncplc run`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Arguments not yet defined.
    #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
    pub rest: Vec<String>,
}

/// Runs `ncplc run`.
pub fn run(_args: Args) -> ExitCode {
    eprintln!("ncplc run: not built yet");
    ExitCode::from(2)
}
