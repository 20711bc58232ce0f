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
    double area; /* pbrt-v4's Area() of each of the shapes these are (an area light's power) */
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

/* The media of the MediumInterface in effect on the shape s (its world box b), which bounds
 * them (docs/surfaces.md, "How surfaces meet media"): the inside one behind pbrt's normal,
 * the outside one before it, which replaces whatever medium a ray was in, as in pbrt-v4. A
 * name that no MakeNamedMedium has given yet is resolved at the end of the file
 * (pbrt_medium_bind). The shape is named by its file and line: what commit's refusals (an
 * open mesh) then say. */
static brume_status shape_media(pbrt_state *S, cJSON *s, const double b[6])
{
    attrs *a = &S->a[S->depth];
    const char *base = strrchr(S->L.file, '/');
    char name[64];
    snprintf(name, sizeof name, "%.50s:%d", base ? base + 1 : S->L.file, S->L.dir_line);
    cJSON_AddStringToObject(s, "name", name);
    brume_status st = BRUME_OK;
    if (a->inside[0] && (st = pbrt_medium_bind(S, a->inside, b, false)) == BRUME_OK)
        cJSON_AddStringToObject(s, "medium_inside", a->inside);
    if (st == BRUME_OK && a->outside[0] && (st = pbrt_medium_bind(S, a->outside, b, true)) == BRUME_OK)
        cJSON_AddStringToObject(s, "medium_outside", a->outside);
    return st;
}

/* An "interface" shape s (owned from here; its box b in world space): a surface with no
 * material that bounds the media of its MediumInterface, crossed by every ray. */
static brume_status shape_interface(pbrt_state *S, cJSON *s, const double b[6])
{
    attrs *a = &S->a[S->depth];
    if (!a->inside[0] && !a->outside[0]) { /* no medium changes there: pbrt-v4 draws nothing */
        cJSON_Delete(s);
        return BRUME_OK;
    }
    cJSON_AddStringToObject(cJSON_AddObjectToObject(s, "material"), "type", "interface");
    brume_status st = shape_media(S, s, b);
    if (st != BRUME_OK) {
        cJSON_Delete(s);
        return st;
    }
    cJSON_AddItemToArray(S->surfaces, s);
    return BRUME_OK;
}

/* The inline mesh of the triangles t (world space), wound as brume's front (pbrt_tris_facing). */
static cJSON *tris_json(const tris *t)
{
    cJSON *s = cJSON_CreateObject();
    cJSON_AddStringToObject(s, "type", "mesh");
    cJSON_AddItemToObject(s, "positions", cJSON_CreateDoubleArray(t->P, 3 * t->nv));
    cJSON_AddItemToObject(s, "indices", cJSON_CreateIntArray(t->idx, 3 * t->nt));
    return s;
}

/* t's triangles turned to pbrt-v4's front (pbrt_tris_facing; N: the mesh's "normal N" or
 * NULL; quadric: a sphere's, disk's or cylinder's). */
static brume_status tris_face(pbrt_state *S, const char *what, const param *N, bool quadric, tris *t)
{
    unsigned char *flip = NULL;
    brume_status st = pbrt_tris_facing(S, what, N, quadric, t->P, t->nv, t->idx, t->nt, &flip);
    pbrt_tris_flip(t->idx, t->nt, flip);
    free(flip);
    return st;
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

/* A drawn shape: s (owned from here) with the current material; b: its world box when it
 * bounds the media of its MediumInterface (a dielectric's), else NULL; area: pbrt-v4's Area()
 * of each shape it is, for an area light's power (not positive: unknown, or differing from
 * one triangle to the next, and refused then). */
static brume_status shape_surface(pbrt_state *S, cJSON *s, const double *b, double area)
{
    attrs *a = &S->a[S->depth];
    cJSON *mat = pbrt_material_json(S, a);
    if (!mat) {
        cJSON_Delete(s);
        return err_status();
    }
    cJSON_AddItemToObject(s, "material", mat);
    if (a->area) {
        double k = a->area_two_sided ? 0.5 : 1.0, Le[3];
        if (a->area_power > 0.0 && !(area > 0.0)) {
            cJSON_Delete(s);
            return pbrt_unsupported(&S->L, "Shape: an area light's \"power\" on a shape whose triangles differ in area "
                                           "or on a PLY mesh (pbrt-v4 gives each triangle, a shape of its own, that power)");
        }
        for (int c = 0; c < 3; c++)
            Le[c] = a->area_power > 0.0 ? a->area_L[c] * k * a->area_power / (PI * area) : a->area_L[c];
        cJSON_AddItemToObject(mat, "emission", cJSON_CreateDoubleArray(Le, 3));
        if (a->area_two_sided)
            cJSON_AddBoolToObject(mat, "two_sided", true);
    }
    brume_status st = b ? shape_media(S, s, b) : BRUME_OK;
    if (st != BRUME_OK) {
        cJSON_Delete(s);
        return st;
    }
    cJSON_AddItemToArray(S->surfaces, s);
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
    /* pbrt-v4's Disk::Area() and Cylinder::Area(), in object space */
    t->area = disk ? 0.5 * phi * (r * r - r_in * r_in) : fabs(z1 - z0) * r * phi;
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

/* Whether a shape's front matters: it emits from one side, it is a dielectric (outside
 * before its front) or it bounds media (bound). */
static bool shape_sided(const attrs *a, bool bound)
{
    return (a->area && !a->area_two_sided) || strcmp(a->material, "dielectric") == 0 || bound;
}

/* "plymesh": the file, read by assimp as any mesh file; brume's mesh builder keeps the
 * file's winding carried through the transform as its front (reversing it under a mirror),
 * pbrt-v4's geometric normal of a mesh without normals; ReverseOrientation reverses it
 * ("reverse_orientation"). A file with normals, whose triangles pbrt-v4 turns toward them,
 * is refused where the side matters. */
static brume_status shape_plymesh(pbrt_state *S, params *ps, const char *what, bool interface, bool bound)
{
    lexer *L = &S->L;
    const attrs *a = &S->a[S->depth];
    brume_status st;
    char file[1024] = "", abs[PATH_MAX];
    if ((st = pbrt_get_string(L, ps, "filename", file, sizeof file)) || (st = pbrt_all_used(L, ps, what)))
        return st;
    if (!file[0])
        return pbrt_fail(L, "%s: no \"string filename\"", what);
    if ((st = pbrt_resolve_file(S, what, file, abs)))
        return st;
    if (shape_sided(a, bound || interface) && pbrt_ply_has_normals(abs))
        return pbrt_unsupported(L, "%s: %s from a PLY mesh with vertex normals (pbrt-v4 turns each triangle's front toward "
                                   "them; brume reads the winding)", what,
                                a->area && !a->area_two_sided ? "a one-sided area light"
                                : interface || bound      ? "media bounded"
                                                          : "a dielectric");
    cJSON *s = placed_surface(S, what, "mesh");
    if (!s)
        return err_status();
    cJSON_AddStringToObject(s, "file", abs);
    if (a->reverse)
        cJSON_AddBoolToObject(s, "reverse_orientation", true);
    if (!interface && !bound)
        return shape_surface(S, s, NULL, 0.0);
    /* the box a homogeneous medium needs: the file's points through the transform */
    double *P = NULL, b[6];
    int *idx = NULL, nv = 0, nt = 0;
    if (mesh_load(abs, &P, &nv, &idx, &nt) != BRUME_OK) {
        cJSON_Delete(s);
        return pbrt_fail(L, "%s: %s", what, err_message());
    }
    for (int i = 0; i < nv; i++) {
        vec3 w = pbrt_m4_point(a->ctm, v3(P[3 * i], P[3 * i + 1], P[3 * i + 2]));
        P[3 * i] = w.x, P[3 * i + 1] = w.y, P[3 * i + 2] = w.z;
    }
    points_box(P, nv, b);
    free(P);
    free(idx);
    return interface ? shape_interface(S, s, b) : shape_surface(S, s, b, 0.0);
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

/* A sphere as SPHERE_LON x SPHERE_LAT cells of triangles turned to pbrt-v4's front: an
 * ellipsoid, or a sphere whose front faces in (pbrt_quadric_reversed). */
static brume_status sphere_mesh(pbrt_state *S, const char *what, double radius, bool interface, bool bound)
{
    if (!(radius > 0.0 && radius <= 1e18))
        return pbrt_fail(&S->L, "%s: \"float radius\" %g is not in (0, 1e18]", what, radius);
    tris t = {0};
    double b[6];
    brume_status st;
    if ((st = sphere_tris(S, what, radius, &t)) == BRUME_OK &&
        (st = pbrt_count_inline(S, what, 3.0 * t.nv + 3.0 * t.nt)) == BRUME_OK &&
        (st = tris_face(S, what, NULL, true, &t)) == BRUME_OK) {
        points_box(t.P, t.nv, b);
        st = interface ? shape_interface(S, tris_json(&t), b)
                       : shape_surface(S, tris_json(&t), bound ? b : NULL, 4.0 * PI * radius * radius);
    }
    tris_free(&t);
    return st;
}

/* "sphere": a brume sphere, or the box of an "interface" sphere's media. */
static brume_status shape_sphere(pbrt_state *S, params *ps, const char *what, bool interface, bool bound)
{
    lexer *L = &S->L;
    const attrs *a = &S->a[S->depth];
    brume_status st;
    double radius = 1.0;
    if ((st = pbrt_get_float(L, ps, "radius", &radius)) || (st = pbrt_all_used(L, ps, what)))
        return st;
    const double *c = a->ctm.m;
    const bool inward = pbrt_quadric_reversed(S) && shape_sided(a, bound || interface);
    if (!interface && a->textured &&
        (inward || !(c[0] > 0.0 && c[1] == 0.0 && c[2] == 0.0 && c[4] == 0.0 && c[5] == c[0] && c[6] == 0.0 &&
                     c[8] == 0.0 && c[9] == 0.0 && c[10] == c[0])))
        return pbrt_unsupported(L, "%s: a textured sphere turned, mirrored or reversed (brume maps a sphere's (u, v) in "
                                   "world axes; a pbrt view without \"Scale -1 1 1\" mirrors the world)", what);
    if (!ctm_similar(S) && !interface)
        return pbrt_unsupported(L, "%s: a sphere under a non-uniform scale or shear (an ellipsoid: brume draws "
                                   "spheres; as an interface it bounds media)", what);
    if (!ctm_similar(S) || inward)
        return sphere_mesh(S, what, radius, interface, bound);
    cJSON *s = placed_surface(S, what, "sphere");
    if (!s)
        return err_status();
    cJSON_AddNumberToObject(s, "radius", radius);
    const double area = 4.0 * PI * radius * radius; /* pbrt-v4's Sphere::Area(), in object space */
    if (!interface && !bound)
        return shape_surface(S, s, NULL, area);
    double P[24], b[6]; /* the box: the corners of the object's cube around it */
    for (int i = 0; i < 8; i++) {
        vec3 w = pbrt_m4_point(S->a[S->depth].ctm, v3(i & 1 ? radius : -radius, i & 2 ? radius : -radius,
                                                      i & 4 ? radius : -radius));
        P[3 * i] = w.x, P[3 * i + 1] = w.y, P[3 * i + 2] = w.z;
    }
    points_box(P, 8, b);
    return interface ? shape_interface(S, s, b) : shape_surface(S, s, b, area);
}

/* The world area of each group of `per` triangles of t (a triangle, or a bilinear patch's
 * two), pbrt-v4's Triangle::Area() and BilinearPatch::Area() of a planar patch: one number when
 * all are equal (to 1e-9 of it), else -1. */
static double tris_area(const tris *t, int per)
{
    double first = -1.0;
    for (int g = 0; g < t->nt / per; g++) {
        double A = 0.0;
        for (int k = 0; k < per; k++) {
            const int *v = &t->idx[3 * (per * g + k)];
            vec3 p0 = v3(t->P[3 * v[0]], t->P[3 * v[0] + 1], t->P[3 * v[0] + 2]);
            vec3 p1 = v3(t->P[3 * v[1]], t->P[3 * v[1] + 1], t->P[3 * v[1] + 2]);
            vec3 p2 = v3(t->P[3 * v[2]], t->P[3 * v[2] + 1], t->P[3 * v[2] + 2]);
            A += 0.5 * v3_length(v3_cross(v3_sub(p1, p0), v3_sub(p2, p0)));
        }
        if (g == 0)
            first = A;
        else if (!(fabs(A - first) <= 1e-9 * first))
            return -1.0;
    }
    return first;
}

/* A Shape's triangles (trianglemesh, bilinearmesh, disk, cylinder) into t, world space,
 * turned to pbrt-v4's front, with their texture coordinates where the material is textured. */
static brume_status shape_tris(pbrt_state *S, const char *type, params *ps, const char *what, tris *t)
{
    lexer *L = &S->L;
    const attrs *a = &S->a[S->depth];
    const bool tri = strcmp(type, "trianglemesh") == 0, round = strcmp(type, "disk") == 0 || strcmp(type, "cylinder") == 0;
    /* shading normals turn the front (pbrt_tris_facing); brume shades by the geometric normal.
       Tangents do not change the geometry: read and not used; uv is read for a texture */
    static const char *const normals[] = {"normal", "normal3", NULL};
    param *N = NULL, *uv = round ? NULL : pbrt_get(ps, "uv");
    brume_status st = round ? BRUME_OK : pbrt_get_array(L, ps, "N", normals, &N);
    if (tri) {
        pbrt_get(ps, "S");
        pbrt_get(ps, "faceIndices");
    }
    int *quad = NULL;
    if (st == BRUME_OK && round)
        st = round_params(S, ps, what, strcmp(type, "disk") == 0, t);
    else if (st == BRUME_OK && (st = mesh_params(S, ps, what, tri ? 3 : 4, t, &quad)) == BRUME_OK &&
             (st = pbrt_all_used(L, ps, what)) == BRUME_OK && !tri)
        st = bilinear_tris(L, quad, t);
    free(quad);
    if (st == BRUME_OK && !round)
        t->area = tris_area(t, tri ? 1 : 2);
    unsigned char *flip = NULL;
    if (st == BRUME_OK)
        st = pbrt_tris_facing(S, what, N && N->n > 0 ? N : NULL, round, t->P, t->nv, t->idx, t->nt, &flip);
    /* texture coordinates before the turn: pbrt-v4's default (u, v) follow the file's order */
    if (st == BRUME_OK && strcmp(a->material, "interface") != 0 && !round && a->textured)
        st = shape_uv(S, what, uv, tri, t);
    if (st == BRUME_OK)
        pbrt_tris_flip(t->idx, t->nt, flip);
    free(flip);
    return st;
}

static brume_status shape_read(pbrt_state *S, const char *type, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    attrs *a = &S->a[S->depth];
    char what[160];
    snprintf(what, sizeof what, "Shape \"%s\"", type);
    const bool interface = strcmp(a->material, "interface") == 0;
    /* a drawn shape a ray crosses (a dielectric) that bounds its MediumInterface's media */
    const bool bound = !interface && (a->inside[0] || a->outside[0]);
    if (interface && S->a[S->depth].area)
        return pbrt_unsupported(L, "%s: an area light on an \"interface\" shape (brume does not draw it)", what);
    if (strcmp(type, "sphere") == 0)
        return shape_sphere(S, ps, what, interface, bound);
    if (strcmp(type, "plymesh") == 0)
        return shape_plymesh(S, ps, what, interface, bound);
    bool tri = strcmp(type, "trianglemesh") == 0, round = strcmp(type, "disk") == 0 || strcmp(type, "cylinder") == 0;
    if (!tri && !round && strcmp(type, "bilinearmesh") != 0)
        return pbrt_unsupported(L, "%s: not supported by brume's pbrt reader (sphere, disk, cylinder, trianglemesh, "
                                   "bilinearmesh, plymesh)", what);
    if (round && (interface || bound))
        return pbrt_unsupported(L, "%s: %s shape that bounds no volume (a medium needs a closed shape)", what,
                                interface ? "an \"interface\"" : "a dielectric MediumInterface");
    tris t = {0};
    if ((st = shape_tris(S, type, ps, what, &t)) || (st = pbrt_count_inline(S, what, 3.0 * t.nv + 3.0 * t.nt))) {
        tris_free(&t);
        return st;
    }
    double b[6];
    points_box(t.P, t.nv, b);
    cJSON *s = tris_json(&t);
    if (!interface && a->textured)
        cJSON_AddItemToObject(s, "uvs", cJSON_CreateDoubleArray(t.uv, 2 * t.nv));
    tris_free(&t);
    return interface ? shape_interface(S, s, b) : shape_surface(S, s, bound ? b : NULL, t.area);
}

/* The media on a shape's two sides. In pbrt-v4 a MediumInterface whose sides are one medium
 * is no transition: rays keep their medium through the shape, as through one without it
 * (an "interface" shape of one medium on both sides is refused: it would change nothing). No
 * ray crosses an opaque shape, so its MediumInterface changes nothing either. What is left,
 * *media, is an "interface" or "dielectric" shape with a transition: it bounds its media
 * (shape_media), the dielectric's inside behind its front as pbrt-v4's. */
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
    *media = interface || strcmp(a->material, "dielectric") == 0;
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
