//! The committed parser `src/grammar.rs` was generated from the committed `src/grammar.lalrpop`:
//! LALRPOP writes the grammar's SHA3-256 into the second line of what it generates.

use sha3::{Digest, Sha3_256};

#[test]
fn the_committed_parser_was_generated_from_the_committed_grammar() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let grammar = std::fs::read(dir.join("grammar.lalrpop")).expect("the grammar");
    let hash: String = Sha3_256::digest(&grammar)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    let parser = std::fs::read_to_string(dir.join("grammar.rs")).expect("the generated parser");
    let mut header = parser.lines();
    assert_eq!(header.next(), Some("// auto-generated: \"lalrpop 0.23.2\""));
    assert_eq!(
        header.next(),
        Some(format!("// sha3: {hash}").as_str()),
        "src/grammar.lalrpop changed: run scripts/gen-parsers.sh and commit src/grammar.rs"
    );
}
