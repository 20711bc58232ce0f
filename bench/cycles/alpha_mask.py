# alpha_mask.py - writes the cloud of `brume compare --alpha T` as a mask picture: white where
# IMAGE's alpha (1 - the media's transmittance, an EXR written by brume render) exceeds T,
# black elsewhere. Cycles' images have alpha 1 everywhere (film not transparent), so two Cycles
# images are compared over brume's cloud with `brume compare A.exr B.exr --mask MASK.exr`
# (docs/validation.md, "Against Blender Cycles").
#   PYTHONPATH=build/python python3 bench/cycles/alpha_mask.py IMAGE.exr MASK.exr [T]
# Uses the Python package over libbrume (the build's python/ folder; docs/python.md).
import sys

from brume._lib import ffi, lib

src, dst = sys.argv[1], sys.argv[2]
threshold = float(sys.argv[3]) if len(sys.argv) > 3 else 0.05
ctx = lib.brume_context_new()
img = ffi.new("brume_image **")
if lib.brume_image_read(ctx, src.encode(), img) != 0:
    sys.exit("alpha_mask.py: %s" % ffi.string(lib.brume_context_last_error(ctx)).decode())
w, h = lib.brume_image_width(img[0]), lib.brume_image_height(img[0])
p = lib.brume_image_pixels(img[0])
out = ffi.new("brume_image **")
if lib.brume_image_new(ctx, w, h, out) != 0:
    sys.exit("alpha_mask.py: %s" % ffi.string(lib.brume_context_last_error(ctx)).decode())
q = lib.brume_image_pixels(out[0])
n = 0
for i in range(w * h):
    v = 1.0 if p[4 * i + 3] > threshold else 0.0
    n += v > 0.0
    q[4 * i] = q[4 * i + 1] = q[4 * i + 2] = v
    q[4 * i + 3] = 1.0
if lib.brume_image_write(ctx, out[0], dst.encode(), ffi.NULL) != 0:
    sys.exit("alpha_mask.py: %s" % ffi.string(lib.brume_context_last_error(ctx)).decode())
print("%s: %d of %d pixels with alpha above %g" % (dst, n, w * h, threshold))
lib.brume_image_release(img[0])
lib.brume_image_release(out[0])
lib.brume_context_release(ctx)
