#!/usr/bin/env bash
# same-images.sh - proves that two versions of brume render every scene byte for byte alike
# (a reshape changes no estimator). It builds both versions out of tree, renders
# the same list of cases with each at low resolution and few samples, a fixed seed and the
# same thread count, to OpenEXR (float32 RGBA, lossless) or, from Python, the raw float32
# array, and compares the files with cmp.
#
#   scripts/same-images.sh BASE [HEAD]     e.g. scripts/same-images.sh main
#                                                scripts/same-images.sh HEAD~1 HEAD
#   scripts/same-images.sh --compare DIR_A DIR_B   the comparison step alone (tests use it)
#
# BASE and HEAD are commits (anything git rev-parse takes). Without HEAD the working tree is
# compared: what git tracks plus untracked files git does not ignore, uncommitted changes
# included, copied aside (the tree and its build/ are left alone).
#
# One line per case: `same`, `DIFFERENT` or `failed to render on BASE|HEAD|both` (with the
# first line brume printed), then a summary. Exit 0 when every case is the same, 1 when one
# differs or failed, 2 when a version does not build or the command line is wrong.
#
# What is rendered (cases() below): every scenes/*.json (the animated ones at frame 7), the
# built-in default scene (no file; each binary's own compiled-in copy), a studio scene of
# every .vdb in data/ and of a .nvdb converted from data/ (`brume render FILE`), scenes/
# fire-vdb.json with the fire.vdb each version generates (`brume gen fire`), fire-velocity.json
# at frame 2 of the two files `brume gen fire --frames` writes, the methods
# no scene file uses on the comparison cloud (single, blasi), adaptive sampling, AOV
# layers, the denoiser, the independent sampler, and through the Python package the
# default scene and a dict with a numpy density. The scene files and data are HEAD's
# (copied, for both versions: a case is the same input rendered twice); the default scene
# and the Python package are each version's own. Slow scenes get fewer pixels or samples
# (scene_args()). Every render has a time limit (SAME_IMAGES_LIMIT seconds, 300).
#
# Builds: cmake RelWithDebInfo with BRUME_WERROR=ON (the flags of `make build`, so that
# ccache, which this script asks for with CCACHE_BASEDIR set to its scratch folder, finds
# the objects a developer's build already compiled), the GPU kernels off (not rendered
# here); targets brume_cli, brume_shared and brume_python, those a version has.
# Environment: SAME_IMAGES_JOBS (build jobs, 2), SAME_IMAGES_THREADS (render threads, 2),
# SAME_IMAGES_ONLY (an extended regex: run only the cases whose name matches),
# SAME_IMAGES_KEEP=1 (keep the scratch folder with the images and logs; its path is
# printed), TMPDIR (where the scratch folder goes), PYTHON (/usr/bin/python3).
#
# What it can see: brume computes in double and writes float32 pixels, so a change smaller
# than one float32 ulp of every pixel is invisible. Measured 2026-11-27 on the part-s branch:
# HG's phase value (src/phase/phase.c, hg_eval) made one double ulp larger (nextafter):
# 38 of 38 the same; made larger by one float32 ulp (x (1 + 2^-23)): 18 cases DIFFERENT
# (every one whose path or single estimator evaluates HG; Blasi's and Stam's scenes,
# which do not, the same), e.g. cloud64 at rmse 1.2e-8, max_rel 4.2e-7.
# Run time on the shared 2-core machine (load average 2 to 12 from other sessions): 4.8 to
# 7.5 minutes, of which 17 to 130 s per build (mostly ccache hits; a version whose sources
# ccache has not seen compiles longer) and 145 to 200 s for the 2 x 38 renders (at most 8 s
# each). `scripts/same-images.sh 2c0c4b6 b80e1c6` (main before and after its first reshape
# commits): 38 of 38 the same, 363 s.
set -u

me=${0##*/}
die() { echo "$me: $*" >&2; exit 2; }

# ---- the comparison step ---------------------------------------------------------------------
# compare_case ID DIR_A DIR_B NAME_A NAME_B: one line for case ID, from DIR_A/ID.{exr,raw,err}
# and DIR_B/ID.{exr,raw,err}; returns 0 for same, 1 otherwise.
output_of() { # DIR ID -> the path of ID's image in DIR, or nothing
    for ext in exr raw; do
        [ -f "$1/$2.$ext" ] && { echo "$1/$2.$ext"; return; }
    done
}
first_error() { # DIR ID -> the first non-empty line of ID's log, or a placeholder
    local line=""
    [ -f "$1/$2.err" ] && line=$(grep -m1 . "$1/$2.err" | cut -c1-200)
    echo "${line:-no image and no message}"
}
# how_different A B NAME_A NAME_B: the sizes, or the first byte that differs; with
# MEASURE_EXR set (a brume tool) also how far apart the pixels are (brume compare B to A)
how_different() {
    local na nb what figures
    na=$(wc -c <"$1") nb=$(wc -c <"$2")
    if [ "$na" -ne "$nb" ] || [ "${1##*.}" != "${2##*.}" ]; then
        what="$3: $na bytes, $4: $nb bytes"
    else
        what="first different byte: $(cmp "$1" "$2" 2>&1 | sed -n 's/.* differ: byte \([0-9]*\).*/\1/p') of $na"
    fi
    if [ -n "${MEASURE_EXR:-}" ] && [ "${1##*.}" = exr ] && [ "${2##*.}" = exr ]; then
        figures=$("$MEASURE_EXR" compare "$2" "$1" 2>/dev/null |
                  sed -n 's/^\(rmse\|max_rel\) \(.*\)$/\1 \2/p' | paste -sd, - | sed 's/,/, /g')
        [ -z "$figures" ] || what="$what; $figures"
    fi
    echo "$what"
}
compare_case() {
    local id=$1 a b
    a=$(output_of "$2" "$id")
    b=$(output_of "$3" "$id")
    if [ -n "$a" ] && [ -n "$b" ]; then
        if [ "${a##*.}" = "${b##*.}" ] && cmp -s "$a" "$b"; then
            printf '%-10s %s\n' same "$id"
            return 0
        fi
        printf '%-10s %s (%s)\n' DIFFERENT "$id" "$(how_different "$a" "$b" "$4" "$5")"
    elif [ -z "$a" ] && [ -z "$b" ]; then
        printf 'failed to render on both: %s: %s\n' "$id" "$(first_error "$2" "$id")"
    elif [ -z "$a" ]; then
        printf 'failed to render on %s: %s: %s\n' "$4" "$id" "$(first_error "$2" "$id")"
    else
        printf 'failed to render on %s: %s: %s\n' "$5" "$id" "$(first_error "$3" "$id")"
    fi
    return 1
}
# compare_dirs DIR_A DIR_B NAME_A NAME_B: every case either folder holds; 0 if all the same
compare_dirs() {
    local ids bad=0 n=0 id
    ids=$( (cd "$1" && ls) && (cd "$2" && ls) ) || return 2
    ids=$(printf '%s\n' "$ids" | sed -n 's/\.\(exr\|raw\|err\)$//p' | sort -u)
    [ -n "$ids" ] || { echo "$me: no images in $1 nor $2" >&2; return 1; }
    for id in $ids; do
        n=$((n + 1))
        compare_case "$id" "$1" "$2" "$3" "$4" || bad=$((bad + 1))
    done
    echo "$((n - bad)) of $n the same"
    [ "$bad" -eq 0 ]
}

if [ "${1:-}" = "--compare" ]; then
    [ $# -eq 3 ] || die "usage: $me --compare DIR_A DIR_B"
    [ -d "$2" ] && [ -d "$3" ] || die "--compare: $2 or $3 is not a folder"
    compare_dirs "$2" "$3" A B
    rc=$?
    [ $rc -le 1 ] || exit 2
    exit $rc
fi

case "${1:-}" in
    -h|--help) sed -n '2,/^set -u/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    "") die "usage: $me BASE [HEAD] (see $me --help)" ;;
    -*) die "unknown option $1 (see $me --help)" ;;
esac
[ $# -le 2 ] || die "usage: $me BASE [HEAD]"

repo=$(git rev-parse --show-toplevel 2>/dev/null) || die "run it inside brume's git repository"
base=$(git rev-parse --verify --quiet "$1^{commit}") || die "$1: not a commit"
base_name="BASE ${1} (${base:0:10})"
if [ $# -eq 2 ]; then
    head=$(git rev-parse --verify --quiet "$2^{commit}") || die "$2: not a commit"
    head_name="HEAD ${2} (${head:0:10})"
else
    head=""
    head_name="HEAD working tree (on $(git rev-parse --short=10 HEAD))"
fi
JOBS=${SAME_IMAGES_JOBS:-2}
THREADS=${SAME_IMAGES_THREADS:-2}
LIMIT=${SAME_IMAGES_LIMIT:-300}
ONLY=${SAME_IMAGES_ONLY:-}
PY=${PYTHON:-/usr/bin/python3}
command -v "$PY" >/dev/null 2>&1 || PY=python3

tmp=$(mktemp -d "${TMPDIR:-/tmp}/same-images.XXXXXX") || die "cannot make a scratch folder"
if [ "${SAME_IMAGES_KEEP:-0}" = 1 ]; then
    trap 'echo "$me: kept $tmp"' EXIT
else
    trap 'rm -rf "$tmp"' EXIT
fi
trap 'exit 130' INT TERM HUP
start=$(date +%s)

# ---- the two versions ------------------------------------------------------------------------
# extract COMMIT|"" DIR: the sources of a commit, or of the working tree, into DIR
extract() {
    mkdir -p "$2"
    if [ -n "$1" ]; then
        git -C "$repo" archive --format=tar "$1" | tar -x -C "$2"
    else # tracked and untracked-not-ignored files; deleted ones are skipped
        (cd "$repo" && git ls-files -z -c -o --exclude-standard |
            tar --null --ignore-failed-read -T - -cf - 2>/dev/null) | tar -x -C "$2"
    fi
}
# build SRC NAME: configures and builds SRC/build; the log is SRC/build.log
build() {
    local src=$1 b=$1/build want="" t have
    if ! cmake -S "$src" -B "$b" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBRUME_WERROR=ON -DBRUME_CUDA=OFF \
            -DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache >"$src/build.log" 2>&1; then
        tail -n 20 "$src/build.log" >&2
        die "$2: cmake failed (log above)"
    fi
    have=$(cmake --build "$b" --target help 2>/dev/null)
    for t in brume_cli brume_shared brume_python; do
        printf '%s\n' "$have" | grep -qE "(^|[ .])$t(:| |\$)" && want="$want $t"
    done
    [ -n "$want" ] || want=all
    # shellcheck disable=SC2086
    if ! cmake --build "$b" -j"$JOBS" --target $want >>"$src/build.log" 2>&1; then
        grep -m 20 -E 'error|Error' "$src/build.log" >&2
        die "$2: the build failed ($src/build.log${SAME_IMAGES_KEEP:+, kept})"
    fi
}
# find_in BUILD NAME: the first file NAME under BUILD
find_in() { find "$1" -name "$2" \( -type f -o -type l \) 2>/dev/null | sort | head -n1; }

export CCACHE_BASEDIR=$tmp # paths relative to the build folder: objects shared across runs
for side in base head; do
    if [ "$side" = base ]; then c=$base; n=$base_name; else c=$head; n=$head_name; fi
    t0=$(date +%s)
    extract "$c" "$tmp/$side" || die "$n: cannot extract the sources"
    build "$tmp/$side" "$n"
    bin=$tmp/$side/build/brume
    [ -x "$bin" ] || bin=$(find_in "$tmp/$side/build" brume)
    [ -x "$bin" ] || die "$n: no brume tool in the build"
    ln -s "$bin" "$tmp/$side.brume"
    lib=$(find_in "$tmp/$side/build" "libbrume.so.[0-9]*") # the SONAME: .so.0 before 1.0, .so.1 since
    pkg=$(find_in "$tmp/$side/build" _cdef.h)
    [ -n "$lib" ] && ln -s "$lib" "$tmp/$side.lib"
    [ -n "$pkg" ] && ln -s "$(dirname "$(dirname "$pkg")")" "$tmp/$side.python"
    echo "built $n in $(($(date +%s) - t0)) s"
done

# The inputs, HEAD's, one copy per side (fire.vdb and the converted .nvdb are made in it).
for side in base head; do
    mkdir -p "$tmp/run-$side" "$tmp/out-$side"
    cp -R "$tmp/head/scenes" "$tmp/head/data" "$tmp/run-$side/"
done
have_python=0
"$PY" -c 'import cffi, numpy' >/dev/null 2>&1 && have_python=1

# ---- the cases -------------------------------------------------------------------------------
COMMON="--seed 7 --quiet"
SIZE="--width 128 --height 96 --spp 4"
# scene_args NAME: the settings of scenes/NAME.json (the common ones come after)
scene_args() {
    case $1 in
        blasi-picture*) echo "--width 96 --height 96 --spp 2 --set blasi.light_rays=131072" ;;
        wdas-*) echo "--width 96 --height 64 --spp 2" ;;
        anim-*) echo "$SIZE --frame 7" ;;
        *) echo "$SIZE" ;;
    esac
}
# cases: one line per case, "ID<TAB>KIND<TAB>ARGS" (KIND cli, cli-fire, cli-fireseq, cli-nvdb or python)
cases() {
    local f name
    for f in "$tmp"/head/scenes/*.json; do
        name=$(basename "$f" .json)
        if [ "$name" = fire-vdb ]; then
            printf '%s\tcli-fire\t%s\n' "$name" "scenes/$name.json $(scene_args "$name")"
        elif [ "$name" = fire-velocity ]; then
            printf '%s\tcli-fireseq\t%s\n' "$name" "scenes/$name.json $(scene_args "$name") --frame 2"
        else
            printf '%s\tcli\t%s\n' "$name" "scenes/$name.json $(scene_args "$name")"
        fi
    done
    printf '%s\tcli\t%s\n' \
        builtin-default "$SIZE" \
        builtin-default.adaptive "--width 128 --height 96 --spp 16 --noise 0.3 --min-spp 4" \
        builtin-default.denoise "$SIZE --denoise" \
        default.single "scenes/default.json $SIZE --method single" \
        cloud64.single "scenes/cloud64.json $SIZE --method single" \
        cloud64.blasi "scenes/cloud64.json $SIZE --method blasi --set blasi.light_rays=131072" \
        cloud64.aov "scenes/cloud64.json $SIZE --aov depth,albedo,normal,variance,samples" \
        cloud64.independent "scenes/cloud64.json $SIZE --set render.sampler=independent"
    for f in "$tmp"/head/data/*.vdb "$tmp"/head/data/*.nvdb; do
        [ -f "$f" ] || continue
        name=$(basename "$f")
        printf '%s\tcli\t%s\n' "studio.$name" "data/$name $SIZE"
    done
    printf '%s\tcli-nvdb\t%s\n' studio.spiral-df3.nvdb "spiral.nvdb $SIZE"
    printf '%s\tpython\t%s\n' python.default default python.array array
}

# The Python cases: the default scene and a dict with a numpy density (docs/python.md).
PY_CASE='import sys, numpy as np, brume
case, out, threads = sys.argv[1], sys.argv[2], int(sys.argv[3])
scene = None
if case == "array":
    z, y, x = np.mgrid[-1:1:24j, -1:1:32j, -1:1:32j]
    rho = np.clip(1.0 - np.sqrt(x**2 + (1.5 * y)**2 + z**2), 0, None).astype(np.float32) * 4
    scene = {"camera": {"position": [0, 0.3, 3.5], "look_at": [0, 0, 0], "fov": 40},
             "background": [0.16, 0.26, 0.50],
             "lights": [{"type": "distant", "direction": [-0.6, -0.7, -0.4], "irradiance": 3}],
             "media": [{"density": {"type": "array", "data": rho, "bounds": [[-1, -0.75, -1], [1, 0.75, 1]]},
                        "sigma_a": 0.05, "sigma_s": 6, "phase": {"type": "hg", "g": 0.6}}]}
img = brume.render(scene, width=96, height=64, spp=4, seed=7, threads=threads)
with open(out + ".tmp", "wb") as f:
    f.write(np.ascontiguousarray(img, dtype=np.float32).tobytes())
import os; os.rename(out + ".tmp", out)'

# render SIDE ID KIND ARGS: renders one case with SIDE's build into out-SIDE/ID.{exr,raw}, or
# leaves out-SIDE/ID.err with what went wrong
render() {
    local side=$1 id=$2 kind=$3 args=$4 run=$tmp/run-$1 out=$tmp/out-$1 bin=$tmp/$1.brume rc
    local log=$out/$id.err
    (
        cd "$run" || exit 1
        case $kind in
            cli-fire) "$bin" gen fire -o scenes/fire.vdb || exit 1 ;;
            cli-fireseq) "$bin" gen fire --resolution 32 --velocity 4 --frames 1-2 -o 'scenes/fire_%04d.nvdb' || exit 1 ;;
            cli-nvdb) "$bin" convert data/spiral.df3 spiral.nvdb || exit 1 ;;
        esac
        if [ "$kind" = python ]; then
            [ -e "$tmp/$side.python" ] && [ -e "$tmp/$side.lib" ] || { echo "this build has no Python package"; exit 1; }
            PYTHONPATH=$tmp/$side.python BRUME_LIBRARY=$tmp/$side.lib PYTHONDONTWRITEBYTECODE=1 \
                timeout "$LIMIT" "$PY" -c "$PY_CASE" "$args" "$out/$id.raw" "$THREADS"
        else
            # shellcheck disable=SC2086
            timeout "$LIMIT" "$bin" render $args $COMMON --threads "$THREADS" -o "$out/$id.exr"
        fi
    ) >"$log" 2>&1
    rc=$?
    if [ $rc -ne 0 ]; then
        rm -f "$out/$id.exr" "$out/$id.raw"
        [ $rc -eq 124 ] && echo "timed out after $LIMIT s" >"$log"
        [ -s "$log" ] || echo "exit status $rc" >"$log"
        return 1
    fi
    rm -f "$log"
}

MEASURE_EXR=$tmp/head.brume
echo "comparing $base_name with $head_name; $THREADS threads; scenes and data from HEAD"
if [ -n "$head" ]; then changed=$(git diff --stat "$base" "$head" -- scenes data | tail -n1)
else changed=$(git diff --stat "$base" -- scenes data | tail -n1); fi
[ -z "$changed" ] || echo "note: scenes/ or data/ differ between BASE and HEAD ($changed); HEAD's are rendered by both"
cases >"$tmp/cases.txt"
bad=0 n=0
while IFS="$(printf '\t')" read -r id kind args; do
    [ -n "$ONLY" ] && ! printf '%s\n' "$id" | grep -qE -- "$ONLY" && continue
    if [ "$kind" = python ] && [ $have_python = 0 ]; then
        printf '%-10s %s (no %s with cffi and numpy)\n' skipped "$id" "$PY"
        continue
    fi
    n=$((n + 1))
    t0=$(date +%s.%N)
    render base "$id" "$kind" "$args"
    t1=$(date +%s.%N)
    render head "$id" "$kind" "$args"
    t2=$(date +%s.%N)
    line=$(compare_case "$id" "$tmp/out-base" "$tmp/out-head" "BASE" "HEAD") || bad=$((bad + 1))
    printf '%s   [%.1f s, %.1f s]\n' "$line" "$(echo "$t1 - $t0" | bc)" "$(echo "$t2 - $t1" | bc)"
    [ "${line%% *}" = same ] || printf '           args: %s\n' "$args"
done <"$tmp/cases.txt"
echo "$((n - bad)) of $n the same; $(($(date +%s) - start)) s in all"
[ "$bad" -eq 0 ]
