#!/usr/bin/env python3
"""pbrt_sensors.py - write data/pbrt_sensors.inc from a pbrt-v4 checkout.

Usage: python3 scripts/pbrt_sensors.py PBRT_V4_DIR > data/pbrt_sensors.inc

Copies, number for number as pbrt-v4's source spells them, the tables brume's named camera
sensors are made from (src/render/film_sensor.c, docs/pbrt.md): every camera's r, g, b
response curves that pbrt-v4 names ("<camera>_r" ... in src/pbrt/util/spectrum.cpp), the 24
ColorChecker swatch reflectances of PixelSensor (src/pbrt/film.cpp), the CIE 1931 colour
matching functions at 1 nm, the CIE daylight basis S0, S1, S2 and the D65 illuminant table.
Run by hand only, never at build or test time; data/README.md gives the provenance and
licences.
"""
import re
import sys


def numbers(text):
    return re.findall(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?", text)


def array(src, name):
    m = re.search(r"const Float " + re.escape(name) + r"\[[^\]]*\]\s*=\s*\{(.*?)\};", src, re.S)
    if not m:
        sys.exit("pbrt_sensors.py: %s not found" % name)
    return numbers(re.sub(r"//[^\n]*", "", m.group(1)))


def emit(name, vals, per_line=8):
    out = ["static const double %s[%d] = {" % (name, len(vals))]
    for i in range(0, len(vals), per_line):
        out.append("    " + ", ".join(vals[i:i + per_line]) + ",")
    out.append("};")
    return "\n".join(out)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    root = sys.argv[1]
    src = open(root + "/src/pbrt/util/spectrum.cpp").read()
    film = open(root + "/src/pbrt/film.cpp").read()
    cams = sorted(set(re.findall(r"const Float (\w+)_r\[\]", src)))
    parts = ["/* pbrt_sensors.inc - data, not code: pbrt-v4's camera sensor curves, the swatches it fits\n"
             " * them on and the CIE tables it uses, copied unchanged into C initialisers by\n"
             " * scripts/pbrt_sensors.py from pbrt-v4 (src/pbrt/util/spectrum.cpp, src/pbrt/film.cpp).\n"
             " * pbrt is Copyright(c) 1998-2020 Matt Pharr, Wenzel Jakob, and Greg Humphreys, licensed\n"
             " * under the Apache License, Version 2.0. The camera curves: PhysLight measurements\n"
             " * contributed by Anders Langlands and Luca Fascione, Copyright (c) 2020, Weta Digital,\n"
             " * Ltd., Apache-2.0. The swatches: BabelColor ColorChecker data, Copyright (c) 2004-2012\n"
             " * Danny Pascale (www.babelcolor.com), used by pbrt-v4 by permission. Provenance and\n"
             " * licences: data/README.md. Compiled in by src/scene/film_sensor.c. */"]
    parts.append("/* CIE 1931 2-degree colour matching functions x, y, z, 360 .. 830 nm at 1 nm */")
    for c in "XYZ":
        v = array(src, "CIE_" + c)
        assert len(v) == 471
        parts.append(emit("pbrt_cie_" + c.lower(), v))
    parts.append("/* CIE daylight basis S0, S1, S2 at the wavelengths pbrt_cie_s_lambda (nm) */")
    parts.append(emit("pbrt_cie_s_lambda", array(src, "CIE_S_lambda")))
    for k in "012":
        parts.append(emit("pbrt_cie_s" + k, array(src, "CIE_S" + k)))
    parts.append("/* CIE D65, interleaved (nm, value): pbrt-v4's sRGB illuminant before its normalisation */")
    parts.append(emit("pbrt_d65", array(src, "CIE_Illum_D6500")))
    m = re.search(r"Spectrum PixelSensor::swatchReflectances\[nSwatchReflectances\]\{(.*?)\)\};", film, re.S)
    sw = re.findall(r"FromInterleaved\(\s*\{(.*?)\}", m.group(1), re.S)
    assert len(sw) == 24
    parts.append("/* the 24 ColorChecker swatch reflectances, each interleaved (nm, value), 380 .. 730 nm */")
    rows = [numbers(s) for s in sw]
    assert all(len(r) == len(rows[0]) for r in rows)
    parts.append("static const double pbrt_swatches[24][%d] = {" % len(rows[0]))
    for r in rows:
        parts.append("    {" + ", ".join(r) + "},")
    parts.append("};")
    parts.append("/* each camera's r, g, b responses, interleaved (nm, value) */")
    n = max(len(array(src, c + "_" + b)) for c in cams for b in "rgb")
    parts.append("#define PBRT_SENSOR_CAMERAS %d\n#define PBRT_SENSOR_MAX %d" % (len(cams), n))
    parts.append("static const struct pbrt_camera_curves {\n    const char *name;\n    int n[3];"
                 "   /* numbers in each curve (twice its points) */\n    double v[3][PBRT_SENSOR_MAX];\n"
                 "} pbrt_cameras[PBRT_SENSOR_CAMERAS] = {")
    for c in cams:
        cur = [array(src, c + "_" + b) for b in "rgb"]
        parts.append('    {"%s", {%d, %d, %d}, {' % (c, len(cur[0]), len(cur[1]), len(cur[2])))
        for v in cur:
            parts.append("        {" + ", ".join(v) + "},")
        parts.append("    }},")
    parts.append("};")
    print("\n".join(parts))


if __name__ == "__main__":
    main()
