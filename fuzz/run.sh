#!/bin/sh
# run.sh - build one libFuzzer target (a grid reader, or the scene reader) with clang and run it briefly.
# Usage: fuzz/run.sh FORMAT BUILD_DIR SECONDS   (FORMAT: raw df3 vol nvdb vdb, scene, or readers:
# the checkpoint and mesh readers, fuzz/fuzz_readers.c)
# FUZZ_RUNS=N runs N inputs instead of SECONDS (the long runs of docs/fuzzing.md).
# FUZZ_TIMEOUT=S: the per-input time limit in wall-clock seconds (default 10, vdb 40); the long
# runs share a loaded machine at low priority and use 60, reporting the slowest input.
# FUZZ_ASAN=0 builds without AddressSanitizer (vdb only: its long run, where forking an ASan
# process per input for the OpenVDB reader costs a second each; see docs/fuzzing.md).
# Crashing inputs are saved as BUILD_DIR/fuzz/crash-FORMAT-*. Seeds: BUILD_DIR/fuzz/seeds/FORMAT (made by the fuzz_seeds program) and, for df3, raw
# and vdb, the real files of data/ (data/README.md). Exits 77 (ctest: skipped) without clang's
# libFuzzer, or without OpenVDB for vdb.
set -eu
fmt=$1 build=$(cd "$2" && pwd) secs=$3
src=$(cd "$(dirname "$0")/.." && pwd)
data="$src/data"
out="$build/fuzz"
mkdir -p "$out/corpus-$fmt"
command -v clang >/dev/null 2>&1 || { echo "fuzz: clang not found, skipped"; exit 77; }
probe="$out/probe.c"
echo 'int LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n) { (void)d; (void)n; return 0; }' > "$probe"
clang -fsanitize=fuzzer "$probe" -o "$out/probe" 2>/dev/null || { echo "fuzz: no libFuzzer (libclang-rt-14-dev), skipped"; exit 77; }

upper=$(echo "$fmt" | tr a-z A-Z)
flags="-g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all -I$src/src -I$src/include -I$src/data -DFUZZ_FORMAT=GRID_FORMAT_$upper -D_POSIX_C_SOURCE=200809L"

# cached_objects NAME COMPILER "FLAGS" FILE...: compiles each FILE to an object once for
# these flags and these sources (and every header of src/ and include/): the targets that
# share them (raw, df3, vol, nvdb; scene and readers) build them once, not once each. The
# folder is named by a hash of the flags and the sources, so a changed file or flag makes a
# new one (the old ones are removed). Prints the objects. ctest runs the fuzz targets one at
# a time (RESOURCE_LOCK fuzz_seeds); a folder is complete once its "done" file exists.
cached_objects() {
    name=$1 cc=$2 cflags=$3
    shift 3
    key=$({ echo "$cc $cflags"; cat "$@" $(find "$src/src" "$src/include" -name '*.h' | sort); } | sha1sum | cut -c1-16)
    dir="$out/obj-$name-$key"
    if [ ! -f "$dir/done" ]; then
        rm -rf "$out/obj-$name-"*
        mkdir -p "$dir"
        i=0 pid=""
        for f in "$@"; do # two at a time
            $cc $cflags -c "$f" -o "$dir/$i-$(basename "$f" .c).o" &
            if [ -n "$pid" ]; then
                wait "$pid" || { wait; return 1; }
                pid=$!
            else
                pid=$!
            fi
            i=$((i + 1))
        done
        [ -z "$pid" ] || wait "$pid" || return 1
        touch "$dir/done"
    fi
    ls "$dir"/*.o
}
csrc="$src/fuzz/fuzz_grid.c $(ls "$src"/src/core/*.c "$src"/src/density/*.c) $src/src/io/atomic.c $src/src/io/grid_io.c $src/src/io/grid_formats.c $src/src/io/grid_raw.c $src/src/io/grid_df3.c $src/src/io/grid_vol.c $src/src/io/grid_nvdb.c $src/src/io/grid_openvdb.c $src/src/io/grid_sandbox.c $src/src/io/sandbox.c $src/src/io/grid_vdb_load.c $src/src/io/vdb_path.c" # the readers and what they stand on
exe="$out/fuzz_$fmt"
if [ "$fmt" = scene ] || [ "$fmt" = readers ]; then
    # the whole library but OpenVDB (C++), and the default scene and build id CMake generated
    flags="$(echo "$flags" | sed 's/-DFUZZ_FORMAT=GRID_FORMAT_[A-Z0-9]*//') -I$build/generated"
    # no GPU kernels: the fuzzers never ask for a GPU, and the PTX would only slow the build
    echo 'const char gpu_ptx[] = "";' > "$out/gpu_ptx_none.c"
    lib="$(find "$src/src" -name '*.c' ! -name grid_sandbox_main.c | sort) $build/default_scene.c $out/gpu_ptx_none.c"
    # a 4 MiB memory budget that a scene cannot raise: each input stays quick and small
    cflags="-std=c11 $flags -DBUDGET_DEFAULT_BYTES=((size_t)4<<20) -DBUDGET_MAX_BYTES=((size_t)4<<20) -DBRUME_HAVE_OPENVDB=0 -I/usr/include/OpenEXR $(pkg-config --cflags libcjson libpng cairo fftw3 assimp)"
    objs=$(cached_objects lib clang "$cflags" $lib) || exit 1
    clang $cflags "$src/fuzz/fuzz_$fmt.c" $objs -o "$exe" $(pkg-config --libs libcjson libpng cairo fftw3) -lOpenEXRCore -lembree3 -lpthread -ldl -lm
elif [ "$fmt" = vdb ]; then
    # OpenVDB's TBB headers trip UBSan in their own code (concurrent_hash_map); ASan only
    flags=$(echo "$flags" | sed 's/,undefined//')
    if [ "${FUZZ_ASAN:-1}" = 0 ]; then
        flags=$(echo "$flags" | sed 's/,address//')
        exe="$out/fuzz_vdb_noasan"
    fi
    [ -f /usr/include/openvdb/openvdb.h ] && [ -f /usr/include/boost/numeric/conversion/conversion_traits.hpp ] ||
        { echo "fuzz: OpenVDB headers missing, skipped"; exit 77; }
    objs=""
    for f in $csrc; do
        o="$out/$(basename "$f" .c).vdb.o"
        clang -std=c11 $flags -DBRUME_HAVE_OPENVDB=1 -c "$f" -o "$o"
        objs="$objs $o"
    done
    for f in grid_vdb grid_vdb_nano grid_vdb_nano_vec3 grid_vdb_write grid_vdb_write_vec3; do
        clang++ -std=c++17 $flags -c "$src/src/io/$f.cpp" -o "$out/$f.o"
        objs="$objs $out/$f.o"
    done
    clang++ $flags $objs -o "$exe" -lopenvdb -ltbb -lImath-3_1 -lfftw3 -ldl -lm
else
    # the readers' objects, shared by raw, df3, vol and nvdb (FUZZ_FORMAT is read by fuzz_grid.c alone)
    cflags="-std=c11 $(echo "$flags" | sed 's/-DFUZZ_FORMAT=GRID_FORMAT_[A-Z0-9]*//') -DBRUME_HAVE_OPENVDB=0"
    objs=$(cached_objects grid clang "$cflags" $(echo "$csrc" | sed "s|$src/fuzz/fuzz_grid.c||")) || exit 1
    clang $cflags "-DFUZZ_FORMAT=GRID_FORMAT_$upper" "$src/fuzz/fuzz_grid.c" $objs -o "$exe" -lfftw3 -ldl -lm
fi
seeds="$build/fuzz/seeds/$fmt"
mkdir -p "$seeds"
extra=""
case $fmt in
    scene) for f in "$src"/scenes/*.json; do cp "$f" "$out/corpus-scene/"; done
           for f in "$src"/tests/bad/scenes/*.json; do cp "$f" "$out/corpus-scene/bad-$(basename "$f")"; done ;;
    readers) # seeds: an edit of the target's valid checkpoint, and the bad meshes of tests/bad
           printf '\000!\000\000\000' > "$out/corpus-readers/ckpt-valid"
           i=0
           for f in "$src"/tests/bad/meshes/*; do
               # not gltf_nested.gltf: under ASan the child has no address-space limit, and it
               # would build its 5.8 GB until the CPU limit (tests/bad runs it with the limit)
               case $f in *.obj) e='\001\000' ;; *.ply) e='\001\001' ;; *.stl) e='\001\002' ;; *) continue ;; esac
               { printf "$e"; cat "$f"; } > "$out/corpus-readers/mesh-$i"
               i=$((i + 1))
           done ;;
    df3) extra="$data/spiral.df3" ;;
    vdb) extra="$data/box_fog_21cube.vdb" ;;
    raw) head -c 4099 "$data/cloud64.raw" > "$out/corpus-raw/cloud64-head" ;;
esac
[ -n "$extra" ] && cp "$extra" "$out/corpus-$fmt/"
# leaks are checked; each input is limited in time and memory
# The vdb target reads through brume's sandbox: libopenvdb runs in a child program per
# input, under CPU and address-space limits, and a hang, a crash or an exhausted limit
# there is a one-line error in brume (docs/grids.md). What the fuzzer watches is brume's
# own process: no crash, leak, hang (-timeout is above the sandbox's own wall-clock limit,
# 15 s for small inputs and 45 s or more under ASan, with room for a loaded machine) or
# multi-line message. Coverage inside the child is not fed
# back (it is another process), so mutation there is blind; it still mutates.
# Under ASan the child has no address-space limit (the shadow needs terabytes): an
# impossible allocation then returns null (a std::bad_alloc, reported) instead of aborting.
# -timeout is per input, in wall-clock seconds: a hang takes minutes, and a machine running
# other tests beside the fuzzer (ctest -j2) can slow one input several times over.
leaks=1
timeout=60
if [ "$fmt" = vdb ]; then
    timeout=150
    # and ASan's own allocation cap stands in for the address-space limit, as in
    # `make test-sanitize`: one mutant must not have the reader touch gigabytes
    ASAN_OPTIONS="allocator_may_return_null=1:max_allocation_size_mb=2048${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
    export ASAN_OPTIONS
    # the child is the build's brume-openvdb-reader (a program, started with posix_spawn), found
    # with the build's OpenVDB module through BRUME_MODULE_PATH
    [ -x "$build/brume-openvdb-reader" ] || { echo "fuzz: $build/brume-openvdb-reader not built, skipped"; exit 77; }
    BRUME_MODULE_PATH=$build
    export BRUME_MODULE_PATH
    cp "$data/wdas_cloud_sixteenth.vdb" "$out/corpus-$fmt/"
fi
timeout=${FUZZ_TIMEOUT:-$timeout}
runs="${FUZZ_RUNS:+-runs=$FUZZ_RUNS}"
if [ -n "${FUZZ_RUNS:-}" ]; then
    secs=0
fi
work="$out/work-$fmt" # scenes name files relative to where they run: an empty folder
mkdir -p "$work"
rc=0
(cd "$work" && "$exe" $runs -max_total_time="$secs" -timeout=$timeout -rss_limit_mb=2048 -print_final_stats=1 -error_exitcode=1 \
    -detect_leaks=$leaks -artifact_prefix="$out/crash-$fmt-" \
    "$out/corpus-$fmt" "$seeds") > "$out/log-$fmt.txt" 2>&1 || rc=$?
tail -n 30 "$out/log-$fmt.txt"
exit $rc
