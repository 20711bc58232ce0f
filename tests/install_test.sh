#!/bin/sh
# install_test.sh - installs the build tree to a temporary prefix and uses it as a user
# would, from outside the source tree (docs/install.md):
#   pkg-config  the header's example built with `pkg-config --cflags --libs brume` runs with no
#               LD_LIBRARY_PATH (the .pc's rpath); `--cflags brume` names no dependency; built
#               with brume-static.pc it needs no libbrume.so, and (with OpenVDB) reads a .vdb
#               through BRUME_MODULE_PATH, and through the install's library folder
#   cmake       a CMake project doing find_package(brume CONFIG): brume::brume and
#               brume::brume_static
#   exports     the exported symbols of libbrume.so are brume_* only; the installed tool runs
#               (and reads a .vdb through the OpenVDB module installed beside libbrume);
#               share/: the example scenes render with their data, the man page, the docs,
#               bash completion
#   python      the installed Python package
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
for f in include/brume.h lib/libbrume.a lib/libbrume.so lib/pkgconfig/brume.pc lib/pkgconfig/brume-static.pc \
         lib/cmake/brume/brumeConfig.cmake bin/brume share/man/man1/brume.1 share/bash-completion/completions/brume \
         share/doc/brume/README.md share/doc/brume/LICENSE share/doc/brume/docs/install.md \
         share/brume/scenes/default.json share/brume/data/README.md share/brume/data/wdas_cloud_sixteenth.vdb; do
    test -e "$prefix/$f" || { echo "install: $f missing under the prefix"; exit 1; }
done
if [ $vdb = 1 ] && ! [ -e "$prefix/lib/libbrume-openvdb.so" ]; then
    echo "install: lib/libbrume-openvdb.so (the OpenVDB module) missing under the prefix"; exit 1
fi
if [ $vdb = 1 ] && ! [ -x "$prefix/lib/brume-openvdb-reader" ]; then
    echo "install: lib/brume-openvdb-reader (the .vdb reader's process) missing under the prefix"; exit 1
fi
soname=$(readelf -d "$prefix/lib/libbrume.so" | sed -n 's/.*Library soname: \[\(.*\)\]/\1/p')
test "$soname" = libbrume.so.1 || { echo "libbrume.so: SONAME '$soname', want libbrume.so.1"; exit 1; }
# the example exactly as the header prints it
sed -n '/^ \* BEGIN EXAMPLE$/,/^ \* END EXAMPLE$/p' "$prefix/include/brume.h" | sed '1d;$d' > "$tmp/example.c"
grep -q brume_render "$tmp/example.c" || { echo "no example in the installed header"; exit 1; }
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
cc=${CC:-cc}
case $mode in
pkg-config)
    # the header's BUILD line, word for word; it runs without LD_LIBRARY_PATH (the rpath)
    $cc -o "$tmp/example" "$tmp/example.c" $(pkg-config --cflags --libs brume)
    readelf -d "$tmp/example" | grep -q 'NEEDED.*libbrume.so.1' || { echo "example does not use libbrume.so.1"; exit 1; }
    (cd "$tmp" && env -u LD_LIBRARY_PATH ./example) | grep -q "rendered 64 x 48" ||
        { echo "the example built with pkg-config does not run from the prefix"; exit 1; }
    test -s "$tmp/example.exr"
    # compiling needs the header only, not the dependencies' include folders
    cflags=$(pkg-config --cflags brume)
    set -- $cflags
    test $# = 1 && test "$(cd "${1#-I}" && pwd -P)" = "$(cd "$prefix/include" && pwd -P)" ||
        { echo "pkg-config --cflags brume: '$cflags', want -I$prefix/include only"; exit 1; }
    # static: brume-static.pc links the archive, with or without --static
    rm -f "$tmp/example.exr"
    $cc -o "$tmp/example_static" "$tmp/example.c" $(pkg-config --static --cflags --libs brume-static)
    if readelf -d "$tmp/example_static" | grep -q 'libbrume'; then echo "static example needs libbrume.so"; exit 1; fi
    (cd "$tmp" && ./example_static) | grep -q "rendered 64 x 48"
    test -s "$tmp/example.exr"
    $cc -o "$tmp/example_static2" "$tmp/example.c" $(pkg-config --cflags --libs brume-static)
    if readelf -d "$tmp/example_static2" | grep -q 'libbrume'; then echo "brume-static without --static needs libbrume.so"; exit 1; fi
    if [ $vdb = 1 ]; then
        # a static program reads a .vdb: the module from BRUME_MODULE_PATH, from anywhere
        cat > "$tmp/readvdb.c" <<'EOT'
#include <brume.h>
#include <stdio.h>
int main(int argc, char **argv)
{
    (void)argc;
    char json[512];
    snprintf(json, sizeof json, "{\"camera\": {\"position\": [0, -3, 0], \"look_at\": [0, 0, 0], \"up\": [0, 0, 1]},"
             " \"lights\": [{\"type\": \"distant\", \"direction\": [0, 1, 0], \"irradiance\": 2}],"
             " \"media\": [{\"density\": {\"type\": \"grid\", \"file\": \"%s\"}, \"sigma_a\": 0.5, \"sigma_s\": 2}],"
             " \"render\": {\"width\": 8, \"height\": 6, \"spp\": 1}}", argv[1]);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.text = json}, NULL, &s) != BRUME_OK) {
        fprintf(stderr, "%s\n", brume_context_last_error(ctx));
        return 1;
    }
    brume_scene_release(s);
    brume_context_release(ctx);
    puts("read the vdb");
    return 0;
}
EOT
        mkdir "$tmp/bin-elsewhere"
        $cc -o "$tmp/bin-elsewhere/readvdb" "$tmp/readvdb.c" $(pkg-config --static --cflags --libs brume-static)
        if (cd "$tmp" && env -u BRUME_MODULE_PATH ./bin-elsewhere/readvdb "$data/box_fog_21cube.vdb") > "$tmp/vdb.log" 2>&1; then
            # the configured install folder may hold a module (an earlier `make install`): fine
            :
        else
            grep -q 'BRUME_MODULE_PATH' "$tmp/vdb.log" ||
                { echo "a static program without the module: the error does not name BRUME_MODULE_PATH"; cat "$tmp/vdb.log"; exit 1; }
        fi
        (cd "$tmp" && BRUME_MODULE_PATH="$prefix/lib" ./bin-elsewhere/readvdb "$data/box_fog_21cube.vdb") | grep -q "read the vdb" ||
            { echo "a static program cannot read a .vdb with BRUME_MODULE_PATH=$prefix/lib"; exit 1; }
        # installed in the prefix's bin/, it finds the module in the prefix's lib/
        cp "$tmp/bin-elsewhere/readvdb" "$prefix/bin/readvdb"
        (cd "$tmp" && env -u BRUME_MODULE_PATH "$prefix/bin/readvdb" "$data/box_fog_21cube.vdb") | grep -q "read the vdb" ||
            { echo "a static program in PREFIX/bin cannot read a .vdb through PREFIX/lib"; exit 1; }
    fi
    ;;
cmake)
    mkdir "$tmp/project"
    cp "$tmp/example.c" "$tmp/project/main.c"
    cat > "$tmp/project/CMakeLists.txt" <<'EOT'
cmake_minimum_required(VERSION 3.18)
project(uses_brume C)
find_package(brume 1.0 CONFIG REQUIRED)
add_executable(example main.c)
target_link_libraries(example PRIVATE brume::brume)
add_executable(example_static main.c)
target_link_libraries(example_static PRIVATE brume::brume_static)
EOT
    cmake -S "$tmp/project" -B "$tmp/project/build" -DCMAKE_PREFIX_PATH="$prefix" > "$tmp/cmake.log" ||
        { cat "$tmp/cmake.log"; exit 1; }
    cmake --build "$tmp/project/build" > "$tmp/build.log" || { cat "$tmp/build.log"; exit 1; }
    (cd "$tmp" && env -u LD_LIBRARY_PATH ./project/build/example) | grep -q "rendered 64 x 48"
    test -s "$tmp/example.exr"
    readelf -d "$tmp/project/build/example" | grep -q 'NEEDED.*libbrume.so.1' || { echo "brume::brume: no libbrume.so.1"; exit 1; }
    if readelf -d "$tmp/project/build/example_static" | grep -q 'libbrume'; then echo "brume::brume_static needs libbrume.so"; exit 1; fi
    rm -f "$tmp/example.exr"
    (cd "$tmp" && ./project/build/example_static) | grep -q "rendered 64 x 48"
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
    # share/brume: the example scenes render from the prefix with the data installed beside them
    share="$prefix/share/brume"
    scenes="cloud64"
    [ $vdb = 1 ] && scenes="$scenes wdas-cloud"
    for sc in $scenes; do
        (cd "$tmp" && "$prefix/bin/brume" render "$share/scenes/$sc.json" --width 8 --height 6 --spp 1 --quiet \
            -o "$tmp/$sc.png") || { echo "share/brume/scenes/$sc.json does not render from the prefix"; exit 1; }
    done
    cmp "$share/data/cloud64.raw" "$data/cloud64.raw"
    # the man page is the help text: every command has its section, with its options
    man1="$prefix/share/man/man1/brume.1"
    for c in $("$prefix/bin/brume" help | awk '/^commands:/ {c = 1; next} /^$/ {c = 0} c && $1 != "help" {print $1}'); do
        grep -q "^\.SS brume $c\$" "$man1" || { echo "brume.1: no section for $c"; exit 1; }
    done
    grep -q -e '--spp' "$man1" || { echo "brume.1: render's --spp missing"; exit 1; }
    if command -v groff >/dev/null 2>&1; then
        w=$(groff -man -Tutf8 -ww -z "$man1" 2>&1) || true
        test -z "$w" || { echo "brume.1: groff warns: $w"; exit 1; }
    fi
    # bash completion: commands, then a command's options, from the installed tool's help
    if command -v bash >/dev/null 2>&1; then
        got=$(PATH="$prefix/bin:$PATH" bash -c '. "$1"; COMP_WORDS=(brume ren); COMP_CWORD=1; _brume; echo "${COMPREPLY[*]}";
              COMP_WORDS=(brume render --sp); COMP_CWORD=2; _brume; echo "${COMPREPLY[*]}"' sh \
              "$prefix/share/bash-completion/completions/brume")
        test "$got" = "render
--spp" || { echo "bash completion: got '$got', want render and --spp"; exit 1; }
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
