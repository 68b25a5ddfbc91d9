#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan: scripts/build-sanitized-core.sh) into
# build-fuzz/ and runs each for a bounded time on a scratch copy of its seed corpus
# (tests/fuzz/corpus/<target>). Fails on any crash, hang, leak or sanitizer report; the
# reproducer is left in build-fuzz/findings/.
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET]   (default 60)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
scripts/build-sanitized-core.sh

export UBSAN_OPTIONS="suppressions=$PWD/tests/fuzz/ubsan.supp:print_stacktrace=1"
findings=build-fuzz/findings
mkdir -p "$findings"
status=0
for target in obj scene plan_db automation sculpt_script mesh_import; do
    work=$(mktemp -d)
    cp tests/fuzz/corpus/$target/* "$work"/
    log=build-fuzz/fuzz_$target.log
    echo "fuzz_$target: ${seconds}s"
    if ./build-fuzz/bin/fuzz_$target "$work" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
           -artifact_prefix="$findings/${target}-" -print_final_stats=1 >"$log" 2>&1; then
        runs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')
        echo "fuzz_$target: ok, $runs executions, corpus $(ls "$work" | wc -l) inputs"
    else
        echo "fuzz_$target: FAILED (log: $log; reproducer in $findings/)"
        grep -E 'ERROR|SUMMARY|runtime error' "$log" | head -5 || true
        status=1
    fi
    rm -rf "$work"
done
exit $status
