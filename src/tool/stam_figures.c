/* stam_figures.c - the plots of Stam 1994 that are not renderings (brume_stam_figure_png): Figure 1,
 * a random blob with and without clamping, and Figure 4, the variance of the optical depth
 * against the distance of the ray from the blob's centre, closed form against a Monte-Carlo
 * estimate over explicit 3-D realizations. docs/stam.md explains both. */
#include "brume.h"

#include <math.h>
#include <pthread.h>

#include <stdio.h>
#include <stdlib.h>

#include "io/chart.h"
#include "core/context.h"
#include "core/error.h"
#include "io/atomic.h"
#include "density/blobs.h"
#include "density/randfield.h"
#include "render/stam_stats.h"

#define FIG1_N 701

static brume_status stam_figure1_png(const char *path, bool quick)
{
    (void)quick; /* one realization along a line: already fast */
    const double h = 1.0, eps = 0.3, alpha = 0.15, eta = 0.25;
    const double peak = 1.0, m = peak * pow(2.0 * PI, 1.5) * h * h * h;
    blob b = {v3(0, 0, 0), m, h};
    blob_field *f = blob_field_new(&b, 1, BLOB_DEFAULT_CUTOFF, path);
    if (!f)
        return err_status();
    randfield_params rp = {{512, 4, 4}, alpha / 3.0, alpha, 7, 0.0, 0.0};
    randfield *q = randfield_new(&rp);
    static double x[FIG1_N], mean[FIG1_N], lo[2][FIG1_N], hi[2][FIG1_N], real[2][FIG1_N], clamp[FIG1_N];
    if (!q) {
        blob_field_release(f);
        return err_prefix("%s", path);
    }
    for (int i = 0; i < FIG1_N; i++) {
        x[i] = -3.5 * h + 7.0 * h * i / (FIG1_N - 1);
        mean[i] = blob_mean_at(f, 0, v3(x[i], 0, 0));
        double Q = randfield_eval(q, v3(x[i] + 5.0, 0, 0));
        clamp[i] = stam_clamp(mean[i], eta);
        for (int c = 0; c < 2; c++) {
            double sigma = sqrt(eps * (c ? clamp[i] : mean[i])); /* Section 4: sigma^2 = eps F_eta(mean) */
            lo[c][i] = mean[i] - sigma;
            hi[c][i] = mean[i] + sigma;
            real[c][i] = mean[i] + sigma * Q;
        }
    }
    randfield_release(q);
    blob_field_release(f);
    chart_series s[2][5];
    chart_panel p[2];
    static char titles[2][96];
    snprintf(titles[0], sizeof titles[0], "no clamping: sigma^2 = eps mean");
    snprintf(titles[1], sizeof titles[1], "clamped, eta = %g: sigma^2 = eps min(mean, eta)", eta);
    for (int c = 0; c < 2; c++) {
        s[c][0] = (chart_series){"mean density", FIG1_N, x, mean, NULL, CHART_LINE, 0};
        s[c][1] = (chart_series){"mean +- sigma", FIG1_N, x, hi[c], NULL, CHART_DASHED, 6};
        s[c][2] = (chart_series){NULL, FIG1_N, x, lo[c], NULL, CHART_DASHED, 6};
        s[c][3] = (chart_series){"a realization", FIG1_N, x, real[c], NULL, CHART_LINE, 1};
        s[c][4] = (chart_series){"F_eta(mean)", FIG1_N, x, clamp, NULL, CHART_THIN, 2};
        p[c] = (chart_panel){titles[c], "position along a line through the centre (units of h)", "density", c ? 5 : 4,
                             s[c], true};
    }
    return chart_png(path,
                     "Stam 1994, Figure 1: a random blob rho = mean + sigma Q (h = 1, peak 1, eps = 0.3, alpha = 0.15 h), "
                     "the same Q in both",
                     2, p);
}

/* Figure 4: one blob (h = 1, peak 0.254), eps 0.6, alpha 0.25, rays along z at distances
 * d = i cell from the centre. Q on a 20 x 4 x 64 lattice of spacing alpha / 1.5: its
 * covariance along z is exactly the gaussian's at any lattice size across (the spectrum
 * factorizes), and the trapezoid rule along lattice lines is exact to e^-44 (docs/stam.md). */
#define F4_NX 20
#define F4_NY 4
#define F4_NZ 64
#define F4_ETAS 4

enum { F4_NR = 19, F4_NC = 61 };

/* Sums of T and T^2 over 2 * pairs explicit realizations of Q, per eta and distance. */
static brume_status f4_realize(int pairs, double eps, double cell, const double *etas,
                               const double mean[F4_NR][F4_NZ], double S[F4_ETAS][F4_NR], double S2[F4_ETAS][F4_NR],
                               const char *path)
{
    const double alpha = 0.25;
    size_t count = (size_t)F4_NX * F4_NY * F4_NZ;
    float *q[2] = {malloc(count * sizeof(float)), malloc(count * sizeof(float))};
    brume_status st = q[0] && q[1] ? BRUME_OK : err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    randfield_params rp = {{F4_NX, F4_NY, F4_NZ}, cell, alpha, 1994, 0.0, 0.0};
    for (int pr = 0; pr < pairs && st == BRUME_OK; pr++) {
        if ((st = randfield_synthesize(&rp, (uint64_t)pr, q[0], q[1])))
            break;
        for (int w = 0; w < 2; w++)
            for (int r = 0; r < F4_NR; r++)
                for (int e = 0; e < F4_ETAS; e++) {
                    double T = 0.0;
                    for (int k = 0; k < F4_NZ; k++) {
                        double sig = sqrt(eps * stam_clamp(mean[r][k], etas[e]));
                        double rho = mean[r][k] + sig * (double)q[w][(size_t)r + F4_NX * (size_t)F4_NY * (size_t)k];
                        T += (k == 0 || k == F4_NZ - 1 ? 0.5 : 1.0) * rho * cell;
                    }
                    S[e][r] += T;
                    S2[e][r] += T * T;
                }
    }
    free(q[0]);
    free(q[1]);
    return st;
}

static brume_status stam_figure4_png(const char *path, bool quick, double *max_z)
{
    const double h = 1.0, eps = 0.6, alpha = 0.25, cell = alpha / 1.5;
    const double etas[F4_ETAS] = {1e30, 0.2, 0.1, 0.05};
    const int pairs = quick ? 60 : 600;
    blob b = {v3(0, 0, 32 * cell), 4.0, h};
    blob_field *f = blob_field_new(&b, 1, BLOB_DEFAULT_CUTOFF, path);
    if (!f)
        return err_status();
    stam_stats_init();
    enum { NR = F4_NR, NC = F4_NC };
    static double mean[NR][F4_NZ], S[F4_ETAS][NR], S2[F4_ETAS][NR];
    static double d_mc[NR], v_mc[F4_ETAS][NR], e_mc[F4_ETAS][NR], d_cf[NC], v_cf[F4_ETAS][NC];
    for (int r = 0; r < NR; r++) {
        d_mc[r] = r * cell;
        for (int k = 0; k < F4_NZ; k++)
            mean[r][k] = blob_mean_at(f, 0, v3(r * cell, 0, k * cell));
        for (int e = 0; e < F4_ETAS; e++)
            S[e][r] = S2[e][r] = 0.0;
    }
    if (f4_realize(pairs, eps, cell, etas, (const double(*)[F4_NZ])mean, S, S2, path) != BRUME_OK) {
        blob_field_release(f);
        return err_prefix("%s", path);
    }
    int M = 2 * pairs;
    double worst = 0.0;
    for (int e = 0; e < F4_ETAS; e++) {
        for (int c = 0; c < NC; c++) {
            d_cf[c] = 3.0 * h * c / (NC - 1);
            blob_ray br = blob_ray_make(f, 0, 32 * cell, d_cf[c] * d_cf[c]);
            v_cf[e][c] = blob_T_var(&br, eps, etas[e], alpha, -1e9, 1e9);
        }
        for (int r = 0; r < NR; r++) {
            double m = S[e][r] / M;
            v_mc[e][r] = (S2[e][r] - M * m * m) / (M - 1);
            e_mc[e][r] = v_mc[e][r] * sqrt(2.0 / (M - 1)); /* T is gaussian */
            blob_ray br = blob_ray_make(f, 0, 32 * cell, d_mc[r] * d_mc[r]);
            double want = blob_T_var(&br, eps, etas[e], alpha, -1e9, 1e9);
            if (want > 0.0)
                worst = fmax(worst, fabs(v_mc[e][r] - want) / (want * sqrt(2.0 / (M - 1))));
        }
    }
    blob_field_release(f);
    if (max_z)
        *max_z = worst;
    chart_series s[2 * F4_ETAS];
    static char labels[2 * F4_ETAS][64];
    for (int e = 0; e < F4_ETAS; e++) {
        if (e == 0)
            snprintf(labels[2 * e], sizeof labels[0], "no clamping");
        else
            snprintf(labels[2 * e], sizeof labels[0], "eta = %g", etas[e]);
        s[2 * e] = (chart_series){labels[2 * e], NC, d_cf, v_cf[e], NULL, CHART_LINE, e};
        s[2 * e + 1] = (chart_series){e == 0 ? "Monte Carlo, +- 1 s.e." : NULL, NR, d_mc, v_mc[e], e_mc[e],
                                      CHART_POINTS, e};
    }
    static char title[256];
    snprintf(title, sizeof title, "Stam 1994, Figure 4: Var T_i against d_i");
    static char sub[128];
    snprintf(sub, sizeof sub, "closed form (lines), %d explicit realizations (points)", M);
    chart_panel p = {sub, "distance d_i of the ray from the centre (units of h)", "Var T_i", 2 * F4_ETAS, s, true};
    return chart_png(path, title, 1, &p);
}

/* The figures keep their series in static arrays: one figure at a time. */
static pthread_mutex_t figure_lock = PTHREAD_MUTEX_INITIALIZER;

brume_status brume_stam_figure_png(brume_context *ctx, int figure, const char *path, bool quick, double *max_z)
{
    err_clear();
    if (max_z)
        *max_z = 0.0;
    if (!path)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_stam_figure_png: path: NULL"));
    if (figure != 1 && figure != 4)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT,
                                       "brume_stam_figure_png: figure: %d (Stam's plots are Figures 1 and 4)", figure));
    const void *owner = atomic_owner(ctx);
    pthread_mutex_lock(&figure_lock);
    brume_status st = figure == 1 ? stam_figure1_png(path, quick) : stam_figure4_png(path, quick, max_z);
    pthread_mutex_unlock(&figure_lock);
    atomic_owner(owner);
    return ctx_report(ctx, st);
}
