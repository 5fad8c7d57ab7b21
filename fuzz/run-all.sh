#!/usr/bin/env bash
# Runs every cargo-fuzz target of ncplc for N seconds each (default 60), one after the other.
#
# Usage:   fuzz/run-all.sh [SECONDS] [TARGET...]
# Needs:   the nightly toolchain and cargo-fuzz (`cargo install cargo-fuzz --locked`).
# Corpora: each target reads the committed seeds in fuzz/seeds/<target>/ and grows its working
#          corpus in fuzz/corpus/<target>/ (git-ignored). A crash lands in fuzz/artifacts/<target>/;
#          the script then stops with a non-zero status and prints the reproduce command.
# Note:    the first build compiles cranelift with AddressSanitizer (about 20 min on 2 busy cores);
#          `FUZZ_FEATURES=--no-default-features` builds and runs only the parsers
#          that do not need cranelift (not plc_*, not partprogram).
# Env:     FUZZ_ARGS="..." adds libFuzzer flags (e.g. "-max_len=4096").
set -euo pipefail
cd "$(dirname "$0")"
secs="${1:-60}"
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
    mapfile -t targets < <(cargo +nightly fuzz list)
    if [ -n "${FUZZ_FEATURES:-}" ]; then
        targets=("${targets[@]/plc_*/}")
        targets=("${targets[@]/partprogram/}")
    fi
fi
# shellcheck disable=SC2086
cargo +nightly fuzz build ${FUZZ_FEATURES:-}
for t in "${targets[@]}"; do
    [ -n "$t" ] || continue
    mkdir -p "corpus/$t" "seeds/$t"
    echo "=== $t: ${secs}s"
    # shellcheck disable=SC2086
    if ! cargo +nightly fuzz run ${FUZZ_FEATURES:-} "$t" "corpus/$t" "seeds/$t" -- \
        -max_total_time="$secs" -rss_limit_mb=2048 -timeout=10 ${FUZZ_ARGS:-}; then
        echo "!!! $t failed; reproduce with: cargo +nightly fuzz run $t fuzz/artifacts/$t/<file>" >&2
        exit 1
    fi
done
echo "all ${#targets[@]} targets ran ${secs}s each without a crash"
