#!/usr/bin/env python3
"""Helpers of bench/pbrt_scenes.sh: stand-ins for the assets a pbrt-v4-scenes copy lacks,
and the image arithmetic of the comparison (standard library only: no numpy here).

  pbrt_scenes_assets.py standins SCENE.pbrt BRUME   write the missing assets beside SCENE
  pbrt_scenes_assets.py film SCENE.pbrt             print pbrt's film size "W H"
  pbrt_scenes_assets.py shrink IN.pfm K OUT.pfm     K x K box means (a full-size pbrt-v4
                                                    image at s spp -> K^2 s spp at 1/K size)
  pbrt_scenes_assets.py png IN.pfm OUT.png MAXW     sRGB 8-bit picture, box-shrunk to <= MAXW
                                                    (one under 160 wide: pixels repeated)
  pbrt_scenes_assets.py ratios A.pfm B.pfm          mean(A) / mean(B) per channel "r/g/b"

Stand-ins are generated, never copied: grids with brume's own `gen cloud` / `gen fire`,
meshes as boxes, skies as a small equal-area octahedral EXR (pbrt-v4's layout for image
infinite lights), textures as grey PNGs, and the one include pbrt-v4-scenes keeps out of
its repository (smoke-plume's density) as a procedural uniformgrid. Each is announced on
stderr as "stand-in: PATH (what)".
"""
import math
import os
import re
import struct
import subprocess
import sys
import zlib

# Where a missing grid file sits in its scene, from the shape that bounds it there (the
# .pbrt's own bounding sphere and medium transform): grid-space boxes for the stand-ins.
GRID_HINTS = {
    # disney-cloud: the same cloud at 1/16 resolution, in this repository (data/README.md),
    # in the same world frame as the quarter one.
    "wdas_cloud_quarter.nvdb": ("convert", "data/wdas_cloud_sixteenth.vdb"),
    # bunny-cloud: a sphere of radius 45 at the origin bounds it.
    "bunny_cloud.nvdb": ("cloud", (-25.0, -20.0, -25.0, 25.0, 20.0, 25.0)),
    # explosion: a sphere of radius 80 about (0, 40, 0) after Scale 1 1 1.6, Rotate 90 x.
    "fire.nvdb": ("fire", 50.0),
    # tests/pbrt_rehearsal/blackbody_slab.pbrt: density 1 on 8 x 4 x 8 voxels (its test).
    "slab.nvdb": ("slab", (-2.0, 1.0, -2.0, 2.0, 1.5, 2.0)),
    # tests/pbrt_conventions/grid_nanovdb.pbrt: grid_uniform.pbrt's 4 x 4 x 4 densities.
    "faces4.nvdb": ("faces4", (0.0, 0.0, 0.0, 1.0, 1.0, 1.0)),
}


def faces4_density(i, j, k):
    """The densities of tests/pbrt_conventions/grid_uniform.pbrt (non-zero outer samples)."""
    return 0.5 + 0.25 * ((i + 2 * j + 3 * k) % 5)


def say(msg):
    sys.stderr.write(msg + "\n")


# ---------------------------------------------------------------- the .pbrt text

def strip_comments(text):
    out = []
    for line in text.split("\n"):
        q = False
        cut = len(line)
        for i, ch in enumerate(line):
            if ch == '"':
                q = not q
            elif ch == "#" and not q:
                cut = i
                break
        out.append(line[:cut])
    return "\n".join(out)


def referenced_files(path, seen=None):
    """(file, referring .pbrt, line number, kind) for every file a .pbrt names."""
    seen = seen if seen is not None else set()
    if path in seen or not os.path.exists(path):
        return []
    seen.add(path)
    text = open(path, encoding="utf-8", errors="replace").read()
    refs = []
    body = strip_comments(text)
    for m in re.finditer(r'"string\s+filename"\s*\[?\s*"([^"]+)"', body):
        directives = re.findall(r'(?m)^\s*([A-Z][A-Za-z]+)\b', body[:m.start()])
        if directives and directives[-1] == "Film":
            continue  # the film's filename is an output
        line = body.count("\n", 0, m.start()) + 1
        refs.append((m.group(1), path, line, "filename"))
    for m in re.finditer(r'\b(Include|Import)\s+"([^"]+)"', body):
        line = body.count("\n", 0, m.start()) + 1
        refs.append((m.group(2), path, line, "include"))
        inc = os.path.join(os.path.dirname(path), m.group(2))
        refs.extend(referenced_files(inc, seen))
    return refs


def film_size(path):
    body = strip_comments(open(path, encoding="utf-8", errors="replace").read())
    m = re.search(r'\bFilm\s+"[^"]*"(.*?)(?=\n\s*[A-Z][A-Za-z]+\s|\Z)', body, re.S)
    w, h = 1280, 720
    if m:
        mw = re.search(r'"integer\s+xresolution"\s*\[?\s*(\d+)', m.group(1))
        mh = re.search(r'"integer\s+yresolution"\s*\[?\s*(\d+)', m.group(1))
        w = int(mw.group(1)) if mw else w
        h = int(mh.group(1)) if mh else h
    return w, h


# ---------------------------------------------------------------- writers

def write_png(path, width, height, rgb_rows):
    """rgb_rows: height rows of width * 3 bytes (top row first)."""
    raw = b"".join(b"\x00" + bytes(r) for r in rgb_rows)

    def chunk(tag, data):
        c = tag + data
        return struct.pack(">I", len(data)) + c + struct.pack(">I", zlib.crc32(c) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def write_exr(path, width, height, pixel):
    """An uncompressed scanline OpenEXR of 32-bit float R, G, B; pixel(x, y) -> (r, g, b)."""
    def attr(name, typ, data):
        return name.encode() + b"\0" + typ.encode() + b"\0" + struct.pack("<i", len(data)) + data

    chans = b"".join(c + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for c in (b"B", b"G", b"R")) + b"\0"
    box = struct.pack("<iiii", 0, 0, width - 1, height - 1)
    head = b"\x76\x2f\x31\x01" + struct.pack("<i", 2)
    head += attr("channels", "chlist", chans) + attr("compression", "compression", b"\0")
    head += attr("dataWindow", "box2i", box) + attr("displayWindow", "box2i", box)
    head += attr("lineOrder", "lineOrder", b"\0") + attr("pixelAspectRatio", "float", struct.pack("<f", 1))
    head += attr("screenWindowCenter", "v2f", struct.pack("<ff", 0, 0))
    head += attr("screenWindowWidth", "float", struct.pack("<f", 1)) + b"\0"
    line_bytes = width * 3 * 4
    first = len(head) + 8 * height
    table = b"".join(struct.pack("<Q", first + y * (8 + line_bytes)) for y in range(height))
    blocks = []
    for y in range(height):
        px = [pixel(x, y) for x in range(width)]
        data = b"".join(struct.pack("<%df" % width, *[p[c] for p in px]) for c in (2, 1, 0))
        blocks.append(struct.pack("<ii", y, len(data)) + data)
    with open(path, "wb") as f:
        f.write(head + table + b"".join(blocks))


def write_ply_boxes(path, boxes, flip=False):
    """Closed boxes (x0, y0, z0, x1, y1, z1), faces wound counter-clockwise seen from
    outside (flip: from inside); an open 'floor and back wall' is given as quads."""
    verts, faces = [], []
    for b in boxes:
        if b[0] == "quad":
            base = len(verts)
            verts.extend(b[1])
            faces.append((base, base + 1, base + 2, base + 3))
            continue
        x0, y0, z0, x1, y1, z1 = b
        base = len(verts)
        verts.extend([(x, y, z) for z in (z0, z1) for y in (y0, y1) for x in (x0, x1)])
        for q in ((0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)):
            faces.append(tuple(base + i for i in (q if not flip else q[::-1])))
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\ncomment stand-in written by brume's bench/pbrt_scenes.sh\n")
        f.write("element vertex %d\nproperty float x\nproperty float y\nproperty float z\n" % len(verts))
        f.write("element face %d\nproperty list uchar int vertex_indices\nend_header\n" % len(faces))
        for v in verts:
            f.write("%.6g %.6g %.6g\n" % v)
        for q in faces:
            f.write("4 %d %d %d %d\n" % q)


# ---------------------------------------------------------------- stand-ins

def equal_area_square_to_sphere(u, v):
    """pbrt-v4's EqualAreaSquareToSphere (Clarberg's octahedral map)."""
    u, v = 2 * u - 1, 2 * v - 1
    up, vp = abs(u), abs(v)
    sd = 1 - (up + vp)
    r = 1 - abs(sd)
    phi = (1 if r == 0 else (vp - up) / r + 1) * math.pi / 4
    z = math.copysign(1 - r * r, sd)
    s = r * math.sqrt(max(0.0, 2 - r * r))
    return (math.copysign(math.cos(phi), u) * s, math.copysign(math.sin(phi), v) * s, z)


def sky_radiance(d):
    """A smooth sky in the light's frame (+z up): blue above, a broad warm sun lobe, a dim
    ground; smooth so that both renderers' image sampling converges fast."""
    sun = (0.48, 0.30, 0.82)
    c = sum(a * b for a, b in zip(d, sun))
    lobe = 4.0 * math.exp(12.0 * (c - 1.0))
    up = max(d[2], 0.0)
    if d[2] < 0:
        return (0.08 + lobe, 0.07 + 0.9 * lobe, 0.06 + 0.7 * lobe)
    return (0.25 + 0.15 * up + lobe, 0.35 + 0.25 * up + 0.9 * lobe, 0.6 + 0.4 * up + 0.7 * lobe)


def standin_sky(path, n=64):
    def px(x, y):
        return sky_radiance(equal_area_square_to_sphere((x + 0.5) / n, (y + 0.5) / n))
    write_exr(path, n, n, px)
    return "%d x %d equal-area octahedral sky, OpenEXR" % (n, n)


def scene_bounds_before(pbrt_path, line):
    """The obj2pbrt comment '# Scene bounds: (x0, y0, z0) - (x1, y1, z1)' of the shape at
    line, searched upwards to the previous Shape."""
    lines = open(pbrt_path, encoding="utf-8", errors="replace").read().split("\n")
    own_shape = False
    for i in range(line - 1, max(-1, line - 16), -1):
        m = re.search(r"Scene bounds:\s*\(([^)]*)\)\s*-\s*\(([^)]*)\)", lines[i])
        if m:
            lo = [float(t) for t in m.group(1).split(",")]
            hi = [float(t) for t in m.group(2).split(",")]
            return tuple(lo + hi)
        if re.match(r"\s*Shape\b", lines[i]):
            if own_shape:
                break
            own_shape = True
    return None


def standin_mesh(path, pbrt_path, line):
    b = scene_bounds_before(pbrt_path, line)
    if b is None:
        write_ply_boxes(path, [(-0.5, -0.5, -0.5, 0.5, 0.5, 0.5)])
        return "unit box (no bounds in the .pbrt)"
    x0, y0, z0, x1, y1, z1 = b
    if max(x1 - x0, y1 - y0, z1 - z0) > 300:
        # a studio backdrop: its floor and its far wall only (a closed box would shut the
        # camera out)
        floor = ("quad", [(x0, y0, z0), (x0, y0, z1), (x1, y0, z1), (x1, y0, z0)])
        wall = ("quad", [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0)])
        write_ply_boxes(path, [floor, wall])
        return "floor and back wall of the bounds in the .pbrt's comment"
    write_ply_boxes(path, [b])
    return "box of the bounds in the .pbrt's comment"


def standin_grid(path, brume):
    name = os.path.basename(path)
    kind, arg = GRID_HINTS.get(name, ("cloud", (-0.5, -0.5, -0.5, 0.5, 0.5, 0.5)))
    if kind == "convert":
        src = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), arg)
        cmd = [brume, "convert", src, path]
        what = "brume convert of this repository's %s" % arg
    elif kind == "slab":
        raw = path + ".raw"
        with open(raw, "wb") as f:
            f.write(struct.pack("<256f", *([1.0] * 256)))
        cmd = [brume, "convert", raw, path, "--dims", "8x4x8", "--bounds", ",".join("%g" % v for v in arg)]
        what = "brume convert of a constant 8 x 4 x 8 grid in %s" % (arg,)
    elif kind == "faces4":
        raw = path + ".raw"
        vals = [faces4_density(i, j, k) for k in range(4) for j in range(4) for i in range(4)]
        with open(raw, "wb") as f:
            f.write(struct.pack("<64f", *vals))
        cmd = [brume, "convert", raw, path, "--dims", "4x4x4", "--bounds", ",".join("%g" % v for v in arg)]
        what = "brume convert of grid_uniform.pbrt's 4 x 4 x 4 densities in %s" % (arg,)
    elif kind == "fire":
        cmd = [brume, "gen", "fire", "--resolution", "64", "--height", "%g" % arg, "-o", path]
        what = "brume gen fire, height %g" % arg
    else:
        cmd = [brume, "gen", "cloud", "--dims", "48x40x48", "--shape", "ellipsoid", "--method",
               "perlin", "--threshold", "0.2", "--bounds", ",".join("%g" % v for v in arg), "-o", path]
        what = "brume gen cloud in %s" % (arg,)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return what


def standin_plume_density(path):
    """smoke-plume's geometry/density_big_0084.pbrt (kept out of pbrt-v4-scenes' text): the
    opening of a uniformgrid medium "smoke" whose parameter list the Include continues."""
    nx, ny, nz = 24, 32, 24
    vals = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                x, y, z = (i + 0.5) / nx, (j + 0.5) / ny, (k + 0.5) / nz
                cx = 0.5 + 0.08 * math.sin(6.0 * y)
                cz = 0.5 + 0.06 * math.cos(5.0 * y)
                r = math.hypot(x - cx, z - cz) / (0.06 + 0.3 * y)
                d = max(0.0, 1 - r * r) * min(1.0, 4 * (1 - y)) * (0.75 + 0.25 * math.sin(20 * y + 7 * x))
                vals.append("%.4f" % d)
    with open(path, "w") as f:
        f.write("# stand-in written by brume's bench/pbrt_scenes.sh: a procedural plume\n")
        f.write('MakeNamedMedium "smoke" "string type" "uniformgrid"\n')
        f.write('  "integer nx" %d "integer ny" %d "integer nz" %d\n' % (nx, ny, nz))
        f.write('  "point3 p0" [0 0 0] "point3 p1" [0.75 1 0.75]\n  "float density" [\n')
        for a in range(0, len(vals), 24):
            f.write("    " + " ".join(vals[a:a + 24]) + "\n")
        f.write("  ]\n")
    return "procedural %d x %d x %d uniformgrid \"smoke\"" % (nx, ny, nz)


def standin_texture(path):
    write_png(path, 16, 16, [[128] * 48 for _ in range(16)])
    return "16 x 16 grey PNG"


def standins(pbrt_path, brume):
    made = 0
    for ref, owner, line, kind in referenced_files(pbrt_path):
        target = os.path.join(os.path.dirname(owner), ref)
        if os.path.exists(target):
            continue
        os.makedirs(os.path.dirname(target) or ".", exist_ok=True)
        ext = os.path.splitext(ref)[1].lower()
        if kind == "include" and ext == ".pbrt" and "density" in os.path.basename(ref):
            what = standin_plume_density(target)
        elif ext in (".nvdb", ".vdb"):
            what = standin_grid(target, brume)
        elif ext == ".ply":
            what = standin_mesh(target, owner, line)
        elif ext in (".exr", ".pfm") and "sky" in os.path.basename(ref):
            what = standin_sky(target)
        elif ext in (".png", ".tga", ".jpg", ".jpeg", ".exr", ".pfm"):
            if ext != ".png":
                write_exr(target, 16, 16, lambda x, y: (0.5, 0.5, 0.5))
                what = "16 x 16 grey OpenEXR"
            else:
                what = standin_texture(target)
        else:
            say("stand-in: %s: none (no generator for this kind of file)" % ref)
            continue
        made += 1
        say("stand-in: %s (%s)" % (os.path.relpath(target, os.path.dirname(pbrt_path)), what))
    return made


# ---------------------------------------------------------------- images

def read_pfm(path):
    with open(path, "rb") as f:
        data = f.read()
    parts = data.split(b"\n", 3)
    kind, dims, scale = parts[0].strip(), parts[1].split(), float(parts[2])
    w, h = int(dims[0]), int(dims[1])
    ch = 3 if kind == b"PF" else 1
    fmt = ("<" if scale < 0 else ">") + "%df" % (w * h * ch)
    vals = struct.unpack(fmt, parts[3][:4 * w * h * ch])
    if ch == 1:
        vals = [v for v in vals for _ in range(3)]
    rows = [vals[(h - 1 - y) * w * 3:(h - y) * w * 3] for y in range(h)]  # top row first
    return w, h, rows


def write_pfm(path, w, h, rows):
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        for y in range(h - 1, -1, -1):
            f.write(struct.pack("<%df" % (w * 3), *rows[y]))


def shrink(w, h, rows, k):
    nw, nh = w // k, h // k
    out = []
    inv = 1.0 / (k * k)
    for y in range(nh):
        acc = [0.0] * (nw * 3)
        for dy in range(k):
            r = rows[y * k + dy]
            for x in range(nw):
                base = x * k * 3
                for dx in range(k):
                    o = base + dx * 3
                    acc[x * 3] += r[o]
                    acc[x * 3 + 1] += r[o + 1]
                    acc[x * 3 + 2] += r[o + 2]
        out.append([a * inv for a in acc])
    return nw, nh, out


def srgb8(v):
    v = 0.0 if not v > 0.0 else min(v, 1.0)
    v = 12.92 * v if v <= 0.0031308 else 1.055 * v ** (1 / 2.4) - 0.055
    return int(v * 255 + 0.5)


def main(argv):
    if len(argv) >= 3 and argv[0] == "standins":
        standins(argv[1], argv[2])
    elif len(argv) == 2 and argv[0] == "film":
        print("%d %d" % film_size(argv[1]))
    elif len(argv) == 4 and argv[0] == "shrink":
        w, h, rows = read_pfm(argv[1])
        write_pfm(argv[3], *shrink(w, h, rows, int(argv[2])))
    elif len(argv) == 4 and argv[0] == "png":
        w, h, rows = read_pfm(argv[1])
        k = 1
        while w // k > int(argv[3]):
            k += 1
        if k > 1:
            w, h, rows = shrink(w, h, rows, k)
        f = max(1, 160 // w)  # a small render's pixels repeated (nearest) to at least 160 wide
        if f > 1:
            rows = [[v for x in range(w) for _ in range(f) for v in r[3 * x:3 * x + 3]] for r in rows for _ in range(f)]
            w, h = w * f, h * f
        write_png(argv[2], w, h, [[srgb8(v) for v in r] for r in rows])
    elif len(argv) == 3 and argv[0] == "ratios":
        means = []
        for path in argv[1:]:
            w, h, rows = read_pfm(path)
            means.append([sum(sum(r[c::3]) for r in rows) / (w * h) for c in range(3)])
        print("/".join("%.3f" % (a / b) if b > 0 else "-" for a, b in zip(*means)))
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
