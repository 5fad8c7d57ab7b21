//! The `ncplc` command-line tool as a library (the binary is `src/main.rs`): argument parsing,
//! printing and exit codes over the crates below it.
//!
//! | module | concept |
//! |---|---|
//! | [`cli`] | the subcommand enum and one module per subcommand; `cli::output` the shared conventions |
//!
//! **Invariants:** this is the only crate that parses arguments, prints results and picks exit
//! codes (0 ok, 1 problems in the input, 2 usage or environment error); it assembles nothing
//! itself — a run, a replay and `ncplc test` go through `controller::Controller::builder`. Nothing
//! depends on this crate.

pub mod cli;
