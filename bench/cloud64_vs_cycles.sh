#!/bin/sh
# cloud64_vs_cycles.sh - brume's path tracer against Blender Cycles on the comparison
# scene of shared/data/SOURCES.md (scenes/cloud64.json), in one script on one machine.
#
#   sh bench/cloud64_vs_cycles.sh [BUILD_DIR]
#
# Needs Debian's blender (Cycles 3.4), python3-openvdb and python3-numpy (to write the
# cloud as a .vdb Blender can load); installs them when run as root and missing.
# Measures:
#   1. Cycles at 64 spp: render time (the render call, scene already loaded) and relative
#      RMSE against a Cycles reference at REF_SPP spp;
#   2. brume at 4..256 spp: render time (the whole `brume render` process) and relative
#      RMSE against a brume reference at REF_SPP spp;
#   3. the time brume needs to reach Cycles' 64-spp error (error ~ 1/sqrt(spp), fitted at
#      the spp closest above it), and the ratio of the two times.
# Relative RMSE = RMSE / mean of the reference, with the reference's own variance removed.
# Also prints the mean radiance of each renderer's reference: the same scene must agree.
set -eu
BUILD=${1:-build}
REF_SPP=${REF_SPP:-1024}
here=$(cd "$(dirname "$0")/.." && pwd)
out=${OUT:-/tmp/brume-cloud64-bench}
mkdir -p "$out"
BRUME="$here/$BUILD/brume"
[ -x "$BRUME" ] || { echo "build brume first (make build)"; exit 1; }

if ! command -v blender >/dev/null || ! command -v bc >/dev/null || ! /usr/bin/python3 -c "import pyopenvdb, numpy" 2>/dev/null; then
    if [ "$(id -u)" -eq 0 ]; then
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends blender bc python3-openvdb python3-numpy >/dev/null
    else
        echo "needs: apt-get install blender bc python3-openvdb python3-numpy"; exit 1
    fi
fi

echo "machine: $(nproc) x $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
echo "blender: $(blender --version 2>/dev/null | head -1)"
/usr/bin/python3 "$here/bench/cycles/raw_to_vdb.py" "$here/../shared/data/cloud64.raw" "$out/cloud64.vdb"

cycles() { # spp out.exr -> prints seconds
    blender -b --python "$here/bench/cycles/cloud64_cycles.py" -- "$out/cloud64.vdb" "$2" "$1" 2 2>/dev/null |
        sed -n 's/^cycles_render_seconds //p'
}
err() { # image reference spp -> relative RMSE with the reference's noise removed
    "$BRUME" compare "$1" "$2" | awk -v n="$3" -v N="$REF_SPP" '/^rel_rmse/ {e=$2; v=e*e*(1-n/N); if (v<0) v=0; printf "%.5f\n", sqrt(v)}'
}
mean_of() { "$BRUME" compare "$1" "$1" | awk '/^mean_ref/ {print $2}'; }

echo "== Cycles reference ($REF_SPP spp)"
t=$(cycles "$REF_SPP" "$out/cycles_ref.exr"); echo "cycles ref: ${t} s, mean $(mean_of "$out/cycles_ref.exr")"
c64=""
for run in 1 2 3; do c64="$c64 $(cycles 64 "$out/cycles_64.exr")"; done
t_c=$(echo $c64 | tr ' ' '\n' | sort -n | sed -n 2p)
e_c=$(err "$out/cycles_64.exr" "$out/cycles_ref.exr" 64)
echo "cycles 64 spp: median ${t_c} s of ($c64 ), relative RMSE $e_c"

echo "== brume reference ($REF_SPP spp)"
"$BRUME" render "$here/scenes/cloud64.json" --spp "$REF_SPP" --seed 99 --quiet -o "$out/brume_ref.exr"
echo "brume ref mean $(mean_of "$out/brume_ref.exr")"
printf "%6s %10s %10s\n" spp seconds rel_rmse
best=""
for spp in 4 8 16 32 64 128 256; do
    ts=""
    for run in 1 2 3; do
        s=$(date +%s.%N)
        "$BRUME" render "$here/scenes/cloud64.json" --spp "$spp" --seed "$spp" --quiet -o "$out/brume_$spp.exr"
        ts="$ts $(echo "$(date +%s.%N) - $s" | bc -l)"
    done
    t=$(echo $ts | tr ' ' '\n' | sort -n | sed -n 2p)
    e=$(err "$out/brume_$spp.exr" "$out/brume_ref.exr" "$spp")
    printf "%6d %10.3f %10s\n" "$spp" "$t" "$e"
    if [ -z "$best" ] && [ "$(echo "$e <= $e_c" | bc -l)" = 1 ]; then best="$spp $t $e"; fi
done
set -- $best
t_b=$(echo "$2 * ($3 / $e_c)^2" | bc -l)
printf "brume reaches Cycles' 64-spp error %.4f in %.2f s (fitted from %s spp: %.3f s at %.4f)\n" "$e_c" "$t_b" "$1" "$2" "$3"
printf "time ratio brume / Cycles: %.3f (target <= 0.5)\n" "$(echo "$t_b / $t_c" | bc -l)"
