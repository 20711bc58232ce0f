/* fractal.c - fractal cloud grids: midpoint displacement, FFTW spectral synthesis, Perlin
 * noise and turbulence, solid-texture shaping and an animated threshold (see fractal.h). */
#include "density/fractal.h"

#include <fftw3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/budget.h"
#include "core/cancel.h"
#include "core/error.h"
#include "core/rng.h"

/* A standard normal number for lattice point `index` (Box-Muller on the counter rng). */
static double gauss(uint64_t seed, uint64_t stream, uint64_t index)
{
    rng r = rng_make(seed, stream, index);
    double u1 = 1.0 - rng_next(&r), u2 = rng_next(&r);
    return sqrt(-2.0 * log(u1)) * cos(2.0 * PI * u2);
}

/* ---- random midpoint displacement ---------------------------------------------------------- */

/* The mean of the points already set around point (i, j, k) of substep `kind` at spacing h
 * (oi, oj, ok: whether each coordinate sits at an odd multiple of h) in the N^3 lattice out. */
static double neighbour_mean(const float *out, int N, int i, int j, int k, int h, int kind, int oi, int oj, int ok)
{
    const size_t sN = (size_t)N;
#define AT(i, j, k) out[(size_t)(i) + sN * ((size_t)(j) + sN * (size_t)(k))]
    double sum = 0.0;
    int cnt = 0;
    if (kind == 3) { /* the 8 corners of the cube */
        for (int c = 0; c < 8; c++) {
            sum += (double)AT(i + ((c & 1) ? h : -h), j + ((c & 2) ? h : -h), k + ((c & 4) ? h : -h));
            cnt++;
        }
    } else {
        /* axis neighbours at distance h already set: for a face centre the 2
         * cube centres along its even axis; for an edge midpoint all 6 (its 2
         * ends and 4 face centres) */
        const int odd[3] = {oi, oj, ok};
        for (int ax = 0; ax < 3; ax++) {
            if (kind == 2 && odd[ax])
                continue;
            for (int sgn = -1; sgn <= 1; sgn += 2) {
                int c[3] = {i, j, k};
                c[ax] += sgn * h;
                if (c[ax] < 0 || c[ax] >= N)
                    continue;
                sum += (double)AT(c[0], c[1], c[2]);
                cnt++;
            }
        }
        if (kind == 2) /* the 4 face corners, diagonal in the face's plane */
            for (int q = 0; q < 4; q++) {
                int c[3] = {i, j, k}, bit = 0;
                for (int ax = 0; ax < 3; ax++)
                    if (odd[ax])
                        c[ax] += ((q >> bit++) & 1) ? h : -h;
                sum += (double)AT(c[0], c[1], c[2]);
                cnt++;
            }
    }
#undef AT
    return sum / cnt;
}

/* Peitgen and Saupe's MidPointFM2D (The Science of Fractal Images, 1988, sec. 2.3.3) in
 * three dimensions. Each level halves the lattice spacing in three substeps that fill, in
 * turn, the cube centres (from the 8 cube corners), the face centres (from the 4 face
 * corners and the 2 neighbouring cube centres) and the edge midpoints (from the 2 edge ends
 * and the 4 neighbouring face centres), each an average of the points at hand plus a
 * gaussian displacement. Spacing shrinks by 2 per level, so for fBm of exponent H the
 * displacement's deviation shrinks by 2^-H per level: 2^(-H/3) per substep here, as P&S
 * use 2^(-H/2) per substep in 2-D.
 *
 * Only the planes k < planes are asked for (a 65 x 65 x 10 grid keeps 10 of the 65^3
 * lattice's planes): a point reads points at most h away, in points set by earlier
 * substeps, so going back from the last substep, each substep must fill the planes up to
 * the bound of the one after it plus that one's h (bound[]). Every point filled is computed
 * as in the whole lattice, from the same points: the same bits. */
brume_status fractal_midpoint(int level, double hurst, uint64_t seed, int planes, float *out)
{
    if (level < 1 || level > 10 || !(hurst > 0.0 && hurst < 1.0))
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "midpoint: level %d outside [1, 10] or H %.17g outside (0, 1)",
                       level, hurst);
    const int N = (1 << level) + 1;
    const size_t sN = (size_t)N;
    if (planes < 1 || planes > N)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "midpoint: %d planes of a lattice of %d", planes, N);
    int bound[3 * 10]; /* substep t (level by level, kinds 3, 2, 1) fills the planes k <= bound[t] */
    int nsub = 3 * level, need = planes - 1;
    for (int t = nsub - 1; t >= 0; t--) {
        int h = 1 << (level - 1 - t / 3); /* the first level's h is 2^(level - 1), the last's 1 */
        bound[t] = need;
        need = need + h < N - 1 ? need + h : N - 1;
    }
#define AT(i, j, k) out[(size_t)(i) + sN * ((size_t)(j) + sN * (size_t)(k))]
    for (int c = 0; c < 8; c++) {
        int i = (c & 1) ? N - 1 : 0, j = (c & 2) ? N - 1 : 0, k = (c & 4) ? N - 1 : 0;
        AT(i, j, k) = (float)gauss(seed, 0, (uint64_t)i + sN * ((uint64_t)j + sN * (uint64_t)k));
    }
    double delta = sqrt(1.0 - pow(2.0, 2.0 * hurst - 2.0)); /* P&S: sigma^2 (1 - 2^(2H-2)) at the first level */
    const double sub = pow(2.0, -hurst / 3.0);
    int t = 0; /* the substep */
    for (int s = N - 1; s >= 2; s /= 2) {
        int h = s / 2;
        delta *= pow(2.0, -hurst); /* first level: delta = (1/2)^H sqrt(1 - 2^(2H-2)) */
        /* substep kind: how many coordinates sit at odd multiples of h (3 centres, 2 faces, 1 edges) */
        for (int kind = 3; kind >= 1; kind--, t++) {
            double dev = delta * pow(sub, 3 - kind);
            for (int k = 0; k <= bound[t]; k += h) {
                if (cancel_load_check("fractal midpoint") != BRUME_OK) /* a plane: 1025^2 points at most */
                    return BRUME_ERROR_CANCELLED;
                for (int j = 0; j < N; j += h)
                    for (int i = 0; i < N; i += h) {
                        int oi = (i % s) == h, oj = (j % s) == h, ok = (k % s) == h;
                        if (oi + oj + ok != kind)
                            continue;
                        double mean = neighbour_mean(out, N, i, j, k, h, kind, oi, oj, ok);
                        uint64_t idx = (uint64_t)i + sN * ((uint64_t)j + sN * (uint64_t)k);
                        AT(i, j, k) = (float)(mean + dev * gauss(seed, 0, idx));
                    }
            }
        }
    }
#undef AT
    return BRUME_OK;
}

/* ---- spectral synthesis -------------------------------------------------------------------- */

/* P&S SpectralSynthesisFM2D (sec. 2.4.5) in 3-D: fBm in E dimensions has the spectral
 * density S(f) ~ 1/|f|^(2H + E); with E = 3 each coefficient is a complex gaussian times
 * |f|^-(H + 3/2). Frequencies are in cycles per voxel, so the field is isotropic in voxel
 * units whatever the dimensions. The c2r transform takes the Hermitian half (x halved). */
brume_status fractal_spectral(const int n[3], double hurst, uint64_t seed, float *out)
{
    if (n[0] < 1 || n[1] < 1 || n[2] < 1 || !(hurst > 0.0 && hurst < 1.0))
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "spectral: bad dimensions or H %.17g outside (0, 1)", hurst);
    int hx = n[0] / 2 + 1;
    size_t ncoef = (size_t)hx * (size_t)n[1] * (size_t)n[2], nreal = (size_t)n[0] * (size_t)n[1] * (size_t)n[2];
    fftw_complex *c = fftw_malloc(ncoef * sizeof *c);
    double *r = fftw_malloc(nreal * sizeof *r);
    if (!c || !r) {
        fftw_free(c);
        fftw_free(r);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "spectral: out of memory");
    }
    /* FFTW is row-major with the last index fastest: dims (nz, ny, nx) keep x fastest */
    fftw_plan plan = fftw_plan_dft_c2r_3d(n[2], n[1], n[0], c, r, FFTW_ESTIMATE);
    for (int k = 0; k < n[2]; k++) {
        if (cancel_load_check("fractal spectral") != BRUME_OK) { /* a plane: 1024 x 513 coefficients at most */
            fftw_destroy_plan(plan);
            fftw_free(c);
            fftw_free(r);
            return BRUME_ERROR_CANCELLED;
        }
        for (int j = 0; j < n[1]; j++)
            for (int i = 0; i < hx; i++) {
                size_t idx = (size_t)i + (size_t)hx * ((size_t)j + (size_t)n[1] * (size_t)k);
                double fx = (double)i / n[0], fy = (double)(j <= n[1] / 2 ? j : j - n[1]) / n[1],
                       fz = (double)(k <= n[2] / 2 ? k : k - n[2]) / n[2];
                double f2 = fx * fx + fy * fy + fz * fz;
                double amp = f2 > 0.0 ? pow(f2, -(hurst + 1.5) / 2.0) : 0.0;
                c[idx][0] = amp * gauss(seed, 1, 2 * idx);
                c[idx][1] = amp * gauss(seed, 1, 2 * idx + 1);
            }
    }
    fftw_execute(plan); /* not interruptible: some seconds at 1024^3 */
    fftw_destroy_plan(plan);
    double mean = 0.0, var = 0.0;
    for (size_t i = 0; i < nreal; i++)
        mean += r[i];
    mean /= (double)nreal;
    for (size_t i = 0; i < nreal; i++)
        var += (r[i] - mean) * (r[i] - mean);
    double inv_sd = var > 0.0 ? 1.0 / sqrt(var / (double)nreal) : 0.0;
    for (size_t i = 0; i < nreal; i++)
        out[i] = (float)((r[i] - mean) * inv_sd);
    fftw_free(c);
    fftw_free(r);
    return BRUME_OK;
}

/* ---- Perlin noise ---------------------------------------------------------------------------- */

void perlin_init(perlin_table *t, uint64_t seed)
{
    for (int i = 0; i < 256; i++)
        t->p[i] = (uint8_t)i;
    rng r = rng_make(seed, 2, 0);
    for (int i = 255; i > 0; i--) { /* Fisher-Yates */
        int j = (int)(rng_next(&r) * (i + 1));
        uint8_t s = t->p[i];
        t->p[i] = t->p[j];
        t->p[j] = s;
    }
    memcpy(t->p + 256, t->p, 256);
}

static double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }
static double lerp(double t, double a, double b) { return a + t * (b - a); }
/* Perlin 2002: 12 edge directions of the cube picked by the low 4 bits of the hash. */
static double grad(int hash, double x, double y, double z)
{
    int h = hash & 15;
    double u = h < 8 ? x : y, v = h < 4 ? y : (h == 12 || h == 14 ? x : z);
    return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

double perlin_noise(const perlin_table *t, vec3 x)
{
    const uint8_t *p = t->p;
    double fx = floor(x.x), fy = floor(x.y), fz = floor(x.z);
    int X = (int)fx & 255, Y = (int)fy & 255, Z = (int)fz & 255;
    double a = x.x - fx, b = x.y - fy, c = x.z - fz;
    double u = fade(a), v = fade(b), w = fade(c);
    int A = p[X] + Y, AA = p[A] + Z, AB = p[A + 1] + Z, B = p[X + 1] + Y, BA = p[B] + Z, BB = p[B + 1] + Z;
    return lerp(w,
                lerp(v, lerp(u, grad(p[AA], a, b, c), grad(p[BA], a - 1, b, c)),
                     lerp(u, grad(p[AB], a, b - 1, c), grad(p[BB], a - 1, b - 1, c))),
                lerp(v, lerp(u, grad(p[AA + 1], a, b, c - 1), grad(p[BA + 1], a - 1, b, c - 1)),
                     lerp(u, grad(p[AB + 1], a, b - 1, c - 1), grad(p[BB + 1], a - 1, b - 1, c - 1))));
}

double perlin_turbulence(const perlin_table *t, vec3 x, int octaves)
{
    double sum = 0.0, f = 1.0;
    for (int o = 0; o < octaves; o++) {
        sum += fabs(perlin_noise(t, v3_scale(x, f))) / f;
        f *= 2.0;
    }
    return sum;
}

/* ---- the cloud --------------------------------------------------------------------------------- */

void fractal_params_default(fractal_params *p)
{
    memset(p, 0, sizeof *p);
    p->n[0] = 65;
    p->n[1] = 65;
    p->n[2] = 10;
    p->seed = 1;
    p->method = FRACTAL_MIDPOINT;
    p->hurst = 0.5;
    p->octaves = 6;
    p->frequency = 2.0;
    p->shape = FRACTAL_SHAPE_SLAB;
    p->falloff = 0.6;
    p->threshold = 0.4;
    p->turbulence = 0.0;
    p->turbulence_frequency = 4.0;
    p->wind = v3(0.0, 0.0, 0.0);
    p->density = 1.0;
}

void fractal_params_from_api(const brume_fractal *f, fractal_params *p)
{
    for (int k = 0; k < 3; k++)
        p->n[k] = f->dims[k];
    p->seed = f->seed;
    p->method = (fractal_method)f->method;
    p->hurst = f->hurst;
    p->octaves = f->octaves;
    p->frequency = f->frequency;
    p->shape = (fractal_shape)f->shape;
    p->falloff = f->falloff;
    p->threshold = f->threshold;
    p->threshold_rate = f->threshold_rate;
    p->turbulence = f->turbulence;
    p->turbulence_frequency = f->turbulence_frequency;
    p->wind = v3(f->wind[0], f->wind[1], f->wind[2]);
    p->time = f->time;
    p->density = f->density;
}

static double smoothstep(double a, double b, double x)
{
    double t = fmin(1.0, fmax(0.0, (x - a) / (b - a)));
    return t * t * (3.0 - 2.0 * t);
}

/* The solid texture s(q), q in [-1, 1]^3. */
static double shape(const fractal_params *p, vec3 q)
{
    double e = 1.0 - p->falloff;
    switch (p->shape) {
    case FRACTAL_SHAPE_NONE: return 1.0;
    case FRACTAL_SHAPE_ELLIPSOID: return 1.0 - smoothstep(e, 1.0, v3_length(q));
    case FRACTAL_SHAPE_SLAB:
        return (1.0 - smoothstep(e, 1.0, fabs(q.z))) * (1.0 - smoothstep(e, 1.0, fabs(q.x))) *
               (1.0 - smoothstep(e, 1.0, fabs(q.y)));
    }
    return 1.0;
}

/* The fBm base f, normalized to [0, 1] over the grid. */
static float *fractal_base(const fractal_params *p)
{
    size_t count = (size_t)p->n[0] * (size_t)p->n[1] * (size_t)p->n[2];
    float *f = malloc(count * sizeof *f);
    if (!f) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "fractal: out of memory");
        return NULL;
    }
    int nmax = p->n[0] > p->n[1] ? p->n[0] : p->n[1];
    nmax = p->n[2] > nmax ? p->n[2] : nmax;
    if (p->method == FRACTAL_MIDPOINT) {
        /* the smallest (2^L + 1)^3 lattice holding the grid; keep its corner block */
        int L = 1;
        while ((1 << L) + 1 < nmax)
            L++;
        size_t N = ((size_t)1 << L) + 1;
        float *lat = malloc(N * N * N * sizeof *lat);
        if (!lat || fractal_midpoint(L, p->hurst, p->seed, p->n[2], lat) != BRUME_OK) {
            if (!lat)
                err_set(BRUME_ERROR_OUT_OF_MEMORY, "fractal: out of memory for a %zu^3 lattice", N);
            free(lat);
            free(f);
            return NULL;
        }
        for (int k = 0; k < p->n[2]; k++)
            for (int j = 0; j < p->n[1]; j++)
                memcpy(f + (size_t)p->n[0] * ((size_t)j + (size_t)p->n[1] * (size_t)k),
                       lat + N * ((size_t)j + N * (size_t)k), (size_t)p->n[0] * sizeof *f);
        free(lat);
    } else if (p->method == FRACTAL_SPECTRAL) {
        if (fractal_spectral(p->n, p->hurst, p->seed, f) != BRUME_OK) {
            free(f);
            return NULL;
        }
    } else {
        perlin_table t;
        perlin_init(&t, p->seed);
        double gain = pow(2.0, -p->hurst);
        for (int k = 0; k < p->n[2]; k++) {
            if (cancel_load_check("fractal") != BRUME_OK) {
                free(f);
                return NULL;
            }
            for (int j = 0; j < p->n[1]; j++)
                for (int i = 0; i < p->n[0]; i++) {
                    vec3 x = v3_scale(v3(i + 0.5, j + 0.5, k + 0.5), p->frequency / nmax);
                    double s = 0.0, a = 1.0;
                    for (int o = 0; o < p->octaves; o++) {
                        s += a * perlin_noise(&t, x);
                        x = v3_scale(x, 2.0);
                        a *= gain;
                    }
                    f[(size_t)i + (size_t)p->n[0] * ((size_t)j + (size_t)p->n[1] * (size_t)k)] = (float)s;
                }
        }
    }
    float lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < count; i++) {
        lo = fminf(lo, f[i]);
        hi = fmaxf(hi, f[i]);
    }
    float inv = hi > lo ? 1.0f / (hi - lo) : 0.0f;
    for (size_t i = 0; i < count; i++)
        f[i] = (f[i] - lo) * inv;
    return f;
}

/* The work before it starts (render.max_work), in noise values and lattice points:
 * the base (Perlin: a value per voxel and octave; midpoint: every point of its (2^L + 1)^3
 * lattice; spectral: the FFT's log2(count) butterflies per voxel and a coefficient), the
 * turbulence (a value per voxel and octave) and the shape (one per voxel). */
static brume_status fractal_check_work(const fractal_params *p, size_t count)
{
    double n = (double)count, base;
    const char *method;
    if (p->method == FRACTAL_MIDPOINT) {
        int nmax = p->n[0] > p->n[1] ? p->n[0] : p->n[1], L = 1;
        nmax = p->n[2] > nmax ? p->n[2] : nmax;
        while ((1 << L) + 1 < nmax)
            L++;
        double N = (double)((1 << L) + 1);
        base = N * N * N;
        method = "midpoint";
    } else if (p->method == FRACTAL_SPECTRAL) {
        base = n * (1.0 + log2(n));
        method = "spectral";
    } else {
        base = n * p->octaves;
        method = "perlin";
    }
    double turbulence = p->turbulence > 0.0 ? n * p->octaves : 0.0;
    char how[160];
    snprintf(how, sizeof how, "%d x %d x %d voxels (a %s base of %.3g, turbulence %.3g, shape %.3g)", p->n[0],
             p->n[1], p->n[2], method, base, turbulence, n);
    return budget_work(base + turbulence + n, "fractal cloud", how);
}

/* Perlin's lattice index is an int: the largest coordinate of the finest octave, the
 * turbulence moved by wind x time included, stays within 1e9 (2^31 is the int's end). */
static brume_status fractal_check_lattice(const fractal_params *p)
{
    double octave = ldexp(1.0, p->octaves - 1), wind_t;
    wind_t = fmax(fabs(p->wind.x * p->time), fmax(fabs(p->wind.y * p->time), fabs(p->wind.z * p->time)));
    double reach = octave * (p->turbulence > 0.0 ? p->turbulence_frequency + wind_t : 0.0);
    if (!(octave * p->frequency <= 1e9) || !(reach <= 1e9))
        return err_set(BRUME_ERROR_RANGE,
                       "fractal: at time %.17g s the noise reaches lattice coordinate %.3g (frequency %.17g, "
                       "turbulence frequency %.17g, wind x time %.3g, %d octaves), beyond 1e9: brume's noise "
                       "lattice is indexed by an int",
                       p->time, fmax(octave * p->frequency, reach), p->frequency, p->turbulence_frequency, wind_t,
                       p->octaves);
    return BRUME_OK;
}

float *fractal_cloud_voxels(const fractal_params *p)
{
    for (int a = 0; a < 3; a++)
        if (p->n[a] < 1 || p->n[a] > 1024) {
            err_set(BRUME_ERROR_INVALID_ARGUMENT, "fractal: dimension %d outside [1, 1024]", p->n[a]);
            return NULL;
        }
    if (!(p->hurst > 0.0 && p->hurst < 1.0) || p->octaves < 1 || p->octaves > 16 || !(p->falloff > 0.0 && p->falloff <= 1.0) ||
        !(p->threshold >= 0.0 && p->threshold < 1.0) || !(p->turbulence >= 0.0) || !(p->density > 0.0) ||
        !isfinite(p->time) || !isfinite(p->threshold_rate) || !isfinite(p->density) || !isfinite(p->turbulence) ||
        !(p->frequency > 0.0) || !(p->turbulence_frequency > 0.0) || !v3_isfinite(p->wind)) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT,
                "fractal: need H in (0, 1), octaves in [1, 16], falloff in (0, 1], threshold in [0, 1), "
                "turbulence >= 0, frequencies and density > 0, finite time and rates");
        return NULL;
    }
    if (fractal_check_lattice(p) != BRUME_OK)
        return NULL;
    /* the memory budget, before anything is allocated: the grid stays, the lattice or the
     * Fourier coefficients are given back when the base is made */
    size_t count = (size_t)p->n[0] * (size_t)p->n[1] * (size_t)p->n[2], temp = 0;
    if (p->method == FRACTAL_MIDPOINT) {
        int nmax = p->n[0] > p->n[1] ? p->n[0] : p->n[1], L = 1;
        nmax = p->n[2] > nmax ? p->n[2] : nmax;
        while ((1 << L) + 1 < nmax)
            L++;
        size_t N = ((size_t)1 << L) + 1;
        temp = N * N * N * sizeof(float);
    } else if (p->method == FRACTAL_SPECTRAL) {
        temp = count * (2 * sizeof(double) + sizeof(double));
    }
    if (fractal_check_work(p, count) != BRUME_OK ||
        budget_take(count * sizeof(float), "fractal cloud grid") != BRUME_OK ||
        budget_take(temp, "fractal cloud lattice") != BRUME_OK)
        return NULL;
    float *f = fractal_base(p);
    budget_give(temp);
    if (!f)
        return NULL;
    perlin_table t;
    perlin_init(&t, p->seed ^ 0x7475726275ULL);
    int nmax = p->n[0] > p->n[1] ? p->n[0] : p->n[1];
    nmax = p->n[2] > nmax ? p->n[2] : nmax;
    double theta = fmin(0.99, fmax(0.0, p->threshold + p->threshold_rate * p->time));
    /* Perlin's turbulence with 6 octaves has mean 0.44 (measured, tests/test_fractal.c);
     * subtracting it keeps the cloud's mean size when the turbulence amplitude grows. */
    const double turb_mean = 0.44;
    for (int k = 0; k < p->n[2]; k++) {
        if (cancel_load_check("fractal") != BRUME_OK) { /* a plane: 1024^2 voxels at most */
            free(f);
            return NULL;
        }
        for (int j = 0; j < p->n[1]; j++)
            for (int i = 0; i < p->n[0]; i++) {
                size_t idx = (size_t)i + (size_t)p->n[0] * ((size_t)j + (size_t)p->n[1] * (size_t)k);
                vec3 q = v3(2.0 * (i + 0.5) / p->n[0] - 1.0, 2.0 * (j + 0.5) / p->n[1] - 1.0,
                            2.0 * (k + 0.5) / p->n[2] - 1.0);
                double g = (double)f[idx];
                if (p->turbulence > 0.0) {
                    vec3 x = v3_scale(v3(i + 0.5, j + 0.5, k + 0.5), p->turbulence_frequency / nmax);
                    x = v3_madd(x, p->wind, p->time);
                    g += p->turbulence * (perlin_turbulence(&t, x, p->octaves) - turb_mean);
                }
                double v = (shape(p, q) * g - theta) / (1.0 - theta);
                f[idx] = (float)(p->density * fmin(1.0, fmax(0.0, v)));
            }
    }
    return f;
}

density *fractal_cloud(const fractal_params *p, box3 bounds, grid_filter filter)
{
    float *v = fractal_cloud_voxels(p);
    if (!v)
        return NULL;
    density *d = density_new_grid(p->n[0], p->n[1], p->n[2], v, bounds, filter);
    if (!d)
        free(v);
    return d;
}
