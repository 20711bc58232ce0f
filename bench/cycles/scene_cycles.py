# scene_cycles.py - renders a brume scene file with Blender Cycles (Debian's blender 3.4),
# for bench/cloud64_vs_cycles.sh: the same camera, sun, medium and settings as brume.
#
#   blender -b --python bench/cycles/scene_cycles.py -- SCENE.json GRID.vdb OUT.exr SPP THREADS [SEED]
#
# Reads the subset of brume's scene format the comparison scenes use (docs/scene-format.md):
# a pinhole camera (position, look_at, up, vertical fov in degrees), a black background,
# one distant light (direction of travel, irradiance, no disk), one medium whose density is
# the grid "density" of GRID.vdb in world units (trilinear), with scalar sigma_a and sigma_s
# per unit density and a Henyey-Greenstein phase function; render width and height. Full
# multiple scattering (volume bounces up to 1024), no denoising, no adaptive sampling, box
# filter of width 1. SEED (default 1) is Cycles' seed: with the same seed, an image of n
# samples is the first n samples of one of N > n (its noise is the reference's own), so an
# image and the reference it is measured against must differ in seed. Prints "cycles_render_seconds S" (the render call alone, scene
# already built and loaded).
import json
import math
import sys
import time

import addon_utils
import bpy
from mathutils import Matrix, Vector

argv = sys.argv[sys.argv.index("--") + 1:]
scene_path, vdb_path, out_path, spp, threads = argv[0], argv[1], argv[2], int(argv[3]), int(argv[4])
seed = int(argv[5]) if len(argv) > 5 else 1
with open(scene_path) as f:
    desc = json.load(f)
cam_d, light_d, med_d, ren_d = desc["camera"], desc["lights"][0], desc["media"][0], desc["render"]
if desc.get("background", 0) != 0 or len(desc["lights"]) != 1 or len(desc["media"]) != 1:
    sys.exit("scene_cycles.py: %s: needs a black background, one light, one medium" % scene_path)
if light_d["type"] != "distant" or med_d["phase"]["type"] != "hg":
    sys.exit("scene_cycles.py: %s: needs a distant light and an hg phase function" % scene_path)

addon_utils.enable("cycles", default_set=True)
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.engine = "CYCLES"
cy = scene.cycles
cy.device = "CPU"
cy.samples = spp
cy.use_adaptive_sampling = False
cy.use_denoising = False
cy.seed = seed
cy.max_bounces = 1024
cy.volume_bounces = 1024
cy.diffuse_bounces = 0
cy.glossy_bounces = 0
cy.transmission_bounces = 0
cy.transparent_max_bounces = 1024
cy.sample_clamp_direct = 0.0
cy.sample_clamp_indirect = 0.0
cy.caustics_reflective = True
cy.caustics_refractive = True
cy.volume_step_rate = 1.0
cy.filter_width = 1.0
scene.render.threads_mode = "FIXED"
scene.render.threads = threads
scene.render.resolution_x = int(ren_d["width"])
scene.render.resolution_y = int(ren_d["height"])
scene.render.resolution_percentage = 100
scene.render.film_transparent = False
scene.view_settings.view_transform = "Standard"
scene.view_settings.look = "None"
scene.view_settings.exposure = 0.0
scene.view_settings.gamma = 1.0
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
scene.render.image_settings.exr_codec = "ZIP"

world = bpy.data.worlds.new("black")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
scene.world = world

# The volume: the VDB's grid "density" in its own world frame; sigma = density * coefficient.
bpy.ops.object.volume_import(filepath=vdb_path, location=(0, 0, 0))
vol = bpy.context.active_object
vol.rotation_euler = (0.0, 0.0, 0.0)  # the importer turns some files (Houdini's) y-up to z-up: keep the file's frame
# Cycles 3.4 spreads voxel (i, j, k)'s value over the index-space cell [i, i + 1] x ..., centred
# on (i, j, k) + 1/2, where OpenVDB (and brume) centre it on (i, j, k): the same file renders
# half a voxel apart (docs/performance.md, "The error's noise"). Moving the object back by half
# a voxel, through the grid's own index-to-object map, makes both render the same cloud.
vol.data.grids.load()
grid = vol.data.grids["density"]
vol.location = grid.matrix_object.to_3x3() @ Vector((-0.5, -0.5, -0.5))
mat = bpy.data.materials.new("medium")
mat.use_nodes = True
nt = mat.node_tree
for n in list(nt.nodes):
    nt.nodes.remove(n)
out = nt.nodes.new("ShaderNodeOutputMaterial")
attr = nt.nodes.new("ShaderNodeAttribute")
attr.attribute_name = "density"
mul_s = nt.nodes.new("ShaderNodeMath")
mul_s.operation = "MULTIPLY"
mul_s.inputs[1].default_value = float(med_d["sigma_s"])
mul_a = nt.nodes.new("ShaderNodeMath")
mul_a.operation = "MULTIPLY"
mul_a.inputs[1].default_value = float(med_d["sigma_a"])
scat = nt.nodes.new("ShaderNodeVolumeScatter")
scat.inputs["Color"].default_value = (1, 1, 1, 1)
scat.inputs["Anisotropy"].default_value = float(med_d["phase"]["g"])
absb = nt.nodes.new("ShaderNodeVolumeAbsorption")
absb.inputs["Color"].default_value = (0, 0, 0, 1)  # sigma_a = density * (1 - color)
add = nt.nodes.new("ShaderNodeAddShader")
nt.links.new(attr.outputs["Fac"], mul_s.inputs[0])
nt.links.new(attr.outputs["Fac"], mul_a.inputs[0])
nt.links.new(mul_s.outputs[0], scat.inputs["Density"])
nt.links.new(mul_a.outputs[0], absb.inputs["Density"])
nt.links.new(scat.outputs[0], add.inputs[0])
nt.links.new(absb.outputs[0], add.inputs[1])
nt.links.new(add.outputs[0], out.inputs["Volume"])
mat.cycles.volume_interpolation = "LINEAR"
mat.cycles.homogeneous_volume = False
vol.data.materials.append(mat)

# The sun: brume's direction is the one light travels along; a sun's light travels along its -Z.
sun_data = bpy.data.lights.new("sun", type="SUN")
sun_data.energy = float(light_d["irradiance"])  # irradiance, W/m^2
sun_data.angle = 0.0
sun = bpy.data.objects.new("sun", sun_data)
scene.collection.objects.link(sun)
travel = Vector(light_d["direction"]).normalized()
sun.rotation_euler = (-travel).to_track_quat("Z", "Y").to_euler()

# The camera looks along its -Z with +Y up: columns (right, up, -forward) from brume's frame.
cam_data = bpy.data.cameras.new("cam")
cam_data.sensor_fit = "VERTICAL"
cam_data.angle_y = math.radians(float(cam_d["fov"]))
cam_data.clip_start = 1e-3  # brume clips nothing: the far scene must not vanish past 100 units
cam_data.clip_end = 1e6
cam = bpy.data.objects.new("cam", cam_data)
scene.collection.objects.link(cam)
pos, look, up = Vector(cam_d["position"]), Vector(cam_d["look_at"]), Vector(cam_d["up"])
fwd = (look - pos).normalized()
right = fwd.cross(up).normalized()
cam_up = right.cross(fwd)
cam.location = pos
cam.rotation_euler = Matrix((right, cam_up, -fwd)).transposed().to_euler()
scene.camera = cam

scene.render.filepath = out_path
t0 = time.perf_counter()
bpy.ops.render.render(write_still=True)
print("cycles_render_seconds %.3f" % (time.perf_counter() - t0))
