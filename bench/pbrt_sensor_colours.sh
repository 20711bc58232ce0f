#!/bin/sh
# pbrt_sensor_colours.sh - brume's camera sensors against pbrt-v4's on coloured light.
#
#   sh bench/pbrt_sensor_colours.sh PBRT_EXE [SENSOR [KELVIN]]     (defaults nikon_d850 5000)
#
# For each of a grey, the 18 chromatic ColorChecker swatches (their linear Rec. 709 lit by
# D65, from the swatch spectra of data/pbrt_sensors.inc; the cyan's red, -0.028, set to 0)
# and the Rec. 709 primaries at 0.5, a 4 x 4 .pbrt whose only light is a uniform sky of that
# `rgb L` is rendered through the `Film "rgb"` sensor SENSOR (and through `cie1931`) by brume
# (its film maps the colour, no noise: every sample sees the sky) and by pbrt-v4 (spectral:
# the sky is pbrt-v4's RGBIlluminantSpectrum of the colour, 65536 samples a pixel, float
# output). One line per colour: the colour, pbrt-v4's mean RGB, brume's, and brume / pbrt-v4
# per channel. pbrt-v4's noise on a mean is about 2e-4 of a channel of 0.5 (the grey line).
# The difference on a colour is brume's linear estimate of the camera's raw values from
# Rec. 709 (docs/pbrt.md, Film `sensor`) against pbrt-v4's sigmoid spectrum of that colour.
# Env: BRUME (default build/brume). Takes about a minute on one core.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
[ $# -ge 1 ] || { sed -n '2,16p' "$0" >&2; exit 2; }
pbrt=$1
sensor=${2:-nikon_d850}
kelvin=${3:-5000}
brume=${BRUME:-$root/build/brume}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mean() { # a PFM's mean R G B
    python3 -c '
import struct, sys
f = open(sys.argv[1], "rb").read().split(b"\n", 3)
w, h = map(int, f[1].split())
v = struct.unpack(("<" if float(f[2]) < 0 else ">") + "f" * (w * h * 3), f[3][:w * h * 12])
print(" ".join("%.5f" % (sum(v[c::3]) / (w * h)) for c in range(3)))' "$1"
}
echo "# brume $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo '?'), pbrt-v4 $pbrt; sky rgb L through the sensor"
for s in "$sensor" cie1931; do
    wb=$kelvin
    [ "$s" != cie1931 ] || wb=0
    echo "# sensor $s, whitebalance $wb: colour | pbrt-v4 RGB | brume RGB | brume / pbrt-v4"
    while read -r r g b; do
        cat > "$tmp/s.pbrt" <<EOF
Film "rgb" "integer xresolution" 4 "integer yresolution" 4 "string sensor" "$s" "float whitebalance" $wb
  "string filename" "$tmp/p.pfm" "bool savefp16" false
Sampler "independent" "integer pixelsamples" 65536
Scale -1 1 1
LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective"
WorldBegin
LightSource "infinite" "rgb L" [$r $g $b]
EOF
        "$pbrt" --nthreads 1 --quiet "$tmp/s.pbrt" > /dev/null 2>&1
        grep -v savefp16 "$tmp/s.pbrt" > "$tmp/b.pbrt" # pbrt-v4's output format: brume's is -o
        "$brume" render "$tmp/b.pbrt" --spp 1 --threads 1 -o "$tmp/b.pfm" > /dev/null 2>&1
        p=$(mean "$tmp/p.pfm")
        q=$(mean "$tmp/b.pfm")
        echo "$r $g $b | $p | $q | $(echo "$p $q" | awk '{printf "%.4f %.4f %.4f", $4 / $1, $5 / $2, $6 / $3}')"
    done <<EOF
0.5 0.5 0.5
0.1724 0.0838 0.0576
0.5479 0.2989 0.2172
0.1104 0.1969 0.3355
0.1042 0.1498 0.0523
0.2246 0.2182 0.4295
0.1244 0.5183 0.4047
0.7153 0.1996 0.0272
0.0648 0.1068 0.3912
0.5410 0.0892 0.1201
0.1045 0.0440 0.1394
0.3556 0.5065 0.0491
0.7794 0.3539 0.0217
0.0231 0.0497 0.2902
0.0663 0.3010 0.0652
0.4301 0.0324 0.0401
0.8567 0.5744 0.0086
0.5035 0.0898 0.3050
0.0000 0.2490 0.3826
0.5 0 0
0 0.5 0
0 0 0.5
EOF
done
