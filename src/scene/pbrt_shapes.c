/* pbrt_shapes.c - pbrt's Shape directive (spheres, boxes, triangle and bilinear meshes, ply
 * files) as brume's surfaces and the bounds of the media they enclose. */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/vec.h"
#include "io/grid_io.h"
#include "io/mesh.h"
#include "io/json.h"
#include "scene/scene_build.h"
#include "scene/pbrt.h"

/* A shape's triangles in world space (pbrt's trianglemesh and bilinearmesh, transformed by
 * the current transform, which may then hold any affine map). */
typedef struct tris {
    double *P; /* 3 nv */
    int *idx;  /* 3 nt */
    int nv, nt;
    double *uv; /* 2 nv texture coordinates, or NULL */
} tris;

static void tris_free(tris *t)
{
    free(t->P);
    free(t->idx);
    free(t->uv);
}

/* "point3 P" and "integer indices" (per = 3 for triangles, 4 for bilinear patches; without
 * indices, the one primitive of exactly `per` points) into t, P transformed to world space. */
static brume_status mesh_params(pbrt_state *S, params *ps, const char *what, int per, tris *t, int **quad)
{
    lexer *L = &S->L;
    static const char *const points[] = {"point3", "point", NULL}, *const ints[] = {"integer", NULL};
    param *P = NULL, *I = NULL;
    brume_status st;
    *quad = NULL;
    if ((st = pbrt_get_array(L, ps, "P", points, &P)) || (st = pbrt_get_array(L, ps, "indices", ints, &I)))
        return st;
    if (!P || P->n % 3)
        return pbrt_fail(L, "%s: \"point3 P\" must be given as x y z triples", what);
    int nv = P->n / 3, ni = I ? I->n : per;
    if (!I && nv != per)
        return pbrt_fail(L, "%s: no \"integer indices\" (allowed only for exactly %d points)", what, per);
    if (ni % per)
        return pbrt_fail(L, "%s: %d indices, not a multiple of %d", what, ni, per);
    if (P->n > SCENE_INLINE_MAX_VALUES || (double)ni / per * 3 * (per - 2) > SCENE_INLINE_MAX_VALUES)
        return pbrt_fail(L, "%s: more than the %d coordinates or triangle indices brume takes inline (a larger mesh "
                            "belongs in a plymesh)", what, SCENE_INLINE_MAX_VALUES);
    int *idx = malloc((size_t)ni * sizeof *idx);
    t->P = malloc((size_t)P->n * sizeof *t->P);
    if (!idx || !t->P) {
        free(idx);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s:%d: %s: out of memory", L->file, L->dir_line, what);
    }
    for (int i = 0; i < ni; i++) {
        double x = I ? I->v[i] : i;
        if (!(x >= 0 && x < nv) || x != floor(x)) {
            free(idx);
            return pbrt_fail(L, "%s: index %d: %g is not a point of P (0 to %d)", what, i, x, nv - 1);
        }
        idx[i] = (int)x;
    }
    m4 ctm = S->a[S->depth].ctm;
    for (int i = 0; i < nv; i++) {
        vec3 w = pbrt_m4_point(ctm, v3(P->v[3 * i], P->v[3 * i + 1], P->v[3 * i + 2]));
        t->P[3 * i] = w.x;
        t->P[3 * i + 1] = w.y;
        t->P[3 * i + 2] = w.z;
    }
    t->nv = nv;
    if (per == 3) {
        t->idx = idx;
        t->nt = ni / 3;
    } else {
        *quad = idx;
        t->nt = ni / 4;
    }
    return BRUME_OK;
}

/* pbrt's bilinear patches (corners p00, p10, p01, p11) as two triangles each, (p00, p10,
 * p11) and (p00, p11, p01), facing along (p10 - p00) x (p01 - p00) as pbrt's patch does:
 * exact for a planar patch (its surface is then the quadrilateral). A non-planar patch is
 * curved, and is refused rather than flattened. */
static brume_status bilinear_tris(lexer *L, const int *quad, tris *t)
{
    int np = t->nt;
    t->idx = malloc((size_t)np * 6 * sizeof *t->idx);
    if (!t->idx)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s:%d: bilinearmesh: out of memory", L->file, L->dir_line);
    for (int i = 0; i < np; i++) {
        const int *q = &quad[4 * i];
        vec3 p[4];
        for (int c = 0; c < 4; c++)
            p[c] = v3(t->P[3 * q[c]], t->P[3 * q[c] + 1], t->P[3 * q[c] + 2]);
        vec3 n = v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0]));
        double size = fmax(v3_length(v3_sub(p[3], p[0])), v3_length(v3_sub(p[2], p[1])));
        if (!(v3_length(n) > 0.0) || fabs(v3_dot(v3_normalize(n), v3_sub(p[3], p[0]))) > 1e-9 * size)
            return pbrt_unsupported(L, "Shape \"bilinearmesh\": patch %d is not planar (or is degenerate): brume renders "
                                       "triangles, exact only for planar patches", i);
        int tri[6] = {q[0], q[1], q[3], q[0], q[3], q[2]};
        memcpy(&t->idx[6 * i], tri, sizeof tri);
    }
    t->nt = 2 * np;
    return BRUME_OK;
}

/* The world box (lo, hi) of n points (x, y, z). */
static void points_box(const double *P, int n, double b[6])
{
    for (int k = 0; k < 3; k++) {
        b[k] = INFINITY;
        b[3 + k] = -INFINITY;
    }
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            b[k] = fmin(b[k], P[3 * i + k]);
            b[3 + k] = fmax(b[3 + k], P[3 * i + k]);
        }
}

/* An "interface" shape s (owned from here; its box b in world space): a surface with no
 * material that bounds the media of its MediumInterface, crossed by every ray
 * (docs/surfaces.md, "How surfaces meet media"): the inside one behind pbrt's normal, the
 * outside one before it, which replaces whatever medium a ray was in, as in pbrt-v4. */
static brume_status shape_interface(pbrt_state *S, cJSON *s, const double b[6])
{
    attrs *a = &S->a[S->depth];
    if (!a->inside[0] && !a->outside[0]) { /* no medium changes there: pbrt-v4 draws nothing */
        cJSON_Delete(s);
        return BRUME_OK;
    }
    /* named by its file and line: what commit's refusals (an open mesh) then say */
    const char *base = strrchr(S->L.file, '/');
    char name[64];
    snprintf(name, sizeof name, "%.50s:%d", base ? base + 1 : S->L.file, S->L.dir_line);
    cJSON_AddStringToObject(s, "name", name);
    cJSON_AddStringToObject(cJSON_AddObjectToObject(s, "material"), "type", "interface");
    brume_status st = BRUME_OK;
    if (a->inside[0] && (st = pbrt_medium_use(S, a->inside, b, false)) == BRUME_OK)
        cJSON_AddStringToObject(s, "medium_inside", a->inside);
    if (st == BRUME_OK && a->outside[0] && (st = pbrt_medium_use(S, a->outside, b, true)) == BRUME_OK)
        cJSON_AddStringToObject(s, "medium_outside", a->outside);
    if (st != BRUME_OK) {
        cJSON_Delete(s);
        return st;
    }
    cJSON_AddItemToArray(S->surfaces, s);
    return BRUME_OK;
}

/* The inline mesh of the triangles t (world space), their winding made pbrt's normal: the
 * object's carried through the transform, which a mirroring one reverses (flip). */
static cJSON *tris_json(const tris *t, bool flip)
{
    if (flip)
        for (int f = 0; f < t->nt; f++) {
            int k = t->idx[3 * f + 1];
            t->idx[3 * f + 1] = t->idx[3 * f + 2];
            t->idx[3 * f + 2] = k;
        }
    cJSON *s = cJSON_CreateObject();
    cJSON_AddStringToObject(s, "type", "mesh");
    cJSON_AddItemToObject(s, "positions", cJSON_CreateDoubleArray(t->P, 3 * t->nv));
    cJSON_AddItemToObject(s, "indices", cJSON_CreateIntArray(t->idx, 3 * t->nt));
    return s;
}

/* Whether the current transform mirrors. */
static bool ctm_mirrors(const pbrt_state *S)
{
    const double *c = S->a[S->depth].ctm.m;
    return c[0] * (c[5] * c[10] - c[6] * c[9]) - c[1] * (c[4] * c[10] - c[6] * c[8]) +
               c[2] * (c[4] * c[9] - c[5] * c[8]) < 0.0;
}

/* A textured mesh's texture coordinates: its "uv", else pbrt-v4's defaults, (0, 0), (1, 0),
 * (1, 1) at a triangle's corners and (0, 0), (1, 0), (0, 1), (1, 1) at a bilinear patch's,
 * each triangle then given its own points. */
static brume_status shape_uv(pbrt_state *S, const char *what, const param *uv, bool tri, tris *t)
{
    static const double corners[12] = {0, 0, 1, 0, 1, 1, /* bilinear_tris' second */ 0, 0, 1, 1, 0, 1};
    if (uv)
        return pbrt_mesh_uv(S, uv, what, t->nv, &t->uv);
    return pbrt_uv_unshare(S, what, &t->P, &t->nv, t->idx, t->nt, corners, tri ? 1 : 2, &t->uv);
}

/* A drawn shape: s (owned from here) with the current diffuse material. */
static brume_status shape_surface(pbrt_state *S, cJSON *s)
{
    attrs *a = &S->a[S->depth];
    cJSON *mat = pbrt_material_json(S, a);
    if (!mat) {
        cJSON_Delete(s);
        return err_status();
    }
    cJSON_AddItemToObject(s, "material", mat);
    if (a->area) {
        cJSON_AddItemToObject(mat, "emission", cJSON_CreateDoubleArray(a->area_L, 3));
        if (a->area_two_sided)
            cJSON_AddBoolToObject(mat, "two_sided", true);
    }
    cJSON_AddItemToArray(S->surfaces, s);
    return BRUME_OK;
}

/* An emitting shape's triangles, and a dielectric's (whose inside is behind its normal), face
 * pbrt's normal: the object's winding carried through the transform, which a mirroring
 * transform (the reader's mirrored world included) reverses in world space, so the winding is
 * reversed back. One-sided emission from a mesh with shading normals N faces them in pbrt-v4
 * (FaceForward), which brume does not read: refused. */
static brume_status emitter_facing(pbrt_state *S, params *ps, const char *what, tris *t)
{
    const attrs *a = &S->a[S->depth];
    const bool sided = strcmp(a->material, "dielectric") == 0;
    if ((!a->area || a->area_two_sided) && !sided)
        return BRUME_OK;
    param *N = pbrt_get(ps, "N");
    if (a->area && !a->area_two_sided && N && N->n > 0)
        return pbrt_unsupported(&S->L, "%s: a one-sided area light on a mesh with \"normal N\" (pbrt-v4 turns the emitting "
                                       "side toward N; give \"bool twosided\" true)", what);
    const double *c = a->ctm.m;
    double det = c[0] * (c[5] * c[10] - c[6] * c[9]) - c[1] * (c[4] * c[10] - c[6] * c[8]) +
                 c[2] * (c[4] * c[9] - c[5] * c[8]);
    for (int f = 0; det < 0.0 && f < t->nt; f++) {
        int k = t->idx[3 * f + 1];
        t->idx[3 * f + 1] = t->idx[3 * f + 2];
        t->idx[3 * f + 2] = k;
    }
    return BRUME_OK;
}

/* A new brume surface of the type, placed by the current transform; NULL after a refusal
 * (shear: brume's transform object is translate, rotate, scale). */
static cJSON *placed_surface(pbrt_state *S, const char *what, const char *type)
{
    m4 m = S->a[S->depth].ctm;
    const double *c = m.m;
    double det = c[0] * (c[5] * c[10] - c[6] * c[9]) - c[1] * (c[4] * c[10] - c[6] * c[8]) +
                 c[2] * (c[4] * c[9] - c[5] * c[8]);
    /* a mesh file is placed with the mirror, which brume's mesh builder meets by reversing
       the winding: the front side stays the mirror image of the file's, pbrt-v4's geometric
       normal under a transform that swaps handedness */
    if (det < 0.0 && strcmp(type, "sphere") == 0)
        m = pbrt_m4_mul(m, pbrt_m4_scale(-1.0, 1.0, 1.0)); /* the same points: the unit sphere is its own mirror image */
    bool oom;
    cJSON *t = pbrt_transform_json(m, &oom);
    if (!t) {
        if (oom)
            pbrt_fail(&S->L, "%s: out of memory", what);
        else
            pbrt_unsupported(&S->L, "%s: a transform with shear", what);
        return NULL;
    }
    cJSON *s = cJSON_CreateObject();
    cJSON_AddStringToObject(s, "type", type);
    cJSON_AddItemToObject(s, "transform", t);
    return s;
}

/* pbrt's disk (at z = height, radius, innerradius, phimax) and cylinder (radius, zmin, zmax,
 * phimax) as triangles, PBRT_ROUND_SEGMENTS per full turn, corners on the exact surface:
 * the facets fall inside it by at most r (1 - cos(pi / 2048)) = 1.2e-6 r, and their normals
 * turn from the surface's by at most pi / 2048 (0.09 degrees). Object space, z up, as pbrt
 * places them; transformed by the current transform. */
#define PBRT_ROUND_SEGMENTS 2048
static brume_status round_params(pbrt_state *S, params *ps, const char *what, bool disk, tris *t)
{
    lexer *L = &S->L;
    double r = 1.0, r_in = 0.0, z0 = disk ? 0.0 : -1.0, z1 = 1.0, phimax = 360.0;
    brume_status st;
    if ((st = pbrt_get_float(L, ps, "radius", &r)) || (st = pbrt_get_float(L, ps, "phimax", &phimax)) ||
        (disk && ((st = pbrt_get_float(L, ps, "height", &z0)) || (st = pbrt_get_float(L, ps, "innerradius", &r_in)))) ||
        (!disk && ((st = pbrt_get_float(L, ps, "zmin", &z0)) || (st = pbrt_get_float(L, ps, "zmax", &z1)))) ||
        (st = pbrt_all_used(L, ps, what)))
        return st;
    if (disk)
        z1 = z0;
    if (!(r > 0.0 && r <= 1e18 && r_in >= 0.0 && r_in < r && phimax > 0.0 && phimax <= 360.0 && fabs(z0) <= 1e18 &&
          fabs(z1) <= 1e18 && (disk || z1 != z0)))
        return pbrt_fail(L, "%s: need 0 <= innerradius < radius, phimax in (0, 360] and zmin != zmax, finite", what);
    int n = (int)ceil(PBRT_ROUND_SEGMENTS * phimax / 360.0);
    double phi = phimax * PI / 180.0, rr[2] = {disk ? r_in : r, r}, zz[2] = {z0, z1};
    bool fan = disk && r_in == 0.0; /* the inner ring is the centre: one triangle a segment */
    t->nv = 2 * (n + 1);
    t->nt = fan ? n : 2 * n;
    t->P = malloc((size_t)t->nv * 3 * sizeof *t->P);
    t->idx = malloc((size_t)t->nt * 3 * sizeof *t->idx);
    t->uv = malloc((size_t)t->nv * 2 * sizeof *t->uv);
    if (!t->P || !t->idx || !t->uv)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s:%d: %s: out of memory", L->file, L->dir_line, what);
    m4 ctm = S->a[S->depth].ctm;
    for (int i = 0; i <= n; i++) /* ring 0: inner edge or bottom, ring 1: outer edge or top */
        for (int k = 0; k < 2; k++) {
            double a = phi * i / n;
            vec3 w = pbrt_m4_point(ctm, v3(rr[k] * cos(a), rr[k] * sin(a), zz[k]));
            double *q = &t->P[3 * (2 * i + k)];
            q[0] = w.x, q[1] = w.y, q[2] = w.z;
            /* pbrt-v4's: u = phi / phimax; v = (rmax - r) / (rmax - rmin) on a disk, (z - zmin) /
               (zmax - zmin) on a cylinder */
            t->uv[2 * (2 * i + k)] = (double)i / n;
            t->uv[2 * (2 * i + k) + 1] = disk ? 1.0 - k : (zz[k] - fmin(z0, z1)) / fabs(z1 - z0);
        }
    /* a segment: a, c on ring 0 at i, i + 1; b, d on ring 1; facing pbrt's normal, +z for the
       disk, outwards for the cylinder */
    int *q = t->idx;
    for (int i = 0; i < n; i++) {
        int a = 2 * i, b = 2 * i + 1, c = 2 * i + 2, d = 2 * i + 3;
        int one[3] = {a, b, d}, two[3] = {a, d, c};
        if (!disk) {
            one[1] = d, one[2] = b;
            two[1] = c, two[2] = d;
        }
        memcpy(q, one, sizeof one);
        q += 3;
        if (!fan) {
            memcpy(q, two, sizeof two);
            q += 3;
        }
    }
    return BRUME_OK;
}

/* "plymesh": the file, read by assimp as any mesh file. */
static brume_status shape_plymesh(pbrt_state *S, params *ps, const char *what, bool interface)
{
    lexer *L = &S->L;
    brume_status st;
    char file[1024] = "", abs[PATH_MAX];
    if ((st = pbrt_get_string(L, ps, "filename", file, sizeof file)) || (st = pbrt_all_used(L, ps, what)))
        return st;
    if (!file[0])
        return pbrt_fail(L, "%s: no \"string filename\"", what);
    if ((st = pbrt_resolve_file(S, what, file, abs)))
        return st;
    if (S->a[S->depth].area && !S->a[S->depth].area_two_sided)
        return pbrt_unsupported(L, "%s: a one-sided area light on a PLY mesh (pbrt-v4 turns the emitting side toward the "
                                   "file's normals; give \"bool twosided\" true)", what);
    cJSON *s = placed_surface(S, what, "mesh");
    if (!s)
        return err_status();
    cJSON_AddStringToObject(s, "file", abs);
    if (!interface)
        return shape_surface(S, s);
    /* the box a homogeneous medium needs: the file's points through the transform */
    double *P = NULL, b[6];
    int *idx = NULL, nv = 0, nt = 0;
    if (mesh_load(abs, &P, &nv, &idx, &nt) != BRUME_OK) {
        cJSON_Delete(s);
        return pbrt_fail(L, "%s: %s", what, err_message());
    }
    for (int i = 0; i < nv; i++) {
        vec3 w = pbrt_m4_point(S->a[S->depth].ctm, v3(P[3 * i], P[3 * i + 1], P[3 * i + 2]));
        P[3 * i] = w.x, P[3 * i + 1] = w.y, P[3 * i + 2] = w.z;
    }
    points_box(P, nv, b);
    free(P);
    free(idx);
    return shape_interface(S, s, b);
}

/* Whether the current transform is a similarity (rotation, mirror, uniform scale,
 * translation): what keeps a sphere a sphere. */
static bool ctm_similar(const pbrt_state *S)
{
    const double *m = S->a[S->depth].ctm.m;
    double g[3][3]; /* the columns' Gram matrix */
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            g[i][j] = m[i] * m[j] + m[4 + i] * m[4 + j] + m[8 + i] * m[8 + j];
    double s2 = (g[0][0] + g[1][1] + g[2][2]) / 3.0, tol = 1e-9 * s2;
    return s2 > 0.0 && fabs(g[0][0] - s2) <= tol && fabs(g[1][1] - s2) <= tol && fabs(g[2][2] - s2) <= tol &&
           fabs(g[0][1]) <= tol && fabs(g[0][2]) <= tol && fabs(g[1][2]) <= tol;
}

/* A sphere under a transform that makes it an ellipsoid, as the interface pbrt-v4's
 * disney-cloud bounds its grid with: the triangles of SPHERE_LON x SPHERE_LAT cells between
 * meridians and parallels, corners on the sphere, facing out in object space (tris_json
 * reverses them under a mirror). The facets lie inside the surface by at most
 * r (1 - cos(pi / SPHERE_LON)) = 7.5e-5 r, before the transform. */
#define SPHERE_LON 256
#define SPHERE_LAT 128
static brume_status sphere_tris(pbrt_state *S, const char *what, double r, tris *t)
{
    t->nv = 2 + (SPHERE_LAT - 1) * SPHERE_LON;
    t->nt = 2 * SPHERE_LON * (SPHERE_LAT - 1);
    t->P = malloc((size_t)t->nv * 3 * sizeof *t->P);
    t->idx = malloc((size_t)t->nt * 3 * sizeof *t->idx);
    if (!t->P || !t->idx)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s:%d: %s: out of memory", S->L.file, S->L.dir_line, what);
    m4 ctm = S->a[S->depth].ctm;
    for (int v = 0; v < t->nv; v++) { /* 0: the north pole, 1: the south pole, then ring by ring */
        int j = v < 2 ? 0 : (v - 2) / SPHERE_LON + 1, i = v < 2 ? 0 : (v - 2) % SPHERE_LON;
        double theta = v == 0 ? 0.0 : v == 1 ? PI : PI * j / SPHERE_LAT, phi = 2.0 * PI * i / SPHERE_LON;
        vec3 w = pbrt_m4_point(ctm, v3(r * sin(theta) * cos(phi), r * sin(theta) * sin(phi), r * cos(theta)));
        t->P[3 * v] = w.x, t->P[3 * v + 1] = w.y, t->P[3 * v + 2] = w.z;
    }
    int *q = t->idx;
    for (int j = 0; j < SPHERE_LAT; j++) /* band j between parallels j and j + 1 */
        for (int i = 0; i < SPHERE_LON; i++) {
            int i1 = (i + 1) % SPHERE_LON;
            int a = j == 0 ? 0 : 2 + (j - 1) * SPHERE_LON + i, b = j == 0 ? 0 : 2 + (j - 1) * SPHERE_LON + i1;
            int c = j == SPHERE_LAT - 1 ? 1 : 2 + j * SPHERE_LON + i, d = j == SPHERE_LAT - 1 ? 1 : 2 + j * SPHERE_LON + i1;
            /* (a, c, d) and (a, d, b) face out: c lies south of a, d east of c */
            if (j < SPHERE_LAT - 1) /* not at the south pole, where c = d */
                *q++ = a, *q++ = c, *q++ = d;
            if (j > 0) /* not at the north pole, where a = b */
                *q++ = a, *q++ = d, *q++ = b;
        }
    t->nt = (int)(q - t->idx) / 3;
    return BRUME_OK;
}

/* "sphere": a brume sphere, or the box of an "interface" sphere's media. */
static brume_status shape_sphere(pbrt_state *S, params *ps, const char *what, bool interface)
{
    lexer *L = &S->L;
    const attrs *a = &S->a[S->depth];
    brume_status st;
    double radius = 1.0;
    if ((st = pbrt_get_float(L, ps, "radius", &radius)) || (st = pbrt_all_used(L, ps, what)))
        return st;
    const double *c = a->ctm.m;
    if (!interface && a->textured &&
        !(c[0] > 0.0 && c[1] == 0.0 && c[2] == 0.0 && c[4] == 0.0 && c[5] == c[0] && c[6] == 0.0 && c[8] == 0.0 &&
          c[9] == 0.0 && c[10] == c[0]))
        return pbrt_unsupported(L, "%s: a textured sphere turned or mirrored (brume maps a sphere's (u, v) in "
                                   "world axes; a pbrt view without \"Scale -1 1 1\" mirrors the world)", what);
    if (!ctm_similar(S) && !interface)
        return pbrt_unsupported(L, "%s: a sphere under a non-uniform scale or shear (an ellipsoid: brume draws "
                                   "spheres; as an interface it bounds media)", what);
    if (!ctm_similar(S)) {
        if (!(radius > 0.0 && radius <= 1e18))
            return pbrt_fail(L, "%s: \"float radius\" %g is not in (0, 1e18]", what, radius);
        tris t = {0};
        double b[6];
        if ((st = sphere_tris(S, what, radius, &t)) == BRUME_OK &&
            (st = pbrt_count_inline(S, what, 3.0 * t.nv + 3.0 * t.nt)) == BRUME_OK) {
            points_box(t.P, t.nv, b);
            st = shape_interface(S, tris_json(&t, ctm_mirrors(S)), b);
        }
        tris_free(&t);
        return st;
    }
    cJSON *s = placed_surface(S, what, "sphere");
    if (!s)
        return err_status();
    cJSON_AddNumberToObject(s, "radius", radius);
    if (!interface)
        return shape_surface(S, s);
    double P[24], b[6]; /* the box: the corners of the object's cube around it */
    for (int i = 0; i < 8; i++) {
        vec3 w = pbrt_m4_point(S->a[S->depth].ctm, v3(i & 1 ? radius : -radius, i & 2 ? radius : -radius,
                                                      i & 4 ? radius : -radius));
        P[3 * i] = w.x, P[3 * i + 1] = w.y, P[3 * i + 2] = w.z;
    }
    points_box(P, 8, b);
    return shape_interface(S, s, b);
}

static brume_status shape_read(pbrt_state *S, const char *type, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    attrs *a = &S->a[S->depth];
    char what[160];
    snprintf(what, sizeof what, "Shape \"%s\"", type);
    bool interface = strcmp(a->material, "interface") == 0;
    if (interface && S->a[S->depth].area)
        return pbrt_unsupported(L, "%s: an area light on an \"interface\" shape (brume does not draw it)", what);
    if (strcmp(type, "sphere") == 0)
        return shape_sphere(S, ps, what, interface);
    if (strcmp(type, "plymesh") == 0)
        return shape_plymesh(S, ps, what, interface);
    bool tri = strcmp(type, "trianglemesh") == 0, round = strcmp(type, "disk") == 0 || strcmp(type, "cylinder") == 0;
    if (!tri && !round && strcmp(type, "bilinearmesh") != 0)
        return pbrt_unsupported(L, "%s: not supported by brume's pbrt reader (sphere, disk, cylinder, trianglemesh, "
                                   "bilinearmesh, plymesh)", what);
    if (round && interface)
        return pbrt_unsupported(L, "%s: an \"interface\" shape that bounds no volume (a medium needs a closed shape)", what);
    /* shading normals and tangents do not change a diffuse surface's geometry: read and not
       used (brume shades by the geometric normal); uv is read for a textured material */
    if (!round)
        pbrt_get(ps, "N");
    param *uv = round ? NULL : pbrt_get(ps, "uv");
    if (tri) {
        pbrt_get(ps, "S");
        pbrt_get(ps, "faceIndices");
    }
    tris t = {0};
    int *quad = NULL;
    if (round)
        st = round_params(S, ps, what, strcmp(type, "disk") == 0, &t);
    else if ((st = mesh_params(S, ps, what, tri ? 3 : 4, &t, &quad)) == BRUME_OK &&
             (st = pbrt_all_used(L, ps, what)) == BRUME_OK && !tri)
        st = bilinear_tris(L, quad, &t);
    if (st) {
        free(quad);
        tris_free(&t);
        return st;
    }
    free(quad);
    if (!interface && !round && a->textured && (st = shape_uv(S, what, uv, tri, &t))) {
        tris_free(&t);
        return st;
    }
    if (interface) {
        double b[6];
        points_box(t.P, t.nv, b);
        if ((st = pbrt_count_inline(S, what, 3.0 * t.nv + 3.0 * t.nt)) == BRUME_OK)
            st = shape_interface(S, tris_json(&t, ctm_mirrors(S)), b);
        tris_free(&t);
        return st;
    }
    if ((st = emitter_facing(S, ps, what, &t)) || (st = pbrt_count_inline(S, what, 3.0 * t.nv + 3.0 * t.nt))) {
        tris_free(&t);
        return st;
    }
    cJSON *s = tris_json(&t, false);
    if (a->textured)
        cJSON_AddItemToObject(s, "uvs", cJSON_CreateDoubleArray(t.uv, 2 * t.nv));
    tris_free(&t);
    return shape_surface(S, s);
}

/* The media on a shape's two sides. In pbrt-v4 a MediumInterface whose sides are one medium
 * is no transition: rays keep their medium through the shape, as through one without it
 * (an "interface" shape of one medium on both sides is refused: it would change nothing). No
 * ray crosses an opaque shape, so its MediumInterface changes nothing either. What is left,
 * *media, is an "interface" shape with a transition: it bounds its media (shape_interface). */
static brume_status shape_sides(pbrt_state *S, bool *media)
{
    const attrs *a = &S->a[S->depth];
    const bool interface = strcmp(a->material, "interface") == 0;
    *media = false;
    if (strcmp(a->inside, a->outside) == 0) {
        if (a->inside[0] && interface)
            return pbrt_fail(&S->L, "MediumInterface \"%s\" \"%s\": the same medium on both sides of an "
                                    "\"interface\" shape is no transition in pbrt-v4 (the shape changes nothing); "
                                    "the medium inside with nothing outside is MediumInterface \"%s\" \"\"",
                             a->inside, a->outside, a->inside);
        return BRUME_OK;
    }
    *media = interface;
    return BRUME_OK;
}

brume_status pbrt_shape_directive(pbrt_state *S, const char *type, params *ps)
{
    attrs *a = &S->a[S->depth];
    bool media;
    brume_status st = shape_sides(S, &media);
    if (st)
        return st;
    /* the shape is read with its media when it bounds them, else none; then the attributes restored */
    char in[sizeof a->inside], out[sizeof a->outside];
    memcpy(in, a->inside, sizeof in);
    memcpy(out, a->outside, sizeof out);
    if (!media)
        a->inside[0] = a->outside[0] = '\0';
    st = shape_read(S, type, ps);
    memcpy(a->inside, in, sizeof in);
    memcpy(a->outside, out, sizeof out);
    return st;
}
