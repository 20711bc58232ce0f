# make_scene.py - tests/blender_test.sh's scene: a .blend with a camera, a sun, a grey sky and
# a VDB volume with a Principled Volume, saved, then rendered with Cycles to an EXR.
#
#   blender -b --factory-startup --python make_scene.py -- GRID.vdb OUT.blend CYCLES.exr SPP [WxH]
import math
import sys

import addon_utils
import bpy
from mathutils import Vector

args = sys.argv[sys.argv.index("--") + 1:]
vdb, blend, exr, spp = args[:4]
width, height = (int(v) for v in args[4].split("x")) if len(args) > 4 else (48, 36)
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
scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = width, height, 100
scene.view_settings.view_transform = "Standard"
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"

world = bpy.data.worlds.new("sky")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.2, 0.3, 0.5, 1)
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.5
scene.world = world

bpy.ops.object.volume_import(filepath=vdb, location=(0, 0, 0))
vol = bpy.context.active_object
vol.rotation_euler = (0.0, 0.0, 0.0)
vol.location = (0.2, 0.0, 0.1)
mat = bpy.data.materials.new("smoke")
mat.use_nodes = True
nt = mat.node_tree
for n in list(nt.nodes):
    nt.nodes.remove(n)
out = nt.nodes.new("ShaderNodeOutputMaterial")
pv = nt.nodes.new("ShaderNodeVolumePrincipled")
pv.inputs["Density"].default_value = 3.0
pv.inputs["Color"].default_value = (0.9, 0.8, 0.7, 1)
pv.inputs["Absorption Color"].default_value = (0.2, 0.2, 0.2, 1)
pv.inputs["Anisotropy"].default_value = 0.4
nt.links.new(pv.outputs[0], out.inputs["Volume"])
mat.cycles.volume_interpolation = "LINEAR"
vol.data.materials.append(mat)

# a ground under the cloud: a mesh exported as glTF, with a Diffuse BSDF
bpy.ops.mesh.primitive_plane_add(size=6, location=(0.3, 0.2, -1.2))
ground = bpy.context.active_object
ground.rotation_euler = (0.1, 0.0, 0.3)
gmat = bpy.data.materials.new("ground")
gmat.use_nodes = True
gn = gmat.node_tree
for n in list(gn.nodes):
    gn.nodes.remove(n)
gout = gn.nodes.new("ShaderNodeOutputMaterial")
diff = gn.nodes.new("ShaderNodeBsdfDiffuse")
diff.inputs["Color"].default_value = (0.5, 0.4, 0.3, 1)
gn.links.new(diff.outputs[0], gout.inputs["Surface"])
ground.data.materials.append(gmat)

sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", type="SUN"))
sun.data.energy = 3.0
sun.data.angle = 0.0
scene.collection.objects.link(sun)
sun.rotation_euler = Vector((0.5, 0.3, 0.8)).to_track_quat("Z", "Y").to_euler()

cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
cam.data.lens = 40
cam.data.clip_start, cam.data.clip_end = 1e-3, 1e6
scene.collection.objects.link(cam)
cam.location = (3.5, -5.0, 1.5)
cam.rotation_euler = (-cam.location).to_track_quat("-Z", "Y").to_euler()
scene.camera = cam

bpy.ops.wm.save_as_mainfile(filepath=blend)
scene.render.filepath = exr
bpy.ops.render.render(write_still=True)
