#!/bin/sh
# stam_switches.sh - the tables of docs/stam.md "The kernel W as a table" and "Overlapping
# blobs": Stam's two optional models measured against `path` as "Measured against the
# reference" measures the default (bench/stam_compare.sh).
#   sh bench/stam_switches.sh [BUILD_DIR [OUT_DIR]]   (run from the source tree)
# scenes/stam-compare.json (the Figure 5 cloud, eps 0.4, eta 0.15, 160 x 120) by stam with
#   - stam.kernel = table: scenes/kernels/poly6.txt, and a gaussian written as a table;
#   - stam.overlap = joint, with either kernel;
# each against `path` (REF_SPP = 64 spp) on the explicit realization of the same Q with the
# same kernel (stam.voxelize, 192 cells), compared by `brume compare --alpha 0.05` (the
# cloud and the whole frame, 95 % tile-bootstrap intervals); the references' own noise
# from a second seed; the cost of joint as the median user time of RUNS interleaved renders.
set -e
B=${1:-build}
BR=$B/brume
TMP=${TMPDIR:-/tmp}/stam-switches
OUT=${2:-$TMP/out}
REF_SPP=${REF_SPP:-64}
RUNS=${RUNS:-3}
S=scenes/stam-compare.json
X="--set stam.voxelize.resolution=192 --set stam.voxelize.realization=true"
K="--set stam.kernel=table --set stam.kernel_file=kernels/poly6.txt" # relative to the scene file
mkdir -p $OUT $TMP
G="--set stam.kernel=table --set stam.kernel_file=$TMP/gauss.txt"
J="--set stam.overlap=joint"
awk 'BEGIN { for (k = 0; k <= 2048; k++) { s = k * 8 / 2048; printf "%.10f %.17g\n", s, exp(-s * s / 2) } }' > $TMP/gauss.txt
echo "load: $(cat /proc/loadavg)"
cmp() { echo "== $1"; shift; $BR compare "$@" --alpha 0.05 | grep -E '^(mean|frame|region) '; }
$BR render $S -q $X --method path --spp $REF_SPP --seed 1 -o $TMP/path.exr
$BR render $S -q $X --method path --spp $REF_SPP --seed 7 -o $TMP/path7.exr
$BR render $S -q $X $K --method path --spp $REF_SPP --seed 1 -o $TMP/path-poly6.exr
$BR render $S -q $X $K --method path --spp $REF_SPP --seed 7 -o $TMP/path-poly6-7.exr
$BR render $S -q -o $TMP/stam.exr
$BR render $S -q $J -o $TMP/stam-joint.exr
$BR render $S -q $G -o $TMP/stam-gtable.exr
$BR render $S -q $K -o $TMP/stam-poly6.exr
$BR render $S -q $K $J -o $TMP/stam-poly6-joint.exr
cmp "path $REF_SPP spp seed 7 vs seed 1, gaussian (the reference's own noise)" $TMP/path7.exr $TMP/path.exr
cmp "path $REF_SPP spp seed 7 vs seed 1, poly6 (the reference's own noise)" $TMP/path-poly6-7.exr $TMP/path-poly6.exr
cmp "stam gaussian table vs stam gaussian (the table's own error)" $TMP/stam-gtable.exr $TMP/stam.exr
cmp "stam gaussian, independent vs path gaussian" $TMP/stam.exr $TMP/path.exr
cmp "stam gaussian, joint vs path gaussian" $TMP/stam-joint.exr $TMP/path.exr -o $OUT/stam-joint-diff.png
cmp "stam poly6, independent vs path poly6" $TMP/stam-poly6.exr $TMP/path-poly6.exr -o $OUT/stam-poly6-diff.png
cmp "stam poly6, joint vs path poly6" $TMP/stam-poly6-joint.exr $TMP/path-poly6.exr
cmp "stam joint vs stam independent (what joint changes)" $TMP/stam-joint.exr $TMP/stam.exr
cmp "path poly6 vs path gaussian (what the kernel changes)" $TMP/path-poly6.exr $TMP/path.exr
$BR render $S -q $K -o $OUT/stam-poly6.png
$BR render $S -q $X $K --method path --spp 64 -o $OUT/stam-poly6-path.png
$BR render $S -q $J -o $OUT/stam-joint.png
rm -f $TMP/times.txt
echo "-- cost: user seconds of a whole frame (load, Q, light cache, render), $RUNS interleaved runs"
for r in $(seq $RUNS); do
  for v in independent joint; do
    /usr/bin/time -f "$v %U" $BR render $S -q --set stam.overlap=$v -o $TMP/t.exr 2>> $TMP/times.txt
    /usr/bin/time -f "$v-poly6 %U" $BR render $S -q $K --set stam.overlap=$v -o $TMP/t.exr 2>> $TMP/times.txt
  done
done
for v in independent joint independent-poly6 joint-poly6; do
  printf '%s median user %s s\n' $v "$(grep "^$v " $TMP/times.txt | awk '{print $2}' | sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')"
done
rm -f $TMP/times.txt
echo "load: $(cat /proc/loadavg)"
