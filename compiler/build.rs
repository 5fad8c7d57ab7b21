//! Build script: generates the LALRPOP parser from `src/grammar.lalrpop` into `$OUT_DIR`.

fn main() {
    // A failure here is a bug in the grammar file, reported by lalrpop with its own message.
    if let Err(e) = lalrpop::Configuration::new()
        .use_cargo_dir_conventions()
        .emit_rerun_directives(true)
        .process()
    {
        eprintln!("lalrpop failed: {e}");
        std::process::exit(1);
    }
}
