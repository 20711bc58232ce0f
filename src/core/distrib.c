/* distrib.c - piecewise-constant distributions sampled by inverting their CDF. */
#include "core/distrib.h"

#include <stddef.h>

#include "core/arena.h"

#include <stdlib.h>
#include <string.h>

int distrib1_init(distrib1 *d, const double *f, int n)
{
    d->n = n;
    d->f = malloc(sizeof *d->f * (size_t)n);
    d->cdf = malloc(sizeof *d->cdf * ((size_t)n + 1));
    if (!d->f || !d->cdf) {
        distrib1_free(d);
        return 0;
    }
    memcpy(d->f, f, sizeof *d->f * (size_t)n);
    d->cdf[0] = 0.0;
    for (int i = 0; i < n; i++)
        d->cdf[i + 1] = d->cdf[i] + d->f[i] / n;
    d->integral = d->cdf[n];
    if (!(d->integral > 0.0)) {
        for (int i = 0; i < n; i++)
            d->f[i] = 1.0;
        for (int i = 0; i <= n; i++)
            d->cdf[i] = (double)i / n;
        d->integral = 1.0;
    } else {
        for (int i = 1; i <= n; i++)
            d->cdf[i] /= d->integral;
    }
    d->cdf[n] = 1.0;
    return 1;
}

void distrib1_free(distrib1 *d)
{
    free(d->f);
    free(d->cdf);
    d->f = d->cdf = NULL;
}

double distrib1_sample(const distrib1 *d, double u, double *pdf, int *bin)
{
    /* largest i with cdf[i] <= u */
    int lo = 0, hi = d->n;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (d->cdf[mid] <= u)
            lo = mid;
        else
            hi = mid;
    }
    double width = d->cdf[lo + 1] - d->cdf[lo];
    double du = width > 0.0 ? (u - d->cdf[lo]) / width : 0.5;
    if (pdf)
        *pdf = d->f[lo] / d->integral;
    if (bin)
        *bin = lo;
    double x = (lo + du) / d->n;
    return x < 1.0 ? x : 0x1.fffffffffffffp-1;
}

double distrib1_pdf(const distrib1 *d, double x)
{
    int i = (int)(x * d->n);
    i = i < 0 ? 0 : (i >= d->n ? d->n - 1 : i);
    return d->f[i] / d->integral;
}

int distrib2_init(distrib2 *d, const double *f, int nu, int nv)
{
    d->nu = nu;
    d->nv = nv;
    d->rows = calloc((size_t)nv, sizeof *d->rows);
    double *marg = malloc(sizeof *marg * (size_t)nv);
    if (!d->rows || !marg) {
        free(d->rows);
        free(marg);
        d->rows = NULL;
        return 0;
    }
    for (int v = 0; v < nv; v++) {
        if (!distrib1_init(&d->rows[v], f + (size_t)v * (size_t)nu, nu)) {
            for (int k = 0; k < v; k++)
                distrib1_free(&d->rows[k]);
            free(d->rows);
            free(marg);
            d->rows = NULL;
            return 0;
        }
        /* a row whose function was all zero was made uniform: its marginal stays 0 */
        double s = 0.0;
        for (int u = 0; u < nu; u++)
            s += f[(size_t)v * (size_t)nu + (size_t)u];
        marg[v] = s / nu;
    }
    int ok = distrib1_init(&d->marginal, marg, nv);
    free(marg);
    if (!ok)
        distrib2_free(d);
    return ok;
}

void distrib2_free(distrib2 *d)
{
    if (d->rows)
        for (int v = 0; v < d->nv; v++)
            distrib1_free(&d->rows[v]);
    free(d->rows);
    d->rows = NULL;
    distrib1_free(&d->marginal);
}

void distrib2_sample(const distrib2 *d, double u1, double u2, double *u, double *v, double *pdf)
{
    double pv, pu;
    int row;
    *v = distrib1_sample(&d->marginal, u2, &pv, &row);
    *u = distrib1_sample(&d->rows[row], u1, &pu, NULL);
    *pdf = pu * pv;
}

double distrib2_pdf(const distrib2 *d, double u, double v)
{
    int row = (int)(v * d->nv);
    row = row < 0 ? 0 : (row >= d->nv ? d->nv - 1 : row);
    return distrib1_pdf(&d->marginal, v) * distrib1_pdf(&d->rows[row], u);
}

void distrib1_device_fix(const distrib1 *d, dev_arena *a, size_t at)
{
    const size_t n = d->f ? (size_t)d->n : 0;
    ARENA_PUT_MEMBER(a, at, distrib1, f, d->f, n * sizeof(double));
    ARENA_PUT_MEMBER(a, at, distrib1, cdf, d->cdf, (n + 1) * sizeof(double));
}

void distrib2_device_fix(const distrib2 *d, dev_arena *a, size_t at)
{
    size_t rows = ARENA_NULL;
    if (d->rows) {
        rows = arena_put(a, d->rows, (size_t)d->nv * sizeof(distrib1));
        for (int v = 0; v < d->nv && rows != ARENA_NULL; v++)
            distrib1_device_fix(&d->rows[v], a, rows + (size_t)v * sizeof(distrib1));
    }
    arena_ptr(a, at + offsetof(distrib2, rows), rows);
    distrib1_device_fix(&d->marginal, a, at + offsetof(distrib2, marginal));
}
