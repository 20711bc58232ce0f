#!/usr/bin/env python3
"""stam_scenes.py - writes the scene files of Stam 1994's Figures 5-8 into scenes/
(scenes/stam-fig*.json). Run from the repository root; the files are committed, so this is
only needed to change them."""
import json
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
# The blobs' peak density is 0.6, four times the top row's eta, so that both rows clamp (with
# the former 0.15 every peak was at most the top row's eta = 0.15, which then clamped nothing);
# sigma_a and sigma_s are divided by 4 to keep the mean optical depth of the earlier scenes, and
# eps is 4 times larger to keep the perturbation's amplitude where nothing is clamped.
FIG5_CLOUD = dict(CLOUD, density=0.6)
OURS = ("Ours, as the paper gives no numbers: camera, sun, sky, albedo (0.99) and the ambient term standing in "
        "for multiple scattering (Section 7 says only 'albedo close to one' and 'a non zero value for the emission "
        "function'), blob sizes, masses and the ellipsoid, alpha, kappa_t, eps and eta. ")
LATTICE = ("Q's lattice covers the blobs (stam.lattice 0), not the paper's 32^3, whose period would repeat across "
           "the cloud (docs/stam.md). ")
for tag, eps, eta, where in [("a", 0.2, 0.15, "top left"), ("b", 1.6, 0.15, "top right"),
                             ("c", 0.2, 0.03, "bottom left"), ("d", 1.6, 0.03, "bottom right")]:
    write(f"scenes/stam-fig5-{tag}.json", {
        "comment": f"Stam 1994, Figure 5 ({where}): one cloud of 200 blobs from an ellipsoid, eps {eps}, eta {eta}. "
                   "The paper's: one cloud of blobs from an ellipsoid, mass falling from its centre (Section 7, after "
                   "Gardner), four pictures, eps low on the left and high on the right, eta high on top and low "
                   "below. Blob peak density 0.6, above eta in both rows, so that the clamping shows: the bottom row "
                   "has fewer holes in the dense parts. " + OURS + LATTICE,
        "camera": {"position": [0.0, 0.3, 6.0], "look_at": [0.0, 0.0, 0.0], "fov": 40},
        "background": SKY, "lights": [SUN],
        "media": [cloud_medium("cloud", [FIG5_CLOUD], sigma_s=2.0, sigma_a=0.0125)],
        "stam": {"eps": eps, "eta": eta, "alpha": 0.06, "seed": 3, "ambient": [0.35, 0.4, 0.5]},
        "render": {"width": 320, "height": 240, "spp": 4, "method": "stam"}})

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

# Figure 6d: fog over a city of boxes, seen from above.
rnd = random.Random(7)
boxes = [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "size": 60,
          "material": {"albedo": 0.3}}]
for i in range(-4, 5):
    for k in range(-4, 5):
        if rnd.random() < 0.15:
            continue
        w = rnd.uniform(0.5, 0.9)
        h = rnd.choice([0.8, 1.2, 1.6, 2.2, 3.0, 4.5])
        x, z = i * 1.4, k * 1.4
        a = rnd.uniform(0.45, 0.75)
        boxes.append({"type": "box", "min": [x - w / 2, 0, z - w / 2], "max": [x + w / 2, h, z + w / 2],
                      "material": {"albedo": [a, a * 0.95, a * 0.9]}})
write("scenes/stam-fig6-city.json", {
    "comment": "Stam 1994, Figure 6: downtown on a foggy day, seen from above: a layer of fog blobs among boxes. "
               "The paper's: an aerial view of a city in fog. Ours: the city (random boxes on a 9 x 9 grid, not "
               "Toronto), the fog as one flat ellipsoid of 900 blobs, the grey sky and sun, and every number. "
               + LATTICE,
    "camera": {"position": [9.0, 13.0, 11.0], "look_at": [0.0, 0.0, 0.0], "fov": 45},
    "background": [0.55, 0.6, 0.68],
    "lights": [{"type": "distant", "direction": [-0.4, -0.8, -0.45], "irradiance": [2.4, 2.3, 2.1]}],
    "surfaces": boxes,
    "media": [{"name": "fog", "sigma_a": 0.02, "sigma_s": 2.0,
               "density": {"type": "blobs", "generators": [
                   {"type": "cloud", "center": [0, 0.6, 0], "radii": [8.0, 0.9, 8.0], "count": 900,
                    "h": [0.3, 0.6], "density": 0.12, "falloff": 0.5, "seed": 4}]}}],
    "stam": {"eps": 0.3, "eta": 0.05, "alpha": 0.12, "seed": 3, "ambient": [0.45, 0.5, 0.55]},
    "render": {"width": 320, "height": 240, "spp": 4, "method": "stam"}})

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
fire = {"type": "fire", "base": [0, 0.05, 0], "height": 1.3, "radius": 0.22, "count": 14, "h": 0.13,
        "density": 3.0, "seed": 3}
room = [
    {"type": "quad", "corner": [-3, 0, -2.5], "edge_u": [0, 0, 6], "edge_v": [6, 0, 0], "material": {"albedo": 0.55}},
    {"type": "quad", "corner": [-3, 0, -2.5], "edge_u": [6, 0, 0], "edge_v": [0, 4, 0], "material": {"albedo": 0.6}},
    {"type": "quad", "corner": [-3, 0, -2.5], "edge_u": [0, 4, 0], "edge_v": [0, 0, 6], "material": {"albedo": 0.6}},
    {"type": "quad", "corner": [3, 0, -2.5], "edge_u": [0, 0, 6], "edge_v": [0, 4, 0], "material": {"albedo": 0.6}},
    {"type": "quad", "corner": [-3, 4, -2.5], "edge_u": [0, 0, 6], "edge_v": [6, 0, 0], "material": {"albedo": 0.5}}]
lights = [{"type": "point", "position": p, "intensity": [1.6, 0.9, 0.35]}
          for p in ([0, 0.25, 0], [0.08, 0.45, 0.05], [-0.07, 0.6, -0.04], [0.03, 0.8, 0.03], [0, 1.0, 0])]
write("scenes/stam-fig8.json", {
    "comment": "Stam 1994, Figure 8: a flame of 14 emissive blobs (albedo 0; emission falls and reddens with height) "
               "under a plume of absorbing smoke, in a room lit by five point lights inside the flame. The paper's: "
               "14 blobs with different emission parameters, point lights placed in the flame so that shadow rays "
               "through the perturbed fire make the patterns on the walls. Ours: the room, the three emission bands, "
               "the smoke plume, the lights' positions and every number. " + LATTICE,
    "camera": {"position": [0.0, 1.3, 4.4], "look_at": [0.0, 1.0, 0.0], "fov": 50},
    "background": 0, "lights": lights, "surfaces": room,
    "media": [
        {"name": "flame core", "sigma_a": 2.0, "sigma_s": 0, "emission": [4.0, 3.2, 1.8],
         "density": {"type": "blobs", "generators": [dict(fire, band=[0.0, 0.35])]}},
        {"name": "flame", "sigma_a": 2.0, "sigma_s": 0, "emission": [3.2, 1.5, 0.35],
         "density": {"type": "blobs", "generators": [dict(fire, band=[0.35, 0.7])]}},
        {"name": "flame tip", "sigma_a": 2.0, "sigma_s": 0, "emission": [2.0, 0.5, 0.08],
         "density": {"type": "blobs", "generators": [dict(fire, band=[0.7, 1.0])]}},
        {"name": "smoke", "sigma_a": 3.0, "sigma_s": 0,
         "density": {"type": "blobs", "generators": [
             {"type": "cloud", "center": [0.1, 1.95, 0], "radii": [0.45, 0.6, 0.45], "count": 60,
              "h": [0.1, 0.22], "density": 0.5, "falloff": 1.0, "seed": 6}]}}],
    "stam": {"eps": 0.4, "eta": 0.3, "alpha": 0.05, "seed": 3},
    "render": {"width": 320, "height": 240, "spp": 4, "method": "stam"}})
