/* randfield.c - Stam's random field Q: gaussian covariance, inverse spectral synthesis with
 * FFTW on a periodic lattice, smooth evolution in time, trilinear lookup (randfield.h). */
#include "density/randfield.h"

#include <fftw3.h>
#include <stdlib.h>

#include "core/budget.h"
#include "core/cancel.h"
#include "core/error.h"
#include "core/rng.h"

/* Signed frequency index of FFT bin j of n: 0, 1, ..., n/2, -(n/2 - 1), ..., -1. */
static inline int freq_index(int j, int n) { return j <= n / 2 ? j : j - n; }

static bool params_ok(const randfield_params *p)
{
    for (int a = 0; a < 3; a++)
        if (p->n[a] < 2 || p->n[a] > 512)
            return false;
    return p->cell > 0.0 && isfinite(p->cell) && p->alpha > 0.0 && isfinite(p->alpha) && isfinite(p->time) &&
           p->rate >= 0.0 && isfinite(p->rate);
}

static brume_status synthesis_cancelled(fftw_plan plan, fftw_plan columns, fftw_complex *c)
{
    fftw_destroy_plan(plan);
    fftw_destroy_plan(columns);
    fftw_free(c);
    return BRUME_ERROR_CANCELLED;
}

brume_status randfield_synthesize(const randfield_params *p, uint64_t index, float *re, float *im)
{
    if (!params_ok(p))
        return err_set(BRUME_ERROR_INVALID_ARGUMENT,
                       "random field: need lattice sizes in [2, 512], cell > 0, alpha > 0, rate >= 0");
    int nx = p->n[0], ny = p->n[1], nz = p->n[2];
    size_t count = (size_t)nx * (size_t)ny * (size_t)nz;
    fftw_complex *c = fftw_malloc(count * sizeof *c);
    if (!c)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "random field: out of memory for %d x %d x %d", nx, ny, nz);
    /* FFTW is row-major, last index fastest: x fastest. In place, and separable, so that it
     * can stop between pieces (a 512^3 lattice's transform takes some 20 s): a 2D transform
     * of each z plane, then the 1D transforms along z, a row of x at a time. FFTW's own 3D plan
     * is the same two steps: the values are those bits (checked over 15 lattice shapes, odd
     * and prime sizes included, against fftw_plan_dft_3d with FFTW 3.3.10). Every plane and
     * row starts a whole number of complex values (16 bytes) from the buffer's start, which
     * keeps FFTW's alignment (fftw_alignment_of), so the two plans run on every piece. */
    int plane_dims[2] = {ny, nx}, column_dims[1] = {nz};
    int plane = nx * ny; /* at most 512^2 */
    fftw_plan plan = fftw_plan_many_dft(2, plane_dims, 1, c, NULL, 1, 0, c, NULL, 1, 0, FFTW_BACKWARD, FFTW_ESTIMATE);
    fftw_plan columns =
        fftw_plan_many_dft(1, column_dims, nx, c, NULL, plane, 1, c, NULL, plane, 1, FFTW_BACKWARD, FFTW_ESTIMATE);
    double dk[3] = {2.0 * PI / (nx * p->cell), 2.0 * PI / (ny * p->cell), 2.0 * PI / (nz * p->cell)};
    double a2 = p->alpha * p->alpha, gsum = 0.0;
    for (int k = 0; k < nz; k++) {
        if (cancel_load_check("random field") != BRUME_OK) /* a plane: 512^2 modes at most */
            return synthesis_cancelled(plan, columns, c);
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++) {
                double kx = dk[0] * freq_index(i, nx), ky = dk[1] * freq_index(j, ny), kz = dk[2] * freq_index(k, nz);
                double k2 = kx * kx + ky * ky + kz * kz;
                double g = exp(-0.5 * a2 * k2);
                gsum += g;
                size_t idx = (size_t)i + (size_t)nx * ((size_t)j + (size_t)ny * (size_t)k);
                /* xi_k exp(i omega_k t) from a counter-based stream per mode: independent of threads */
                rng r = rng_make(p->seed, index, idx);
                double u1 = rng_next(&r), u2 = rng_next(&r);
                double rad = sqrt(-2.0 * log(1.0 - u1));
                double phase = 2.0 * PI * u2 + p->rate * (1.0 + p->alpha * sqrt(k2)) * p->time;
                double amp = sqrt(g);
                /* Box-Muller: (rad cos, rad sin) are two independent N(0, 1): a + i b with
                 * phase uniform; rotating by omega t keeps it circular gaussian */
                c[idx][0] = amp * rad * cos(phase);
                c[idx][1] = amp * rad * sin(phase);
            }
    }
    double norm = 1.0 / sqrt(gsum);
    for (int k = 0; k < nz; k++) {
        if (cancel_load_check("random field") != BRUME_OK) /* a plane's 2D transform */
            return synthesis_cancelled(plan, columns, c);
        fftw_execute_dft(plan, c + (size_t)k * (size_t)plane, c + (size_t)k * (size_t)plane);
    }
    for (int j = 0; j < ny; j++) {
        if (cancel_load_check("random field") != BRUME_OK) /* nx transforms of nz points */
            return synthesis_cancelled(plan, columns, c);
        fftw_execute_dft(columns, c + (size_t)j * (size_t)nx, c + (size_t)j * (size_t)nx);
    }
    fftw_destroy_plan(plan);
    fftw_destroy_plan(columns);
    for (size_t i = 0; i < count; i++) {
        re[i] = (float)(c[i][0] * norm);
        if (im)
            im[i] = (float)(c[i][1] * norm);
    }
    fftw_free(c);
    return BRUME_OK;
}

randfield *randfield_new(const randfield_params *p)
{
    if (!params_ok(p)) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "random field: need lattice sizes in [2, 512], cell > 0, alpha > 0");
        return NULL;
    }
    size_t count = (size_t)p->n[0] * (size_t)p->n[1] * (size_t)p->n[2];
    /* the lattice stays; its complex Fourier coefficients are given back once synthesized */
    if (budget_take(count * sizeof(float), "random field lattice") != BRUME_OK ||
        budget_take(count * 2 * sizeof(double), "random field lattice (Fourier coefficients)") != BRUME_OK)
        return NULL;
    randfield *q = calloc(1, sizeof *q);
    if (q)
        q->q = malloc(count * sizeof *q->q);
    if (!q || !q->q) {
        free(q);
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "random field: out of memory");
        return NULL;
    }
    for (int a = 0; a < 3; a++)
        q->n[a] = p->n[a];
    q->inv_cell = 1.0 / p->cell;
    brume_status st = randfield_synthesize(p, 0, q->q, NULL);
    budget_give(count * 2 * sizeof(double));
    if (st != BRUME_OK) {
        randfield_release(q);
        return NULL;
    }
    return q;
}

void randfield_release(randfield *q)
{
    if (!q)
        return;
    free(q->q);
    free(q);
}

/* Lattice coordinate x split into a wrapped node index and a fraction. */
static inline int wrap_split(double x, int n, double *frac)
{
    double f = floor(x);
    *frac = x - f;
    if (!(fabs(f) < 1e15)) /* NaN, infinite or beyond exact integer conversion */
        return 0;
    long long i = (long long)f % n;
    return (int)(i < 0 ? i + n : i);
}

double randfield_eval(const randfield *q, vec3 p)
{
    double fx, fy, fz;
    int nx = q->n[0], ny = q->n[1], nz = q->n[2];
    int i0 = wrap_split(p.x * q->inv_cell, nx, &fx), j0 = wrap_split(p.y * q->inv_cell, ny, &fy),
        k0 = wrap_split(p.z * q->inv_cell, nz, &fz);
    if (!isfinite(fx) || !isfinite(fy) || !isfinite(fz))
        return 0.0;
    int i1 = i0 + 1 == nx ? 0 : i0 + 1, j1 = j0 + 1 == ny ? 0 : j0 + 1, k1 = k0 + 1 == nz ? 0 : k0 + 1;
    const float *v = q->q;
    size_t sy = (size_t)nx, sz = (size_t)nx * (size_t)ny;
    size_t r00 = (size_t)j0 * sy + (size_t)k0 * sz, r10 = (size_t)j1 * sy + (size_t)k0 * sz;
    size_t r01 = (size_t)j0 * sy + (size_t)k1 * sz, r11 = (size_t)j1 * sy + (size_t)k1 * sz;
#define LERP_X(r) ((double)v[(r) + (size_t)i0] + fx * ((double)v[(r) + (size_t)i1] - (double)v[(r) + (size_t)i0]))
    double c00 = LERP_X(r00), c10 = LERP_X(r10), c01 = LERP_X(r01), c11 = LERP_X(r11);
#undef LERP_X
    double c0 = c00 + fy * (c10 - c00), c1 = c01 + fy * (c11 - c01);
    return c0 + fz * (c1 - c0);
}
