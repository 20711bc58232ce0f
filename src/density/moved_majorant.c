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
 * The displacement is v(x) dt with v read at x itself, so a cell only needs the radius of
 * its own points' motion: with a local bound (the caller's, from the velocity's cell bounds
 * over the cell) each cell takes the filter of the smallest radius R 2^-l (or 0) at or above
 * it, one separable filter per level used.
 * The result is a field of majorants only (no values: density_eval gives 0; no lower bound
 * and no control: 0), on the same lattice widened by the padding, or on cells of f^3 of
 * them when that lattice would exceed MOVED_MAX_CELLS. The tree majorants of a large
 * NanoVDB box have no lattice: one of 64 cells along the longest axis, each bounded by the
 * field's max, stands in for it (valid, loose). */
#include <stdlib.h>

#include "core/budget.h"
#include "core/error.h"
#include "density/density_impl.h"

/* Cells of the moved majorant grid at most: 16 MiB of floats. */
#define MOVED_MAX_CELLS ((size_t)1 << 22)
/* Voxels a field may move within the shutter, at most (per axis, in its voxel space). */
#define MOVED_MAX_VOXELS 1e6
/* Radii of the local dilation: radius 2^-l for l < MOVED_LEVELS - 1, and 0. */
#define MOVED_LEVELS 8

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

double density_abs_bound_in_box(const density *d, box3 world_box)
{
    const double all = fmax(fabs(d->rho_min), fabs(d->rho_max));
    if (!d->maj || !d->mino || d->kind == DENSITY_BLOBS)
        return all;
    /* the cells the box touches, in cell space (the box's image's bounding box) */
    const box3 c = affine3_apply_box(&d->w2c, world_box);
    const double lo[3] = {c.lo.x, c.lo.y, c.lo.z}, hi[3] = {c.hi.x, c.hi.y, c.hi.z};
    int a0[3], a1[3];
    for (int a = 0; a < 3; a++) {
        if (!(lo[a] < d->mn[a]) || !(hi[a] >= 0.0)) /* outside the voxel box: lookups give 0 */
            return 0.0;
        a0[a] = lo[a] <= 0.0 ? 0 : (int)lo[a];
        a1[a] = hi[a] >= d->mn[a] - 1 ? d->mn[a] - 1 : (int)hi[a];
    }
    double m = 0.0;
    for (int k = a0[2]; k <= a1[2]; k++)
        for (int j = a0[1]; j <= a1[1]; j++)
            for (int i = a0[0]; i <= a1[0]; i++) {
                size_t q = (size_t)i + (size_t)d->mn[0] * ((size_t)j + (size_t)d->mn[1] * (size_t)k);
                m = fmax(m, fmax(fabs((double)d->maj[q]), fabs((double)d->mino[q])));
            }
    /* the cell bounds are rounded outwards for values >= 0 only: one part in 10^6 covers a
     * negative minimum's rounding */
    return fmin(all, m * (1.0 + 1e-6));
}

/* rho's majorant lattice, or for a large NanoVDB box's tree (no lattice) a coarse one of 64
 * cells along the longest axis, each bounded by the field's max. */
static void lattice_of(const density *rho, lattice *l)
{
    *l = (lattice){.maj = rho->maj, .mc = rho->mcell};
    for (int a = 0; a < 3; a++) {
        l->mn[a] = rho->mn[a];
        l->moff[a] = rho->moff[a];
    }
    if (rho->maj)
        return;
    int longest = rho->n[0] > rho->n[1] ? rho->n[0] : rho->n[1];
    longest = longest > rho->n[2] ? longest : rho->n[2];
    l->mc = (longest + 63) / 64;
    for (int a = 0; a < 3; a++) {
        l->mn[a] = (rho->n[a] + l->mc - 1) / l->mc;
        l->moff[a] = 0;
    }
    float u = (float)rho->rho_max;
    l->uniform = (double)u < rho->rho_max ? nextafterf(u, INFINITY) : u;
}

/* Each moved cell's radius from the local bound: level lv has the radius radius 2^-lv (the
 * last level, 0: no motion), and a cell takes the smallest level at or above its own bound
 * (level[o]). The moved grid has M cells of C voxels placed by v2w. Returns the levels used
 * (bit lv). */
static int assign_levels(const int M[3], int C, const affine3 *v2w, double radius, moved_radius_fn local,
                         const void *user, unsigned char *level)
{
    int used = 0;
    const size_t nM = (size_t)M[0] * (size_t)M[1] * (size_t)M[2];
    for (size_t o = 0; o < nM; o++) {
        const int oi = (int)(o % (size_t)M[0]), oj = (int)(o / (size_t)M[0] % (size_t)M[1]),
                  ok = (int)(o / ((size_t)M[0] * (size_t)M[1]));
        const box3 vb = {v3((double)oi * C, (double)oj * C, (double)ok * C),
                         v3((double)(oi + 1) * C, (double)(oj + 1) * C, (double)(ok + 1) * C)};
        const double r = local(user, affine3_apply_box(v2w, vb));
        int lv = 0; /* r above the radius (rounding): the whole radius is all there is */
        while (r <= radius && lv < MOVED_LEVELS - 1 && !(r > radius * ldexp(1.0, -(lv + 1))))
            lv++;
        if (lv == MOVED_LEVELS - 1 && r > 0.0) /* the last level is no motion at all */
            lv = MOVED_LEVELS - 2;
        level[o] = (unsigned char)lv;
        used |= 1 << lv;
    }
    return used;
}

/* Before the moved grid of M cells (f^3 lattice cells each) is allocated: its voxel range,
 * and its bytes (*kept) and the filter passes' (*passes) taken from the scene's memory limit
 * (render.max_memory_mb, core/budget.h) like every other grid's; the caller gives the passes
 * back once freed. false with err_set, nothing taken. */
static bool moved_check(const lattice *l, const int M[3], int f, bool local, size_t *kept, size_t *passes)
{
    if ((int64_t)M[0] * f * l->mc > INT32_MAX || (int64_t)M[1] * f * l->mc > INT32_MAX ||
        (int64_t)M[2] * f * l->mc > INT32_MAX) {
        err_set(BRUME_ERROR_RANGE, "moved majorant: %d x %d x %d cells of %d voxels exceed the voxel range", M[0], M[1],
                M[2], f * l->mc);
        return false;
    }
    const size_t nM = (size_t)M[0] * (size_t)M[1] * (size_t)M[2];
    const size_t x = (size_t)M[0], y = (size_t)M[1];
    *kept = nM * sizeof(float);
    *passes = ((size_t)l->mn[0] * (size_t)l->mn[1] + x * (size_t)l->mn[1] + x * y) * (size_t)l->mn[2] * sizeof(float) +
              (local ? nM * (sizeof(float) + 1) : 0); /* src, p1, p2; lev and level */
    if (budget_take(*kept, "moved majorant grid") != BRUME_OK)
        return false;
    if (budget_take(*passes, "moved majorant grid (filter passes)") != BRUME_OK) {
        budget_give(*kept);
        return false;
    }
    return true;
}

/* The padding: the voxels P[a] the radius spans along each axis of rho, and the cells Q[a]
 * of the lattice a point can reach within it; false with err_set past MOVED_MAX_VOXELS. */
static bool moved_padding(const density *rho, const lattice *l, double radius, double P[3], int Q[3])
{
    for (int a = 0; a < 3; a++) {
        const double *w = rho->w2v.m + 4 * a;
        P[a] = radius * sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        if (!(P[a] <= MOVED_MAX_VOXELS)) {
            err_set(BRUME_ERROR_RANGE, "the velocity moves the field by up to %g voxels along axis %d within the "
                    "shutter: more than the %g brume tracks", P[a], a, MOVED_MAX_VOXELS);
            return false;
        }
        Q[a] = (int)ceil(P[a] / l->mc);
    }
    return true;
}

/* The coarsening f (returned): the moved grid's cells hold f^3 of the lattice's, M[a] of
 * them per axis, at most MOVED_MAX_CELLS in all. */
static int moved_coarsening(const lattice *l, const int Q[3], int M[3])
{
    int f = 1;
    for (;; f++) {
        size_t cells = 1;
        for (int a = 0; a < 3; a++) {
            M[a] = (int)(((int64_t)l->mn[a] + 2 * (int64_t)Q[a] + f - 1) / f);
            cells *= (size_t)M[a];
        }
        if (cells <= MOVED_MAX_CELLS)
            break;
    }
    return f;
}

/* The filter passes of each level in `used` (bit lv) from the lattice's maxima src, through
 * p1 and p2, into maj (or, with local bounds, into lev, then into maj where level says). */
static void moved_filter(const lattice *l, const int M[3], int f, const int Q[3], const double P[3], int used,
                         bool local, float *src, float *p1, float *p2, float *maj, float *lev,
                         const unsigned char *level)
{
    const size_t nM = (size_t)M[0] * (size_t)M[1] * (size_t)M[2];
    /* moved cell o covers lattice cells [o f - Q, (o + 1) f - Q); a point there reaches q <= Q
     * more on each side (q from its level): [o f - Q - q, (o + 1) f - Q + q) */
    int n0[3] = {l->mn[0], l->mn[1], l->mn[2]}, n1[3] = {M[0], l->mn[1], l->mn[2]}, n2[3] = {M[0], M[1], l->mn[2]};
    for (int lv = 0; lv < MOVED_LEVELS; lv++) {
        if (!(used & (1 << lv)))
            continue;
        int q[3];
        for (int a = 0; a < 3; a++)
            q[a] = lv == MOVED_LEVELS - 1 ? 0 : (int)ceil(ldexp(P[a], -lv) / l->mc);
        float *out = local ? lev : maj;
        max_pass(src, n0, p1, n1, 0, f, Q[0] + q[0], f + 2 * q[0]);
        max_pass(p1, n1, p2, n2, 1, f, Q[1] + q[1], f + 2 * q[1]);
        max_pass(p2, n2, out, M, 2, f, Q[2] + q[2], f + 2 * q[2]);
        for (size_t o = 0; local && o < nM; o++)
            if (level[o] == lv)
                maj[o] = lev[o];
    }
}

density *density_new_moved_majorant(const density *rho, double radius, moved_radius_fn local, const void *user)
{
    if (!(radius >= 0.0) || !isfinite(radius)) {
        err_set(BRUME_ERROR_RANGE, "moved majorant: radius %g must be finite and >= 0", radius);
        return NULL;
    }
    lattice l;
    lattice_of(rho, &l);
    int Q[3], M[3];
    double P[3];
    if (!moved_padding(rho, &l, radius, P, Q))
        return NULL;
    const int f = moved_coarsening(&l, Q, M);
    const size_t nM = (size_t)M[0] * (size_t)M[1] * (size_t)M[2];
    size_t kept, passes;
    if (!moved_check(&l, M, f, local != NULL, &kept, &passes))
        return NULL;
    density *d = calloc(1, sizeof *d);
    float *src = malloc((size_t)l.mn[0] * (size_t)l.mn[1] * (size_t)l.mn[2] * sizeof *src);
    float *p1 = malloc((size_t)M[0] * (size_t)l.mn[1] * (size_t)l.mn[2] * sizeof *p1);
    float *p2 = malloc((size_t)M[0] * (size_t)M[1] * (size_t)l.mn[2] * sizeof *p2);
    float *maj = malloc(nM * sizeof *maj), *lev = local ? malloc(nM * sizeof *lev) : NULL;
    unsigned char *level = local ? malloc(nM) : NULL;
    if (!d || !src || !p1 || !p2 || !maj || (local && (!lev || !level))) {
        free(d), free(src), free(p1), free(p2), free(maj), free(lev), free(level);
        budget_give(kept + passes);
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "moved majorant: out of memory for %d x %d x %d cells", M[0], M[1], M[2]);
        return NULL;
    }
    /* its voxel space: rho's shifted so that lattice cell -Q starts at 0; cells of f mc voxels */
    const affine3 shift = affine3_translate(
        v3(-(double)(Q[0] * l.mc + l.moff[0]), -(double)(Q[1] * l.mc + l.moff[1]), -(double)(Q[2] * l.mc + l.moff[2])));
    const affine3 v2w = affine3_compose(&rho->v2w, &shift);
    const int C = f * l.mc;
    for (int k = 0; k < l.mn[2]; k++)
        for (int j = 0; j < l.mn[1]; j++)
            for (int i = 0; i < l.mn[0]; i++)
                src[(size_t)i + (size_t)l.mn[0] * ((size_t)j + (size_t)l.mn[1] * (size_t)k)] = lattice_at(&l, i, j, k);
    /* bit l: level l's filter is needed (only the whole radius without local bounds) */
    const int used = local ? assign_levels(M, C, &v2w, radius, local, user, level) : 1;
    moved_filter(&l, M, f, Q, P, used, local != NULL, src, p1, p2, maj, lev, level);
    free(src), free(p1), free(p2), free(lev), free(level);
    budget_give(passes);
    d->kind = DENSITY_GRID;
    d->filter = GRID_NEAREST;
    d->mcell = C;
    for (int a = 0; a < 3; a++) {
        d->n[a] = M[a] * d->mcell;
        d->mn[a] = M[a];
        d->moff[a] = 0;
    }
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
