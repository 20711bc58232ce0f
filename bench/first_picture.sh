#!/bin/sh
# first_picture.sh - `make render`'s first picture: the default scene after 15 s of rendering,
# denoised (`brume render --time 15 --denoise`), against a converged reference, and the same
# at a fixed spp (independent of the machine's load).
#
#   sh bench/first_picture.sh [BUILD_DIR]
#   SPP="17 27" sh bench/first_picture.sh       # the fixed spp (default 17 and 27: what 15 s gave
#                                                # on 2 loaded and 2 quiet cores, issue 49)
#   TIME=0 sh bench/first_picture.sh            # the fixed spp only
#   SEEDS="1 2" sh bench/first_picture.sh       # each fixed spp with these seeds (default 1); with
#                                                # two or more, the figures of their mean too, and
#                                                # the block error split into noise and bias
#   REF=/tmp/first-picture-ref.exr              # the reference (default); made when missing:
#                                                # 1024 spp, seed 1001, no noise target, with the
#                                                # variance and depth layers (about 1.6 CPU s per
#                                                # spp: 27 CPU minutes); keep it out of the repository
#   REF_SPP=256                                  # a shorter reference (its variance is removed from
#                                                # the figures, so it is unbiased, only noisier)
#
# Figures (bench_first_picture, built by `cmake --build BUILD_DIR --target bench_first_picture`):
# the relative RMS error of luminance over the pixels that are not sky, per pixel and over
# 8 x 8-pixel blocks, and the mean's deviation, for the denoised picture and its raw layer,
# with the reference's own variance removed (bench/bench_first_picture.c). The images are
# written to OUT (default /tmp/first-picture) and kept.
set -eu
BUILD=${1:-build}
REF=${REF:-/tmp/first-picture-ref.exr}
OUT=${OUT:-/tmp/first-picture}
SPP=${SPP:-17 27}
SEEDS=${SEEDS:-1}
TIME=${TIME:-15}
REF_SPP=${REF_SPP:-1024}
BRUME=$BUILD/brume
CMP=$BUILD/bench/bench_first_picture
[ -x "$BRUME" ] || { echo "first_picture.sh: $BRUME: not built"; exit 2; }
[ -x "$CMP" ] || { echo "first_picture.sh: $CMP: not built (cmake --build $BUILD --target bench_first_picture)"; exit 2; }
mkdir -p "$OUT"
echo "commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown); scene: the built-in default scene (scenes/default.json)"
echo "load: $(cat /proc/loadavg)"
if [ ! -f "$REF" ]; then
    echo "making the reference $REF ($REF_SPP spp)"
    "$BRUME" render --spp "$REF_SPP" --seed 1001 --set render.noise=0 --aov variance,depth --quiet -o "$REF"
fi
IMAGES=""
if [ "$TIME" != 0 ]; then
    # make render's command, to an EXR (the PNG holds the same pixels, tone mapped)
    "$BRUME" render --time "$TIME" --denoise -o "$OUT/time$TIME.exr" 2>&1 | tail -n 2
    IMAGES="$OUT/time$TIME.exr"
fi
for n in $SPP; do
    for s in $SEEDS; do
        /usr/bin/time -f "spp $n, seed $s: %U s user, %S s system, %e s wall" \
            "$BRUME" render --spp "$n" --seed "$s" --set render.noise=0 --denoise --quiet -o "$OUT/spp$n-seed$s.exr"
    done
done
echo "load: $(cat /proc/loadavg)"
if [ -n "$IMAGES" ]; then
    # shellcheck disable=SC2086
    "$CMP" "$REF" $IMAGES
fi
for n in $SPP; do
    SAME=""
    for s in $SEEDS; do
        SAME="$SAME $OUT/spp$n-seed$s.exr"
    done
    # shellcheck disable=SC2086
    "$CMP" --mean "$REF" $SAME
done
