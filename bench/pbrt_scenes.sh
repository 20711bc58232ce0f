#!/bin/sh
# pbrt_scenes.sh - pbrt-v4-scenes' media scenes rendered from their own, unmodified .pbrt
# files by brume and, when given, by pbrt-v4 at the same size and samples.
#
#   sh bench/pbrt_scenes.sh PBRT_V4_SCENES_DIR [PBRT_EXE]
#   K=8 SPP=1 SCENES="disney-cloud explosion" sh bench/pbrt_scenes.sh ~/pbrt-v4-scenes ~/pbrt-v4/build/pbrt
#   PICTURES=docs/images sh bench/pbrt_scenes.sh ...   # also the side-by-side PNGs of docs/pbrt-scenes.md
#
# PBRT_V4_SCENES_DIR is a checkout of github.com/mmp/pbrt-v4-scenes (any part of it: a scene
# whose .pbrt is absent is reported as such); SCENES may also name .pbrt files of that folder
# (tests/pbrt_rehearsal: SCENES="fog_camera.pbrt blackbody_slab.pbrt ink_ball.pbrt"). Per scene:
#   1. its folder is copied to a temporary folder, and every file the .pbrt (and what it
#      includes) names but the copy lacks gets a stand-in (bench/pbrt_scenes_assets.py:
#      grids by `brume gen cloud` / `brume gen fire`, boxes for meshes, a small equal-area
#      octahedral EXR sky, grey textures, a procedural uniformgrid for smoke-plume's density
#      include), each named on stderr;
#   2. brume renders the .pbrt as it is, at 1/K of the film's size (--width, --height) and
#      K^2 SPP samples a pixel (--spp); nothing else is overridden;
#   3. with PBRT_EXE, pbrt-v4 renders the same file at the film's own size and SPP samples a
#      pixel (--spp, --outfile: pbrt-v4 has no option for the film's size), and its image is
#      averaged over K x K blocks: the same pixels at the same samples per pixel as brume's.
#      `brume compare` then gives the ratio of the means (with its 95 % block-bootstrap
#      interval), the ratio of each channel's means, and the relative RMSE (the noise of
#      both images included);
#   4. one line: "rendered" (times, figures) or "refused" (brume's one-line message), or
#      "pbrt-v4 failed" (pbrt-v4's last line). Under a refusal, where brume has --lenient,
#      one "stops" line per construct a --lenient translation skips (what else stands in
#      the scene's way; malformed input still ends that listing).
# With PICTURES=DIR, brume's and pbrt-v4's images are written as DIR/pbrt-SCENE-brume.png
# and DIR/pbrt-SCENE-pbrt.png (sRGB, clamped, at most 320 pixels wide; a render under 160
# wide has its pixels repeated), by the same code for both so that they differ only where the
# renders do. tests/pbrt_conventions holds small scenes of one convention each
# (SCENES="grid_uniform.pbrt ...", K=1: docs/pbrt-scenes.md).
# Env: BRUME (default build/brume), K (4), SPP (1), BRUME_SPP (brume's samples a pixel when
# there is no PBRT_EXE; default K^2 SPP), SCENES (all eight), THREADS (brume's and
# pbrt-v4's threads; default all cores), KEEP=1 keeps the temporary folder.
# Times are wall-clock on whatever else the machine runs: they are for orientation only.
set -eu

here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
[ $# -ge 1 ] || { sed -n '2,30p' "$0" >&2; exit 2; }
scenes_dir=$(cd "$1" && pwd)
pbrt=${2:-}
[ -z "$pbrt" ] || pbrt=$(cd "$(dirname "$pbrt")" && pwd)/$(basename "$pbrt")
brume=${BRUME:-$root/build/brume}
case $brume in /*) ;; *) brume=$(pwd)/$brume ;; esac
K=${K:-4}
SPP=${SPP:-1}
bspp=$((K * K * SPP))
if [ -n "${BRUME_SPP:-}" ]; then
    [ -z "$pbrt" ] || { echo "pbrt_scenes.sh: BRUME_SPP is for brume alone (with pbrt-v4 both take SPP)" >&2; exit 2; }
    bspp=$BRUME_SPP
fi
SCENES=${SCENES:-"disney-cloud bunny-cloud clouds explosion smoke-plume dambreak0 dambreak1 crown"}
assets="python3 $here/pbrt_scenes_assets.py"
[ -x "$brume" ] || { echo "pbrt_scenes.sh: $brume: no brume binary (set BRUME)" >&2; exit 2; }
if [ -n "${PICTURES:-}" ]; then
    mkdir -p "$PICTURES"
    PICTURES=$(cd "$PICTURES" && pwd)
fi
lenient=""
"$brume" help render 2>&1 | grep -q -- '--lenient' && lenient=1
thr_b=""; thr_p=""
if [ -n "${THREADS:-}" ]; then thr_b="--threads $THREADS"; thr_p="--nthreads $THREADS"; fi

scene_file() {
    case $1 in
        disney-cloud) echo disney-cloud/disney-cloud.pbrt ;;
        bunny-cloud) echo bunny-cloud/bunny-cloud.pbrt ;;
        clouds) echo clouds/clouds.pbrt ;;
        explosion) echo explosion/explosion.pbrt ;;
        smoke-plume) echo smoke-plume/plume.pbrt ;;
        dambreak0) echo dambreak/dambreak0.pbrt ;;
        dambreak1) echo dambreak/dambreak1.pbrt ;;
        crown) echo crown/crown.pbrt ;;
        *) echo "$1" ;;
    esac
}

now() { date +%s.%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", b - a }'; }

tmp=$(mktemp -d)
[ -n "${KEEP:-}" ] || trap 'rm -rf "$tmp"' EXIT INT TERM

brume_rev=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo "?")
echo "# brume $brume_rev ($("$brume" --version 2>&1 | head -1)); K=$K, pbrt-v4 at SPP=$SPP spp, brume at $bspp spp and 1/$K size"
[ -z "$pbrt" ] || echo "# pbrt-v4: $pbrt ($(git -C "$(dirname "$pbrt")/.." rev-parse --short HEAD 2>/dev/null || echo "?"))"
for name in $SCENES; do
    rel=$(scene_file "$name")
    case $rel in */*) folder=${rel%%/*} ;; *) folder=. ;; esac
    if [ ! -f "$scenes_dir/$rel" ]; then
        printf '%-19s absent     (%s not in %s)\n' "$name" "$rel" "$scenes_dir"
        continue
    fi
    work=$tmp/$name
    mkdir -p "$work/$folder"
    cp -R "$scenes_dir/$folder/." "$work/$folder/"
    file=$work/$rel
    $assets standins "$file" "$brume" 2> "$work/standins.txt" || true
    sed "s/^/# $name: /" "$work/standins.txt" >&2
    set -- $($assets film "$file")
    w=$(( $1 / K )); h=$(( $2 / K ))
    t0=$(now)
    # shellcheck disable=SC2086
    if (cd "$(dirname "$file")" && "$brume" render "$(basename "$file")" -q $thr_b \
            --width "$w" --height "$h" --spp "$bspp" -o "$work/brume.pfm") \
            > "$work/brume.log" 2>&1; then
        tb=$(secs "$t0" "$(now)")
    else
        printf '%-19s refused    %s\n' "$name" "$(grep -v '^$' "$work/brume.log" | tail -1)"
        if [ -n "$lenient" ]; then
            # everything else brume would skip: the warnings of a translation with --lenient,
            # and the line that ends it where the file is malformed for brume's reader
            (cd "$(dirname "$file")" && "$brume" render "$(basename "$file")" --lenient -q \
                --width 4 --height 4 --spp 1 -o "$work/lenient.pfm") > "$work/lenient.log" 2>&1 || true
            sed -n 's/^brume: warning: \(.*\) (ignored: --lenient)$/\1/p; s/^brume: \([^ ]*\.pbrt:[0-9]*: .*\)$/\1/p' \
                "$work/lenient.log" | sed "s/^/$(printf '%-19s' '') stops      /" | awk '!seen[$0]++'
        fi
        continue
    fi
    [ -z "${PICTURES:-}" ] || $assets png "$work/brume.pfm" "$PICTURES/pbrt-${name%.pbrt}-brume.png" 320
    if [ -z "$pbrt" ]; then
        printf '%-19s rendered   brume %5ss (%dx%d, %d spp)\n' "$name" "$tb" "$w" "$h" "$bspp"
        continue
    fi
    t0=$(now)
    # shellcheck disable=SC2086
    if (cd "$(dirname "$file")" && "$pbrt" --quiet $thr_p --spp "$SPP" --outfile "$work/pbrt_full.pfm" \
            "$(basename "$file")") > "$work/pbrt.log" 2>&1; then
        tp=$(secs "$t0" "$(now)")
    else
        printf '%-19s rendered   brume %5ss; pbrt-v4 failed: %s\n' "$name" "$tb" \
            "$(grep -v '^$' "$work/pbrt.log" | tail -1)"
        continue
    fi
    $assets shrink "$work/pbrt_full.pfm" "$K" "$work/pbrt.pfm"
    [ -z "${PICTURES:-}" ] || $assets png "$work/pbrt.pfm" "$PICTURES/pbrt-${name%.pbrt}-pbrt.png" 320
    "$brume" compare "$work/brume.pfm" "$work/pbrt.pfm" --boot 400 > "$work/compare.txt" 2>&1 || true
    ratio=$(awk '$1 == "frame" && $2 == "ratio" { print $3, $4, $5 }' "$work/compare.txt")
    rel_rmse=$(awk '$1 == "rel_rmse" { print $2 }' "$work/compare.txt")
    mean=$(awk '$1 == "mean" { print $2 }' "$work/compare.txt")
    mean_ref=$(awk '$1 == "mean_ref" { print $2 }' "$work/compare.txt")
    rgb=$($assets ratios "$work/brume.pfm" "$work/pbrt.pfm")
    printf '%-19s rendered   brume %5ss, pbrt-v4 %5ss (%dx%d, %d spp); mean %s vs %s: ratio %s, r/g/b %s; rel_rmse %s\n' \
        "$name" "$tb" "$tp" "$w" "$h" $((K * K * SPP)) "$mean" "$mean_ref" "$ratio" "$rgb" "$rel_rmse"
done
