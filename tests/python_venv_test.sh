#!/bin/sh
# python_venv_test.sh - the Python package as a user installs it (docs/python.md): the build
# installed to a temporary prefix, a fresh venv that takes cffi and numpy from Debian
# (--system-site-packages), then `pip install --no-build-isolation --no-index ./python` from a
# copy of python/ and include/ (nothing downloaded; setup.py finds the prefix's libbrume
# through pkg-config). The installed package then renders, writes .exr and .png through
# libbrume, shows itself to a notebook (_repr_png_), reads its settings back as set and
# refuses the ambiguous time=. The venv is made --without-pip and Debian's pip (seen through
# the system site) installs into it: the same pip, without copying one into every venv.
#   python_venv_test.sh SOURCE_DIR BUILD_DIR PYTHON
# Exits 77 (ctest: skipped) without the venv module, pip or setuptools (python3-venv,
# python3-pip, python3-setuptools).
set -eu
src=$1
build=$2
py=$3
{ "$py" -c 'import venv, setuptools' && "$py" -m pip --version; } >/dev/null 2>&1 ||
    { echo "python venv: no venv, pip or setuptools (python3-venv, python3-pip, python3-setuptools), skipped"; exit 77; }
tmp=$(mktemp -d "${TMPDIR:-/tmp}/brume-venv-XXXXXX")
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" > "$tmp/install.log"
mkdir "$tmp/src"
cp -r "$src/python" "$src/include" "$tmp/src/"
rm -rf "$tmp/src/python/build" "$tmp/src/python/"*.egg-info
"$py" -m venv --system-site-packages --without-pip "$tmp/venv"
PKG_CONFIG_PATH="$tmp/prefix/lib/pkgconfig" "$tmp/venv/bin/python" -m pip install --no-build-isolation --no-index \
    --disable-pip-version-check -q "$tmp/src/python" > "$tmp/pip.log" 2>&1 ||
    { cat "$tmp/pip.log"; echo "pip install failed"; exit 1; }
cd "$tmp"
env -u BRUME_LIBRARY -u PYTHONPATH PYTHONDONTWRITEBYTECODE=1 "$tmp/venv/bin/python" - "$tmp" <<'EOT'
import os, sys
import numpy as np
import brume
tmp = sys.argv[1]
assert brume.__file__.startswith(os.path.join(tmp, "venv")), brume.__file__
assert os.path.exists(os.path.join(os.path.dirname(brume.__file__), "py.typed"))
img = brume.render(None, width=24, height=16, spp=2, filter="box")
assert isinstance(img, brume.Image) and isinstance(img, np.ndarray) and img.shape == (16, 24, 4)
png = img._repr_png_()
assert png[:8] == b"\x89PNG\r\n\x1a\n", png[:8]
brume.write(img, os.path.join(tmp, "x.exr"))
img.write(os.path.join(tmp, "x.png"), exposure=1, tonemap="filmic")
assert open(os.path.join(tmp, "x.png"), "rb").read(8) == png[:8]
with brume.Scene(None, width=24, height=16, filter="box") as s:
    assert s.settings["filter"] == "box", s.settings["filter"]
try:
    brume.render(None, time=1)
except TypeError as e:
    assert "frame_time" in str(e) and "time_budget" in str(e), e
else:
    raise SystemExit("time= was taken")
print("venv: brume", brume.version(), "from", os.path.dirname(brume.__file__))
EOT
echo "ok python venv install"
