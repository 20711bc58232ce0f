# cloud64_cycles.py - renders the comparison scene of ../shared/data/SOURCES.md with
# Blender Cycles (Debian's blender), for bench/cloud64_vs_cycles.sh.
#
#   blender -b --python bench/cycles/cloud64_cycles.py -- CLOUD.vdb OUT.exr SPP THREADS
#
# Scene (SOURCES.md, section 4): +z up; sigma_t = 20 at density 1, albedo 0.9
# (sigma_s = 18, sigma_a = 2), Henyey-Greenstein g = 0.6; one sun travelling along
# (-1, -1, -1)/sqrt 3 with irradiance pi; pinhole camera at (0, -2.5, 0) looking at the
# origin, vertical fov 30 degrees, 256 x 256, black background. Full multiple scattering
# (volume bounces up to 1024), no denoising, no adaptive sampling. Prints
# "cycles_render_seconds S" (the render call alone, scene already built and loaded).
import math
import sys
import time

import addon_utils
import bpy
from mathutils import Vector

argv = sys.argv[sys.argv.index("--") + 1:]
vdb_path, out_path, spp, threads = argv[0], argv[1], int(argv[2]), int(argv[3])

addon_utils.enable("cycles", default_set=True)
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.engine = "CYCLES"
cy = scene.cycles
cy.device = "CPU"
cy.samples = spp
cy.use_adaptive_sampling = False
cy.use_denoising = False
cy.seed = 1
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
scene.render.resolution_x = 256
scene.render.resolution_y = 256
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

# The volume: a VDB whose grid "density" holds cloud64's values at voxel centres.
bpy.ops.object.volume_import(filepath=vdb_path, location=(0, 0, 0))
vol = bpy.context.active_object
mat = bpy.data.materials.new("cloud")
mat.use_nodes = True
nt = mat.node_tree
for n in list(nt.nodes):
    nt.nodes.remove(n)
out = nt.nodes.new("ShaderNodeOutputMaterial")
attr = nt.nodes.new("ShaderNodeAttribute")
attr.attribute_name = "density"
mul_s = nt.nodes.new("ShaderNodeMath")
mul_s.operation = "MULTIPLY"
mul_s.inputs[1].default_value = 18.0
mul_a = nt.nodes.new("ShaderNodeMath")
mul_a.operation = "MULTIPLY"
mul_a.inputs[1].default_value = 2.0
scat = nt.nodes.new("ShaderNodeVolumeScatter")
scat.inputs["Color"].default_value = (1, 1, 1, 1)
scat.inputs["Anisotropy"].default_value = 0.6
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

# The sun: light travels along (-1, -1, -1)/sqrt 3; a sun's light travels along its -Z.
sun_data = bpy.data.lights.new("sun", type="SUN")
sun_data.energy = math.pi  # irradiance, W/m^2
sun_data.angle = 0.0
sun = bpy.data.objects.new("sun", sun_data)
scene.collection.objects.link(sun)
travel = Vector((-1.0, -1.0, -1.0)).normalized()
sun.rotation_euler = (-travel).to_track_quat("Z", "Y").to_euler()

cam_data = bpy.data.cameras.new("cam")
cam_data.sensor_fit = "VERTICAL"
cam_data.angle_y = math.radians(30.0)
cam = bpy.data.objects.new("cam", cam_data)
scene.collection.objects.link(cam)
cam.location = (0.0, -2.5, 0.0)
cam.rotation_euler = (Vector((0, 0, 0)) - cam.location).to_track_quat("-Z", "Y").to_euler()
scene.camera = cam

scene.render.filepath = out_path
t0 = time.perf_counter()
bpy.ops.render.render(write_still=True)
print("cycles_render_seconds %.3f" % (time.perf_counter() - t0))
