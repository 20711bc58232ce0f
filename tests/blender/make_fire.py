# make_fire.py - tests/blender_fire_test.sh's scene: a small fire written here with pyopenvdb
# (grids "density", "temperature" and "flame"), imported as a volume object with a Principled
# Volume that emits as fire artists set it (Emission Strength from the "flame" attribute
# times a constant, an Emission Color, Blackbody Intensity with a tint and the "temperature"
# attribute), a dim sky, saved, then rendered with Cycles to an EXR.
#
#   blender -b --factory-startup --python make_fire.py -- FIRE.vdb OUT.blend CYCLES.exr SPP [WxH]
import math
import sys

import addon_utils
import bpy

try:
    import pyopenvdb as vdb
except ImportError:
    print("skipped: no pyopenvdb (python3-openvdb)")
    sys.exit(77)

args = sys.argv[sys.argv.index("--") + 1:]
vdb_path, blend, exr, spp = args[:4]
width, height = (int(v) for v in args[4].split("x")) if len(args) > 4 else (40, 40)

# The fire: a ball of smoke (density falling from 1 to 0 at radius 7 voxels) around a hot
# core (temperature up to 2.4 x 1000 K) and flames (0 outside radius 5): every voxel that
# emits has density, as brume emits where the density is (docs/scene-format.md, "Emission").
N, R = 16, 7.0
density, temperature, flame = vdb.FloatGrid(), vdb.FloatGrid(), vdb.FloatGrid()
da, ta, fa = density.getAccessor(), temperature.getAccessor(), flame.getAccessor()
for k in range(N):
    for j in range(N):
        for i in range(N):
            r = math.sqrt((i - 7.5) ** 2 + (j - 7.5) ** 2 + (k - 6.5) ** 2 * 0.7)
            d = max(0.0, 1.0 - r / R)
            if d <= 0.0:
                continue
            da.setValueOn((i, j, k), d)
            ta.setValueOn((i, j, k), 2.4 * d ** 0.5)
            f = max(0.0, 1.0 - r / 5.0)
            if f > 0.0:
                fa.setValueOn((i, j, k), f)
for g, name in ((density, "density"), (temperature, "temperature"), (flame, "flame")):
    g.name = name
    g.gridClass = vdb.GridClass.FOG_VOLUME
    g.transform = vdb.createLinearTransform(voxelSize=1.0 / 8.0)
vdb.write(vdb_path, grids=[density, temperature, flame])

addon_utils.enable("cycles", default_set=True)
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.engine = "CYCLES"
cy = scene.cycles
cy.device = "CPU"
cy.samples = int(spp)
cy.use_adaptive_sampling = False
cy.use_denoising = False
cy.seed = 7
cy.max_bounces = cy.volume_bounces = cy.transparent_max_bounces = cy.diffuse_bounces = 1024
cy.sample_clamp_direct = cy.sample_clamp_indirect = 0.0
cy.filter_width = 1.0
# Cycles 3.4 ray-marches volumes: small steps, so that its bias is below the test's noise
cy.volume_step_rate = 0.05
cy.volume_preview_step_rate = 0.05
cy.volume_max_steps = 4096
scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = width, height, 100
scene.view_settings.view_transform = "Standard"
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"

world = bpy.data.worlds.new("sky")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.2, 0.3, 0.5, 1)
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.1
scene.world = world

bpy.ops.object.volume_import(filepath=vdb_path, location=(0, 0, 0))
vol = bpy.context.active_object
vol.name = "fire"
vol.rotation_euler = (0.0, 0.0, 0.0)
vol.location = (-1.0, -1.0, -0.8)
vol.data.render.step_size = 0.0  # Cycles' automatic step, times the scene's step rate
mat = bpy.data.materials.new("fire")
mat.use_nodes = True
nt = mat.node_tree
for n in list(nt.nodes):
    nt.nodes.remove(n)
out = nt.nodes.new("ShaderNodeOutputMaterial")
pv = nt.nodes.new("ShaderNodeVolumePrincipled")
pv.inputs["Density"].default_value = 4.0
pv.inputs["Color"].default_value = (0.6, 0.6, 0.6, 1)
pv.inputs["Absorption Color"].default_value = (0.0, 0.0, 0.0, 1)
pv.inputs["Anisotropy"].default_value = 0.2
pv.inputs["Emission Color"].default_value = (1.0, 0.45, 0.15, 1)
attr = nt.nodes.new("ShaderNodeAttribute")
attr.attribute_name = "flame"
mul = nt.nodes.new("ShaderNodeMath")
mul.operation = "MULTIPLY"
mul.inputs[1].default_value = 1.5
nt.links.new(attr.outputs["Fac"], mul.inputs[0])
nt.links.new(mul.outputs[0], pv.inputs["Emission Strength"])
pv.inputs["Blackbody Intensity"].default_value = 1.0
pv.inputs["Blackbody Tint"].default_value = (1.0, 0.9, 0.8, 1)
pv.inputs["Temperature"].default_value = 1000.0
pv.inputs["Temperature Attribute"].default_value = "temperature"
nt.links.new(pv.outputs[0], out.inputs["Volume"])
mat.cycles.volume_interpolation = "LINEAR"
vol.data.materials.append(mat)

cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
cam.data.lens = 50
cam.data.clip_start, cam.data.clip_end = 1e-3, 1e6
scene.collection.objects.link(cam)
cam.location = (2.5, -4.0, 1.2)
cam.rotation_euler = (-cam.location).to_track_quat("-Z", "Y").to_euler()
scene.camera = cam

bpy.ops.wm.save_as_mainfile(filepath=blend)
scene.render.filepath = exr
bpy.ops.render.render(write_still=True)
