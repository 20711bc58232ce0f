#!/bin/sh
# blasi_figures.sh - the comparison table of docs/blasi.md and its pictures.
#   sh bench/blasi_figures.sh [BUILD_DIR [OUT_DIR]]   (run from the source tree)
# Writes into OUT_DIR (default $TMPDIR/blasi-figures/out), never into docs/ unless OUT_DIR says
# so (sh bench/blasi_figures.sh build docs/images refreshes the pictures of docs/blasi.md).
# The paper's three views are `brume figures` (docs/gallery.md). For each mixture of Figure 7 the first view at
# 200 x 200 by blasi (paper and physical variants) and by path (the reference), and
# compares them with `brume compare` (mean and max relative difference, difference images).
set -e
B=${1:-build}
BR=$B/brume
TMP=${TMPDIR:-/tmp}/blasi-figures
OUT=${2:-$TMP/out}
mkdir -p $OUT $TMP
# scene variants: the first view with each Figure 7 mixture
for m in rayleigh:0.5:-0.46:0.46 hazy:0.12:-0.5:0.7 murky:0.19:-0.65:0.91; do
  name=${m%%:*}; rest=${m#*:}; r=${rest%%:*}; rest=${rest#*:}; k=${rest%%:*}; kp=${rest#*:}
  sed "s/\"r\": 0.12, \"k\": -0.5, \"kprime\": 0.7/\"r\": $r, \"k\": $k, \"kprime\": $kp/" \
      scenes/blasi-picture1.json > $TMP/$name.json
  $BR render $TMP/$name.json -q --method path --width 200 --height 200 --spp ${REF_SPP:-256} --seed 1000003 -o $TMP/$name-path.exr
  for v in paper physical; do
    /usr/bin/time -f "%e" -o $TMP/$name-$v.time $BR render $TMP/$name.json -q --width 200 --height 200 \
        --set blasi.variant=$v -o $TMP/$name-$v.exr
    echo "== $name $v: $(cat $TMP/$name-$v.time) s"
    $BR compare $TMP/$name-$v.exr $TMP/$name-path.exr -o $OUT/blasi-diff-$name-$v.png
  done
  $BR render $TMP/$name.json -q --method path --width 200 --height 200 --spp 64 -o $OUT/blasi-path-$name.png
  $BR render $TMP/$name.json -q --width 200 --height 200 --set blasi.variant=paper -o $OUT/blasi-paper-$name.png
  $BR render $TMP/$name.json -q --width 200 --height 200 --set blasi.variant=physical -o $OUT/blasi-physical-$name.png
done
