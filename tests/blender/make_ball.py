# make_ball.py - tests/blender_fire_test.sh's second scene: a sphere mesh whose material is
# a Principled Volume alone (Density 1.5, a colour, Emission Strength 0.4 x an Emission
# Color), under a dim sky, saved, then rendered with Cycles to an EXR. The exporter makes it
# a mesh bounding its medium (docs/production.md), which brume renders.
#
#   blender -b --factory-startup --python make_ball.py -- OUT.blend CYCLES.exr
import sys

import addon_utils
import bpy

args = sys.argv[sys.argv.index("--") + 1:]
blend, exr = args[:2]
addon_utils.enable("cycles", default_set=True)
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.engine = "CYCLES"
cy = scene.cycles
cy.device = "CPU"; cy.samples = 256; cy.use_adaptive_sampling = False; cy.use_denoising = False; cy.seed = 7
cy.max_bounces = cy.volume_bounces = cy.transparent_max_bounces = cy.diffuse_bounces = 1024
cy.sample_clamp_direct = cy.sample_clamp_indirect = 0.0
cy.filter_width = 1.0
cy.volume_step_rate = 0.05
cy.volume_max_steps = 4096
scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 40, 40, 100
scene.view_settings.view_transform = "Standard"
scene.render.image_settings.file_format = "OPEN_EXR"; scene.render.image_settings.color_depth = "32"
world = bpy.data.worlds.new("sky"); world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.2, 0.3, 0.5, 1)
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.3
scene.world = world
bpy.ops.mesh.primitive_uv_sphere_add(radius=1, location=(0, 0, 0), segments=48, ring_count=24)
ball = bpy.context.active_object
ball.name = "fogball"
mat = bpy.data.materials.new("fog"); mat.use_nodes = True; nt = mat.node_tree
for n in list(nt.nodes): nt.nodes.remove(n)
out = nt.nodes.new("ShaderNodeOutputMaterial"); pv = nt.nodes.new("ShaderNodeVolumePrincipled")
pv.inputs["Density"].default_value = 1.5
pv.inputs["Color"].default_value = (0.7, 0.6, 0.5, 1)
pv.inputs["Emission Strength"].default_value = 0.4
pv.inputs["Emission Color"].default_value = (1.0, 0.5, 0.2, 1)
nt.links.new(pv.outputs[0], out.inputs["Volume"])
ball.data.materials.append(mat)
cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam")); cam.data.lens = 50
scene.collection.objects.link(cam); cam.location = (2.5, -4.0, 1.2)
cam.rotation_euler = (-cam.location).to_track_quat("-Z", "Y").to_euler(); scene.camera = cam
bpy.ops.wm.save_as_mainfile(filepath=blend)
scene.render.filepath = exr
bpy.ops.render.render(write_still=True)
