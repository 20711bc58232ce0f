#!/bin/sh
# fuzz_brief.sh - runs the libFuzzer targets (fuzz/run.sh: raw df3 vol nvdb vdb scene readers) for
# SECONDS each, one after the other at low priority, and prints per target the inputs executed
# and the crashes found (saved as BUILD_DIR/fuzz/crash-FORMAT-*). A bench, not CI: ctest runs
# each target 4 s (fuzz.*); this is the standing attack's longer run (docs/fuzzing.md).
# Usage: bench/fuzz_brief.sh [BUILD_DIR [SECONDS [TARGET...]]]   (default build 60, all but vdb)
set -u
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src/build} secs=${2:-60}
[ $# -gt 2 ] && { shift 2; targets=$*; } || targets="raw df3 vol nvdb scene readers"
mkdir -p "$build/fuzz/seeds"
"$build/fuzz_seeds" "$build/fuzz/seeds" >/dev/null || { echo "fuzz_brief: build fuzz_seeds first"; exit 1; }
status=0
for t in $targets; do
    log="$build/fuzz/brief-$t.log"
    before=$(ls "$build"/fuzz/crash-"$t"-* 2>/dev/null | wc -l)
    nice -n 10 sh "$src/fuzz/run.sh" "$t" "$build" "$secs" >"$log" 2>&1
    rc=$?
    after=$(ls "$build"/fuzz/crash-"$t"-* 2>/dev/null | wc -l)
    runs=$(grep -o 'number_of_executed_units: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*$')
    [ $rc -eq 77 ] && { echo "$t: skipped ($(tail -1 "$log"))"; continue; }
    echo "$t: ${runs:-0} inputs in ${secs} s, exit $rc, $((after - before)) new crash files (log: $log)"
    [ $rc -eq 0 ] || status=1
done
exit $status
