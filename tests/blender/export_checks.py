# export_checks.py - tests/blender_fire_test.sh's checks of what the exporter does with a
# mesh whose material is a volume only: an axis-aligned box becomes a homogeneous medium in
# that box (emission per unit length from a constant Emission Strength); a sphere becomes a
# mesh with an interface material bounding its medium (medium_inside), and brume renders
# the export. Exits 1 on a wrong answer.
#
#   blender -b --factory-startup --python export_checks.py -- EXPORTER.py OUT_DIR BRUME
#
#   blender -b --factory-startup --python export_checks.py -- EXPORTER.py OUT_DIR
import importlib.util
import json
import subprocess
import sys

import bpy

exporter, out_dir, brume = sys.argv[sys.argv.index("--") + 1:][:3]
spec = importlib.util.spec_from_file_location("brume_export", exporter)
be = importlib.util.module_from_spec(spec)
spec.loader.exec_module(be)

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
scene.collection.objects.link(cam)
cam.location = (0, -6, 0)
cam.rotation_euler = (1.5707963, 0, 0)
scene.camera = cam


def volume_material(name, strength):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    pv = nt.nodes.new("ShaderNodeVolumePrincipled")
    pv.inputs["Density"].default_value = 2.0
    pv.inputs["Emission Strength"].default_value = strength
    pv.inputs["Emission Color"].default_value = (1.0, 0.5, 0.25, 1)
    nt.links.new(pv.outputs[0], out.inputs["Volume"])
    return mat


bpy.ops.mesh.primitive_cube_add(size=2, location=(0.5, 0, 0))
box = bpy.context.active_object
box.name = "fogbox"
box.scale = (1, 2, 0.5)
box.data.materials.append(volume_material("fog", 3.0))
bpy.context.view_layer.update()
path = out_dir + "/box.json"
be.export(scene, path)
m = json.load(open(path))["media"][0]
ok = m["density"] == {"type": "constant", "value": 1, "bounds": [[-0.5, -2.0, -0.5], [1.5, 2.0, 0.5]]}
ok &= m["emission"] == [3.0, 1.5, 0.75] and m["emission_units"] == "radiance_per_length"
print("box medium:", json.dumps(m["density"]), m.get("emission"), "ok" if ok else "WRONG")

bpy.ops.mesh.primitive_uv_sphere_add(radius=1, location=(0, 3, 0))
ball = bpy.context.active_object
ball.name = "fogball"
ball.data.materials.append(volume_material("fog2", 0.5))
bpy.context.view_layer.update()
path = out_dir + "/ball.json"
be.export(scene, path)
desc = json.load(open(path))
ms = {m["name"]: m for m in desc["media"]}
surf = [x for x in desc["surfaces"] if x.get("name") == "fogball"]
good = len(surf) == 1 and surf[0]["material"] == {"type": "interface"} and surf[0]["medium_inside"] == "fogball"
good &= "fogball" in ms and ms["fogball"]["density"]["type"] == "constant"
b = ms["fogball"]["density"]["bounds"] if "fogball" in ms else [[0] * 3, [0] * 3]
good &= all(b[0][i] < c - 0.99 and b[1][i] > c + 0.99 for i, c in enumerate((0, 3, 0)))
print("sphere medium:", "bounded by the mesh" if good else "WRONG", json.dumps(surf[0] if surf else None)[:200])
ok &= good
rc = subprocess.call([brume, "render", "--spp", "4", "--width", "16", "--height", "12", "-q", "-o",
                      out_dir + "/ball.png", path])
print("brume renders it:", "ok" if rc == 0 else "FAILED (%d)" % rc)
ok &= rc == 0
sys.exit(0 if ok else 1)
