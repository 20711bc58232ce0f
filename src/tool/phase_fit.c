/* phase_fit.c - least-squares fit of Blasi's two-lobe Schlick mixture (Eq. 22).
 *
 * The error integrals are sums over fixed quadrature nodes in the angle theta (composite
 * Gauss-Legendre, FIT_PANELS panels of FIT_ORDER nodes), where the target is evaluated
 * once. The minimizer is a grid search over the whole domain followed by Nelder-Mead
 * (Nelder and Mead 1965, with the coefficients of Lagarias et al. 1998) from the best
 * grid points; docs/phase-functions.md compares the result with the paper's Figure 7. */
#include "brume.h"

#include <math.h>

#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/error.h"
#include "phase/phase.h"
#include "phase/quadrature.h"
#include "scene/scene_build.h"

#define FIT_PANELS 180
#define FIT_ORDER 8
#define FIT_NODES (FIT_PANELS * FIT_ORDER)
/* |k| stays below this in the search, a Schlick peak of (1 + K) / (1 - K) = 2e4. */
#define FIT_K_MAX 0.9999
#define FIT_STARTS 6

typedef struct fit_problem {
    brume_phase_fit_norm norm;
    double t[FIT_NODES];   /* cos(theta) at the nodes */
    double w[FIT_NODES];   /* quadrature weight of the norm's measure (dt or d theta) */
    double phi[FIT_NODES]; /* target phi = 4 pi p at the nodes (its log for the log norm) */
    double scale;          /* 1 / (integral of phi^2) for the L2 norms, 1/2 for the log norm */
} fit_problem;

static bool norm_from_name(const char *name, brume_phase_fit_norm *out)
{
    static const brume_phase_fit_norm all[] = {BRUME_PHASE_FIT_COS, BRUME_PHASE_FIT_ANGLE, BRUME_PHASE_FIT_LOG};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        if (strcmp(name, brume_phase_fit_norm_name(all[i])) == 0) {
            *out = all[i];
            return true;
        }
    return false;
}

const char *brume_phase_fit_norm_name(brume_phase_fit_norm norm)
{
    switch (norm) {
    case BRUME_PHASE_FIT_COS: return "cos";
    case BRUME_PHASE_FIT_ANGLE: return "angle";
    case BRUME_PHASE_FIT_LOG: return "log";
    }
    return "?";
}

/* Nodes uniform in theta crowd near both poles in t, where the forward and backward peaks
 * of the targets and of Schlick lobes with |k| near 1 are. */
static brume_status fit_problem_init(fit_problem *fp, const phase *target, brume_phase_fit_norm norm)
{
    double x[FIT_ORDER], wx[FIT_ORDER];
    quad_gauss_legendre(FIT_ORDER, x, wx);
    double h = PI / FIT_PANELS;
    double sum = 0.0;
    fp->norm = norm;
    for (int i = 0; i < FIT_PANELS; i++)
        for (int j = 0; j < FIT_ORDER; j++) {
            int n = i * FIT_ORDER + j;
            double theta = h * (i + 0.5 * (x[j] + 1.0));
            double dtheta = 0.5 * h * wx[j];
            fp->t[n] = cos(theta);
            fp->w[n] = norm == BRUME_PHASE_FIT_ANGLE ? dtheta : dtheta * sin(theta);
            double phi = 4.0 * PI * phase_eval(target, fp->t[n]);
            if (norm == BRUME_PHASE_FIT_LOG) {
                if (!(phi > 0.0))
                    return err_set(BRUME_ERROR_RANGE,
                                   "phase fit: the log norm needs a positive target, got %g at "
                                   "%.2f degrees",
                                   phi, theta * 180.0 / PI);
                phi = log(phi);
            } else {
                sum += fp->w[n] * phi * phi;
            }
            fp->phi[n] = phi;
        }
    fp->scale = norm == BRUME_PHASE_FIT_LOG ? 0.5 : 1.0 / sum;
    return BRUME_OK;
}

/* Blasi Eq. 22 as phi (integral 2 over t). */
static double schlick_mix_phi(double r, double k, double kp, double t)
{
    double d = 1.0 - k * t, dp = 1.0 - kp * t;
    return r * (1.0 - k * k) / (d * d) + (1.0 - r) * (1.0 - kp * kp) / (dp * dp);
}

static double fit_problem_error(const fit_problem *fp, double r, double k, double kp)
{
    double s = 0.0;
    if (fp->norm == BRUME_PHASE_FIT_LOG) {
        for (int n = 0; n < FIT_NODES; n++) {
            double e = log(schlick_mix_phi(r, k, kp, fp->t[n])) - fp->phi[n];
            s += fp->w[n] * e * e;
        }
    } else {
        for (int n = 0; n < FIT_NODES; n++) {
            double e = schlick_mix_phi(r, k, kp, fp->t[n]) - fp->phi[n];
            s += fp->w[n] * e * e;
        }
    }
    return sqrt(s * fp->scale);
}

static double fit_error(const phase *target, brume_phase_fit_norm norm, double r, double k, double kprime)
{
    if (!(r >= 0.0 && r <= 1.0) || !(fabs(k) < 1.0) || !(fabs(kprime) < 1.0))
        return (double)NAN;
    fit_problem *fp = malloc(sizeof *fp);
    if (!fp)
        return (double)NAN;
    double e = fit_problem_init(fp, target, norm) == BRUME_OK ? fit_problem_error(fp, r, k, kprime) : (double)NAN;
    free(fp);
    return e;
}

/* Unconstrained coordinates y to (r, k, k'): r = sin^2 y0, k = K sin y1, k' = K sin y2. */
static void fit_unmap(const double y[3], double *r, double *k, double *kp)
{
    double s = sin(y[0]);
    *r = s * s;
    *k = FIT_K_MAX * sin(y[1]);
    *kp = FIT_K_MAX * sin(y[2]);
}

static double fit_objective(const fit_problem *fp, const double y[3])
{
    double r, k, kp;
    fit_unmap(y, &r, &k, &kp);
    return fit_problem_error(fp, r, k, kp);
}

/* Nelder-Mead on the 3 unconstrained coordinates, from y with initial steps of 0.15 rad.
 * On return y is the best vertex and its value is returned. */
static double nelder_mead(const fit_problem *fp, double y[3])
{
    enum { D = 3 };
    double v[D + 1][D], f[D + 1];
    for (int i = 0; i <= D; i++) {
        for (int j = 0; j < D; j++)
            v[i][j] = y[j] + (i == j + 1 ? 0.15 : 0.0);
        f[i] = fit_objective(fp, v[i]);
    }
    for (int iter = 0; iter < 5000; iter++) {
        /* Order: best first, worst last (insertion sort of 4 vertices). */
        for (int i = 1; i <= D; i++)
            for (int j = i; j > 0 && f[j] < f[j - 1]; j--) {
                double tf = f[j];
                f[j] = f[j - 1];
                f[j - 1] = tf;
                for (int c = 0; c < D; c++) {
                    double tv = v[j][c];
                    v[j][c] = v[j - 1][c];
                    v[j - 1][c] = tv;
                }
            }
        double size = 0.0;
        for (int i = 1; i <= D; i++)
            for (int c = 0; c < D; c++)
                size = fmax(size, fabs(v[i][c] - v[0][c]));
        if (size < 1e-10 && f[D] - f[0] <= 1e-15 * fmax(f[0], 1e-300))
            break;
        double centroid[D] = {0.0}, xr[D], xe[D], xc[D];
        for (int i = 0; i < D; i++)
            for (int c = 0; c < D; c++)
                centroid[c] += v[i][c] / D;
        for (int c = 0; c < D; c++)
            xr[c] = centroid[c] + (centroid[c] - v[D][c]);
        double fr = fit_objective(fp, xr);
        if (fr < f[0]) {
            for (int c = 0; c < D; c++)
                xe[c] = centroid[c] + 2.0 * (centroid[c] - v[D][c]);
            double fe = fit_objective(fp, xe);
            memcpy(v[D], fe < fr ? xe : xr, sizeof v[D]);
            f[D] = fe < fr ? fe : fr;
            continue;
        }
        if (fr < f[D - 1]) {
            memcpy(v[D], xr, sizeof v[D]);
            f[D] = fr;
            continue;
        }
        /* Contraction, outside when the reflected point beats the worst, else inside. */
        bool outside = fr < f[D];
        for (int c = 0; c < D; c++)
            xc[c] = outside ? centroid[c] + 0.5 * (xr[c] - centroid[c])
                            : centroid[c] + 0.5 * (v[D][c] - centroid[c]);
        double fc = fit_objective(fp, xc);
        if (fc < (outside ? fr : f[D])) {
            memcpy(v[D], xc, sizeof v[D]);
            f[D] = fc;
            continue;
        }
        for (int i = 1; i <= D; i++) { /* shrink toward the best */
            for (int c = 0; c < D; c++)
                v[i][c] = v[0][c] + 0.5 * (v[i][c] - v[0][c]);
            f[i] = fit_objective(fp, v[i]);
        }
    }
    int best = 0;
    for (int i = 1; i <= D; i++)
        if (f[i] < f[best])
            best = i;
    memcpy(y, v[best], sizeof v[best]);
    return f[best];
}

static brume_status fit_schlick_mix(const phase *target, brume_phase_fit_norm norm, brume_phase_fit *out)
{
    fit_problem *fp = malloc(sizeof *fp);
    if (!fp)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "phase fit: out of memory");
    brume_status st = fit_problem_init(fp, target, norm);
    if (st != BRUME_OK) {
        free(fp);
        return st;
    }
    /* Grid: r in steps of 0.05, k <= k' in steps of 0.05 over [-0.95, 0.95] and the
     * extremes +-0.99; the FIT_STARTS best points seed Nelder-Mead. */
    static const int nk = 41;
    double kgrid[41];
    kgrid[0] = -0.99;
    kgrid[40] = 0.99;
    for (int i = 1; i < 40; i++)
        kgrid[i] = -0.95 + 0.05 * (i - 1);
    double best_f[FIT_STARTS], best_p[FIT_STARTS][3];
    for (int i = 0; i < FIT_STARTS; i++)
        best_f[i] = INFINITY;
    for (int ir = 0; ir <= 20; ir++)
        for (int i = 0; i < nk; i++)
            for (int j = i; j < nk; j++) {
                double r = 0.05 * ir, e = fit_problem_error(fp, r, kgrid[i], kgrid[j]);
                if (!(e < best_f[FIT_STARTS - 1]))
                    continue;
                int s = FIT_STARTS - 1;
                for (; s > 0 && e < best_f[s - 1]; s--) {
                    best_f[s] = best_f[s - 1];
                    memcpy(best_p[s], best_p[s - 1], sizeof best_p[s]);
                }
                best_f[s] = e;
                best_p[s][0] = r;
                best_p[s][1] = kgrid[i];
                best_p[s][2] = kgrid[j];
            }
    double best = INFINITY, best_y[3] = {0.0, 0.0, 0.0};
    for (int s = 0; s < FIT_STARTS && isfinite(best_f[s]); s++) {
        double y[3] = {asin(sqrt(best_p[s][0])), asin(best_p[s][1] / FIT_K_MAX), asin(best_p[s][2] / FIT_K_MAX)};
        double f = nelder_mead(fp, y);
        f = nelder_mead(fp, y); /* a restart escapes a collapsed simplex */
        if (f < best) {
            best = f;
            memcpy(best_y, y, sizeof y);
        }
    }
    double r, k, kp;
    fit_unmap(best_y, &r, &k, &kp);
    if (k > kp) { /* the same function with the lobes swapped */
        double tk = k;
        k = kp;
        kp = tk;
        r = 1.0 - r;
    }
    out->r = r;
    out->k = k;
    out->kprime = kp;
    out->error = fit_problem_error(fp, r, k, kp);
    free(fp);
    return BRUME_OK;
}

/* ---- the public calls ----------------------------------------------------------------------- */

brume_status brume_phase_fit_norm_from_name(brume_context *ctx, const char *name, brume_phase_fit_norm *out)
{
    err_clear();
    if (!name || !out)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_phase_fit_norm_from_name: %s: NULL",
                                       !name ? "name" : "out"));
    if (!norm_from_name(name, out))
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "norm '%s': expected cos, angle or log", name));
    return ctx_report(ctx, BRUME_OK);
}

double brume_phase_fit_error(const brume_phase *target, brume_phase_fit_norm norm, double r, double k, double kprime)
{
    if (!target || (unsigned)norm > BRUME_PHASE_FIT_LOG)
        return NAN;
    return fit_error(target->p, norm, r, k, kprime);
}

brume_status brume_phase_fit_schlick_mix(brume_context *ctx, const brume_phase *target, brume_phase_fit_norm norm,
                                         brume_phase_fit *out)
{
    err_clear();
    if (!target || !out)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_phase_fit_schlick_mix: %s: NULL",
                                       !target ? "target" : "out"));
    memset(out, 0, sizeof *out);
    if ((unsigned)norm > BRUME_PHASE_FIT_LOG)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_phase_fit_schlick_mix: norm: %d unknown",
                                       (int)norm));
    return ctx_report(ctx, fit_schlick_mix(target->p, norm, out));
}
