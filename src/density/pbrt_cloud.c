/* pbrt_cloud.c - pbrt-v4's procedural cloud (its CloudMedium's density, DENSITY_PBRT_CLOUD):
 * Perlin's gradient noise with his reference permutation, the lookup point perturbed by two
 * octaves of the noise's finite-difference gradient (wispiness), five octaves summed, and a
 * fall-off with height y in the cloud's own space:
 *   d = clamp((1 - y) 4.5 density fbm, 0, 1) + 2 max(0, 1/2 - y), clamped to [0, 1].
 * Evaluated where it is looked up, not sampled into a grid. Voxel space is the cloud's box
 * [p0, p1] in PBRT_CLOUD_CELLS^3 majorant cells, each bounded by 1 (the field's maximum), or
 * by 0 where the whole cell lies at y >= 1 (the field is 0 there). The permutation is held
 * by the density itself, so the GPU's byte copy of it carries it. */
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "density/density_impl.h"

#define PBRT_CLOUD_CELLS 8

/* Ken Perlin's reference permutation of 0 .. 255 ("Improving Noise", 2002), the one pbrt-v4's
 * NoisePerm repeats. */
static const unsigned char perlin_permutation[256] = {
    151, 160, 137, 91,  90,  15,  131, 13,  201, 95,  96,  53,  194, 233, 7,   225, 140, 36,  103, 30,  69,  142,
    8,   99,  37,  240, 21,  10,  23,  190, 6,   148, 247, 120, 234, 75,  0,   26,  197, 62,  94,  252, 219, 203,
    117, 35,  11,  32,  57,  177, 33,  88,  237, 149, 56,  87,  174, 20,  125, 136, 171, 168, 68,  175, 74,  165,
    71,  134, 139, 48,  27,  166, 77,  146, 158, 231, 83,  111, 229, 122, 60,  211, 133, 230, 220, 105, 92,  41,
    55,  46,  245, 40,  244, 102, 143, 54,  65,  25,  63,  161, 1,   216, 80,  73,  209, 76,  132, 187, 208, 89,
    18,  169, 200, 196, 135, 130, 116, 188, 159, 86,  164, 100, 109, 198, 173, 186, 3,   64,  52,  217, 226, 250,
    124, 123, 5,   202, 38,  147, 118, 126, 255, 82,  85,  212, 207, 206, 59,  227, 47,  16,  58,  17,  182, 189,
    28,  42,  223, 183, 170, 213, 119, 248, 152, 2,   44,  154, 163, 70,  221, 153, 101, 155, 167, 43,  172, 9,
    129, 22,  39,  253, 19,  98,  108, 110, 79,  113, 224, 232, 178, 185, 112, 104, 218, 246, 97,  228, 251, 34,
    242, 193, 238, 210, 144, 12,  191, 179, 162, 241, 81,  51,  145, 235, 249, 14,  239, 107, 49,  192, 214, 31,
    181, 199, 106, 157, 184, 84,  204, 176, 115, 121, 50,  45,  127, 4,   150, 254, 138, 236, 205, 93,  222, 114,
    67,  29,  24,  72,  243, 141, 128, 195, 78,  66,  215, 61,  156, 180};

/* The gradient of lattice point (x, y, z) (each in [0, 256]) dotted with the offset. */
static double noise_grad(const unsigned char *perm, int x, int y, int z, double dx, double dy, double dz)
{
    int h = perm[(perm[(perm[x & 255] + y) & 255] + z) & 255] & 15;
    double u = h < 8 || h == 12 || h == 13 ? dx : dy;
    double v = h < 4 || h == 12 || h == 13 ? dy : dz;
    return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

static double noise_weight(double t) { return t * t * t * (t * (6.0 * t - 15.0) + 10.0); }
static double noise_lerp(double t, double a, double b) { return (1.0 - t) * a + t * b; }

/* x modulo 2^30 toward zero, as pbrt-v4 keeps the cell index in an int (exact: a power of two) */
static double noise_wrap(double x)
{
    const double m = 1073741824.0;
    double q = x / m;
    q = q >= 0.0 ? floor(q) : -floor(-q);
    return x - q * m;
}

double pbrt_noise(const unsigned char *perm, vec3 p)
{
    double x = noise_wrap(p.x), y = noise_wrap(p.y), z = noise_wrap(p.z);
    double fx = floor(x), fy = floor(y), fz = floor(z);
    int ix = (int)fx & 255, iy = (int)fy & 255, iz = (int)fz & 255;
    double dx = x - fx, dy = y - fy, dz = z - fz;
    double w[8];
    for (int c = 0; c < 8; c++) {
        int a = c & 1, b = (c >> 1) & 1, e = c >> 2;
        w[c] = noise_grad(perm, ix + a, iy + b, iz + e, dx - a, dy - b, dz - e);
    }
    double wx = noise_weight(dx), wy = noise_weight(dy), wz = noise_weight(dz);
    double x00 = noise_lerp(wx, w[0], w[1]), x10 = noise_lerp(wx, w[2], w[3]);
    double x01 = noise_lerp(wx, w[4], w[5]), x11 = noise_lerp(wx, w[6], w[7]);
    return noise_lerp(wz, noise_lerp(wy, x00, x10), noise_lerp(wy, x01, x11));
}

double pbrt_cloud_eval(const pbrt_cloud *c, const unsigned char *perm, vec3 p)
{
    const double step = (double)1.99f; /* pbrt-v4's octave ratio, a float */
    vec3 pp = v3_scale(p, c->frequency);
    if (c->wispiness > 0.0) { /* the lookup moved along the noise's forward-difference gradient */
        double vomega = (double)0.05f * c->wispiness, vlambda = 10.0;
        for (int i = 0; i < 2; i++) {
            vec3 q = v3_scale(pp, vlambda);
            const double h = (double)0.01f;
            double n = pbrt_noise(perm, q);
            vec3 g = v3(pbrt_noise(perm, v3(q.x + h, q.y, q.z)) - n, pbrt_noise(perm, v3(q.x, q.y + h, q.z)) - n,
                        pbrt_noise(perm, v3(q.x, q.y, q.z + h)) - n);
            pp = v3_madd(pp, g, vomega / h);
            vomega *= 0.5;
            vlambda *= step;
        }
    }
    double d = 0.0, omega = 0.5, lambda = 1.0;
    for (int i = 0; i < 5; i++) {
        d += omega * pbrt_noise(perm, v3_scale(pp, lambda));
        omega *= 0.5;
        lambda *= step;
    }
    d = fmin(1.0, fmax(0.0, (1.0 - p.y) * 4.5 * c->density * d));
    d += 2.0 * fmax(0.0, 0.5 - p.y);
    return fmin(1.0, fmax(0.0, d));
}

double pbrt_cloud_at(const density *d, vec3 u)
{
    const pbrt_cloud *c = &d->cloud;
    vec3 p = v3(c->p0[0] + u.x * (c->p1[0] - c->p0[0]) / d->n[0], c->p0[1] + u.y * (c->p1[1] - c->p0[1]) / d->n[1],
                c->p0[2] + u.z * (c->p1[2] - c->p0[2]) / d->n[2]);
    return pbrt_cloud_eval(c, d->cloud_perm, p);
}

density *density_new_pbrt_cloud(const pbrt_cloud *c)
{
    for (int a = 0; a < 3; a++)
        if (!(c->p1[a] > c->p0[a]) || !isfinite(c->p0[a]) || !isfinite(c->p1[a])) {
            err_set(BRUME_ERROR_RANGE, "pbrt cloud: p1 must exceed p0 on every axis (finite)");
            return NULL;
        }
    if (!(c->density >= 0.0 && c->density <= 1e30 && c->wispiness >= 0.0 && c->wispiness <= 1e30 &&
          c->frequency >= 0.0 && c->frequency <= 1e30)) {
        err_set(BRUME_ERROR_RANGE, "pbrt cloud: density, wispiness and frequency must be in [0, 1e30]");
        return NULL;
    }
    density *d = calloc(1, sizeof *d);
    const size_t cells = (size_t)PBRT_CLOUD_CELLS * PBRT_CLOUD_CELLS * PBRT_CLOUD_CELLS;
    float *maj = calloc(cells, sizeof *maj);
    if (!d || !maj) {
        free(d);
        free(maj);
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "pbrt cloud: out of memory");
        return NULL;
    }
    d->kind = DENSITY_PBRT_CLOUD;
    d->filter = GRID_TRILINEAR;
    d->cloud = *c;
    memcpy(d->cloud_perm, perlin_permutation, sizeof d->cloud_perm);
    d->mcell = 1;
    for (int a = 0; a < 3; a++) {
        d->n[a] = d->mn[a] = PBRT_CLOUD_CELLS;
        d->moff[a] = 0;
    }
    /* the field is 0 at y >= 1: (1 - y) <= 0 and 1/2 - y < 0 */
    for (int j = 0; j < PBRT_CLOUD_CELLS; j++) {
        double y_lo = c->p0[1] + j * (c->p1[1] - c->p0[1]) / PBRT_CLOUD_CELLS;
        for (int k = 0; k < PBRT_CLOUD_CELLS; k++)
            for (int i = 0; i < PBRT_CLOUD_CELLS; i++)
                maj[(size_t)i + PBRT_CLOUD_CELLS * ((size_t)j + PBRT_CLOUD_CELLS * (size_t)k)] = y_lo >= 1.0 ? 0.0f : 1.0f;
    }
    d->maj = maj;
    affine3 v2w = {{(c->p1[0] - c->p0[0]) / PBRT_CLOUD_CELLS, 0, 0, c->p0[0], 0, (c->p1[1] - c->p0[1]) / PBRT_CLOUD_CELLS,
                    0, c->p0[1], 0, 0, (c->p1[2] - c->p0[2]) / PBRT_CLOUD_CELLS, c->p0[2]}};
    if (!density_set_placement(d, &v2w, "pbrt cloud")) {
        free(maj);
        free(d);
        return NULL;
    }
    density_set_active_box(d);
    d->rho_min = 0.0;
    d->rho_max = 1.0;
    d->active = cells;
    d->memory = sizeof *d + cells * sizeof *maj;
    return d;
}
