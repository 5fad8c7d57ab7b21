#!/usr/bin/env bash
# Runs every cargo-fuzz target of ncplc, one after the other, one libFuzzer job at a time.
#
# Usage:   fuzz/run-all.sh [SECONDS] [TARGET...]          each target for SECONDS (default 60)
#          fuzz/run-all.sh --resume TOTAL [TARGET...]     continue campaigns to TOTAL executions
# Needs:   the nightly toolchain and cargo-fuzz (`cargo install cargo-fuzz --locked`).
# Corpora: each target reads the committed seeds in fuzz/seeds/<target>/ and grows its working
#          corpus in fuzz/corpus/<target>/ (git-ignored). A crash lands in fuzz/artifacts/<target>/;
#          the script then stops with a non-zero status and prints the reproduce command.
# Resume:  fuzz/executions.tsv (committed) records per target the executions and campaigns run so
#          far. `--resume TOTAL` runs each target whose count is below TOTAL in chunks of at most
#          FUZZ_CHUNK executions (default 1000000, `-runs=`), adding each finished chunk to the
#          file at once (written to a temporary file and renamed), so an interrupted campaign
#          resumes where the last chunk ended. When a target reaches TOTAL, its corpus is
#          minimised (`cargo fuzz cmin`) and copied into fuzz/seeds/<target>/ when the minimised
#          corpus is at most FUZZ_SEED_KB kilobytes (default 64): the repo keeps small corpora.
# Note:    the first build compiles cranelift with AddressSanitizer (about 20 min on 2 busy cores);
#          `FUZZ_FEATURES=--no-default-features` builds and runs only the parsers
#          that do not need cranelift (not plc_*, not partprogram).
# Env:     FUZZ_ARGS="..." adds libFuzzer flags (e.g. "-max_len=4096"). Every run is
#          one in-process libFuzzer run (no `-jobs`: libFuzzer's job mode logs to fuzz-<n>.log in the
#          current directory, which campaigns side by side would share).
#          FUZZ_JOB=<name> names this campaign's logs (logs/<target>.<name>.log), so that two
#          campaigns of the same target can run side by side (one per core) on the shared corpus
#          and add their executions to fuzz/executions.tsv, each under the lock; such a job does
#          not minimise the corpus at its end (run once more without FUZZ_JOB for that).
#          FUZZ_SANITIZER=none builds without AddressSanitizer (cargo fuzz `-s none`): several times
#          the executions per second; panics, timeouts and the RSS limit are still caught. Use the
#          same value for every command of a campaign (another value rebuilds everything).
#          FUZZ_BUILD_ARGS="..." adds cargo-fuzz build flags, e.g. `--no-trace-compares`: no
#          comparison tracing (libFuzzer's CMP-guided mutation); for the targets that compile with
#          cranelift, where most of that tracing is inside cranelift, 2.4x (partprogram) to 6.7x
#          (fanuc_macro) the executions per second and more coverage features found per minute.
#          Other flags rebuild everything: give such a campaign its own CARGO_TARGET_DIR.
set -euo pipefail
cd "$(dirname "$0")"
state=executions.tsv
resume=""
if [ "${1:-}" = "--resume" ]; then
    resume="${2:?--resume needs the total number of executions per target}"
    shift 2
    secs=""
else
    secs="${1:-60}"
    shift || true
fi
targets=("$@")
san=()
if [ -n "${FUZZ_SANITIZER:-}" ]; then
    san=(--sanitizer "$FUZZ_SANITIZER")
fi
if [ ${#targets[@]} -eq 0 ]; then
    mapfile -t targets < <(cargo +nightly fuzz list)
    if [ -n "${FUZZ_FEATURES:-}" ]; then
        targets=("${targets[@]/plc_*/}")
        targets=("${targets[@]/partprogram/}")
    fi
fi

# The executions and campaigns recorded for target $1 ("0 0" when none).
recorded() {
    awk -F'\t' -v t="$1" '$1 == t { print $2, $3; found = 1 } END { if (!found) print 0, 0 }' \
        "$state" 2>/dev/null || echo "0 0"
}

# Adds $2 executions and one campaign to target $1 in the state file, atomically.
record() {
    local t="$1" n="$2" tmp
    # Campaigns running side by side (other targets) update the file one at a time.
    exec 9>"$state.lock"
    flock 9
    tmp="$(mktemp "$state.XXXXXX")"
    {
        echo -e "# target\texecutions\tcampaigns"
        awk -F'\t' -v t="$t" -v n="$n" '
            /^#/ { next }
            $1 == t { print t "\t" $2 + n "\t" $3 + 1; found = 1; next }
            { print }
            END { if (!found) print t "\t" n "\t" 1 }' "$state" 2>/dev/null \
            || echo -e "$t\t$n\t1"
    } >"$tmp"
    mv "$tmp" "$state"
    flock -u 9
}

# The executions libFuzzer reports in log $1: "Done N runs" (-runs reached) or the last "#N".
executions() {
    local n
    n="$(grep -o 'Done [0-9]* runs' "$1" | tail -1 | grep -o '[0-9]*' || true)"
    if [ -z "$n" ]; then
        n="$(grep -o '^#[0-9]*' "$1" | tail -1 | tr -d '#' || true)"
    fi
    echo "${n:-0}"
}

# Minimises corpus/$1 and keeps it in seeds/$1 when it is small.
keep_corpus() {
    local t="$1" kb
    # shellcheck disable=SC2086
    cargo +nightly fuzz cmin ${san[@]+"${san[@]}"} ${FUZZ_FEATURES:-} ${FUZZ_BUILD_ARGS:-} "$t" "corpus/$t" >/dev/null 2>&1 || return 0
    kb="$(du -sk "corpus/$t" | cut -f1)"
    if [ "$kb" -le "${FUZZ_SEED_KB:-64}" ]; then
        cp -n "corpus/$t"/* "seeds/$t"/ 2>/dev/null || true
        echo "=== $t: minimised corpus (${kb} KB) kept in fuzz/seeds/$t"
    else
        echo "=== $t: minimised corpus is ${kb} KB (> ${FUZZ_SEED_KB:-64}): not kept in fuzz/seeds"
    fi
}

fail() {
    echo "!!! $1 failed; reproduce with: cargo +nightly fuzz run $1 fuzz/artifacts/$1/<file>" >&2
    exit 1
}

# shellcheck disable=SC2086
cargo +nightly fuzz build ${san[@]+"${san[@]}"} ${FUZZ_FEATURES:-} ${FUZZ_BUILD_ARGS:-}
mkdir -p logs
for t in "${targets[@]}"; do
    [ -n "$t" ] || continue
    mkdir -p "corpus/$t" "seeds/$t"
    if [ -z "$resume" ]; then
        echo "=== $t: ${secs}s"
        log="logs/$t${FUZZ_JOB:+.$FUZZ_JOB}.log"
        # shellcheck disable=SC2086
        cargo +nightly fuzz run ${san[@]+"${san[@]}"} ${FUZZ_FEATURES:-} ${FUZZ_BUILD_ARGS:-} "$t" "corpus/$t" "seeds/$t" -- \
            -max_total_time="$secs" -rss_limit_mb=2048 -timeout=10 \
            ${FUZZ_ARGS:-} 2>"$log" || fail "$t"
        record "$t" "$(executions "$log")"
        continue
    fi
    read -r done_runs _ < <(recorded "$t")
    while [ "$done_runs" -lt "$resume" ]; do
        chunk=$((resume - done_runs))
        [ "$chunk" -le "${FUZZ_CHUNK:-1000000}" ] || chunk="${FUZZ_CHUNK:-1000000}"
        echo "=== $t: $done_runs of $resume executions; running $chunk more"
        log="logs/$t${FUZZ_JOB:+.$FUZZ_JOB}.log"
        # shellcheck disable=SC2086
        cargo +nightly fuzz run ${san[@]+"${san[@]}"} ${FUZZ_FEATURES:-} ${FUZZ_BUILD_ARGS:-} "$t" "corpus/$t" "seeds/$t" -- \
            -runs="$chunk" -rss_limit_mb=2048 -timeout=10 \
            ${FUZZ_ARGS:-} 2>"$log" || fail "$t"
        n="$(executions "$log")"
        [ "$n" -gt 0 ] || { echo "!!! $t: no executions in $log" >&2; exit 1; }
        record "$t" "$n"
        # Re-read: a campaign of the same target beside this one (FUZZ_JOB) adds its own.
        read -r done_runs _ < <(recorded "$t")
    done
    echo "=== $t: $done_runs executions recorded"
    if [ -n "${FUZZ_JOB:-}" ]; then
        # Another job of this target may still write to the corpus: minimise it once all ended
        # (`fuzz/run-all.sh --resume TOTAL <target>` again does only that).
        echo "=== $t: corpus not minimised (FUZZ_JOB=$FUZZ_JOB)"
    else
        keep_corpus "$t"
    fi
done
if [ -z "$resume" ]; then
    echo "all targets ran ${secs}s each without a crash (executions in fuzz/$state)"
else
    echo "all targets reached $resume executions without a crash (fuzz/$state)"
fi
