#!/bin/sh
# blasi_figures.sh - the comparison table of docs/blasi.md ("Against the reference") and its
# pictures.
#   sh bench/blasi_figures.sh [BUILD_DIR [OUT_DIR]]   (run from the source tree)
# Writes into OUT_DIR (default $TMPDIR/blasi-figures/out), never into docs/ unless OUT_DIR says
# so (sh bench/blasi_figures.sh build docs/images refreshes the pictures of docs/blasi.md).
# The paper's three views are `brume figures` (docs/gallery.md). For each mixture of Figure 7:
# the first view at 200 x 200 by path (the reference, REF_SPP = 256 spp, and a second reference
# at another seed: the reference's own noise) and by blasi in both variants, compared with
# `brume compare --alpha 0.05` (the cloud: the reference's alpha above 0.05, and the whole
# frame; 95 % tile-bootstrap intervals) and, over SEEDS (4) independent blasi renders,
# `brume compare --scene ... --seeds` (mean +- standard error over the seeds).
set -e
B=${1:-build}
BR=$B/brume
TMP=${TMPDIR:-/tmp}/blasi-figures
OUT=${2:-$TMP/out}
SEEDS=${SEEDS:-4}
REF_SPP=${REF_SPP:-256}
mkdir -p $OUT $TMP
echo "load: $(cat /proc/loadavg)"
# scene variants: the first view with each Figure 7 mixture
for m in rayleigh:0.5:-0.46:0.46 hazy:0.12:-0.5:0.7 murky:0.19:-0.65:0.91; do
  name=${m%%:*}; rest=${m#*:}; r=${rest%%:*}; rest=${rest#*:}; k=${rest%%:*}; kp=${rest#*:}
  sed "s/\"r\": 0.12, \"k\": -0.5, \"kprime\": 0.7/\"r\": $r, \"k\": $k, \"kprime\": $kp/" \
      scenes/blasi-picture1.json > $TMP/$name.json
  $BR render $TMP/$name.json -q --method path --width 200 --height 200 --spp $REF_SPP --seed 1000003 -o $TMP/$name-path.exr
  $BR render $TMP/$name.json -q --method path --width 200 --height 200 --spp $REF_SPP --seed 2000003 -o $TMP/$name-path2.exr
  echo "== $name: the reference's own noise (path $REF_SPP spp, seed 2000003 against seed 1000003)"
  $BR compare $TMP/$name-path2.exr $TMP/$name-path.exr --alpha 0.05 | grep -E '^(frame|region) '
  for v in paper physical; do
    /usr/bin/time -f "%e" -o $TMP/$name-$v.time $BR render $TMP/$name.json -q --width 200 --height 200 \
        --set blasi.variant=$v -o $TMP/$name-$v.exr
    echo "== $name $v: $(cat $TMP/$name-$v.time) s"
    $BR compare $TMP/$name-$v.exr $TMP/$name-path.exr --alpha 0.05 -o $OUT/blasi-diff-$name-$v.png | grep -E '^(mean|frame|region) '
    echo "-- $name $v over $SEEDS seeds"
    $BR compare --scene $TMP/$name.json --seeds $SEEDS --width 200 --height 200 --set blasi.variant=$v \
        $TMP/$name-path.exr --alpha 0.05 | grep -v '^seed'
  done
  $BR render $TMP/$name.json -q --method path --width 200 --height 200 --spp 64 -o $OUT/blasi-path-$name.png
  $BR render $TMP/$name.json -q --width 200 --height 200 --set blasi.variant=paper -o $OUT/blasi-paper-$name.png
  $BR render $TMP/$name.json -q --width 200 --height 200 --set blasi.variant=physical -o $OUT/blasi-physical-$name.png
done
