# brume_export.py - exports the open Blender scene to a brume scene file (docs/production.md,
# "Blender"), and optionally runs brume on it:
#
#   blender -b file.blend --python python/blender/brume_export.py -- OUT.json
#   blender -b file.blend --python python/blender/brume_export.py -- OUT.json brume render -o out.png
#
# The first argument after "--" is the scene file to write; what follows, when given, is the
# command run after the export with OUT.json appended (a `brume render` with its flags).
# What is exported, and how each Blender setting maps to brume's units, is listed in
# docs/production.md; anything it cannot map is an error naming the object and the setting,
# never a silent approximation.
import json
import math
import os
import re
import subprocess
import sys

import bpy
from mathutils import Vector


class ExportError(Exception):
    pass


def vec(v):
    return [float(x) for x in v]


def camera_json(scene):
    cam = scene.camera
    if cam is None:
        raise ExportError("the scene has no camera")
    data = cam.data
    if data.type != "PERSP":
        raise ExportError("camera %s: type %s (brume has a perspective camera)" % (cam.name, data.type))
    m = cam.matrix_world
    pos = m.to_translation()
    rot = m.to_3x3().normalized()
    fwd = -rot.col[2]
    up = rot.col[1]
    w = scene.render.resolution_x * scene.render.pixel_aspect_x
    h = scene.render.resolution_y * scene.render.pixel_aspect_y
    # Blender's field of view spans the sensor's fit axis (AUTO: the longer image side)
    fit = data.sensor_fit
    if fit == "AUTO":
        fit = "HORIZONTAL" if w >= h else "VERTICAL"
    sensor = data.sensor_height if fit == "VERTICAL" and data.sensor_fit != "AUTO" else data.sensor_width
    half = 0.5 * sensor / data.lens  # tan of half the angle along the fit axis
    tan_v = half if fit == "VERTICAL" else half * h / w
    c = {
        "position": vec(pos),
        "look_at": vec(pos + fwd),
        "up": vec(up),
        "fov": math.degrees(2.0 * math.atan(tan_v)),
    }
    if data.dof.use_dof:
        # thin lens: aperture radius = focal length / (2 f-number), millimetres to metres
        c["aperture_radius"] = data.lens / (2.0 * data.dof.aperture_fstop) / 1000.0 * scene.unit_settings.scale_length
        dist = data.dof.focus_distance
        if data.dof.focus_object is not None:
            dist = (data.dof.focus_object.matrix_world.to_translation() - pos).dot(fwd)
        c["focus_distance"] = dist
    return c


def light_json(obj):
    d = obj.data
    m = obj.matrix_world
    color = Vector(d.color)
    axis = -(m.to_3x3().normalized().col[2])  # a Blender light shines along its -Z
    if d.type == "SUN":
        return {"type": "distant", "direction": vec(axis), "irradiance": vec(color * d.energy),
                "angular_radius": math.degrees(0.5 * d.angle)}
    if d.type == "POINT":
        if d.shadow_soft_size > 0:
            raise ExportError("light %s: a point light of radius %g (brume's point lights have none; use 0)" %
                              (obj.name, d.shadow_soft_size))
        # Cycles: a point light of power P (W) has intensity P / (4 pi) W/sr
        return {"type": "point", "position": vec(m.to_translation()), "intensity": vec(color * d.energy / (4 * math.pi))}
    if d.type == "SPOT":
        if d.shadow_soft_size > 0 or d.spot_blend > 0:
            raise ExportError("light %s: spot radius or blend (brume's spot is a point with a smooth cone: set both 0)"
                              % obj.name)
        # Cycles' spot of power P has the intensity of the point light of power P inside its cone
        cone = math.degrees(0.5 * d.spot_size)
        return {"type": "spot", "position": vec(m.to_translation()), "direction": vec(axis),
                "intensity": vec(color * d.energy / (4 * math.pi)), "cone_angle": cone, "falloff_start": cone}
    if d.type == "AREA":
        if d.shape != "DISK":
            raise ExportError("light %s: area shape %s (brume has disk area lights)" % (obj.name, d.shape))
        r = 0.5 * d.size * m.to_scale()[0]
        # one-sided Lambertian emitter of power P and area A: radiance P / (pi A)
        return {"type": "disk", "position": vec(m.to_translation()), "direction": vec(axis), "radius": r,
                "radiance": vec(color * d.energy / (math.pi * math.pi * r * r))}
    raise ExportError("light %s: type %s" % (obj.name, d.type))


def world_json(scene):
    world = scene.world
    if world is None:
        return None
    if not world.use_nodes:
        return vec(world.color)
    out = next((n for n in world.node_tree.nodes if n.type == "OUTPUT_WORLD"), None)
    if out is None or not out.inputs["Surface"].is_linked:
        return None
    bg = out.inputs["Surface"].links[0].from_node
    if bg.type != "BACKGROUND":
        raise ExportError("world: surface node %s (brume reads a Background node)" % bg.type)
    strength = bg.inputs["Strength"].default_value
    col = bg.inputs["Color"]
    if not col.is_linked:
        return vec(Vector(col.default_value[:3]) * strength)
    env = col.links[0].from_node
    if env.type != "TEX_ENVIRONMENT" or env.projection != "EQUIRECTANGULAR" or env.inputs["Vector"].is_linked:
        raise ExportError("world: color from %s (brume reads a constant or an equirectangular image)" % env.type)
    return {"file": bpy.path.abspath(env.image.filepath), "scale": strength, "up": [0, 0, 1]}


def principled_volume(obj, mat):
    if mat is None or not mat.use_nodes:
        raise ExportError("volume %s: no node material" % obj.name)
    out = next((n for n in mat.node_tree.nodes if n.type == "OUTPUT_MATERIAL"), None)
    if out is None or not out.inputs["Volume"].is_linked:
        raise ExportError("volume %s: nothing in the material's Volume output" % obj.name)
    pv = out.inputs["Volume"].links[0].from_node
    if pv.type != "PRINCIPLED_VOLUME":
        raise ExportError("volume %s: volume shader %s (brume maps a Principled Volume)" % (obj.name, pv.type))
    for name in ("Color", "Density", "Absorption Color", "Anisotropy", "Emission Color", "Blackbody Intensity",
                 "Blackbody Tint", "Temperature"):
        if pv.inputs[name].is_linked:
            raise ExportError("volume %s: Principled Volume input %s is linked (brume maps constants)" % (obj.name, name))
    return pv


def strength_source(obj, socket):
    """Emission Strength: a constant, or an Attribute node's Fac (a grid), alone or times a
    constant through a Math node's Multiply: (grid name or None, factor)."""
    if not socket.is_linked:
        return None, socket.default_value
    node, factor = socket.links[0].from_node, 1.0
    if node.type == "MATH" and node.operation == "MULTIPLY" and not node.use_clamp:
        a, b = node.inputs[0], node.inputs[1]
        linked = [i for i in (a, b) if i.is_linked]
        if len(linked) == 1:
            factor = (b if linked[0] is a else a).default_value
            node = linked[0].links[0].from_node
            socket = linked[0]
    if node.type == "ATTRIBUTE" and node.attribute_type == "GEOMETRY" and socket.links[0].from_socket.name == "Fac":
        return node.attribute_name, factor
    raise ExportError("volume %s: Principled Volume Emission Strength from %s (brume maps a constant or an Attribute "
                      "node's Fac, optionally times a constant)" % (obj.name, node.type))


def emission_keys(obj, pv, grids, fluid=None):
    """The medium's emission keys (docs/production.md, "Emission"): Cycles emits per unit length
    wherever the volume is, independent of density: brume's "radiance_per_length" units."""
    keys = {}
    color = Vector(pv.inputs["Emission Color"].default_value[:3])
    grid, factor = strength_source(obj, pv.inputs["Emission Strength"])
    if grid is not None:
        if fluid is not None and grid in fluid:
            grid = fluid[grid]
        if grid not in grids:
            raise ExportError("volume %s: Emission Strength from the attribute %r, which is no grid of the file" %
                              (obj.name, grid))
        if factor > 0 and color.length > 0:
            keys["emission_field"] = {"grid": grid, "color": vec(color * factor)}
    elif factor > 0 and color.length > 0:
        keys["emission"] = vec(color * factor)
    intensity = pv.inputs["Blackbody Intensity"].default_value
    if intensity > 0:
        tattr = pv.inputs["Temperature Attribute"].default_value
        tsock = pv.inputs["Temperature"].default_value
        bb = {"model": "blender", "intensity": min(intensity, 1.0),
              "tint": vec(pv.inputs["Blackbody Tint"].default_value[:3]), "temperature_scale": tsock}
        if intensity > 1:
            raise ExportError("volume %s: Blackbody Intensity %g (brume maps 0 to 1)" % (obj.name, intensity))
        if fluid is not None and tattr == "temperature":
            # Cycles' temperature of a smoke domain: flame > 0.01 maps to ignition + flame
            # (max - ignition), in thousands of kelvin, else 0 (Blender's fluid RNA)
            d = fluid["domain"]
            span = d.flame_max_temp - d.flame_ignition
            keys["temperature"] = {"grid": fluid["flame"]}
            bb["temperature_scale"] = tsock * span
            bb["temperature_offset"] = -d.flame_ignition / span
            bb["cutoff"] = tsock * (d.flame_ignition + 0.01 * span)
        elif tattr in grids:
            keys["temperature"] = {"grid": tattr}
        else:
            raise ExportError("volume %s: Blackbody Intensity without a temperature grid (Temperature Attribute %r is "
                              "no grid of the file; brume's blackbody reads a grid)" % (obj.name, tattr))
        keys["blackbody"] = bb
    if keys:
        keys["emission_units"] = "radiance_per_length"
    cattr = pv.inputs["Color Attribute"].default_value if "Color Attribute" in pv.inputs else ""
    if cattr and cattr in grids:
        raise ExportError("volume %s: Color Attribute %r (a colour grid scaling the scattering colour is not mapped)" %
                          (obj.name, cattr))
    return keys


def medium_coefficients(pv):
    # Cycles 3.4's Principled Volume (svm_node_principled_volume): sigma_s = D c and
    # sigma_a = D (1 - c) (1 - sqrt(a)) per unit of the density attribute, with D the Density
    # input, c the Color and a the Absorption Color (Cycles takes the square root of a;
    # without it the test's blue mean was 0.32 % darker than Cycles', 5 standard errors)
    D = pv.inputs["Density"].default_value
    c = Vector(pv.inputs["Color"].default_value[:3])
    a = Vector([math.sqrt(max(x, 0.0)) for x in pv.inputs["Absorption Color"].default_value[:3]])
    sigma_s = [D * c[i] for i in range(3)]
    sigma_a = [D * max(1 - c[i], 0) * max(1 - a[i], 0) for i in range(3)]
    return {"sigma_a": sigma_a, "sigma_s": sigma_s, "phase": {"type": "hg", "g": pv.inputs["Anisotropy"].default_value}}


def volume_json(obj, scene):
    data = obj.data
    pv = principled_volume(obj, obj.active_material)
    path = bpy.path.abspath(data.filepath)
    data.grids.load()
    attr = pv.inputs["Density Attribute"].default_value if "Density Attribute" in pv.inputs else pv.density_attribute
    grid = data.grids.get(attr)
    if grid is None:
        raise ExportError("volume %s: no grid %r in %s" % (obj.name, attr, path))
    density = {"type": "grid", "file": path, "grid": attr, "filter": "trilinear"}
    if data.is_sequence:
        # Blender: the file of scene frame f is number f - frame_start + 1 + frame_offset
        head, tail = os.path.split(path)
        runs = list(re.finditer(r"\d+", tail))
        if not runs:
            raise ExportError("volume %s: a sequence whose file name has no frame number" % obj.name)
        r = runs[-1]
        density["file"] = os.path.join(head, tail[:r.start()] + "#" * len(r.group()) + tail[r.end():])
        density["frame_offset"] = 1 - data.frame_start + data.frame_offset
        density["beyond"] = {"NONE": "refuse", "CLIP": "hold", "EXTEND": "hold", "REPEAT": "loop",
                             "PING_PONG": "refuse"}[data.sequence_mode]
    # Placement: the object's matrix after the file's own; Cycles 3.4 centres voxel i's value
    # on the index cell [i, i + 1], OpenVDB and brume on i (docs/validation.md): moving the
    # grid by half a voxel renders what Cycles renders.
    loc, rot, scl = obj.matrix_world.decompose()
    half = obj.matrix_world.to_3x3() @ (grid.matrix_object.to_3x3() @ Vector((0.5, 0.5, 0.5)))
    axis, angle = rot.to_axis_angle()
    density["transform"] = {"translate": vec(loc + half), "rotate": {"axis": vec(axis), "angle": math.degrees(angle)},
                            "scale": vec(scl)}
    m = {"name": obj.name, "density": density}
    m.update(medium_coefficients(pv))
    m.update(emission_keys(obj, pv, [g.name for g in data.grids]))
    return m


def volume_material(obj):
    """The mesh's material when its output has a Volume and no Surface (a volume-only
    material), else None."""
    mat = obj.active_material
    out = next((n for n in mat.node_tree.nodes if n.type == "OUTPUT_MATERIAL"), None) if mat and mat.use_nodes else None
    if out is None or not out.inputs["Volume"].is_linked:
        return None
    if out.inputs["Surface"].is_linked:
        raise ExportError("mesh %s: material %s has both a Surface and a Volume (brume maps one of them)" %
                          (obj.name, mat.name))
    return mat


def fluid_domain(obj):
    return next((m.domain_settings for m in obj.modifiers if m.type == "FLUID" and m.fluid_type == "DOMAIN"), None)


def fluid_json(obj, scene, d):
    """A smoke/fire domain with a Principled Volume: the domain's cached OpenVDB frame at the
    scene's current frame, placed as Cycles places a domain's voxels (over the domain mesh's
    bounding box, then the object's matrix), its Cycles attributes mapped to the cache's
    grids. Not checked against a Cycles render: Debian's Blender 3.4 does not bake here."""
    if d.domain_type != "GAS":
        raise ExportError("mesh %s: a %s fluid domain (brume exports smoke and fire, GAS, domains)" %
                          (obj.name, d.domain_type))
    if d.cache_data_format != "OPENVDB":
        raise ExportError("mesh %s: fluid cache format %s (brume reads the OpenVDB cache)" % (obj.name,
                                                                                           d.cache_data_format))
    if d.use_adaptive_domain:
        raise ExportError("mesh %s: an adaptive fluid domain (its cache moves within the domain; not mapped)" % obj.name)
    path = os.path.join(bpy.path.abspath(d.cache_directory), "data", "fluid_data_%04d.vdb" % scene.frame_current)
    if not os.path.isfile(path):
        raise ExportError("mesh %s: no baked fluid cache for frame %d (%s): bake the domain first" %
                          (obj.name, scene.frame_current, path))
    vol = bpy.data.volumes.new("brume_export_probe")
    try:
        vol.filepath = path
        vol.grids.load()
        names = [g.name for g in vol.grids]
        grid = vol.grids.get("density")
        if grid is None:
            raise ExportError("mesh %s: the fluid cache %s has no density grid" % (obj.name, path))
        to_index = grid.matrix_object.inverted()  # the cache's own placement, undone
    finally:
        bpy.data.volumes.remove(vol)
    pv = principled_volume(obj, obj.active_material)
    attr = pv.inputs["Density Attribute"].default_value
    if attr != "density":
        raise ExportError("mesh %s: Density Attribute %r (a smoke domain's density is its density grid)" %
                          (obj.name, attr))
    # Cycles spreads the domain's res voxels over the domain mesh's bounding box, voxel i's
    # value at the centre of the i-th of res cells: object p = p0 + (i + 1/2) (p1 - p0) / res
    corners = [Vector(c) for c in obj.bound_box]
    p0 = Vector([min(c[i] for c in corners) for i in range(3)])
    p1 = Vector([max(c[i] for c in corners) for i in range(3)])
    res = d.domain_resolution
    cell = Vector([(p1[i] - p0[i]) / res[i] for i in range(3)])
    lin = to_index.to_3x3()
    if any(abs(lin[r][c]) > 1e-9 * abs(lin[r][r]) for r in range(3) for c in range(3) if r != c):
        raise ExportError("mesh %s: the fluid cache %s is not axis-aligned in its own frame" % (obj.name, path))
    loc, rot, scl = obj.matrix_world.decompose()
    axis, angle = rot.to_axis_angle()
    # the file's point x is index to_index x; object p0 + (index + 1/2) cell; then the object's
    # matrix: scale by its scale times cell / (the file's voxel size), rotate, translate
    s_file = Vector([lin[i][i] for i in range(3)])
    t_file = to_index.to_translation()
    o_obj = Vector([p0[i] + (t_file[i] + 0.5) * cell[i] for i in range(3)])
    density = {"type": "grid", "file": path, "grid": "density", "filter": "trilinear",
               "transform": {"scale": [scl[i] * cell[i] * s_file[i] for i in range(3)],
                             "rotate": {"axis": vec(axis), "angle": math.degrees(angle)},
                             "translate": vec(loc + rot @ Vector([scl[i] * o_obj[i] for i in range(3)]))}}
    m = {"name": obj.name, "density": density}
    m.update(medium_coefficients(pv))
    # Cycles' smoke attributes: "flame" is the flame grid, "temperature" the flame mapped to
    # kelvin / 1000 (emission_keys), "density" the density
    m.update(emission_keys(obj, pv, names, fluid={"domain": d, "flame": "flame"}))
    return m


def volume_mesh_json(obj, mat, folder):
    """A mesh whose material is a volume only: a homogeneous medium filling the mesh, as
    Cycles fills it, emitting per unit length inside it. An axis-aligned box in world space
    is the medium's own box (a free medium: CPU and GPU); any other closed mesh bounds the
    medium (docs/surfaces.md, "Bounded media": the mesh, with an interface material, names it
    as medium_inside; path and single on the CPU). (medium, surface or None)."""
    pv = principled_volume(obj, mat)
    if pv.inputs["Emission Strength"].is_linked or pv.inputs["Blackbody Intensity"].default_value > 0:
        raise ExportError("mesh %s: emission from an attribute or a blackbody in a mesh's volume (no grid to read)" %
                          obj.name)
    world = [obj.matrix_world @ v.co for v in obj.data.vertices]
    if not world:
        raise ExportError("mesh %s: a volume material on a mesh without vertices" % obj.name)
    lo = Vector([min(p[i] for p in world) for i in range(3)])
    hi = Vector([max(p[i] for p in world) for i in range(3)])
    size = (hi - lo).length
    corner = lambda p: all(min(abs(p[i] - lo[i]), abs(p[i] - hi[i])) <= 1e-6 * size for i in range(3))
    is_box = len(world) == 8 and all(corner(p) for p in world) and \
        len({tuple(round(x, 9) for x in p) for p in world}) == 8
    # the density's box: the mesh's, a little larger when the mesh bounds the medium
    pad = 0.0 if is_box else 1e-4 * size
    m = {"name": obj.name, "density": {"type": "constant", "value": 1,
                                       "bounds": [vec(lo - Vector((pad,) * 3)), vec(hi + Vector((pad,) * 3))]}}
    m.update(medium_coefficients(pv))
    m.update(emission_keys(obj, pv, []))
    if is_box:
        return m, None
    surf = mesh_json(obj, folder, material=False)
    surf["material"] = {"type": "interface"}
    surf["medium_inside"] = obj.name
    return m, surf


def mesh_json(obj, folder, material=True):
    path = os.path.join(folder, "%s.glb" % re.sub(r"[^A-Za-z0-9_.-]", "_", obj.name))
    bpy.ops.object.select_all(action="DESELECT")
    obj.select_set(True)
    bpy.ops.export_scene.gltf(filepath=path, use_selection=True, export_format="GLB", export_apply=True)
    albedo = [0.8, 0.8, 0.8]  # Cycles renders a mesh without material as a 0.8 grey diffuse
    mat = obj.active_material
    if mat is not None and material:
        out = next((n for n in mat.node_tree.nodes if n.type == "OUTPUT_MATERIAL"), None) if mat.use_nodes else None
        bsdf = out.inputs["Surface"].links[0].from_node if out and out.inputs["Surface"].is_linked else None
        # brume's surfaces are Lambertian: a Diffuse BSDF of roughness 0 maps exactly (a
        # Principled BSDF has a specular lobe brume does not have)
        if bsdf is None or bsdf.type != "BSDF_DIFFUSE" or bsdf.inputs["Color"].is_linked or \
                bsdf.inputs["Roughness"].default_value != 0 or bsdf.inputs["Normal"].is_linked:
            raise ExportError("mesh %s: material %s (brume maps a Diffuse BSDF of roughness 0)" % (obj.name, mat.name))
        albedo = vec(bsdf.inputs["Color"].default_value[:3])
    # glTF is y-up: the exporter turned Blender's z-up; turn it back
    return {"type": "mesh", "name": obj.name, "file": path, "material": {"albedo": albedo},
            "transform": {"rotate": {"axis": [1, 0, 0], "angle": 90}}}


def export(scene, out_path):
    folder = os.path.dirname(os.path.abspath(out_path))
    r = scene.render
    desc = {
        "comment": "exported from Blender %s by python/blender/brume_export.py" % bpy.app.version_string,
        "camera": camera_json(scene),
        "lights": [],
        "media": [],
        "surfaces": [],
        "render": {"width": r.resolution_x * r.resolution_percentage // 100,
                   "height": r.resolution_y * r.resolution_percentage // 100,
                   "spp": scene.cycles.samples if hasattr(scene, "cycles") else 16,
                   "fps": r.fps / r.fps_base, "method": "path", "max_depth": 1024,
                   # brume has no Blackman-Harris filter: a box of Cycles' filter width stands
                   # for it (the documented approximation of docs/production.md)
                   "filter": {"type": "box", "width": scene.cycles.filter_width if hasattr(scene, "cycles") else 1.0}},
    }
    bg = world_json(scene)
    if bg is not None:
        desc["background"] = bg
    for obj in scene.objects:
        if obj.hide_render:
            continue
        if obj.type == "LIGHT":
            desc["lights"].append(light_json(obj))
        elif obj.type == "VOLUME":
            desc["media"].append(volume_json(obj, scene))
        elif obj.type == "MESH" and fluid_domain(obj) is not None:
            desc["media"].append(fluid_json(obj, scene, fluid_domain(obj)))
        elif obj.type == "MESH" and volume_material(obj) is not None:
            medium, surf = volume_mesh_json(obj, volume_material(obj), folder)
            desc["media"].append(medium)
            if surf is not None:
                desc["surfaces"].append(surf)
        elif obj.type == "MESH":
            desc["surfaces"].append(mesh_json(obj, folder))
        elif obj.type not in ("CAMERA", "EMPTY"):
            raise ExportError("object %s: type %s is not exported" % (obj.name, obj.type))
    with open(out_path, "w") as f:
        json.dump(desc, f, indent=1)
    return scene.frame_start, scene.frame_end


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if not argv:
        sys.exit("brume_export.py: usage: blender -b FILE.blend --python brume_export.py -- OUT.json [brume render ...]")
    try:
        first, last = export(bpy.context.scene, argv[0])
    except ExportError as e:
        sys.exit("brume_export.py: %s: %s" % (bpy.data.filepath or "<unsaved>", e))
    print("brume_export.py: wrote %s (frames %d-%d)" % (argv[0], first, last))
    if len(argv) > 1:
        sys.exit(subprocess.call(argv[1:] + [argv[0]]))


if __name__ == "__main__":
    main()
