#!/bin/sh
# stam_compare.sh - the tables of docs/stam.md "Measured against the reference" and "As
# printed and as corrected", and their pictures.
#   sh bench/stam_compare.sh [BUILD_DIR [OUT_DIR]]   (run from the source tree)
# scenes/stam-compare.json (the Figure 5 cloud, eps 0.4, eta 0.15, 160 x 120) by stam, against
# `path` (REF_SPP = 256 spp) and `single` (64 spp) on the explicit realization of the same Q
# (stam.voxelize, 192 cells) and on the mean field, each compared with `brume compare --alpha
# 0.05` (the cloud and the whole frame, 95 % tile-bootstrap intervals); the stam variants also
# over SEEDS (4) render seeds (mean +- s.e.); the reference's own noise from a second seed.
set -e
B=${1:-build}
BR=$B/brume
TMP=${TMPDIR:-/tmp}/stam-compare
OUT=${2:-$TMP/out}
SEEDS=${SEEDS:-4}
REF_SPP=${REF_SPP:-256}
S=scenes/stam-compare.json
X="--set stam.voxelize.resolution=192 --set stam.voxelize.realization=true"
M="--set stam.voxelize.resolution=192 --set stam.voxelize.realization=false"
A0="--set stam.ambient=[0,0,0]"
mkdir -p $OUT $TMP
echo "load: $(cat /proc/loadavg)"
cmp() { echo "== $1"; shift; $BR compare "$@" --alpha 0.05 | grep -E '^(mean|frame|region) '; }
$BR render $S -q $X --method path --spp $REF_SPP --seed 1 -o $TMP/path.exr
$BR render $S -q $X --method path --spp $REF_SPP --seed 7 -o $TMP/path7.exr
$BR render $S -q $X $A0 --method single --spp 64 -o $TMP/single-x.exr
$BR render $S -q $M $A0 --method single --spp 64 -o $TMP/single-m.exr
$BR render $S -q --set stam.variant=corrected -o $TMP/corrected.exr
$BR render $S -q --set stam.variant=paper -o $TMP/paper.exr
$BR render $S -q $A0 -o $TMP/stam-a0.exr
$BR render $S -q $A0 --set stam.eps=0 -o $TMP/stam-a0-eps0.exr
cmp "path $REF_SPP spp seed 7 vs seed 1 (the reference's own noise)" $TMP/path7.exr $TMP/path.exr
cmp "stam corrected vs path, explicit realization" $TMP/corrected.exr $TMP/path.exr -o $OUT/stam-variant-diff-corrected.png
cmp "stam paper vs path, explicit realization" $TMP/paper.exr $TMP/path.exr -o $OUT/stam-variant-diff-paper.png
cmp "stam ambient 0 vs single, explicit realization" $TMP/stam-a0.exr $TMP/single-x.exr -o $OUT/stam-compare-diff-single.png
cmp "stam ambient 0, eps 0 vs single, mean field" $TMP/stam-a0-eps0.exr $TMP/single-m.exr
cmp "single, mean field vs single, explicit realization" $TMP/single-m.exr $TMP/single-x.exr
cp $OUT/stam-variant-diff-corrected.png $OUT/stam-compare-diff-path.png
for v in corrected paper; do
  echo "-- stam $v over $SEEDS render seeds"
  $BR compare --scene $S --seeds $SEEDS --set stam.variant=$v $TMP/path.exr --alpha 0.05 | grep -v '^seed'
done
$BR render $S -q --set stam.variant=corrected -o $OUT/stam-variant-corrected.png
$BR render $S -q --set stam.variant=paper -o $OUT/stam-variant-paper.png
cp $OUT/stam-variant-corrected.png $OUT/stam-compare-stam.png
$BR render $S -q $X --method path --spp 64 -o $OUT/stam-compare-path.png
