#!/bin/sh
# Regenerates the two LALRPOP parsers from their grammars and writes them beside them
# (compiler/src/grammar.rs, partprogram/src/grammar.rs). The parsers are committed so that a build
# does not compile LALRPOP; `cargo test -p compiler -p partprogram` fails when a grammar changed
# and its parser was not regenerated.
set -eu
cd "$(dirname "$0")/.."
if ! lalrpop --version 2>/dev/null | grep -q "0.23.2"; then
    cargo install lalrpop --version 0.23.2 --locked
fi
lalrpop --force compiler/src/grammar.lalrpop partprogram/src/grammar.lalrpop
