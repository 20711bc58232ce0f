/* scene_shapes.c - the public surface builders (brume.h): spheres, boxes, quads, planes,
 * triangle meshes from arrays or files, with a transform and a material, and their motion. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/budget.h"
#include "core/error.h"
#include "io/mesh.h"
#include "scene/scene.h"
#include "scene/scene_build.h"
#include "scene/scene_material_build.h"
#include "surface/material_hit.h"

void brume_material_default(brume_material *m)
{
    if (!m)
        return;
    *m = (brume_material){.albedo = {0.8, 0.8, 0.8}, .exponent = 50.0, .type = BRUME_MATERIAL_DIFFUSE, .eta = 1.5,
                          .conductor_eta = {MATERIAL_CU_ETA}, .conductor_k = {MATERIAL_CU_K}, .thickness = 0.01,
                          .max_depth = 10, .nsamples = 1, .remap_roughness = true, .amount = 0.5};
}

/* What every shape builder checks: the scene, the transform, the material and the name. */
typedef struct shape_args {
    affine3 xf;
    material m;
    char name[64];
} shape_args;

static brume_status shape_begin(const char *fn, brume_scene *s, const double *transform, const brume_material *bm,
                                const char *name, shape_args *a)
{
    brume_status st = build_check_scene(fn, s);
    if (st)
        return st;
    a->xf = affine3_identity();
    if (transform) {
        affine3 inv;
        memcpy(a->xf.m, transform, sizeof a->xf.m);
        if (!affine3_invert(&a->xf, &inv))
            return err_set(BRUME_ERROR_RANGE, "%s: transform: not finite and invertible", fn);
    }
    brume_material def;
    a->m = (material){.type = MATERIAL_DIFFUSE};
    if (!bm) {
        brume_material_default(&def);
        bm = &def;
    }
    if (name && strlen(name) >= sizeof a->name)
        return err_set(BRUME_ERROR_RANGE, "%s: name: longer than %zu bytes", fn, sizeof a->name - 1);
    if (name)
        snprintf(a->name, sizeof a->name, "%s", name);
    else
        snprintf(a->name, sizeof a->name, "surfaces[%d]", s->surf ? surfaces_count(s->surf) : 0);
    if ((st = material_build(fn, "material", bm, 0, &a->m)))
        return st;
    if (!s->surf && !(s->surf = surfaces_new())) {
        budget_give(material_bytes(&a->m));
        material_release(&a->m);
        return err_prefix("%s", fn);
    }
    return BRUME_OK;
}

/* After an add: a scene whose first shape failed keeps no empty surfaces object, nor the
 * texture built for the shape. */
static brume_status shape_end(const char *fn, brume_scene *s, shape_args *a, brume_status st)
{
    if (st) { /* the surfaces took the textures only on success */
        budget_give(material_bytes(&a->m));
        material_release(&a->m);
    }
    if (st && surfaces_count(s->surf) == 0) {
        surfaces_release(s->surf);
        s->surf = NULL;
    }
    return st ? err_prefix("%s", fn) : BRUME_OK;
}

/* Adds a mesh after transforming its vertices (pos, modified) to world space. */
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
    static const double uv[8] = {0, 0, 1, 0, 1, 1, 0, 1}; /* as pbrt-v4's bilinear patch */
    brume_status st = add_mesh(S, pos, 4, idx, 2, xf, m, name);
    return st ? st : surfaces_set_uv(S, surfaces_count(S) - 1, uv, 4);
}

brume_status brume_scene_add_sphere(brume_context *ctx, brume_scene *s, const double center[3], double radius,
                                    const double *transform, const brume_material *mat, const char *name)
{
    static const char fn[] = "brume_scene_add_sphere";
    err_clear();
    vec3 c;
    brume_status st;
    if ((st = build_check_scene(fn, s)) || (st = build_need(fn, 1, "center", (const void *)center)) ||
        (st = build_point(fn, "center", center, &c)) ||
        (st = build_number(fn, "radius", radius, 1e-12, 1e30)))
        return ctx_report(ctx, st);
    shape_args a;
    if ((st = shape_begin(fn, s, transform, mat, name, &a)))
        return ctx_report(ctx, st);
    /* a sphere stays a sphere under similarity transforms only */
    double sx = v3_length(affine3_apply_dir(&a.xf, v3(1, 0, 0))), sy = v3_length(affine3_apply_dir(&a.xf, v3(0, 1, 0))),
           sz = v3_length(affine3_apply_dir(&a.xf, v3(0, 0, 1)));
    if (fabs(sx - sy) > 1e-9 * sx || fabs(sx - sz) > 1e-9 * sx)
        st = err_set(BRUME_ERROR_UNSUPPORTED, "transform: a sphere takes a uniform scale only (use a mesh for ellipsoids)");
    else
        st = surfaces_add_sphere(s->surf, affine3_apply(&a.xf, c), radius * sx, &a.m, a.name);
    return ctx_report(ctx, shape_end(fn, s, &a, st));
}

brume_status brume_scene_add_box(brume_context *ctx, brume_scene *s, const double min[3], const double max[3],
                                 const double *transform, const brume_material *mat, const char *name)
{
    static const char fn[] = "brume_scene_add_box";
    err_clear();
    vec3 lo, hi;
    brume_status st;
    if ((st = build_check_scene(fn, s)) || (st = build_need(fn, 2, "min", (const void *)min, "max", (const void *)max)) ||
        (st = build_point(fn, "min", min, &lo)) ||
        (st = build_point(fn, "max", max, &hi)))
        return ctx_report(ctx, st);
    if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z))
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: min, max: need min < max on every axis", fn));
    shape_args a;
    if ((st = shape_begin(fn, s, transform, mat, name, &a)))
        return ctx_report(ctx, st);
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
    return ctx_report(ctx, shape_end(fn, s, &a, add_mesh(s->surf, pos, 8, idx, 12, &a.xf, &a.m, a.name)));
}

brume_status brume_scene_add_quad(brume_context *ctx, brume_scene *s, const double corner[3], const double edge_u[3],
                                  const double edge_v[3], const double *transform, const brume_material *mat,
                                  const char *name)
{
    static const char fn[] = "brume_scene_add_quad";
    err_clear();
    vec3 c, u, v;
    brume_status st;
    if ((st = build_check_scene(fn, s)) ||
        (st = build_need(fn, 3, "corner", (const void *)corner, "edge_u", (const void *)edge_u, "edge_v",
                         (const void *)edge_v)) ||
        (st = build_point(fn, "corner", corner, &c)) ||
        (st = build_point(fn, "edge_u", edge_u, &u)) || (st = build_point(fn, "edge_v", edge_v, &v)))
        return ctx_report(ctx, st);
    if (!(v3_length(v3_cross(u, v)) > 0.0))
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: edge_u, edge_v: must not be parallel", fn));
    shape_args a;
    if ((st = shape_begin(fn, s, transform, mat, name, &a)))
        return ctx_report(ctx, st);
    return ctx_report(ctx, shape_end(fn, s, &a, add_quad(s->surf, c, u, v, &a.xf, &a.m, a.name)));
}

brume_status brume_scene_add_plane(brume_context *ctx, brume_scene *s, const double point[3], const double normal[3],
                                   double size, const double *transform, const brume_material *mat,
                                   const char *name)
{
    static const char fn[] = "brume_scene_add_plane";
    err_clear();
    vec3 p, n;
    brume_status st;
    if ((st = build_check_scene(fn, s)) || (st = build_need(fn, 2, "point", (const void *)point, "normal", (const void *)normal)) ||
        (st = build_point(fn, "point", point, &p)) ||
        (st = build_direction(fn, "normal", normal, &n)) || (st = build_number(fn, "size", size, 1e-9, 1e30)))
        return ctx_report(ctx, st);
    shape_args a;
    if ((st = shape_begin(fn, s, transform, mat, name, &a)))
        return ctx_report(ctx, st);
    frame f = frame_from_n(n);
    vec3 u = v3_scale(f.s, size), v = v3_scale(f.t, size);
    vec3 c = v3_sub(p, v3_scale(v3_add(u, v), 0.5));
    return ctx_report(ctx, shape_end(fn, s, &a, add_quad(s->surf, c, u, v, &a.xf, &a.m, a.name)));
}

brume_status brume_scene_add_mesh(brume_context *ctx, brume_scene *s, const double *positions, int nv,
                                  const int *indices, int ntri, const double *transform,
                                  const brume_material *mat, const char *name)
{
    static const char fn[] = "brume_scene_add_mesh";
    err_clear();
    brume_status st;
    if ((st = build_check_scene(fn, s)))
        return ctx_report(ctx, st);
    if (!positions)
        return ctx_report(ctx, build_null(fn, "positions"));
    if (!indices)
        return ctx_report(ctx, build_null(fn, "indices"));
    if ((st = build_number(fn, "nv", nv, 3, 1 << 28)) || (st = build_number(fn, "ntri", ntri, 1, 1 << 28)))
        return ctx_report(ctx, st);
    for (long i = 0; i < 3L * nv; i++)
        if (!isfinite(positions[i]))
            return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: positions[%ld]: %g is not finite", fn, i, positions[i]));
    for (long i = 0; i < 3L * ntri; i++)
        if (indices[i] < 0 || indices[i] >= nv)
            return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: indices[%ld]: %d outside [0, %d)", fn, i, indices[i], nv));
    shape_args a;
    if ((st = shape_begin(fn, s, transform, mat, name, &a)))
        return ctx_report(ctx, st);
    double *pos = malloc(sizeof *pos * 3 * (size_t)nv);
    if (!pos)
        return ctx_report(ctx, shape_end(fn, s, &a, err_set(BRUME_ERROR_OUT_OF_MEMORY, "out of memory")));
    memcpy(pos, positions, sizeof *pos * 3 * (size_t)nv);
    st = add_mesh(s->surf, pos, nv, indices, ntri, &a.xf, &a.m, a.name);
    free(pos);
    return ctx_report(ctx, shape_end(fn, s, &a, st));
}

brume_status brume_scene_add_mesh_file(brume_context *ctx, brume_scene *s, const char *path, const double *transform,
                                       const brume_material *mat, const char *name)
{
    static const char fn[] = "brume_scene_add_mesh_file";
    err_clear();
    brume_status st;
    if ((st = build_check_scene(fn, s)))
        return ctx_report(ctx, st);
    if (!path)
        return ctx_report(ctx, build_null(fn, "path"));
    shape_args a;
    if ((st = shape_begin(fn, s, transform, mat, name, &a)))
        return ctx_report(ctx, st);
    double *pos = NULL, *uv = NULL;
    int *idx = NULL, nv = 0, ntri = 0;
    if ((st = mesh_load_uv(path, &pos, &nv, &idx, &ntri, &uv)) == BRUME_OK)
        st = add_mesh(s->surf, pos, nv, idx, ntri, &a.xf, &a.m, a.name);
    if (st == BRUME_OK && uv) /* the file's (u, v); without them pbrt-v4's per triangle */
        st = surfaces_set_uv(s->surf, surfaces_count(s->surf) - 1, uv, nv);
    free(pos);
    free(idx);
    free(uv);
    return ctx_report(ctx, shape_end(fn, s, &a, st));
}

int brume_scene_surface_count(const brume_scene *s) { return s && s->surf ? surfaces_count(s->surf) : 0; }

brume_status brume_scene_set_surface_motion(brume_context *ctx, brume_scene *s, int index,
                                            const brume_transform_key *keys, int n)
{
    static const char fn[] = "brume_scene_set_surface_motion";
    err_clear();
    brume_status st = build_check_scene(fn, s);
    if (st)
        return ctx_report(ctx, st);
    if (!keys)
        return ctx_report(ctx, build_null(fn, "keys"));
    int count = brume_scene_surface_count(s);
    if (index < 0 || index >= count)
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: surface: %d is not a surface of the scene (it has %d)",
                                       fn, index, count));
    motion mo;
    if ((st = build_motion(fn, keys, n, &mo)))
        return ctx_report(ctx, st);
    if ((st = surfaces_set_motion(s->surf, index, &mo)))
        return ctx_report(ctx, err_prefix("%s", fn));
    return ctx_report(ctx, BRUME_OK);
}

brume_status brume_scene_set_mesh_uv(brume_context *ctx, brume_scene *s, int index, const double *uv, int nv)
{
    static const char fn[] = "brume_scene_set_mesh_uv";
    err_clear();
    brume_status st;
    if ((st = build_check_scene(fn, s)) || (st = build_need(fn, 1, "uv", (const void *)uv)))
        return ctx_report(ctx, st);
    if (!s->surf || index < 0 || index >= surfaces_count(s->surf))
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: index %d: no such surface", fn, index));
    return ctx_report(ctx, surfaces_set_uv(s->surf, index, uv, nv) ? err_prefix("%s", fn) : BRUME_OK);
}
