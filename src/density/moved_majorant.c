/* moved_majorant.c - majorants of a density field moved by any displacement up to a radius:
 * the bound that velocity motion blur tracks against (docs/animation.md, "Velocity motion
 * blur").
 *
 * A medium blurred by its velocity is looked up at x - v(x) dt (medium.h): the density seen
 * at x is rho(y) for some y with |y - x| <= R = max |v| max |dt|. So
 *   rho(x - v(x) dt) <= max { rho(y) : |y - x| <= R },
 * the max filter of rho over a ball of radius R, and anything above that is a majorant. In
 * voxel space the ball lies within a box of half-widths P_a = R |row a of world->voxel|
 * (Cauchy-Schwarz on each row of the linear map), so a cell of rho's majorant lattice
 * bounds the moved field over the cells within ceil(P_a / cell) of it: the lattice's
 * majorants dilated by that many cells per axis, a separable max filter (three passes).
 * The result is a field of majorants only (no values: density_eval gives 0; no lower bound
 * and no control: 0), on the same lattice widened by the padding, or on cells of f^3 of
 * them when that lattice would exceed MOVED_MAX_CELLS. The tree majorants of a large
 * NanoVDB box have no lattice: one of 64 cells along the longest axis, each bounded by the
 * field's max, stands in for it (valid, loose). */
#include <stdlib.h>

#include "core/error.h"
#include "density/density_impl.h"

/* Cells of the moved majorant grid at most: 16 MiB of floats. */
#define MOVED_MAX_CELLS ((size_t)1 << 22)
/* Voxels a field may move within the shutter, at most (per axis, in its voxel space). */
#define MOVED_MAX_VOXELS 1e6

/* rho's majorant lattice: cells of mc voxels from voxel -moff, mn per axis; maj NULL: every
 * cell bounded by `uniform`. */
typedef struct lattice {
    int mn[3], mc, moff[3];
    const float *maj;
    float uniform;
} lattice;

static float lattice_at(const lattice *l, int i, int j, int k)
{
    return l->maj ? l->maj[(size_t)i + (size_t)l->mn[0] * ((size_t)j + (size_t)l->mn[1] * (size_t)k)] : l->uniform;
}

/* One pass of the max filter along axis ax: in has dims ni (cells of the source along ax,
 * already-filtered sizes on the others), out has no cells along ax; out cell o takes the
 * max of in cells [o f - lo, o f - lo + span) clipped to [0, ni[ax]). */
static void max_pass(const float *in, const int ni[3], float *out, const int no[3], int ax, int f, int lo, int span)
{
    const size_t sx = 1, sy = (size_t)ni[0], sz = (size_t)ni[0] * (size_t)ni[1];
    const size_t stride[3] = {sx, sy, sz};
    for (int k = 0; k < no[2]; k++)
        for (int j = 0; j < no[1]; j++)
            for (int i = 0; i < no[0]; i++) {
                const int o[3] = {i, j, k};
                int a = o[ax] * f - lo, b = a + span;
                a = a < 0 ? 0 : a;
                b = b > ni[ax] ? ni[ax] : b;
                size_t base = 0;
                for (int c = 0; c < 3; c++)
                    base += c == ax ? 0 : (size_t)o[c] * stride[c];
                float m = 0.0f;
                for (int q = a; q < b; q++) {
                    float v = in[base + (size_t)q * stride[ax]];
                    m = v > m ? v : m;
                }
                out[(size_t)i + (size_t)no[0] * ((size_t)j + (size_t)no[1] * (size_t)k)] = m;
            }
}

density *density_new_moved_majorant(const density *rho, double radius)
{
    if (!(radius >= 0.0) || !isfinite(radius)) {
        err_set(BRUME_ERROR_RANGE, "moved majorant: radius %g must be finite and >= 0", radius);
        return NULL;
    }
    lattice l = {.maj = rho->maj, .mc = rho->mcell};
    for (int a = 0; a < 3; a++) {
        l.mn[a] = rho->mn[a];
        l.moff[a] = rho->moff[a];
    }
    if (!rho->maj) { /* a large NanoVDB box's tree: a coarse lattice bounded by the max */
        int longest = rho->n[0] > rho->n[1] ? rho->n[0] : rho->n[1];
        longest = longest > rho->n[2] ? longest : rho->n[2];
        l.mc = (longest + 63) / 64;
        for (int a = 0; a < 3; a++) {
            l.mn[a] = (rho->n[a] + l.mc - 1) / l.mc;
            l.moff[a] = 0;
        }
        float u = (float)rho->rho_max;
        l.uniform = (double)u < rho->rho_max ? nextafterf(u, INFINITY) : u;
    }
    /* padding: cells of the lattice a point can reach within the radius, per axis */
    int Q[3];
    for (int a = 0; a < 3; a++) {
        const double *w = rho->w2v.m + 4 * a;
        double P = radius * sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        if (!(P <= MOVED_MAX_VOXELS)) {
            err_set(BRUME_ERROR_RANGE, "the velocity moves the field by up to %g voxels along axis %d within the "
                    "shutter: more than the %g brume tracks", P, a, MOVED_MAX_VOXELS);
            return NULL;
        }
        Q[a] = (int)ceil(P / l.mc);
    }
    /* the coarsening f: the moved grid's cells hold f^3 of the lattice's */
    int f = 1, M[3];
    for (;; f++) {
        size_t cells = 1;
        for (int a = 0; a < 3; a++) {
            M[a] = (int)(((int64_t)l.mn[a] + 2 * (int64_t)Q[a] + f - 1) / f);
            cells *= (size_t)M[a];
        }
        if (cells <= MOVED_MAX_CELLS)
            break;
    }
    density *d = calloc(1, sizeof *d);
    float *src = malloc((size_t)l.mn[0] * (size_t)l.mn[1] * (size_t)l.mn[2] * sizeof *src);
    float *p1 = malloc((size_t)M[0] * (size_t)l.mn[1] * (size_t)l.mn[2] * sizeof *p1);
    float *p2 = malloc((size_t)M[0] * (size_t)M[1] * (size_t)l.mn[2] * sizeof *p2);
    float *maj = malloc((size_t)M[0] * (size_t)M[1] * (size_t)M[2] * sizeof *maj);
    if (!d || !src || !p1 || !p2 || !maj) {
        free(d), free(src), free(p1), free(p2), free(maj);
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "moved majorant: out of memory for %d x %d x %d cells", M[0], M[1], M[2]);
        return NULL;
    }
    for (int k = 0; k < l.mn[2]; k++)
        for (int j = 0; j < l.mn[1]; j++)
            for (int i = 0; i < l.mn[0]; i++)
                src[(size_t)i + (size_t)l.mn[0] * ((size_t)j + (size_t)l.mn[1] * (size_t)k)] = lattice_at(&l, i, j, k);
    /* moved cell o covers lattice cells [o f - Q, (o + 1) f - Q); a point there reaches Q more
     * on each side: [o f - 2 Q, (o + 1) f) */
    int n0[3] = {l.mn[0], l.mn[1], l.mn[2]}, n1[3] = {M[0], l.mn[1], l.mn[2]}, n2[3] = {M[0], M[1], l.mn[2]};
    max_pass(src, n0, p1, n1, 0, f, 2 * Q[0], f + 2 * Q[0]);
    max_pass(p1, n1, p2, n2, 1, f, 2 * Q[1], f + 2 * Q[1]);
    max_pass(p2, n2, maj, M, 2, f, 2 * Q[2], f + 2 * Q[2]);
    free(src), free(p1), free(p2);
    if ((int64_t)M[0] * f * l.mc > INT32_MAX || (int64_t)M[1] * f * l.mc > INT32_MAX ||
        (int64_t)M[2] * f * l.mc > INT32_MAX) {
        free(d), free(maj);
        err_set(BRUME_ERROR_RANGE, "moved majorant: %d x %d x %d cells of %d voxels exceed the voxel range", M[0], M[1],
                M[2], f * l.mc);
        return NULL;
    }
    /* its voxel space: rho's shifted so that lattice cell -Q starts at 0; cells of f mc voxels */
    d->kind = DENSITY_GRID;
    d->filter = GRID_NEAREST;
    d->mcell = f * l.mc;
    for (int a = 0; a < 3; a++) {
        d->n[a] = M[a] * d->mcell;
        d->mn[a] = M[a];
        d->moff[a] = 0;
    }
    const affine3 shift = affine3_translate(
        v3(-(double)(Q[0] * l.mc + l.moff[0]), -(double)(Q[1] * l.mc + l.moff[1]), -(double)(Q[2] * l.mc + l.moff[2])));
    const affine3 v2w = affine3_compose(&rho->v2w, &shift);
    d->maj = maj;
    if (!density_set_placement(d, &v2w, "moved majorant")) {
        density_release(d);
        return NULL;
    }
    d->rho_min = 0.0;
    d->rho_max = rho->rho_max;
    d->memory = (size_t)M[0] * (size_t)M[1] * (size_t)M[2] * sizeof *maj;
    return d;
}
