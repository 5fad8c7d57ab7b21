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
# The partprogram parser's errors never list the tokens that were expected (its messages name the
# unexpected one and give a hint of their own), but LALRPOP computes that list at every syntax
# error: one parse simulation per terminal. On error-dense input (and under the fuzzer) that was
# a fifth of the parse, so the generated function is emptied.
perl -0pi -e 's/(fn __expected_tokens_from_states<.*?-> alloc::vec::Vec<alloc::string::String>\n    \{\n).*?\n    \}\n/$1        \/\/ Emptied by scripts\/gen-parsers.sh: partprogram reports no expected tokens.\n        alloc::vec::Vec::new()\n    }\n/s' partprogram/src/grammar.rs
grep -q "Emptied by scripts/gen-parsers.sh" partprogram/src/grammar.rs
