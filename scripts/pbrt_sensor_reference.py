#!/usr/bin/env python3
"""pbrt_sensor_reference.py - pbrt-v4's film response to a grey light, for tests/test_pbrt_sensor.c.

Usage: python3 scripts/pbrt_sensor_reference.py PBRT_V4_DIR CAMERA KELVIN

Computes, from pbrt-v4's own source text (not from brume's data file or code), what pbrt-v4's
RGB film writes for a light whose spectrum is that of an "rgb L" [1 1 1] (the sRGB colour
space's D65, of luminance 1) seen by CAMERA's sensor white-balanced at KELVIN (0: 6500, as
pbrt-v4): RGBFromXYZ XYZFromSensorRGB (integral of the camera's curves times D65), with
XYZFromSensorRGB fitted as PixelSensor's constructor fits it and RGBFromXYZ made from the
sRGB primaries and D65's integrated white point as RGBColorSpace makes it. Also prints
XYZFromSensorRGB and the raw camera values of that white (r, g, b). Plain Python, run by hand only.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pbrt_sensors import array  # noqa: E402  (the text of one pbrt-v4 table)

LMIN, LMAX = 360, 830


def dense(pairs):
    """pbrt-v4's PiecewiseLinearSpectrum::FromInterleaved sampled at whole nm."""
    lam, val = pairs[0::2], pairs[1::2]
    out = []
    for l in range(LMIN, LMAX + 1):
        if l <= lam[0]:
            out.append(val[0])
        elif l >= lam[-1]:
            out.append(val[-1])
        else:
            j = max(i for i in range(len(lam)) if lam[i] <= l)
            if lam[j] == l:
                out.append(val[j])
            else:
                t = (l - lam[j]) / (lam[j + 1] - lam[j])
                out.append(val[j] + t * (val[j + 1] - val[j]))
    return out


def inner(*fs):
    return sum(math.prod(v) for v in zip(*fs))


def inv3(m):
    a, b, c, d, e, f, g, h, i = m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2]
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    return [[(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det],
            [(f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det],
            [(d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det]]


def mul(a, b):
    return [[sum(a[r][k] * b[k][c] for k in range(3)) for c in range(3)] for r in range(3)]


def mulv(a, v):
    return [sum(a[r][k] * v[k] for k in range(3)) for r in range(3)]


def daylight(src, T):
    cct = T * 1.4388 / 1.4380
    if cct < 4000:
        c, h, kb = 299792458.0, 6.62606957e-34, 1.3806488e-23
        return [2 * h * c * c / ((l * 1e-9) ** 5 * (math.exp(h * c / (l * 1e-9 * kb * cct)) - 1))
                for l in range(LMIN, LMAX + 1)]
    if cct <= 7000:
        x = -4.607e9 / cct ** 3 + 2.9678e6 / cct ** 2 + 0.09911e3 / cct + 0.244063
    else:
        x = -2.0064e9 / cct ** 3 + 1.9018e6 / cct ** 2 + 0.24748e3 / cct + 0.23704
    y = -3 * x * x + 2.870 * x - 0.275
    M = 0.0241 + 0.2562 * x - 0.7341 * y
    M1 = (-1.3515 - 1.7703 * x + 5.9114 * y) / M
    M2 = (0.0300 - 31.4424 * x + 30.0717 * y) / M
    lam = [float(v) for v in array(src, "CIE_S_lambda")]
    s0, s1, s2 = ([float(v) for v in array(src, n)] for n in ("CIE_S0", "CIE_S1", "CIE_S2"))
    pairs = []
    for i in range(len(lam)):
        pairs += [lam[i], (s0[i] + s1[i] * M1 + s2[i] * M2) * 0.01]
    return dense(pairs)


def main():
    root, cam, T = sys.argv[1], sys.argv[2], float(sys.argv[3])
    src = open(root + "/src/pbrt/util/spectrum.cpp").read()
    film = open(root + "/src/pbrt/film.cpp").read()
    cmf = [[float(v) for v in array(src, "CIE_" + c)] for c in "XYZ"]
    d65 = dense([float(v) for v in array(src, "CIE_Illum_D6500")])
    curves = [dense([float(v) for v in array(src, cam + "_" + b)]) for b in "rgb"]
    body = film[film.index("swatchReflectances[nSwatchReflectances]{"):]
    swatches = []
    for chunk in body.split("FromInterleaved(")[1:25]:
        txt = chunk[chunk.index("{") + 1:chunk.index("}")]
        swatches.append(dense([float(v) for v in txt.replace("\n", " ").split(",") if v.strip()]))
    ill = daylight(src, T if T > 0 else 6500.0)
    g_ill, y_ill, y_w = inner(curves[1], ill), inner(cmf[1], ill), inner(cmf[1], d65)
    A = [[inner(curves[c], s, ill) / g_ill for c in range(3)] for s in swatches]
    B = [[inner(cmf[c], s, d65) / y_w * y_ill / g_ill for c in range(3)] for s in swatches]
    AtA = [[sum(r[i] * r[j] for r in A) for j in range(3)] for i in range(3)]
    AtB = [[sum(A[k][i] * B[k][j] for k in range(len(A))) for j in range(3)] for i in range(3)]
    X = mul(inv3(AtA), AtB)
    xyz_from_raw = [[X[c][r] for c in range(3)] for r in range(3)]  # the transpose
    W = [inner(cmf[c], d65) for c in range(3)]
    W = [v / W[1] for v in W]
    wx, wy = W[0] / sum(W), W[1] / sum(W)
    prim = [(0.64, 0.33), (0.30, 0.60), (0.15, 0.06)]
    P = [[x / y for x, y in prim], [1.0, 1.0, 1.0], [(1 - x - y) / y for x, y in prim]]
    C = mulv(inv3(P), [wx / wy, 1.0, (1 - wx - wy) / wy])
    xyz_from_rgb = [[P[r][c] * C[c] for c in range(3)] for r in range(3)]
    rgb_from_xyz = inv3(xyz_from_rgb)
    raw = [inner(curves[c], d65) / y_w for c in range(3)]
    out = mulv(mul(rgb_from_xyz, xyz_from_raw), raw)
    for r in range(3):
        print("XYZFromSensorRGB row %d: %.7f %.7f %.7f" % ((r,) + tuple(xyz_from_raw[r])))
    print("raw white %.6f %.6f %.6f" % tuple(raw))
    print("film white %.6f %.6f %.6f" % tuple(out))


if __name__ == "__main__":
    main()
