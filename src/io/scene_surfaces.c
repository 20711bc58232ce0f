/* scene_surfaces.c - the "surfaces" array of a scene file: shapes, transforms, materials. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/xform.h"
#include "io/json.h"
#include "io/mesh.h"
#include "io/scene_keys.h"
#include "io/scene_surfaces.h"

static const double BIG = 1e30;

static brume_status parse_material(const cJSON *j, jloc at, material *m)
{
    static const char *const keys[] = {"albedo", "specular", "exponent", "emission", "two_sided", NULL};
    m->albedo = col(0.8);
    m->specular = col(0.0);
    m->exponent = 50.0;
    m->emission = col(0.0);
    m->two_sided_emission = false;
    if (!j)
        return BRUME_OK;
    brume_status st = json_check_object(j, at, keys);
    if (st) return st;
    if ((st = json_color(j, at, "albedo", 0, 0.0, 1.0, &m->albedo))) return st;
    if ((st = json_color(j, at, "specular", 0, 0.0, 1.0, &m->specular))) return st;
    if ((st = json_number(j, at, "exponent", 0, 0.0, 1e6, &m->exponent))) return st;
    if ((st = json_color(j, at, "emission", 0, 0.0, BIG, &m->emission))) return st;
    if ((st = json_bool(j, at, "two_sided", 0, &m->two_sided_emission))) return st;
    for (int c = 0; c < BRUME_NSAMPLES; c++)
        if (m->albedo.c[c] + m->specular.c[c] > 1.0)
            return err_set(BRUME_ERROR_RANGE, "%s: %s: albedo + specular = %g > 1 would create energy", at.file,
                           at.path, m->albedo.c[c] + m->specular.c[c]);
    return BRUME_OK;
}

/* Adds a mesh after transforming its vertices to world space. */
static brume_status add_mesh(surfaces *S, double *pos, int nv, const int *idx, int ntri, const affine3 *xf,
                             const material *m, const char *name)
{
    for (int i = 0; i < nv; i++) {
        vec3 p = affine3_apply(xf, v3(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]));
        pos[3 * i] = p.x;
        pos[3 * i + 1] = p.y;
        pos[3 * i + 2] = p.z;
    }
    int flip = affine3_det(xf) < 0.0; /* a mirroring transform reverses the winding */
    if (!flip)
        return surfaces_add_mesh(S, pos, nv, idx, ntri, m, name);
    int *fl = malloc(sizeof *fl * 3 * (size_t)ntri);
    if (!fl)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "surface '%s': out of memory", name);
    for (int t = 0; t < ntri; t++) {
        fl[3 * t] = idx[3 * t];
        fl[3 * t + 1] = idx[3 * t + 2];
        fl[3 * t + 2] = idx[3 * t + 1];
    }
    brume_status st = surfaces_add_mesh(S, pos, nv, fl, ntri, m, name);
    free(fl);
    return st;
}

/* A parallelogram: corner c, edges u and v; front side along u x v. */
static brume_status add_quad(surfaces *S, vec3 c, vec3 u, vec3 v, const affine3 *xf, const material *m,
                             const char *name)
{
    vec3 p[4] = {c, v3_add(c, u), v3_add(v3_add(c, u), v), v3_add(c, v)};
    double pos[12];
    for (int i = 0; i < 4; i++) {
        pos[3 * i] = p[i].x;
        pos[3 * i + 1] = p[i].y;
        pos[3 * i + 2] = p[i].z;
    }
    static const int idx[6] = {0, 1, 2, 0, 2, 3};
    return add_mesh(S, pos, 4, idx, 2, xf, m, name);
}

static brume_status add_box(surfaces *S, vec3 lo, vec3 hi, const affine3 *xf, const material *m, const char *name)
{
    double pos[24];
    for (int i = 0; i < 8; i++) {
        pos[3 * i] = (i & 1) ? hi.x : lo.x;
        pos[3 * i + 1] = (i & 2) ? hi.y : lo.y;
        pos[3 * i + 2] = (i & 4) ? hi.z : lo.z;
    }
    /* outward, counter-clockwise seen from outside */
    static const int idx[36] = {0, 2, 3, 0, 3, 1, /* -z */ 4, 5, 7, 4, 7, 6, /* +z */
                                0, 1, 5, 0, 5, 4, /* -y */ 2, 6, 7, 2, 7, 3, /* +y */
                                0, 4, 6, 0, 6, 2, /* -x */ 1, 3, 7, 1, 7, 5 /* +x */};
    return add_mesh(S, pos, 8, idx, 12, xf, m, name);
}

static brume_status parse_surface(const cJSON *j, jloc at, surfaces *S)
{
    char type[32], name[64] = "";
    brume_status st = json_object_type(j, at, type, sizeof type);
    if (st) return st;
    static const char *const sphere_keys[] = {"type", "name", "material", "transform", "keyframes", "center",
                                              "radius", NULL};
    static const char *const box_keys[] = {"type", "name", "material", "transform", "keyframes", "min", "max", NULL};
    static const char *const quad_keys[] = {"type", "name", "material", "transform", "keyframes", "corner",
                                            "edge_u", "edge_v", NULL};
    static const char *const plane_keys[] = {"type", "name", "material", "transform", "keyframes", "point",
                                             "normal", "size", NULL};
    static const char *const mesh_keys[] = {"type", "name", "material", "transform", "keyframes", "file", NULL};
    const char *const *keys = strcmp(type, "sphere") == 0  ? sphere_keys
                              : strcmp(type, "box") == 0   ? box_keys
                              : strcmp(type, "quad") == 0  ? quad_keys
                              : strcmp(type, "plane") == 0 ? plane_keys
                              : strcmp(type, "mesh") == 0  ? mesh_keys
                                                           : NULL;
    if (!keys)
        return err_set(BRUME_ERROR_PARSE,
                       "%s: %s.type: unknown surface type '%s' (known: sphere, box, quad, plane, mesh)", at.file,
                       at.path, type);
    if ((st = json_check_object(j, at, keys))) return st;
    if ((st = json_string(j, at, "name", 0, name, sizeof name))) return st;
    if (!name[0])
        snprintf(name, sizeof name, "%s", at.path);
    char kp[256];
    material m;
    if ((st = parse_material(cJSON_GetObjectItemCaseSensitive(j, "material"),
                             (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "material")}, &m)))
        return st;
    affine3 xf;
    if ((st = json_transform(cJSON_GetObjectItemCaseSensitive(j, "transform"),
                              (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "transform")}, &xf)))
        return st;

    if (strcmp(type, "sphere") == 0) {
        vec3 c = v3(0, 0, 0);
        double r = 1.0;
        if ((st = json_vec3(j, at, "center", 0, &c))) return st;
        if ((st = json_number(j, at, "radius", 0, 1e-12, BIG, &r))) return st;
        /* a sphere stays a sphere under similarity transforms only */
        vec3 ax = affine3_apply_dir(&xf, v3(1, 0, 0)), ay = affine3_apply_dir(&xf, v3(0, 1, 0)),
             az = affine3_apply_dir(&xf, v3(0, 0, 1));
        double sx = v3_length(ax), sy = v3_length(ay), sz = v3_length(az);
        if (fabs(sx - sy) > 1e-9 * sx || fabs(sx - sz) > 1e-9 * sx)
            return err_set(BRUME_ERROR_UNSUPPORTED,
                           "%s: %s.transform: a sphere takes a uniform scale only (use a mesh for ellipsoids)",
                           at.file, at.path);
        st = surfaces_add_sphere(S, affine3_apply(&xf, c), r * sx, &m, name);
    } else if (strcmp(type, "box") == 0) {
        vec3 lo, hi;
        if ((st = json_vec3(j, at, "min", 1, &lo))) return st;
        if ((st = json_vec3(j, at, "max", 1, &hi))) return st;
        if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z))
            return err_set(BRUME_ERROR_RANGE, "%s: %s: need min < max on every axis", at.file, at.path);
        st = add_box(S, lo, hi, &xf, &m, name);
    } else if (strcmp(type, "quad") == 0) {
        vec3 c, u, v;
        if ((st = json_vec3(j, at, "corner", 1, &c))) return st;
        if ((st = json_vec3(j, at, "edge_u", 1, &u))) return st;
        if ((st = json_vec3(j, at, "edge_v", 1, &v))) return st;
        if (!(v3_length(v3_cross(u, v)) > 0.0))
            return err_set(BRUME_ERROR_RANGE, "%s: %s: edge_u and edge_v must not be parallel", at.file, at.path);
        st = add_quad(S, c, u, v, &xf, &m, name);
    } else if (strcmp(type, "plane") == 0) {
        /* a square of side `size` centred on `point`, front side along `normal` */
        vec3 p, n;
        double size = 100.0;
        if ((st = json_vec3(j, at, "point", 1, &p))) return st;
        if ((st = json_vec3(j, at, "normal", 1, &n))) return st;
        if (!(v3_length(n) > 0.0))
            return err_set(BRUME_ERROR_RANGE, "%s: %s.normal: must not be the zero vector", at.file, at.path);
        if ((st = json_number(j, at, "size", 0, 1e-9, BIG, &size))) return st;
        frame f = frame_from_n(v3_normalize(n));
        vec3 u = v3_scale(f.s, size), v = v3_scale(f.t, size);
        vec3 c = v3_sub(p, v3_scale(v3_add(u, v), 0.5));
        st = add_quad(S, c, u, v, &xf, &m, name);
    } else {
        char file[1024], path[2048];
        if ((st = json_string(j, at, "file", 1, file, sizeof file))) return st;
        json_resolve_path(at.file, file, path, sizeof path);
        double *pos = NULL;
        int *idx = NULL, nv = 0, ntri = 0;
        if ((st = mesh_load(path, &pos, &nv, &idx, &ntri)))
            return err_prefix("%s: %s.file", at.file, at.path);
        st = add_mesh(S, pos, nv, idx, ntri, &xf, &m, name);
        free(pos);
        free(idx);
    }
    if (st)
        return err_prefix("%s: %s", at.file, at.path);
    const cJSON *keys_j = cJSON_GetObjectItemCaseSensitive(j, "keyframes");
    if (keys_j) {
        /* the object moves: the keyed transform applies after its own `transform` */
        motion mo;
        if ((st = keys_parse_motion(keys_j, (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "keyframes")}, &mo)))
            return st;
        if ((st = surfaces_set_motion(S, surfaces_count(S) - 1, &mo)))
            return err_prefix("%s: %s.keyframes", at.file, at.path);
    }
    return BRUME_OK;
}

brume_status scene_parse_surfaces(const cJSON *arr, const char *file, surfaces **out)
{
    *out = NULL;
    if (!cJSON_IsArray(arr))
        return err_set(BRUME_ERROR_PARSE, "%s: surfaces: expected an array", file);
    if (cJSON_GetArraySize(arr) == 0)
        return BRUME_OK;
    surfaces *S = surfaces_new();
    if (!S)
        return err_prefix("%s: surfaces", file);
    int i = 0;
    for (const cJSON *e = arr->child; e; e = e->next, i++) {
        char kp[64];
        snprintf(kp, sizeof kp, "surfaces[%d]", i);
        brume_status st = parse_surface(e, (jloc){file, kp}, S);
        if (st) {
            surfaces_release(S);
            return st;
        }
    }
    *out = S;
    return BRUME_OK;
}
