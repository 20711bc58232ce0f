#!/usr/bin/env python3
"""gen_null_test.py - writes the NULL-argument test from include/brume.h, so that it
cannot drift from the header: every public function is called once with each pointer
parameter NULL (the others valid). A function returning brume_status must return
BRUME_ERROR_INVALID_ARGUMENT and set its out pointers to NULL; one returning a pointer must
return NULL; the others must simply not crash. Parameters the header allows to be NULL are
listed in OPTIONAL below (a new optional one must be added here, on purpose).

usage: gen_null_test.py include/brume.h OUT.c"""
import re
import sys

# function -> parameters documented as "may be NULL" (NULL is a valid value there)
OPTIONAL = {
    "brume_context_set_error_callback": {"fn", "user"},
    "brume_scene_new": {"name"},
    "brume_scene_load": {"src", "opts"},  # src NULL is the default scene
    "brume_scene_text": {"src", "opts"},  # src NULL is the default scene
    "brume_scene_check_frames": {"src", "opts"},
    "brume_scene_frame_camera": {"media"},
    "brume_image_write": {"opts"},
    "brume_image_encode_png": {"opts"},  # issue-15's, like brume_image_write
    "brume_scene_set_background_image": {"up"},
    "brume_scene_set_background_equal_area": {"world_from_map"},
    "brume_density_new_array": {"release", "user"},
    "brume_density_load": {"opts"},
    "brume_density_load_rgb": {"opts"},
    "brume_scene_set_camera_medium": {"name"},  # NULL clears it
    "brume_grid_file_list": {"opts"},
    "brume_grid_sequence_extent": {"opts"},
    "brume_grid_gen_upres": {"opts"},
    "brume_grid_convert_vdb_to_nvdb": {"grid"},  # NULL: every grid
    "brume_density_load_velocity": {"opts"},
    "brume_scene_set_medium_velocity": {"map"},  # NULL = the identity
    "brume_scene_set_medium_temperature": {"bb"},
    "brume_density_new_blobs": {"velocity"},
    "brume_scene_add_medium": {"phase"},
    "brume_scene_add_sphere": {"transform", "material", "name"},
    "brume_scene_add_box": {"transform", "material", "name"},
    "brume_scene_add_quad": {"transform", "material", "name"},
    "brume_scene_add_plane": {"transform", "material", "name"},
    "brume_scene_add_mesh": {"transform", "material", "name"},
    "brume_scene_add_mesh_file": {"transform", "material", "name"},
    "brume_scene_set_surface_media": {"inside", "outside"},  # NULL: no medium on that side
    "brume_output_check": {"scene"},
    "brume_image_compare_region": {"mask"},  # NULL: the whole frame
    "brume_image_diff_png": {"mask"},
    "brume_image_sheet_png": {"title", "col_labels", "row_labels", "captions", "opts"},
    "brume_image_check_values": {"name"},
    "brume_stam_figure_png": {"max_z"},
}
# functions whose result is not an operation's status or a new object: they must only not
# crash (a string that is never NULL, the context's own last status)
NO_RESULT_CHECK = {"brume_context_last_error", "brume_context_last_status", "brume_status_string", "brume_version"}
# the context is optional everywhere but in its own functions: a NULL ctx only means that
# the call reports through its status alone (brume.h, ERRORS)
CTX_OPTIONAL = True


def strip_comments(text):
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    return re.sub(r"//[^\n]*", " ", text)


def prototypes(header):
    text = strip_comments(open(header).read())
    text = re.sub(r"#[^\n]*", " ", text)
    # typedef'd function pointer types are not functions
    fnptr_types = set(re.findall(r"typedef\s+[^;]*?\(\s*\*\s*(\w+)\s*\)", text))
    out = []
    for m in re.finditer(r"([A-Za-z_][\w \t\*]*?)\b(brume_\w+)\s*\(([^()]*)\)\s*;", text):
        ret, name, params = m.group(1).strip(), m.group(2), m.group(3).strip()
        if ret.startswith("typedef") or "typedef" in ret:
            continue
        ps = []
        if params and params != "void":
            for p in params.split(","):
                p = " ".join(p.split())
                pm = re.match(r"(.*?)(\w+)\s*(\[[^\]]*\])?$", p)
                ptype, pname, arr = pm.group(1).strip(), pm.group(2), pm.group(3)
                pointer = "*" in ptype or arr is not None
                if arr is not None:
                    ptype = ptype + " *"
                ps.append((ptype, pname, pointer, ptype.strip() in fnptr_types))
        out.append((ret, name, ps))
    return out


def value(ptype, pname, fname):
    """A valid C expression of type ptype."""
    t = ptype.replace(" ", "")
    base = t.replace("const", "")
    if base == "brume_context*":
        return "ctx"
    if base == "brume_scene*":
        return "(%s)scene_c" % ptype if "const" in t else "scene_u"
    if base == "brume_image*":
        return "image"
    if base == "brume_density*":
        return "density"
    if base == "brume_phase*":
        return "phase"
    if t == "brume_phase*const*":  # the lobes of a mixture (an out pointer is brume_phase **)
        return "lobes"
    if base == "brume_render_job*":
        return "job"
    if base.endswith("**"):
        return "(%s)out_ptr" % ptype
    if base == "char*":
        return {"key": "\"blasi.r\"", "value": "\"0.5\"", "text": "\"{}\"", "name": "\"isotropic\""}.get(
            pname, "\"brume-null-test\"")
    if base.endswith("*"):
        return "(%s)(void *)blob" % ptype
    if base in ("double",):
        return "1.0"
    if base in ("int", "long", "size_t", "uint64_t", "unsigned"):
        return "1"
    if base == "bool":
        return "false"
    return "(%s)0" % ptype  # enums


def main():
    header, out_path = sys.argv[1], sys.argv[2]
    protos = prototypes(header)
    names = {p[1] for p in protos}
    lines = []
    w = lines.append
    w("/* null_test.c - generated by tests/gen_null_test.py from include/brume.h; do not edit. */")
    w("#include <stdio.h>")
    w("#include <stdlib.h>")
    w("#include <string.h>")
    w("#include \"brume.h\"")
    w("")
    w("static int failures;")
    w("static void check(bool ok, const char *what)")
    w("{")
    w("    if (!ok) {")
    w("        fprintf(stderr, \"FAIL %s\\n\", what);")
    w("        failures++;")
    w("    }")
    w("}")
    w("")
    w("int main(void)")
    w("{")
    w("    static _Alignas(64) unsigned char blob[1 << 16];")
    w("    void *out_ptr[3]; /* out arrays (brume_density_load_rgb) take three */")
    w("    brume_context *ctx = brume_context_new();")
    w("    brume_scene *scene_u = NULL, *scene_c = NULL;")
    w("    if (brume_scene_new(ctx, NULL, &scene_u) != BRUME_OK || brume_scene_new(ctx, NULL, &scene_c) != BRUME_OK ||")
    w("        brume_scene_commit(ctx, scene_c) != BRUME_OK) {")
    w("        fprintf(stderr, \"setup: %s\\n\", brume_context_last_error(ctx));")
    w("        return 1;")
    w("    }")
    w("    brume_image *image = NULL;")
    w("    if (brume_image_new(ctx, 2, 2, &image) != BRUME_OK) {")
    w("        fprintf(stderr, \"setup: %s\\n\", brume_context_last_error(ctx));")
    w("        return 1;")
    w("    }")
    w("    brume_density *density = NULL;")
    w("    brume_phase *phase = NULL, *lobes[1];")
    w("    const double box[6] = {-1, -1, -1, 1, 1, 1};")
    w("    if (brume_density_new_constant(ctx, 1.0, box, &density) != BRUME_OK ||")
    w("        brume_phase_new_hg(ctx, 0.5, &phase) != BRUME_OK || brume_phase_new_hg(ctx, 0.2, &lobes[0]) != BRUME_OK) {")
    w("        fprintf(stderr, \"setup: %s\\n\", brume_context_last_error(ctx));")
    w("        return 1;")
    w("    }")
    if "brume_render_begin" in names:
        w("    brume_render_job *job = NULL;")
        w("    if (brume_render_begin(ctx, scene_c, &job) != BRUME_OK) {")
        w("        fprintf(stderr, \"setup: %s\\n\", brume_context_last_error(ctx));")
        w("        return 1;")
        w("    }")
    ncalls = 0
    skip_release = {"brume_context_release", "brume_scene_release", "brume_image_release", "brume_density_release",
                    "brume_phase_release", "brume_render_job_release"}
    for ret, fname, params in protos:
        if any("va_list" in p[0] for p in params):
            continue  # no portable va_list to pass: tests/test_api_grids.c calls brume_vformat_message
        optional = OPTIONAL.get(fname, set())
        for i, (ptype, pname, pointer, fnptr) in enumerate(params):
            if not pointer or fnptr or pname in optional or ptype.replace(" ", "") == "void*":
                continue
            own = fname.startswith("brume_context_")
            if pname == "ctx" and CTX_OPTIONAL and not own:
                continue
            args = []
            for j, (qt, qn, qp, qf) in enumerate(params):
                if j == i:
                    args.append("NULL")
                elif qf:
                    args.append("NULL")
                else:
                    args.append(value(qt, qn, fname))
            call = "%s(%s)" % (fname, ", ".join(args))
            what = "%s with %s NULL" % (fname, pname)
            ncalls += 1
            has_out = any(qt.replace(" ", "").endswith("**") for j, (qt, qn, qp, qf) in enumerate(params) if j != i)
            w("    /* %s */" % what)
            if has_out:
                w("    out_ptr[0] = out_ptr[1] = out_ptr[2] = (void *)blob;")
            r = ret.replace(" ", "")
            if fname in NO_RESULT_CHECK:
                w("    (void)%s;" % call)
            elif r == "brume_status":
                w("    check(%s == BRUME_ERROR_INVALID_ARGUMENT, \"%s: status\");" % (call, what))
                w("    check(strstr(brume_context_last_error(ctx), \"NULL\") != NULL, \"%s: message\");" % what)
            elif r.endswith("*") and fname not in skip_release:
                w("    check(%s == NULL, \"%s: result\");" % (call, what))
            else:
                w("    (void)%s;" % call if r != "void" else "    %s;" % call)
            if has_out:
                w("    check(out_ptr[0] == NULL, \"%s: out pointer set to NULL\");" % what)
    w("    /* the objects given beside the NULL ones were left whole: they still work */")
    w("    brume_scene *s = NULL;")
    w("    check(brume_scene_new(ctx, NULL, &s) == BRUME_OK, \"scene after the calls\");")
    w("    check(brume_scene_add_medium(ctx, s, &(brume_medium){.sigma_s = {1, 1, 1}}, density, phase) == BRUME_OK,")
    w("          \"density and phase kept by the caller after failed calls\");")
    w("    check(brume_scene_medium_count(s) == 1 && brume_scene_medium_count(scene_u) == 0, \"media counts\");")
    w("    brume_scene_release(s);")
    if "brume_render_begin" in names:
        w("    brume_render_job_release(job);")
    w("    brume_phase_release(lobes[0]);")
    w("    brume_image_release(image);")
    w("    brume_scene_release(scene_u);")
    w("    brume_scene_release(scene_c);")
    w("    brume_context_release(ctx);")
    w("    printf(\"%%d calls with a NULL pointer, %%d failures\\n\", %d, failures);" % ncalls)
    w("    return failures != 0 || %d < 100;" % ncalls)
    w("}")
    open(out_path, "w").write("\n".join(lines) + "\n")


main()
