//! The committed LALRPOP parsers (`compiler/src/grammar.rs`, `partprogram/src/grammar.rs`) were
//! generated from the committed grammars: LALRPOP writes the grammar's SHA3-256 into the second
//! line of what it generates, and `scripts/gen-parsers.sh` regenerates both (and empties the
//! partprogram parser's list of expected tokens, which its diagnostics never show).

use sha3::{Digest, Sha3_256};

use crate::e2e_common::root;

#[test]
fn each_committed_parser_was_generated_from_its_committed_grammar() {
    for krate in ["compiler", "partprogram"] {
        let dir = root().join(krate).join("src");
        let grammar = std::fs::read(dir.join("grammar.lalrpop")).expect("the grammar");
        let hash: String = Sha3_256::digest(&grammar)
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        let parser = std::fs::read_to_string(dir.join("grammar.rs")).expect("the parser");
        let mut header = parser.lines();
        assert_eq!(header.next(), Some("// auto-generated: \"lalrpop 0.23.2\""));
        assert_eq!(
            header.next(),
            Some(format!("// sha3: {hash}").as_str()),
            "{krate}/src/grammar.lalrpop changed: run scripts/gen-parsers.sh and commit the parser"
        );
        assert_eq!(
            parser.contains("Emptied by scripts/gen-parsers.sh"),
            krate == "partprogram",
            "{krate}/src/grammar.rs: regenerate it with scripts/gen-parsers.sh, not lalrpop alone"
        );
    }
}
