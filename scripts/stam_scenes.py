#!/usr/bin/env python3
"""stam_scenes.py - writes the scene files of Stam 1994's Figures 5-8 into scenes/
(scenes/stam-fig*.json). Run from the repository root; the files are committed, so this is
only needed to change them."""
import json
import math
import random

SKY = [0.32, 0.48, 0.78]
SUN = {"type": "distant", "direction": [-0.6, -0.55, -0.58], "irradiance": [3.0, 2.9, 2.7]}


def cloud_medium(name, gens, sigma_s=8.0, velocity=None, sigma_a=0.05):
    d = {"type": "blobs", "generators": gens}
    if velocity:
        d["velocity"] = velocity
    return {"name": name, "sigma_a": sigma_a, "sigma_s": sigma_s, "density": d}


def write(path, scene):
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")


CLOUD = {"type": "cloud", "center": [0, 0, 0], "radii": [1.6, 0.75, 1.0], "count": 200,
         "h": [0.12, 0.35], "density": 0.15, "falloff": 1.0, "seed": 5}

# Figure 5: one cloud, four settings. Left column low perturbation (eps), right high;
# top row high clamping value (eta), bottom row low.
# Chosen so that eta visibly changes the picture (docs/stam.md, "Figure 5"): 30 large blobs
# of equal peak density 0.6 (falloff 0; the mass still falls from the centre, as the blobs'
# radius does), so that few blobs overlap on a ray and a blob's own perturbation is not
# averaged away by its neighbours'; the top row's eta = 0.3 clamps only the blobs' cores, the
# bottom row's 0.03 nearly all of each blob; a cloud optically thin enough (sigma_s 1.5, 0.7 to
# 1.1 per blob through its centre) for its holes to show, and lit so that it is much brighter
# than the sky (sun 7, ambient 0.6): where the cloud's own radiance J is close to the sky's, a
# hole changes nothing in the picture, which is what hid eta in the earlier scenes; Q's
# correlation length alpha = 0.1 makes the holes a few pixels wide at 640 x 480.
FIG5_CLOUD = dict(CLOUD, count=30, h=[0.3, 0.5], density=0.6, falloff=0.0)
FIG5_SUN = {"type": "distant", "direction": [-0.6, -0.55, -0.58], "irradiance": [7.0, 6.8, 6.4]}
OURS = ("Ours, as the paper gives no numbers: camera, sun, sky, albedo (0.99) and the ambient term standing in "
        "for multiple scattering (Section 7 says only 'albedo close to one' and 'a non zero value for the emission "
        "function'), blob sizes, masses and the ellipsoid, alpha, kappa_t, eps and eta. ")
LATTICE = ("Q's lattice covers the blobs (stam.lattice 0), not the paper's 32^3, whose period would repeat across "
           "the cloud (docs/stam.md). ")
for tag, eps, eta, where in [("a", 0.2, 0.3, "top left"), ("b", 1.6, 0.3, "top right"),
                             ("c", 0.2, 0.03, "bottom left"), ("d", 1.6, 0.03, "bottom right")]:
    write(f"scenes/stam-fig5-{tag}.json", {
        "comment": f"Stam 1994, Figure 5 ({where}): one cloud of 30 blobs from an ellipsoid, eps {eps}, eta {eta}. "
                   "The paper's: one cloud of blobs from an ellipsoid, mass falling from its centre (Section 7, after "
                   "Gardner), four pictures, eps low on the left and high on the right, eta high on top and low "
                   "below. Ours: 30 large blobs of equal peak density 0.6 (falloff 0: the mass falls from the centre "
                   "with the blobs' radius), above eta in both rows; a thin cloud (sigma_s 1.5) lit much brighter than "
                   "the sky (sun 7, ambient 0.6), so that the holes the perturbation cuts show: the bottom row, clamped "
                   "harder, keeps its blobs whole (docs/stam.md). The paper's size, 640 x 480. " + OURS + LATTICE,
        "camera": {"position": [0.0, 0.3, 6.0], "look_at": [0.0, 0.0, 0.0], "fov": 40},
        "background": SKY, "lights": [FIG5_SUN],
        "media": [cloud_medium("cloud", [FIG5_CLOUD], sigma_s=1.5, sigma_a=0.0094)],
        "stam": {"eps": eps, "eta": eta, "alpha": 0.1, "seed": 3, "ambient": [0.6, 0.62, 0.66]},
        "render": {"width": 640, "height": 480, "spp": 4, "method": "stam"}})

# Figure 6a: a self-shadowed cloud, lit from behind and to the side, over a ground plane.
write("scenes/stam-fig6-shadow.json", {
    "comment": "Stam 1994, Figure 6: a cloud with self-shadowing (sun from the side), and its shadow on the ground. "
               "The paper's: a cloud of blobs casting its shadow, shadow rays carrying the realized transparency "
               "(Section 6.3). " + OURS + "The ground plane and the sun from the side are ours, to show both "
               "shadows. " + LATTICE,
    "camera": {"position": [1.5, 0.4, 6.5], "look_at": [0.0, -0.2, 0.0], "fov": 42},
    "background": SKY,
    "lights": [{"type": "distant", "direction": [0.9, -0.35, 0.25], "irradiance": [3.2, 3.0, 2.8]}],
    "surfaces": [{"type": "plane", "point": [0, -1.6, 0], "normal": [0, 1, 0], "size": 60,
                  "material": {"albedo": [0.35, 0.42, 0.25]}}],
    "media": [cloud_medium("cloud", [dict(CLOUD, count=300, seed=11)], sigma_s=12.0)],
    "stam": {"eps": 0.2, "eta": 0.08, "alpha": 0.06, "seed": 3, "ambient": [0.25, 0.3, 0.4]},
    "render": {"width": 320, "height": 240, "spp": 4, "method": "stam"}})

# Figure 6b, c: two clusters of clouds.
for tag, seed, n in [("a", 21, 6), ("b", 42, 12)]:
    write(f"scenes/stam-fig6-cluster-{tag}.json", {
        "comment": f"Stam 1994, Figure 6: a cluster of {n} clouds from random ellipsoids. The paper's: clusters "
                   "made by generating such ellipsoids at random (Section 7). " + OURS + "The number of clouds and "
                   "the box they are drawn in are ours. " + LATTICE,
        "camera": {"position": [0.0, 1.0, 16.0], "look_at": [0.0, 0.0, 0.0], "fov": 45},
        "background": SKY, "lights": [SUN],
        "media": [cloud_medium("clouds", [{
            "type": "cluster", "bounds_min": [-6, -1, -3], "bounds_max": [6, 2, 3], "clouds": n,
            "radii_min": [0.8, 0.4, 0.6], "radii_max": [2.0, 0.9, 1.4], "count": 120,
            "h": [0.12, 0.35], "density": 0.15, "falloff": 1.0, "seed": seed}])],
        "stam": {"eps": 0.2, "eta": 0.1, "alpha": 0.06, "seed": 3, "ambient": [0.35, 0.4, 0.5]},
        "render": {"width": 320, "height": 240, "spp": 4, "method": "stam"}})

# Figure 6d: fog over a city of boxes, seen from above at an angle. The fog is a veil through
# which the buildings fade with distance: a layer of overlapping blobs on a jittered lattice
# (spacing 2, h 1.6, so that their sum is nearly uniform), over the whole ground the camera
# sees, its density falling with height (three layers of blobs at y = 0, 2, 4 with peak
# densities 1, 0.55, 0.2 of 0.02), and a weak perturbation (eps 0.03) with a long correlation
# length (alpha 0.8). The earlier scene's one flat ellipsoid of small blobs, perturbed hard,
# made a cotton layer around the buildings' bases.
rnd = random.Random(7)
CITY_N = 7  # a 15 x 15 grid of blocks, 1.4 apart
FOG_SPACING, FOG_H, FOG_RADIUS, FOG_PEAK = 2.0, 1.6, 26.0, 0.02
boxes = [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "size": 56,
          "material": {"albedo": 0.3}}]
for i in range(-CITY_N, CITY_N + 1):
    for k in range(-CITY_N, CITY_N + 1):
        if rnd.random() < 0.15:
            continue
        w = rnd.uniform(0.5, 0.9)
        h = rnd.choice([0.8, 1.2, 1.6, 2.2, 3.0, 4.5])
        x, z = i * 1.4, k * 1.4
        a = rnd.uniform(0.45, 0.75)
        boxes.append({"type": "box", "min": [x - w / 2, 0, z - w / 2], "max": [x + w / 2, h, z + w / 2],
                      "material": {"albedo": [a, a * 0.95, a * 0.9]}})
jit = random.Random(11)
fog = []
n = int(FOG_RADIUS / FOG_SPACING)
for y, f in [(0.0, 1.0), (2.0, 0.55), (4.0, 0.2)]:
    for i in range(-n, n + 1):
        for k in range(-n, n + 1):
            x = (i + jit.uniform(-0.3, 0.3)) * FOG_SPACING
            z = (k + jit.uniform(-0.3, 0.3)) * FOG_SPACING
            yy = y + jit.uniform(-0.2, 0.2) * FOG_SPACING
            if x * x + z * z > FOG_RADIUS * FOG_RADIUS:
                continue
            mass = FOG_PEAK * f * (2 * math.pi) ** 1.5 * FOG_H ** 3  # peak density FOG_PEAK f
            fog.append([round(x, 3), round(yy, 3), round(z, 3), round(mass, 5), FOG_H])
write("scenes/stam-fig6-city.json", {
    "comment": "Stam 1994, Figure 6: downtown on a foggy day, seen from above: a veil of fog through which the "
               "buildings fade with distance. The paper's: an aerial view of a city in fog. Ours: the city (random "
               "boxes on a 15 x 15 grid, not Toronto), the fog as %d blobs on a jittered lattice in three layers "
               "thinning with height (not an ellipsoid: a layer that covers the ground in view), the weak "
               "perturbation (eps 0.03) with a long correlation length (alpha 0.8), the grey sky and sun, and "
               "every number. The paper's size, 640 x 480. " % len(fog) + LATTICE,
    "camera": {"position": [13.0, 11.0, 15.0], "look_at": [-1.5, 0.0, -1.5], "fov": 45},
    "background": [0.55, 0.6, 0.68],
    "lights": [{"type": "distant", "direction": [-0.4, -0.8, -0.45], "irradiance": [2.4, 2.3, 2.1]}],
    "surfaces": boxes,
    "media": [{"name": "fog", "sigma_a": 0.02, "sigma_s": 2.0,
               "density": {"type": "blobs", "blobs": fog}}],
    "stam": {"eps": 0.03, "eta": 0.05, "alpha": 0.8, "seed": 3, "ambient": [0.45, 0.5, 0.55]},
    "render": {"width": 640, "height": 480, "spp": 2, "method": "stam"}})

# Figure 7: a cloud drifting past a tall tower, four frames (stam.time 0, 1, 2, 3).
tower = [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "size": 200, "material": {"albedo": [0.3, 0.35, 0.25]}},
    {"type": "box", "min": [-0.25, 0, -0.25], "max": [0.25, 9.0, 0.25], "material": {"albedo": 0.7}},
    {"type": "sphere", "center": [0, 6.5, 0], "radius": 0.7, "material": {"albedo": 0.75}},
    {"type": "box", "min": [-0.06, 9.0, -0.06], "max": [0.06, 11.5, 0.06], "material": {"albedo": 0.6}}]
for t in range(4):
    write(f"scenes/stam-fig7-t{t}.json", {
        "comment": f"Stam 1994, Figure 7: a cloud drifting past a tall tower, frame {t} (stam.time {t}); "
                   "the blobs move with the medium's velocity and Q evolves and drifts with them. The paper's: four "
                   "frames of a cloud interacting with a tower (Toronto's CN Tower), the cloud occluding it and "
                   "shadowed by it. Ours: the tower's shape (a box, a sphere, a mast), the drift speed and Q's "
                   "evolution in time (the paper does not say how Q evolves: each Fourier mode turns, docs/stam.md). "
                   + OURS + LATTICE,
        "camera": {"position": [0.0, 5.0, 16.0], "look_at": [0.0, 6.0, 0.0], "fov": 45},
        "background": SKY, "lights": [SUN], "surfaces": tower,
        "media": [cloud_medium("cloud", [dict(CLOUD, center=[-3.2, 6.3, 0.2], radii=[2.2, 0.9, 1.3],
                                              count=260, seed=8)], velocity=[1.6, 0.0, 0.0])],
        "stam": {"eps": 0.2, "eta": 0.1, "alpha": 0.06, "seed": 3, "time": t, "rate": 0.7,
                 "ambient": [0.35, 0.4, 0.5]},
        "render": {"width": 240, "height": 320, "spp": 4, "method": "stam"}})

# Figure 8: a flame of 14 emissive blobs (three bands: white core, orange, red tip) under a
# plume of absorbing smoke, in a room lit by five point lights inside the flame.
# The smoke is a plume that starts at the flame's tip and rises to the ceiling: blobs along a
# slowly wandering axis, growing (h 0.1 to 0.35) and thinning with height (the earlier scene's
# ellipsoid of smoke floated above the flame, detached). The random light patterns on the walls
# and floor that the paper points out are the shadows of the perturbed flame and smoke cast by
# the five lights (shadow rays carry the realized transparency, Section 6.3): they show when
# the flame is nearly opaque on average (sigma_a 6) and strongly perturbed (eps 8, eta 3 above
# every blob's peak so nothing is clamped, alpha 0.03), so that light leaves the flame through
# the holes the perturbation cuts, and when the lights are bright enough for the walls to be
# seen (intensity 12, 7, 2.6). With sigma_a 2, eps 0.4, eta 0.3 the flame was thin and barely
# perturbed, and the five lights' shadows averaged into smooth walls.
fire = {"type": "fire", "base": [0, 0.05, 0], "height": 1.3, "radius": 0.22, "count": 14, "h": 0.13,
        "density": 3.0, "seed": 3}
room = [
    {"type": "quad", "corner": [-3, 0, -2.5], "edge_u": [0, 0, 6], "edge_v": [6, 0, 0], "material": {"albedo": 0.55}},
    {"type": "quad", "corner": [-3, 0, -2.5], "edge_u": [6, 0, 0], "edge_v": [0, 4, 0], "material": {"albedo": 0.6}},
    {"type": "quad", "corner": [-3, 0, -2.5], "edge_u": [0, 4, 0], "edge_v": [0, 0, 6], "material": {"albedo": 0.6}},
    {"type": "quad", "corner": [3, 0, -2.5], "edge_u": [0, 0, 6], "edge_v": [0, 4, 0], "material": {"albedo": 0.6}},
    {"type": "quad", "corner": [-3, 4, -2.5], "edge_u": [0, 0, 6], "edge_v": [6, 0, 0], "material": {"albedo": 0.5}}]
lights = [{"type": "point", "position": p, "intensity": [12.0, 7.0, 2.6]}
          for p in ([0, 0.25, 0], [0.08, 0.45, 0.05], [-0.07, 0.6, -0.04], [0.03, 0.8, 0.03], [0, 1.0, 0])]
PLUME_BASE, PLUME_TOP = 1.15, 3.8  # the flame's tip (fire base 0.05 + most of its height 1.3) to near the ceiling
pr = random.Random(6)
smoke = []
y, x, z = PLUME_BASE, 0.0, 0.0
while y < PLUME_TOP:
    s = (y - PLUME_BASE) / (PLUME_TOP - PLUME_BASE)
    h = 0.1 + 0.25 * s
    for _ in range(3):
        mass = 0.8 * (1 - 0.6 * s) * (2 * math.pi) ** 1.5 * h ** 3  # peak density 0.8 falling to 0.32
        smoke.append([round(x + pr.gauss(0, 0.6 * h), 3), round(y + pr.uniform(-0.3, 0.3) * h, 3),
                      round(z + pr.gauss(0, 0.6 * h), 3), round(mass, 5), round(h, 3)])
    x += pr.gauss(0.03, 0.05)
    z += pr.gauss(0, 0.04)
    y += 0.7 * h
write("scenes/stam-fig8.json", {
    "comment": "Stam 1994, Figure 8: a flame of 14 emissive blobs (albedo 0; emission falls and reddens with height) "
               "under a plume of absorbing smoke rising from the flame's tip, in a room lit by five point lights "
               "inside the flame. The paper's: 14 blobs with different emission parameters, smoke on top of the "
               "flame with zero emission (a perfect absorber), albedo 0, point lights placed in the flame so that "
               "shadow rays through the perturbed fire make random patterns on the walls. Ours: the room, the three "
               "emission bands, the plume (%d blobs along a wandering axis, growing and thinning with height), the "
               "lights' positions and intensities, a nearly opaque and strongly perturbed flame (sigma_a 6, eps 8, "
               "eta 3, alpha 0.03) so that the patterns show, and every number. The paper's size, 640 x 480. "
               % len(smoke) + LATTICE,
    "camera": {"position": [0.0, 1.6, 4.4], "look_at": [0.0, 1.5, 0.0], "fov": 55},
    "background": 0, "lights": lights, "surfaces": room,
    "media": [
        {"name": "flame core", "sigma_a": 6.0, "sigma_s": 0, "emission": [4.0, 3.2, 1.8],
         "density": {"type": "blobs", "generators": [dict(fire, band=[0.0, 0.35])]}},
        {"name": "flame", "sigma_a": 6.0, "sigma_s": 0, "emission": [3.2, 1.5, 0.35],
         "density": {"type": "blobs", "generators": [dict(fire, band=[0.35, 0.7])]}},
        {"name": "flame tip", "sigma_a": 6.0, "sigma_s": 0, "emission": [2.0, 0.5, 0.08],
         "density": {"type": "blobs", "generators": [dict(fire, band=[0.7, 1.0])]}},
        {"name": "smoke", "sigma_a": 3.0, "sigma_s": 0, "density": {"type": "blobs", "blobs": smoke}}],
    "stam": {"eps": 8.0, "eta": 3.0, "alpha": 0.03, "seed": 3},
    "render": {"width": 640, "height": 480, "spp": 4, "method": "stam"}})
