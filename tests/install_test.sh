#!/bin/sh
# install_test.sh - installs the build tree to a temporary prefix and uses it as a user
# would, from outside the source tree: the header's example built with pkg-config (shared,
# then static with --static), with a CMake project doing find_package(brume CONFIG), and
# the exported symbols of libbrume.so checked to be brume_* only. Where the build has OpenVDB,
# the installed tool and the installed Python package each read a .vdb of data/,
# through the OpenVDB module installed beside libbrume (src/io/grid_vdb_load.c).
#   install_test.sh BUILD_DIR pkg-config|cmake|exports
#   install_test.sh BUILD_DIR python PYTHON PYTHON_DIR   (the package from the prefix)
set -eu
build=$1
mode=$2
data=$(cd "$(dirname "$0")/../data" && pwd)
vdb=0
[ -e "$build/libbrume-openvdb.so" ] && vdb=1
tmp=$(mktemp -d "${TMPDIR:-/tmp}/brume-install-XXXXXX")
trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"
cmake --install "$build" --prefix "$prefix" > "$tmp/install.log"
for f in include/brume.h lib/libbrume.a lib/libbrume.so lib/pkgconfig/brume.pc lib/cmake/brume/brumeConfig.cmake bin/brume; do
    test -e "$prefix/$f" || { echo "install: $f missing under the prefix"; exit 1; }
done
if [ $vdb = 1 ] && ! [ -e "$prefix/lib/libbrume-openvdb.so" ]; then
    echo "install: lib/libbrume-openvdb.so (the OpenVDB module) missing under the prefix"; exit 1
fi
soname=$(readelf -d "$prefix/lib/libbrume.so" | sed -n 's/.*Library soname: \[\(.*\)\]/\1/p')
test "$soname" = libbrume.so.0 || { echo "libbrume.so: SONAME '$soname', want libbrume.so.0"; exit 1; }
# the example exactly as the header prints it
sed -n '/^ \* BEGIN EXAMPLE$/,/^ \* END EXAMPLE$/p' "$prefix/include/brume.h" | sed '1d;$d' > "$tmp/example.c"
grep -q brume_render "$tmp/example.c" || { echo "no example in the installed header"; exit 1; }
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
cc=${CC:-cc}
case $mode in
pkg-config)
    # the header's BUILD line, word for word
    $cc -o "$tmp/example" "$tmp/example.c" $(pkg-config --cflags --libs brume)
    readelf -d "$tmp/example" | grep -q 'NEEDED.*libbrume.so.0' || { echo "example does not use libbrume.so.0"; exit 1; }
    (cd "$tmp" && LD_LIBRARY_PATH="$prefix/lib" ./example) | grep -q "rendered 64 x 48"
    test -s "$tmp/example.exr"
    # static: the archive and every private dependency from pkg-config --static
    rm -f "$tmp/example.exr"
    $cc -o "$tmp/example_static" "$tmp/example.c" $(pkg-config --cflags brume) "$prefix/lib/libbrume.a" \
        $(pkg-config --libs --static brume | sed 's/-lbrume\b//')
    if readelf -d "$tmp/example_static" | grep -q 'libbrume'; then echo "static example needs libbrume.so"; exit 1; fi
    (cd "$tmp" && ./example_static) | grep -q "rendered 64 x 48"
    test -s "$tmp/example.exr"
    ;;
cmake)
    mkdir "$tmp/project"
    cp "$tmp/example.c" "$tmp/project/main.c"
    cat > "$tmp/project/CMakeLists.txt" <<'EOT'
cmake_minimum_required(VERSION 3.18)
project(uses_brume C)
find_package(brume 0.1 CONFIG REQUIRED)
add_executable(example main.c)
target_link_libraries(example PRIVATE brume::brume)
EOT
    cmake -S "$tmp/project" -B "$tmp/project/build" -DCMAKE_PREFIX_PATH="$prefix" > "$tmp/cmake.log" ||
        { cat "$tmp/cmake.log"; exit 1; }
    cmake --build "$tmp/project/build" > "$tmp/build.log" || { cat "$tmp/build.log"; exit 1; }
    (cd "$tmp" && ./project/build/example) | grep -q "rendered 64 x 48"
    test -s "$tmp/example.exr"
    ;;
exports)
    bad=$(nm -D --defined-only "$prefix/lib/libbrume.so" | awk '$2 != "A" && $3 !~ /^brume_/ {print $3}' | head -5)
    test -z "$bad" || { echo "libbrume.so exports non-brume symbols: $bad"; exit 1; }
    n=$(nm -D --defined-only "$prefix/lib/libbrume.so" | grep -c ' T brume_')
    test "$n" -ge 50 || { echo "libbrume.so exports only $n brume_ functions"; exit 1; }
    # the tool runs from the prefix
    "$prefix/bin/brume" render --width 8 --height 6 --spp 1 --quiet -o "$tmp/t.png"
    test -s "$tmp/t.png"
    if [ $vdb = 1 ]; then
        (cd "$tmp" && "$prefix/bin/brume" info "$data/box_fog_21cube.vdb") > "$tmp/info.txt" ||
            { echo "the installed brume cannot read a .vdb"; exit 1; }
        grep -q "fog volume" "$tmp/info.txt" || { echo "brume info: no grid listed"; cat "$tmp/info.txt"; exit 1; }
    fi
    ;;
python)
    py=$3
    pydir="$prefix/$4"
    test -f "$pydir/brume/__init__.py" || { echo "python: no package under $pydir"; exit 1; }
    # from a folder outside the source and build trees, with nothing but the prefix
    (cd "$tmp" && env -u BRUME_LIBRARY PYTHONDONTWRITEBYTECODE=1 PYTHONPATH="$pydir" "$py" -c '
import brume, numpy as np, sys
assert brume.__file__.startswith(sys.argv[1]), brume.__file__
rho = np.zeros((8, 8, 8), np.float32); rho[2:6, 2:6, 2:6] = 2.0
img = brume.render({"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0]},
                    "lights": [{"type": "distant", "direction": [0, 0, -1], "irradiance": 2}],
                    "media": [{"density": {"type": "array", "data": rho, "bounds": [[-1, -1, -1], [1, 1, 1]]},
                               "sigma_a": 0.5, "sigma_s": 2}]}, width=16, height=12, spp=2)
assert img.shape == (12, 16, 4) and img.dtype == np.float32 and img[..., 3].max() > 0.5
try:
    brume.render("missing.json")
except brume.Error as e:
    assert "missing.json" in str(e)
else:
    raise SystemExit("no brume.Error")
if sys.argv[3] == "1":  # a .vdb, through the installed OpenVDB module
    img = brume.render({"camera": {"position": [0, -3, 0], "look_at": [0, 0, 0], "up": [0, 0, 1]},
                        "lights": [{"type": "distant", "direction": [0, 1, 0], "irradiance": 2}],
                        "media": [{"density": {"type": "grid", "file": sys.argv[2] + "/box_fog_21cube.vdb"},
                                   "sigma_a": 0.5, "sigma_s": 2}]}, width=16, height=12, spp=2)
    assert img[..., 3].max() > 0.1, img[..., 3].max()
print("installed package", brume.__file__, "libbrume", brume.version())
' "$pydir" "$data" $vdb)
    ;;
*) echo "usage: install_test.sh BUILD_DIR pkg-config|cmake|exports|python"; exit 2 ;;
esac
echo "ok install $mode"
