# mean.py - tests/blender_test.sh's check: the mean radiance (each of R, G, B) of brume's
# image against Cycles', to the standard error of the mean pixel difference (pixels taken as
# independent samples; pairing the pixels removes the picture's own variation, leaving the
# two renderers' noise): exits 1 beyond 4 standard errors.
#
#   blender -b --factory-startup --python mean.py -- CYCLES.exr BRUME.exr
import sys

import bpy
import numpy as np

a_path, b_path = sys.argv[sys.argv.index("--") + 1:][:2]


def load(path):
    img = bpy.data.images.load(path)
    px = np.array(img.pixels[:], dtype=np.float64).reshape(-1, 4)[:, :3]
    return px


a, b = load(a_path), load(b_path)
bad = False
for c, name in enumerate("RGB"):
    ma, mb = a[:, c].mean(), b[:, c].mean()
    se = (b[:, c] - a[:, c]).std(ddof=1) / np.sqrt(len(a))
    z = (mb - ma) / se
    print("mean %s: cycles %.6f brume %.6f (%+.2f %%), %.2f standard errors" % (name, ma, mb, 100 * (mb / ma - 1), z))
    bad |= abs(z) > 4
sys.exit(1 if bad else 0)
