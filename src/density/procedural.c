/* procedural.c - the default scene's cloud: value-noise fBm carved by a cumulus shape. */
#include <stdio.h>
#include <stdlib.h>

#include "core/budget.h"
#include "core/cancel.h"
#include "core/error.h"
#include "core/rng.h"
#include "density/density.h"

#define PROCEDURAL_OCTAVES 5 /* of the fBm: the work of a voxel (render.max_work) */

/* Lattice value in [-1, 1] at integer point (i, j, k). */
static double lattice(int64_t i, int64_t j, int64_t k, uint64_t seed)
{
    uint64_t h = hash_mix64(seed ^ hash_mix64((uint64_t)i * 0x9e3779b97f4a7c15ULL ^
                                              hash_mix64((uint64_t)j * 0xc2b2ae3d27d4eb4fULL ^
                                                         (uint64_t)k * 0x165667b19e3779f9ULL)));
    return (double)(h >> 11) * 0x1.0p-52 - 1.0;
}

static double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

/* Value noise with a quintic fade; range about [-1, 1]. */
static double value_noise(vec3 p, uint64_t seed)
{
    double fx = floor(p.x), fy = floor(p.y), fz = floor(p.z);
    int64_t i = (int64_t)fx, j = (int64_t)fy, k = (int64_t)fz;
    double ax = fade(p.x - fx), ay = fade(p.y - fy), az = fade(p.z - fz);
    double v[2][2][2];
    for (int c = 0; c < 8; c++)
        v[c & 1][(c >> 1) & 1][c >> 2] = lattice(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2), seed);
    double x00 = v[0][0][0] + (v[1][0][0] - v[0][0][0]) * ax, x10 = v[0][1][0] + (v[1][1][0] - v[0][1][0]) * ax;
    double x01 = v[0][0][1] + (v[1][0][1] - v[0][0][1]) * ax, x11 = v[0][1][1] + (v[1][1][1] - v[0][1][1]) * ax;
    double y0 = x00 + (x10 - x00) * ay, y1 = x01 + (x11 - x01) * ay;
    return y0 + (y1 - y0) * az;
}

static double fbm(vec3 p, uint64_t seed, int octaves)
{
    double sum = 0.0, amp = 0.5;
    for (int o = 0; o < octaves; o++) {
        sum += amp * value_noise(p, seed + (uint64_t)o);
        p = v3_scale(p, 2.03);
        amp *= 0.5;
    }
    return sum;
}

static double smoothstep(double a, double b, double x)
{
    double t = fmin(1.0, fmax(0.0, (x - a) / (b - a)));
    return t * t * (3.0 - 2.0 * t);
}

/* Cumulus shape in [-1, 1]^3 (y up): a flattened base and three domes; > 0 inside. */
static double cumulus_shape(vec3 q)
{
    static const double domes[4][4] = {
        /* centre x, y, z, radius */
        {0.0, -0.15, 0.0, 0.62}, {-0.35, 0.05, 0.1, 0.42}, {0.3, 0.1, -0.05, 0.45}, {0.0, 0.3, 0.05, 0.38}};
    double s = -1.0;
    for (int i = 0; i < 4; i++) {
        vec3 c = v3(domes[i][0], domes[i][1], domes[i][2]);
        vec3 dq = v3_sub(q, c);
        dq.y *= 1.25;
        s = fmax(s, 1.0 - v3_length(dq) / domes[i][3]);
    }
    return s * smoothstep(-0.55, -0.4, q.y); /* flat bottom */
}

density *density_new_procedural_cloud(int n, uint64_t seed, box3 bounds)
{
    if (n < 2 || n > 1024) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "procedural cloud: resolution %d outside [2, 1024]", n);
        return NULL;
    }
    size_t count = (size_t)n * (size_t)n * (size_t)n;
    char how[64];
    snprintf(how, sizeof how, "%d^3 voxels x %d octaves of noise", n, PROCEDURAL_OCTAVES);
    if (budget_work((double)count * PROCEDURAL_OCTAVES, "procedural cloud", how) != BRUME_OK ||
        budget_take(count * sizeof(float), "procedural cloud") != BRUME_OK)
        return NULL;
    float *data = malloc(count * sizeof *data);
    if (!data) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "procedural cloud: out of memory for %d^3 voxels", n);
        return NULL;
    }
    double vmax = 0.0;
    for (int k = 0; k < n; k++) {
        if (cancel_load_check("procedural cloud") != BRUME_OK) { /* a slice of 512^2: some 0.1 s */
            free(data);
            budget_give(count * sizeof(float));
            return NULL;
        }
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) {
                vec3 q = v3(2.0 * (i + 0.5) / n - 1.0, 2.0 * (j + 0.5) / n - 1.0, 2.0 * (k + 0.5) / n - 1.0);
                double shape = cumulus_shape(q);
                double noise = fbm(v3_scale(q, 3.0), seed, PROCEDURAL_OCTAVES);
                double v = fmax(0.0, 2.5 * shape + 0.9 * noise);
                data[(size_t)i + (size_t)n * ((size_t)j + (size_t)n * (size_t)k)] = (float)v;
                vmax = fmax(vmax, v);
            }
    }
    if (vmax > 0.0)
        for (size_t i = 0; i < count; i++)
            data[i] = (float)((double)data[i] / vmax);
    density *d = density_new_grid(n, n, n, data, bounds, GRID_TRILINEAR);
    if (!d)
        free(data);
    return d;
}
