/* blasi_field.c - the density Blasi's passes see when blasi.interpolate is trilinear
 * (docs/blasi.md, "Interpolation"): the field trilinear between the voxels' centres,
 * clamped to the outermost samples (the grids' own reconstruction, density/density_impl.h),
 * its mean over each voxel (st->rho: what the walks skip by) and its mean along a ray's
 * crossing of one voxel; the view pass reads the stored source the same way. */
#include <float.h>

#include "render/blasi_state.h"

static inline int clamp_index(int v, int hi) { return v < 0 ? 0 : (v > hi ? hi : v); }

/* The interpolated values at voxel-space point u of medium bm: the density (v[0]) and, with
 * source, the stored source's three channels (v[1..3]). */
static void field_at(const blasi_state *st, const blasi_medium *bm, vec3 u, bool source, double v[4])
{
    const double x[3] = {u.x - 0.5, u.y - 0.5, u.z - 0.5};
    int lo[3], hi[3];
    double a[3];
    for (int ax = 0; ax < 3; ax++) {
        double f = floor(x[ax]);
        a[ax] = x[ax] - f;
        lo[ax] = clamp_index((int)f, bm->n[ax] - 1);
        hi[ax] = clamp_index((int)f + 1, bm->n[ax] - 1);
    }
    const size_t nx = (size_t)bm->n[0], ny = (size_t)bm->n[1];
    for (int c = 0; c < 4; c++)
        v[c] = 0.0;
    for (int q = 0; q < 8; q++) {
        int i = q & 1 ? hi[0] : lo[0], j = q & 2 ? hi[1] : lo[1], k = q & 4 ? hi[2] : lo[2];
        double w = (q & 1 ? a[0] : 1 - a[0]) * (q & 2 ? a[1] : 1 - a[1]) * (q & 4 ? a[2] : 1 - a[2]);
        size_t at = bm->offset + (size_t)i + nx * ((size_t)j + ny * (size_t)k);
        v[0] += w * (double)st->field[at];
        for (int c = 0; source && c < 3; c++)
            v[1 + c] += w * (double)st->S[3 * at + (size_t)c];
    }
}

double blasi_field_point(const blasi_state *st, const blasi_medium *bm, vec3 u)
{
    double v[4];
    field_at(st, bm, u, false, v);
    return v[0];
}

/* Along a line inside one voxel the trilinear field is a cubic polynomial between the
 * planes through the voxel's centre (where the interpolation's corners change), and
 * Simpson's rule is exact for cubics: the mean is Simpson's sum over those (at most four)
 * pieces. */
double blasi_crossing_mean(const blasi_state *st, const blasi_medium *bm, vec3 a, vec3 b, color *S)
{
    const double pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z};
    double cut[5] = {0.0};
    int n = 1;
    for (int ax = 0; ax < 3; ax++) {
        const double mid = floor(0.5 * (pa[ax] + pb[ax])) + 0.5, dx = pb[ax] - pa[ax];
        if (dx == 0.0)
            continue;
        const double s = (mid - pa[ax]) / dx;
        if (s > 0.0 && s < 1.0) { /* insertion into the sorted cuts */
            int q = n++;
            while (q > 1 && cut[q - 1] > s) {
                cut[q] = cut[q - 1];
                q--;
            }
            cut[q] = s;
        }
    }
    cut[n] = 1.0;
    const vec3 d = v3_sub(b, a);
    const bool source = S != NULL;
    double sum[4] = {0.0, 0.0, 0.0, 0.0}, f0[4], fm[4], f1[4];
    field_at(st, bm, a, source, f0);
    for (int q = 0; q < n; q++) {
        const double s0 = cut[q], s1 = cut[q + 1];
        field_at(st, bm, v3_madd(a, d, 0.5 * (s0 + s1)), source, fm);
        field_at(st, bm, q + 1 == n ? b : v3_madd(a, d, s1), source, f1);
        for (int c = 0; c < 4; c++) {
            sum[c] += (s1 - s0) * (f0[c] + 4.0 * fm[c] + f1[c]) / 6.0;
            f0[c] = f1[c];
        }
    }
    for (int c = 0; source && c < 3; c++)
        S->c[c] = sum[1 + c] > 0.0 ? sum[1 + c] : 0.0;
    return sum[0] > 0.0 ? sum[0] : 0.0;
}

/* The voxel-mean weights of the trilinear field along one axis: a voxel's half towards a
 * neighbour blends it with weight 1/4 on average, so the mean over the voxel is
 * 1/8, 3/4, 1/8 of the values at i - 1, i, i + 1 (indices clamped to the grid). */
void blasi_field_means(blasi_state *st, const blasi_medium *bm)
{
    static const double w[3] = {0.125, 0.75, 0.125};
    const float *F = st->field + bm->offset;
    float *dst = st->rho + bm->offset;
    const size_t nx = (size_t)bm->n[0], ny = (size_t)bm->n[1];
    for (int k = 0; k < bm->n[2]; k++)
        for (int j = 0; j < bm->n[1]; j++)
            for (int i = 0; i < bm->n[0]; i++) {
                double sum = 0.0;
                for (int c = 0; c < 27; c++) {
                    const int di = c % 3, dj = (c / 3) % 3, dk = c / 9;
                    const size_t x = (size_t)clamp_index(i + di - 1, bm->n[0] - 1),
                                 y = (size_t)clamp_index(j + dj - 1, bm->n[1] - 1),
                                 z = (size_t)clamp_index(k + dk - 1, bm->n[2] - 1);
                    sum += w[di] * w[dj] * w[dk] * (double)F[x + nx * (y + ny * z)];
                }
                float m = (float)sum;
                /* a field that is not 0 somewhere in the voxel keeps the voxel non-empty */
                *dst++ = sum > 0.0 && m == 0.0f ? FLT_TRUE_MIN : m;
            }
}
