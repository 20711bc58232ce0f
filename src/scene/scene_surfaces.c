/* scene_surfaces.c - the "surfaces" array of a scene file: shapes, transforms, materials,
 * keyframes, each built with brume_scene_add_SHAPE. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/xform.h"
#include "io/json.h"
#include "io/mesh.h"
#include "scene/scene_build.h"
#include "scene/scene_json_texture.h"
#include "scene/scene_keys.h"
#include "scene/scene_material.h"
#include "scene/scene_surfaces.h"

static const double BIG = 1e30;

static brume_status jvec(const cJSON *j, jloc at, const char *key, int required, double out[3])
{
    vec3 v = v3(out[0], out[1], out[2]);
    brume_status st = json_vec3(j, at, key, required, &v);
    if (st == BRUME_OK)
        v3_to_array(v, out);
    return st;
}

/* The numbers of the array j[key] (at most SCENE_INLINE_MAX_VALUES, a multiple of 3) into
 * *out (malloc'd, the caller frees); *n their count. Integers in [0, imax) when imax > 0. */
static brume_status inline_numbers(const cJSON *j, jloc at, const char *key, double imax, double **out, int *n)
{
    *out = NULL;
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(j, key);
    int count = cJSON_IsArray(a) ? cJSON_GetArraySize(a) : -1;
    if (count < 3 || count % 3 != 0)
        return err_set(BRUME_ERROR_PARSE, "%s: %s.%s: expected an array of triples (3 n numbers, n >= 1)", at.file,
                       at.path, key);
    if (count > SCENE_INLINE_MAX_VALUES)
        return err_set(BRUME_ERROR_RANGE, "%s: %s.%s: %d numbers, over the %d an inline mesh may hold (a larger mesh "
                       "belongs in a file)", at.file, at.path, key, count, SCENE_INLINE_MAX_VALUES);
    double *v = malloc((size_t)count * sizeof *v);
    if (!v)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: %s.%s: out of memory", at.file, at.path, key);
    int i = 0;
    for (const cJSON *e = a->child; e; e = e->next, i++) {
        double x = cJSON_IsNumber(e) ? e->valuedouble : (double)NAN;
        bool ok = imax > 0 ? (x >= 0 && x < imax && x == floor(x)) : (x >= -BIG && x <= BIG);
        if (!ok) {
            free(v);
            if (imax > 0)
                return err_set(BRUME_ERROR_RANGE, "%s: %s.%s[%d]: expected a vertex index in [0, %g)", at.file,
                               at.path, key, i, imax);
            return err_set(BRUME_ERROR_RANGE, "%s: %s.%s[%d]: expected a finite number", at.file, at.path, key, i);
        }
        v[i] = x;
    }
    *out = v;
    *n = count;
    return BRUME_OK;
}

/* "uvs" [u, v, ...] of the mesh just added, one pair per vertex of its nv. */
static brume_status parse_uvs(const cJSON *j, jloc at, brume_scene *s, int nv)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(j, "uvs");
    if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != 2 * nv)
        return err_set(BRUME_ERROR_PARSE, "%s: %s.uvs: expected an array of %d numbers (u, v per vertex)", at.file,
                       at.path, 2 * nv);
    double *uv = malloc(2 * (size_t)nv * sizeof *uv);
    if (!uv)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: %s.uvs: out of memory", at.file, at.path);
    int i = 0;
    for (const cJSON *e = a->child; e; e = e->next, i++) {
        uv[i] = cJSON_IsNumber(e) ? e->valuedouble : (double)NAN;
        if (!(fabs(uv[i]) <= BIG)) {
            free(uv);
            return err_set(BRUME_ERROR_RANGE, "%s: %s.uvs[%d]: expected a finite number", at.file, at.path, i);
        }
    }
    brume_status st = brume_scene_set_mesh_uv(NULL, s, brume_scene_surface_count(s) - 1, uv, nv);
    free(uv);
    return st ? err_prefix("%s: %s.uvs", at.file, at.path) : BRUME_OK;
}

/* A mesh's "reverse_orientation": its front the other side, each triangle's winding reversed
 * (pbrt-v4's ReverseOrientation). */
static void reverse_winding(int *idx, int ntri)
{
    for (int t = 0; t < ntri; t++) {
        int k = idx[3 * t + 1];
        idx[3 * t + 1] = idx[3 * t + 2];
        idx[3 * t + 2] = k;
    }
}

/* A mesh file with "reverse_orientation": read here, its winding reversed, then built as an
 * inline one (a file without it: brume_scene_add_mesh_file). */
static brume_status add_reversed_mesh_file(brume_scene *s, const char *path, const double *xf,
                                           const brume_material *m, const char *name)
{
    double *pos = NULL;
    int *idx = NULL, nv = 0, ntri = 0;
    brume_status st = mesh_load(path, &pos, &nv, &idx, &ntri);
    if (st == BRUME_OK) {
        reverse_winding(idx, ntri);
        st = brume_scene_add_mesh(NULL, s, pos, nv, idx, ntri, xf, m, name);
    }
    free(pos);
    free(idx);
    return st;
}

/* A mesh given inline: `positions` [x, y, z, ...] and `indices` [i, j, k, ...] (counter-
 * clockwise seen from the front), built by brume_scene_add_mesh. */
static brume_status parse_inline_mesh(const cJSON *j, jloc at, brume_scene *s, const double *xf,
                                      const brume_material *m, const char *name, bool reverse)
{
    double *p = NULL, *t = NULL;
    int np = 0, nt = 0;
    brume_status st = inline_numbers(j, at, "positions", 0, &p, &np);
    if (st == BRUME_OK)
        st = inline_numbers(j, at, "indices", np / 3, &t, &nt);
    int *idx = st == BRUME_OK ? malloc((size_t)nt * sizeof *idx) : NULL;
    if (st == BRUME_OK && !idx)
        st = err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: %s.indices: out of memory", at.file, at.path);
    if (st == BRUME_OK) {
        for (int i = 0; i < nt; i++)
            idx[i] = (int)t[i];
        if (reverse)
            reverse_winding(idx, nt / 3);
        if (brume_scene_add_mesh(NULL, s, p, np / 3, idx, nt / 3, xf, m, name))
            st = err_prefix("%s: %s", at.file, at.path);
    }
    if (st == BRUME_OK && cJSON_HasObjectItem(j, "uvs"))
        st = parse_uvs(j, at, s, np / 3);
    free(p);
    free(t);
    free(idx);
    return st;
}

/* The keys a surface of the given type may have; NULL for an unknown type. */
static const char *const *surface_keys(const char *type)
{
    static const char *const sphere_keys[] = {"type", "name", "material", "transform", "keyframes", "center",
                                              "radius", "medium_inside", "medium_outside", NULL};
    static const char *const box_keys[] = {"type", "name", "material", "transform", "keyframes", "min", "max", "medium_inside", "medium_outside", NULL};
    static const char *const quad_keys[] = {"type", "name", "material", "transform", "keyframes", "corner",
                                            "edge_u", "edge_v", "medium_inside", "medium_outside", NULL};
    static const char *const plane_keys[] = {"type", "name", "material", "transform", "keyframes", "point",
                                             "normal", "size", "medium_inside", "medium_outside", NULL};
    static const char *const mesh_keys[] = {"type", "name", "material", "transform", "keyframes", "file", "positions",
                                            "indices", "medium_inside", "medium_outside", "uvs",
                                            "reverse_orientation", NULL};
    return strcmp(type, "sphere") == 0  ? sphere_keys
           : strcmp(type, "box") == 0   ? box_keys
           : strcmp(type, "quad") == 0  ? quad_keys
           : strcmp(type, "plane") == 0 ? plane_keys
           : strcmp(type, "mesh") == 0  ? mesh_keys
                                        : NULL;
}

/* The shape of surface j (its type's keys) added to s with transform xf, material m and name. */
static brume_status add_shape(const cJSON *j, jloc at, brume_scene *s, const char *type, const affine3 *xf,
                              const brume_material *m, const char *name)
{
    brume_status st;
    if (strcmp(type, "sphere") == 0) {
        double c[3] = {0, 0, 0}, r = 1.0;
        if ((st = jvec(j, at, "center", 0, c))) return st;
        if ((st = json_number(j, at, "radius", 0, 1e-12, BIG, &r))) return st;
        st = brume_scene_add_sphere(NULL, s, c, r, xf->m, m, name);
    } else if (strcmp(type, "box") == 0) {
        double lo[3], hi[3];
        if ((st = jvec(j, at, "min", 1, lo))) return st;
        if ((st = jvec(j, at, "max", 1, hi))) return st;
        if (!(lo[0] < hi[0] && lo[1] < hi[1] && lo[2] < hi[2]))
            return err_set(BRUME_ERROR_RANGE, "%s: %s: need min < max on every axis", at.file, at.path);
        st = brume_scene_add_box(NULL, s, lo, hi, xf->m, m, name);
    } else if (strcmp(type, "quad") == 0) {
        double c[3], u[3], v[3];
        if ((st = jvec(j, at, "corner", 1, c))) return st;
        if ((st = jvec(j, at, "edge_u", 1, u))) return st;
        if ((st = jvec(j, at, "edge_v", 1, v))) return st;
        st = brume_scene_add_quad(NULL, s, c, u, v, xf->m, m, name);
    } else if (strcmp(type, "plane") == 0) {
        /* a square of side `size` centred on `point`, front side along `normal` */
        double p[3], n[3], size = 100.0;
        if ((st = jvec(j, at, "point", 1, p))) return st;
        if ((st = jvec(j, at, "normal", 1, n))) return st;
        if (!(v3_length(v3(n[0], n[1], n[2])) > 0.0))
            return err_set(BRUME_ERROR_RANGE, "%s: %s.normal: must not be the zero vector", at.file, at.path);
        if ((st = json_number(j, at, "size", 0, 1e-9, BIG, &size))) return st;
        st = brume_scene_add_plane(NULL, s, p, n, size, xf->m, m, name);
    } else if (cJSON_HasObjectItem(j, "positions") || cJSON_HasObjectItem(j, "indices")) {
        bool reverse = false;
        if (cJSON_HasObjectItem(j, "file"))
            return err_set(BRUME_ERROR_PARSE, "%s: %s: give either file or positions and indices", at.file, at.path);
        if ((st = json_bool(j, at, "reverse_orientation", 0, &reverse))) return st;
        return parse_inline_mesh(j, at, s, xf->m, m, name, reverse);
    } else {
        char file[1024], path[2048];
        bool reverse = false;
        if ((st = json_bool(j, at, "reverse_orientation", 0, &reverse))) return st;
        if (cJSON_HasObjectItem(j, "uvs"))
            return err_set(BRUME_ERROR_PARSE, "%s: %s.uvs: given with positions and indices only", at.file, at.path);
        if ((st = json_string(j, at, "file", 1, file, sizeof file))) return st;
        json_resolve_path(at.file, file, path, sizeof path);
        st = reverse ? add_reversed_mesh_file(s, path, xf->m, m, name)
                     : brume_scene_add_mesh_file(NULL, s, path, xf->m, m, name);
    }
    return st ? err_prefix("%s: %s", at.file, at.path) : BRUME_OK;
}

/* A material {"type": "interface"}: the surface has no material, it only bounds media
 * (docs/surfaces.md, "How surfaces meet media"); *interface says whether m is one. */
static brume_status parse_interface(const cJSON *m, jloc at, bool *interface)
{
    static const char *const keys[] = {"type", NULL};
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(m, "type");
    *interface = cJSON_IsString(t) && strcmp(t->valuestring, "interface") == 0;
    return *interface ? json_check_object(m, at, keys) : BRUME_OK;
}

/* The surface just added bounds medium_inside / medium_outside (names of media), or is an
 * interface: brume_scene_set_surface_media. */
static brume_status parse_surface_media(const cJSON *j, jloc at, brume_scene *s, bool interface)
{
    char in[64] = "", out[64] = "";
    brume_status st;
    if ((st = json_string(j, at, "medium_inside", 0, in, sizeof in))) return st;
    if ((st = json_string(j, at, "medium_outside", 0, out, sizeof out))) return st;
    if (!interface && !in[0] && !out[0])
        return BRUME_OK;
    if (interface && !in[0] && !out[0])
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s.material: an interface only bounds media: give "
                       "medium_inside or medium_outside", at.file, at.path);
    if (brume_scene_set_surface_media(NULL, s, brume_scene_surface_count(s) - 1, in, out, interface))
        return err_prefix("%s: %s", at.file, at.path);
    return BRUME_OK;
}

static brume_status parse_surface(const cJSON *j, jloc at, brume_scene *s)
{
    char type[32], name[64] = "";
    brume_status st = json_object_type(j, at, type, sizeof type);
    if (st) return st;
    const char *const *keys = surface_keys(type);
    if (!keys)
        return err_set(BRUME_ERROR_PARSE,
                       "%s: %s.type: unknown surface type '%s' (known: sphere, box, quad, plane, mesh)", at.file,
                       at.path, type);
    if ((st = json_check_object(j, at, keys))) return st;
    if ((st = json_string(j, at, "name", 0, name, sizeof name))) return st;
    if (!name[0])
        snprintf(name, sizeof name, "%s", at.path);
    char kp[256];
    brume_material m;
    const cJSON *mj = cJSON_GetObjectItemCaseSensitive(j, "material");
    jloc mat = {at.file, json_key_path(kp, sizeof kp, at.path, "material")};
    bool interface = false;
    if (mj && (st = parse_interface(mj, mat, &interface))) return st;
    scene_material_store sm;
    affine3 xf; /* a mesh may be mirrored (negative scales): its winding is reversed with it */
    if ((st = scene_parse_material(interface ? NULL : mj, mat, &m, &sm)) ||
        (st = json_transform(cJSON_GetObjectItemCaseSensitive(j, "transform"),
                             (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "transform")},
                             strcmp(type, "mesh") == 0, &xf)) ||
        (st = add_shape(j, at, s, type, &xf, &m, name))) {
        scene_material_store_free(&sm);
        return st;
    }
    scene_material_store_free(&sm);
    if ((st = parse_surface_media(j, at, s, interface)))
        return st;
    const cJSON *keys_j = cJSON_GetObjectItemCaseSensitive(j, "keyframes");
    if (keys_j) {
        /* the object moves: the keyed transform applies after its own `transform` */
        brume_transform_key k[MOTION_MAX_KEYS];
        int n = 0;
        jloc kat = {at.file, json_key_path(kp, sizeof kp, at.path, "keyframes")};
        if ((st = keys_parse_motion(keys_j, kat, k, &n))) return st;
        if ((st = brume_scene_set_surface_motion(NULL, s, brume_scene_surface_count(s) - 1, k, n)))
            return err_prefix("%s: %s", at.file, kat.path);
    }
    return BRUME_OK;
}

brume_status scene_parse_surfaces(const cJSON *arr, const char *file, brume_scene *s)
{
    if (!cJSON_IsArray(arr))
        return err_set(BRUME_ERROR_PARSE, "%s: surfaces: expected an array", file);
    int i = 0;
    for (const cJSON *e = arr->child; e; e = e->next, i++) {
        char kp[64];
        snprintf(kp, sizeof kp, "surfaces[%d]", i);
        brume_status st = parse_surface(e, (jloc){file, kp}, s);
        if (st)
            return st;
    }
    return BRUME_OK;
}
