#!/bin/sh
# bench_read_ahead.sh - what reading the next frame while a frame renders saves, as a user
# runs it: `brume render` over a 4-frame sequence of .vdb files (four copies of
# data/wdas_cloud_sixteenth.vdb, 1.6 MB each, read through the sandboxed OpenVDB reader), the
# whole process's wall time with read-ahead (the default) and with --no-read-ahead, for the
# render on every core and on one thread (a core left free for the read). Runs alternate
# between the two, medians of RUNS; the machine's load is printed, since a shared machine
# slows every sample. The frames are checked to be the same bytes both ways.
#
#   bench/bench_read_ahead.sh BUILD_DIR [RUNS]     (default RUNS = 5)
set -eu
BUILD=${1:?usage: bench_read_ahead.sh BUILD_DIR [RUNS]}
RUNS=${2:-5}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BRUME="$BUILD/brume"
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
for k in 1 2 3 4; do cp "$ROOT/data/wdas_cloud_sixteenth.vdb" "$OUT/cloud_000$k.vdb"; done
cat > "$OUT/s.json" <<'JSON'
{"camera": {"frame": "media", "position": [1, 0.5, 1], "look_at": [0, 0, 0], "fov": 30},
 "lights": [{"type": "distant", "direction": [0.3, -1, -0.4], "irradiance": 3}],
 "media": [{"density": {"type": "grid", "file": "cloud_####.vdb", "frame_offset": 1}, "sigma_a": 0, "sigma_s": 1}],
 "render": {"width": 96, "height": 96, "spp": 2}}
JSON
now() { date +%s.%N; }
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg), $(date -u '+%Y-%m-%d %H:%M UTC')"
printf '%-9s %12s %14s %7s\n' threads read-ahead no-read-ahead ratio
for threads in 0 1; do
    with="" without=""
    for r in $(seq "$RUNS"); do
        t1=$(now)
        "$BRUME" render "$OUT/s.json" --frames 0-3 --threads "$threads" -q -o "$OUT/a_%d.png"
        t2=$(now)
        "$BRUME" render "$OUT/s.json" --frames 0-3 --threads "$threads" -q --no-read-ahead -o "$OUT/b_%d.png"
        t3=$(now)
        with="$with $(echo "$t2 - $t1" | bc -l)"
        without="$without $(echo "$t3 - $t2" | bc -l)"
        for k in 0 1 2 3; do cmp -s "$OUT/a_$k.png" "$OUT/b_$k.png" || { echo "frame $k differs" >&2; exit 1; }; done
    done
    w=$(echo $with | tr ' ' '\n' | median)
    wo=$(echo $without | tr ' ' '\n' | median)
    label=$threads; [ "$threads" = 0 ] && label="all"
    printf '%-9s %11.2fs %13.2fs %7.3f\n' "$label" "$w" "$wo" "$(echo "$w / $wo" | bc -l)"
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
