/* pbrt_facing.c - the front of a pbrt-v4 shape as brume's winding: which side emits a
 * one-sided area light, which side of a dielectric is outside, and which of a
 * MediumInterface's media lies on which side (docs/pbrt.md, "ReverseOrientation"). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/vec.h"
#include "scene/pbrt.h"

static double m4_det3(const m4 *a)
{
    const double *c = a->m;
    return c[0] * (c[5] * c[10] - c[6] * c[9]) - c[1] * (c[4] * c[10] - c[6] * c[8]) + c[2] * (c[4] * c[9] - c[5] * c[8]);
}

bool pbrt_ctm_mirrors(const pbrt_state *S) { return m4_det3(&S->a[S->depth].ctm) < 0.0; }

/* pbrt-v4's quadrics (sphere, disk, cylinder) compute their normal in object space, reverse
 * it where ReverseOrientation or a handedness-swapping transform says so (flipNormal), and
 * carry it to the world as a normal: under a mirror the world normal is the carried one
 * reversed. The reader's own mirror of the world (pbrt_camera.c) is not a transform of the
 * file's, so it does not count. */
bool pbrt_quadric_reversed(const pbrt_state *S)
{
    return S->a[S->depth].reverse != (pbrt_ctm_mirrors(S) != S->mirror);
}

brume_status pbrt_tris_facing(pbrt_state *S, const char *what, const param *N, bool quadric, const double *P, int nv,
                              const int *idx, int nt, unsigned char **flip)
{
    const attrs *a = &S->a[S->depth];
    *flip = NULL;
    if (N && N->n != 3 * nv)
        return pbrt_fail(&S->L, "%s: \"normal N\" has %d numbers, not 3 for each of the %d points of P", what, N->n, nv);
    m4 inv;
    if (N && !pbrt_m4_inverse(a->ctm, &inv))
        return pbrt_fail(&S->L, "%s: the current transform is not invertible", what);
    unsigned char *f = malloc((size_t)nt + 1);
    if (!f)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s:%d: %s: out of memory", S->L.file, S->L.dir_line, what);
    /* the world winding's normal is the carried one reversed under a mirror; pbrt-v4's front
       is the carried one (triangles) reversed by ReverseOrientation, or the quadric's rule */
    const bool mirror = pbrt_ctm_mirrors(S);
    const bool reverse = quadric ? pbrt_quadric_reversed(S) : a->reverse;
    for (int t = 0; t < nt; t++) {
        bool fl = mirror != reverse;
        if (N) {
            /* FaceForward(n, ns) at the triangle's centre: ns the mean of its points' N, each
               carried by the inverse transpose and reversed by ReverseOrientation */
            const int *v = &idx[3 * t];
            vec3 p0 = v3(P[3 * v[0]], P[3 * v[0] + 1], P[3 * v[0] + 2]);
            vec3 p1 = v3(P[3 * v[1]], P[3 * v[1] + 1], P[3 * v[1] + 2]);
            vec3 p2 = v3(P[3 * v[2]], P[3 * v[2] + 1], P[3 * v[2] + 2]);
            vec3 ng = v3_cross(v3_sub(p1, p0), v3_sub(p2, p0)), ns = v3(0, 0, 0);
            for (int k = 0; k < 3; k++) {
                const double *n = &N->v[3 * v[k]];
                const double *m = inv.m;
                ns = v3_add(ns, v3(m[0] * n[0] + m[4] * n[1] + m[8] * n[2], m[1] * n[0] + m[5] * n[1] + m[9] * n[2],
                                   m[2] * n[0] + m[6] * n[1] + m[10] * n[2]));
            }
            if (a->reverse)
                ns = v3_neg(ns);
            double d = v3_dot(ng, ns);
            if (d != 0.0) /* a zero mean N keeps the normal as it is, as pbrt-v4's does */
                fl = d < 0.0;
        }
        f[t] = fl;
    }
    *flip = f;
    return BRUME_OK;
}

void pbrt_tris_flip(int *idx, int nt, const unsigned char *flip)
{
    for (int t = 0; flip && t < nt; t++)
        if (flip[t]) {
            int k = idx[3 * t + 1];
            idx[3 * t + 1] = idx[3 * t + 2];
            idx[3 * t + 2] = k;
        }
}

/* Whether the PLY file's vertices carry normals (its header names "nx"): pbrt-v4 then turns
 * each triangle's front toward them (FaceForward), which brume, reading positions only, does
 * not. Another format, or a header it cannot find: false. */
bool pbrt_ply_has_normals(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return false;
    char head[8192];
    size_t n = fread(head, 1, sizeof head - 1, f);
    fclose(f);
    head[n] = '\0';
    char *end = strstr(head, "end_header");
    if (strncmp(head, "ply", 3) != 0 || !end)
        return false;
    *end = '\0';
    for (char *p = strstr(head, "property"); p; p = strstr(p + 1, "property")) {
        char type[32], name[64];
        if (sscanf(p, "property %31s %63s", type, name) == 2 && strcmp(name, "nx") == 0)
            return true;
    }
    return false;
}
