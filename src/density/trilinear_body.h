/* trilinear_body.h - trilinear reconstruction and the dense voxel arrays' lookups over one
 * real type (core/real_names.h) and one grid type TRILINEAR_GRID, which has the fields
 * n[3], data (float voxels), bricked, nbx, nby of density_impl.h's density: included there
 * in double over a density, and in float over the float stages' view of a dense grid
 * (render/track_float.h). Inline: the estimator reads them at every tentative collision. */
#include "core/real_names.h"

#ifndef BRUME_DENSITY_TRILINEAR_SHARED
#define BRUME_DENSITY_TRILINEAR_SHARED
#include <stddef.h>
/* Bricked voxel arrays: voxel (i, j, k) of brick (i / 4, j / 2, k / 2) sits at
 * 16 brick + (i % 4) + 4 (j % 2) + 8 (k % 2), bricks x fastest, each brick one 64-byte cache
 * line (the array is 64-byte aligned), so a trilinear lookup's 8 voxels span 2.8 lines on
 * average instead of 4.3 with rows. The offsets are separable: x, y and z parts added. */
#define DENSITY_BRICK_FLOATS 16
static inline size_t dense_brick_x(int i) { return (size_t)(i >> 2) * 16 + (size_t)(i & 3); }
static inline size_t dense_brick_yn(int nbx, int j)
{
    return (size_t)(j >> 1) * 16 * (size_t)nbx + (size_t)((j & 1) << 2);
}
static inline size_t dense_brick_zn(int nbx, int nby, int k)
{
    return (size_t)(k >> 1) * 16 * (size_t)nbx * (size_t)nby + (size_t)((k & 1) << 3);
}
static inline int trilinear_clamp(int v, int hi) { return v < 0 ? 0 : (v > hi ? hi : v); }
#endif

/* The type of a voxel's or a cell's index: size_t, or 32 bits where a grid has fewer than
 * 2^32 voxels (gpu/stages.cu: 32-bit address arithmetic takes half the registers) */
#ifndef GRID_INDEX
#define GRID_INDEX size_t
#endif

/* How a voxel is read: a plain load, or the GPU's read-only path (gpu/stages.cu sets it to
 * __ldg, ld.global.nc) */
#ifndef GRID_LOAD
#define GRID_LOAD(p) (*(p))
#endif

/* Trilinear reconstruction between voxel centres, clamped to the outermost samples, shared
 * by every grid kind: trilinear_corners gives the 2 x 2 x 2 corner voxels around u (voxel
 * space) as ijk[axis][0 or 1] and the weights a[axis]; trilinear_blend mixes the corner
 * values c[x + 2 y + 4 z]. */
static inline void RN(trilinear_corners)(RN(vec3) u, const int n[3], int ijk[3][2], R a[3])
{
    const R x[3] = {u.x - RC(0.5), u.y - RC(0.5), u.z - RC(0.5)};
    for (int ax = 0; ax < 3; ax++) {
        R f = R_FLOOR(x[ax]);
        int i = (int)f;
        a[ax] = x[ax] - f;
        ijk[ax][0] = trilinear_clamp(i, n[ax] - 1);
        ijk[ax][1] = trilinear_clamp(i + 1, n[ax] - 1);
    }
}
static inline R RN(trilinear_blend)(const R c[8], const R a[3])
{
    R c00 = c[0] * (1 - a[0]) + c[1] * a[0], c10 = c[2] * (1 - a[0]) + c[3] * a[0];
    R c01 = c[4] * (1 - a[0]) + c[5] * a[0], c11 = c[6] * (1 - a[0]) + c[7] * a[0];
    R c0 = c00 * (1 - a[1]) + c10 * a[1], c1 = c01 * (1 - a[1]) + c11 * a[1];
    return c0 * (1 - a[2]) + c1 * a[2];
}

/* ---- dense voxel arrays (d->data: a dense grid, or a small NanoVDB box's copy) ---------------- */
static inline R RN(dense_at)(const TRILINEAR_GRID *d, int i, int j, int k)
{
    if (d->bricked)
        return (R)GRID_LOAD(&d->data[(GRID_INDEX)dense_brick_x(i) + (GRID_INDEX)dense_brick_yn(d->nbx, j) +
                                     (GRID_INDEX)dense_brick_zn(d->nbx, d->nby, k)]);
    const GRID_INDEX n0 = (GRID_INDEX)d->n[0], n1 = (GRID_INDEX)d->n[1];
    return (R)GRID_LOAD(&d->data[(GRID_INDEX)i + n0 * ((GRID_INDEX)j + n1 * (GRID_INDEX)k)]);
}

/* Trilinear between voxel centres, clamped to the outermost samples; u in voxel space. */
static inline R RN(dense_trilinear)(const TRILINEAR_GRID *d, RN(vec3) u)
{
    int ijk[3][2];
    R a[3], c[8];
    RN(trilinear_corners)(u, d->n, ijk, a);
    if (d->bricked) {
        const GRID_INDEX x0 = (GRID_INDEX)dense_brick_x(ijk[0][0]), x1 = (GRID_INDEX)dense_brick_x(ijk[0][1]);
        const GRID_INDEX y0 = (GRID_INDEX)dense_brick_yn(d->nbx, ijk[1][0]);
        const GRID_INDEX y1 = (GRID_INDEX)dense_brick_yn(d->nbx, ijk[1][1]);
        const GRID_INDEX z0 = (GRID_INDEX)dense_brick_zn(d->nbx, d->nby, ijk[2][0]);
        const GRID_INDEX z1 = (GRID_INDEX)dense_brick_zn(d->nbx, d->nby, ijk[2][1]);
        const float *v = d->data;
        c[0] = GRID_LOAD(&v[x0 + y0 + z0]), c[1] = GRID_LOAD(&v[x1 + y0 + z0]);
        c[2] = GRID_LOAD(&v[x0 + y1 + z0]), c[3] = GRID_LOAD(&v[x1 + y1 + z0]);
        c[4] = GRID_LOAD(&v[x0 + y0 + z1]), c[5] = GRID_LOAD(&v[x1 + y0 + z1]);
        c[6] = GRID_LOAD(&v[x0 + y1 + z1]), c[7] = GRID_LOAD(&v[x1 + y1 + z1]);
        return RN(trilinear_blend)(c, a);
    }
    for (int q = 0; q < 8; q++)
        c[q] = RN(dense_at)(d, ijk[0][q & 1], ijk[1][(q >> 1) & 1], ijk[2][q >> 2]);
    return RN(trilinear_blend)(c, a);
}

#include "core/real_names_end.h"
