#!/bin/sh
# hostile_slow.sh - the slow cases of the hostile corpus: valid values at the top of their range
# (images up to 65536 pixels wide, thousands of samples per pixel, 1024 threads, long time
# budgets), which must render, but take too long for `make test` (tests/hostile/SLOW.tsv,
# written by tests/hostile/make_hostile.py; the rest of the corpus is ctest's hostile.corpus).
# Usage: bench/hostile_slow.sh [BUILD_DIR]   (default build); prints each failing case and the
# replay's wall time. Extra arguments after the folder go to replay.py (e.g. --only spp).
set -eu
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src/build}
[ $# -gt 0 ] && shift
exec python3 "$src/tests/hostile/replay.py" "$build/brume" --manifest "$src/tests/hostile/SLOW.tsv" --jobs 1 --time-scale 6 "$@"
