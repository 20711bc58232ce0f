/* phase.c - phase functions: evaluation, exact sampling, pdf and mean cosine.
 *
 * Every function is written in t = cos(theta), the cosine between the incoming and the
 * outgoing propagation directions. The density of t that a sampler draws from is
 * 2 pi p(t) = phi(t) / 2 on [-1, 1]; derivations are in docs/phase-functions.md. */
#include "phase/phase.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/budget.h"
#include "core/error.h"
#include "core/number.h"
#include "core/regular_file.h"
#include "core/sampling.h"
#include "phase/quadrature.h"
#include "core/arena.h"

/* Entries of the inverse-CDF table of the Mie functions: x = (1 + t) / 2 at u = i / N. */
#define MIE_TABLE_SIZE 64
/* A phase table (phase_load_tabulated): lines of at most this many bytes, at most this many
 * rows; its memory is counted against the scene's budget (core/budget.h). */
#define PHASE_TABLE_LINE_MAX 4096
#define PHASE_TABLE_MAX (1 << 24)

struct phase {
    phase_kind kind;

    /* Henyey-Greenstein: |g| < 1, and the constants of Eq. 19 divided by 4 pi. */
    double g, hg_1pg2, hg_2g, hg_c;

    /* Schlick: |k| < 1; schlick_c = (1 - k^2) / (4 pi). */
    double k, schlick_c;

    /* Mie (Eq. 18): phi = 1/2 + mie_c x^m with x = (1 + t) / 2, m = 2^mie_log2m and
     * mie_c = (m + 1) / 2; mie_scale = 2 / (integral of phi over t) / (4 pi), so
     * p = mie_scale phi. The CDF of t is (x + x^(m+1)) / 2, and mie_x[i] solves
     * x + x^(m+1) = 2 u for u = i / MIE_TABLE_SIZE. */
    int mie_log2m;
    double mie_c, mie_scale;
    double mie_x[MIE_TABLE_SIZE + 1];

    /* Mixture: n lobes (owned), normalized weights w, and their running sums wsum[0..n]
     * (wsum[0] = 0, wsum[n] = 1). Tabulated: n nodes t[0] = -1 < ... < t[n-1] = 1 with
     * values pt[] per steradian (normalized), and cdf[i] = P(T <= t[i]). */
    int n;
    phase **lobes;
    double *w, *wsum;
    double *t, *pt, *cdf;

    double mean_cos; /* precomputed for the kinds that need a sum or a table */
};

static phase *phase_alloc(phase_kind kind)
{
    phase *p = calloc(1, sizeof *p);
    if (!p) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "phase: out of memory");
        return NULL;
    }
    p->kind = kind;
    return p;
}

void phase_release(phase *p)
{
    if (!p)
        return;
    if (p->kind == PHASE_MIXTURE)
        for (int i = 0; i < p->n; i++)
            phase_release(p->lobes[i]);
    free(p->lobes);
    free(p->w);
    free(p->wsum);
    free(p->t);
    free(p->pt);
    free(p->cdf);
    free(p);
}

phase_kind phase_get_kind(const phase *p) { return p->kind; }

int phase_lobe_count(const phase *p) { return p->kind == PHASE_MIXTURE ? p->n : 0; }

const phase *phase_lobe(const phase *p, int i, double *weight)
{
    *weight = p->w[i];
    return p->lobes[i];
}

double phase_schlick_k(const phase *p) { return p->kind == PHASE_SCHLICK ? p->k : (double)NAN; }

/* ---- closed forms of each kind ---------------------------------------------------------- */

/* Blasi Eq. 17: phi = 3/4 (1 + t^2). Its CDF is F(t) = (t^3 + 3 t + 4) / 8; F(t) = u is the
 * depressed cubic t^3 + 3 t + 4 - 8 u = 0 with one real root (Cardano):
 * t = A - 1/A, A = cbrt(z + sqrt(z^2 + 1)), z = 4 u - 2. Odd in z, so evaluate at |z|
 * to avoid cancellation. */
static double rayleigh_sample_cos(double u)
{
    double z = 4.0 * u - 2.0;
    double az = fabs(z);
    double a = cbrt(az + sqrt(az * az + 1.0));
    return copysign(a - 1.0 / a, z);
}

static double mie_pow_m(const phase *p, double x)
{
    for (int i = 0; i < p->mie_log2m; i++)
        x *= x;
    return x;
}

/* Blasi Eq. 18. */
static double mie_eval(const phase *p, double t)
{
    double x = 0.5 * (1.0 + t);
    return p->mie_scale * (0.5 + p->mie_c * mie_pow_m(p, x));
}

/* Solves x + x^(m+1) = 2 u for x in [0, 1] by Newton from x0 >= the root. The left side
 * is increasing and convex, so from the right Newton decreases monotonically to the root. */
static double mie_solve_x(const phase *p, double u, double x0)
{
    double m = (double)(1 << p->mie_log2m);
    double x = x0;
    for (int iter = 0; iter < 60; iter++) {
        double xm = mie_pow_m(p, x);
        double step = (x + x * xm - 2.0 * u) / (1.0 + (m + 1.0) * xm);
        if (!(step > 0.0))
            break; /* at the root (or one ulp left of it) */
        x -= step;
        if (step <= 1e-15 * x)
            break;
    }
    return x < 0.0 ? 0.0 : x;
}

/* Inverse-CDF table lookup gives a bracket [x_i, x_i+1]; Newton from its upper end then
 * converges in two or three steps to the exact inverse of the closed-form CDF. */
static double mie_sample_cos(const phase *p, double u)
{
    double fi = u * MIE_TABLE_SIZE;
    int i = (int)fi;
    if (i > MIE_TABLE_SIZE - 1)
        i = MIE_TABLE_SIZE - 1;
    if (i < 0)
        i = 0;
    double x = mie_solve_x(p, u, p->mie_x[i + 1]);
    return 2.0 * x - 1.0;
}

/* Mean cosine of Eq. 18: with the density of x equal to phi(2x - 1) on [0, 1],
 * E[x] = 1/4 + c / (m + 2), E[t] = 2 E[x] - 1 (hazy 0.4, murky 8/17). */
static double mie_mean_cos(const phase *p)
{
    double m = (double)(1 << p->mie_log2m);
    return 2.0 * (0.25 + p->mie_c / (m + 2.0)) - 1.0;
}

/* Blasi Eq. 19, divided by 4 pi. */
static double hg_eval(const phase *p, double t)
{
    double denom = p->hg_1pg2 - p->hg_2g * t;
    return p->hg_c / (denom * sqrt(denom));
}

/* Inverse CDF of HG in t. The textbook form t = (1 + g^2 - s^2) / (2g),
 * s = (1 - g^2) / (1 + g v), v = 2u - 1, cancels badly for small g; expanding it gives
 * t = (v + g (v^2 + 3) / 2 + g^2 v + g^3 (v^2 - 1) / 2) / (1 + g v)^2, exact for every g
 * (t = v at g = 0, t(-1) = -1, t(1) = 1). */
static double hg_sample_cos(double g, double u)
{
    double v = 2.0 * u - 1.0;
    double d = 1.0 + g * v;
    double num = v + g * (0.5 * (v * v + 3.0) + g * (v + 0.5 * g * (v * v - 1.0)));
    double t = num / (d * d);
    return fmin(1.0, fmax(-1.0, t));
}

/* Blasi Eq. 21, divided by 4 pi. */
static double schlick_eval(const phase *p, double t)
{
    double d = 1.0 - p->k * t;
    return p->schlick_c / (d * d);
}

/* Blasi Eq. 23: t = (2u + k - 1) / (2ku - k + 1), the inverse of the CDF
 * F(t) = (1 - k)(1 + t) / (2 (1 - k t)); forward (t near 1) for k > 0. */
static double schlick_sample_cos(double k, double u)
{
    double t = (2.0 * u + k - 1.0) / (2.0 * k * u - k + 1.0);
    return fmin(1.0, fmax(-1.0, t));
}

/* Mean cosine of Eq. 21: 1/k - (1 - k^2) atanh(k) / k^2, which cancels for small k;
 * there the series sum_j 2 k^(2j+1) / ((2j+1)(2j+3)) = 2k/3 + 2k^3/15 + ... is used. */
static double schlick_mean_cos(double k)
{
    if (fabs(k) < 0.2) {
        double s = 0.0, kp = k;
        for (int j = 0; j < 14; j++, kp *= k * k)
            s += 2.0 * kp / ((2.0 * j + 1.0) * (2.0 * j + 3.0));
        return s;
    }
    return 1.0 / k - (1.0 - k * k) * atanh(k) / (k * k);
}

/* Index i with t[i] <= x <= t[i+1] among n increasing nodes (x clamped to the range). */
static int table_segment(const double *t, int n, double x)
{
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (t[mid] <= x)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* Linear in t between nodes. */
static double tabulated_eval(const phase *p, double x)
{
    if (x <= p->t[0])
        return p->pt[0];
    if (x >= p->t[p->n - 1])
        return p->pt[p->n - 1];
    int i = table_segment(p->t, p->n, x);
    double h = p->t[i + 1] - p->t[i];
    if (!(h > 0.0))
        return p->pt[i];
    double s = (x - p->t[i]) / h;
    return p->pt[i] + s * (p->pt[i + 1] - p->pt[i]);
}

/* The density of t is linear on each segment, so its CDF is quadratic there: find the
 * segment by bisection on cdf[], then solve (b - a) h s^2 / 2 + a h s = m for the fraction s
 * of the segment in the cancellation-free form s = 2 m / (h (a + sqrt(a^2 + 2 (b - a) m / h))). */
static double tabulated_sample_cos(const phase *p, double u)
{
    int lo = 0, hi = p->n - 1; /* invariant: cdf[lo] <= u < cdf[hi] or hi = n - 1 */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (p->cdf[mid] <= u)
            lo = mid;
        else
            hi = mid;
    }
    double h = p->t[lo + 1] - p->t[lo];
    double a = 2.0 * PI * p->pt[lo], b = 2.0 * PI * p->pt[lo + 1];
    double m = u - p->cdf[lo];
    double disc = a * a + 2.0 * (b - a) * m / h;
    double denom = h * (a + sqrt(fmax(0.0, disc)));
    double s = denom > 0.0 ? 2.0 * m / denom : 0.0;
    return fmin(p->t[lo + 1], fmax(p->t[lo], p->t[lo] + fmin(1.0, s) * h));
}

/* ---- constructors ------------------------------------------------------------------------ */

phase *phase_new_isotropic(void) { return phase_alloc(PHASE_ISOTROPIC); }

phase *phase_new_rayleigh(void) { return phase_alloc(PHASE_RAYLEIGH); }

static phase *phase_new_mie(phase_kind kind, int log2m, double c)
{
    phase *p = phase_alloc(kind);
    if (!p)
        return NULL;
    p->mie_log2m = log2m;
    p->mie_c = c;
    /* Normalize numerically: a 24-point Gauss-Legendre rule is exact for the degree-32
     * polynomial phi, and gives exactly 2 (the paper's constants are already normalized,
     * see docs/phase-functions.md). */
    double x[24], w[24], integral = 0.0;
    quad_gauss_legendre(24, x, w);
    p->mie_scale = 1.0;
    for (int i = 0; i < 24; i++)
        integral += w[i] * mie_eval(p, x[i]);
    p->mie_scale = 2.0 / integral * INV_4PI;
    p->mie_x[MIE_TABLE_SIZE] = 1.0;
    for (int i = MIE_TABLE_SIZE - 1; i >= 0; i--)
        p->mie_x[i] = mie_solve_x(p, (double)i / MIE_TABLE_SIZE, p->mie_x[i + 1]);
    p->mean_cos = mie_mean_cos(p);
    return p;
}

phase *phase_new_mie_hazy(void) { return phase_new_mie(PHASE_MIE_HAZY, 3, 4.5); }
phase *phase_new_mie_murky(void) { return phase_new_mie(PHASE_MIE_MURKY, 5, 16.5); }

phase *phase_new_hg(double g)
{
    if (!(fabs(g) < 1.0)) {
        err_set(BRUME_ERROR_RANGE, "henyey-greenstein g = %g: need |g| < 1", g);
        return NULL;
    }
    phase *p = phase_alloc(PHASE_HENYEY_GREENSTEIN);
    if (!p)
        return NULL;
    p->g = g;
    p->hg_1pg2 = 1.0 + g * g;
    p->hg_2g = 2.0 * g;
    p->hg_c = INV_4PI * (1.0 - g * g);
    return p;
}

phase *phase_new_schlick(double k)
{
    if (!(fabs(k) < 1.0)) {
        err_set(BRUME_ERROR_RANGE, "schlick k = %g: need |k| < 1", k);
        return NULL;
    }
    phase *p = phase_alloc(PHASE_SCHLICK);
    if (!p)
        return NULL;
    p->k = k;
    p->schlick_c = INV_4PI * (1.0 - k * k);
    return p;
}

phase *phase_new_mixture(int n, const double *weights, phase *const *lobes)
{
    if (n < 1) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "phase mixture: %d lobes: need at least 1", n);
        return NULL;
    }
    double sum = 0.0;
    for (int i = 0; i < n; i++) {
        if (!(weights[i] >= 0.0) || !isfinite(weights[i])) {
            err_set(BRUME_ERROR_RANGE, "phase mixture: weight %d = %g: need a finite weight >= 0",
                    i, weights[i]);
            return NULL;
        }
        if (!lobes[i]) {
            err_set(BRUME_ERROR_INVALID_ARGUMENT, "phase mixture: lobe %d is NULL", i);
            return NULL;
        }
        sum += weights[i];
    }
    if (!(sum > 0.0) || !isfinite(sum)) {
        err_set(BRUME_ERROR_RANGE, "phase mixture: weights sum to %g: need a positive sum", sum);
        return NULL;
    }
    phase *p = phase_alloc(PHASE_MIXTURE);
    if (!p)
        return NULL;
    p->lobes = malloc((size_t)n * sizeof *p->lobes);
    p->w = malloc((size_t)n * sizeof *p->w);
    p->wsum = malloc((size_t)(n + 1) * sizeof *p->wsum);
    if (!p->lobes || !p->w || !p->wsum) {
        phase_release(p); /* n is still 0: the lobes stay the caller's */
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "phase mixture: out of memory");
        return NULL;
    }
    p->wsum[0] = 0.0;
    for (int i = 0; i < n; i++) {
        p->lobes[i] = lobes[i];
        p->w[i] = weights[i] / sum;
        p->wsum[i + 1] = p->wsum[i] + p->w[i];
        p->mean_cos += p->w[i] * phase_mean_cosine(lobes[i]);
    }
    p->wsum[n] = 1.0;
    p->n = n;
    return p;
}

phase *phase_new_schlick_mix(double r, double k, double kprime)
{
    if (!(r >= 0.0 && r <= 1.0)) {
        err_set(BRUME_ERROR_RANGE, "schlick mixture r = %g: need r in [0, 1]", r);
        return NULL;
    }
    phase *lobes[2] = {phase_new_schlick(k), NULL};
    if (!lobes[0])
        return NULL;
    lobes[1] = phase_new_schlick(kprime);
    if (!lobes[1]) {
        err_set(BRUME_ERROR_RANGE, "schlick mixture k' = %g: need |k'| < 1", kprime);
        phase_release(lobes[0]);
        return NULL;
    }
    double w[2] = {r, 1.0 - r};
    phase *p = phase_new_mixture(2, w, lobes);
    if (!p) {
        phase_release(lobes[0]);
        phase_release(lobes[1]);
    }
    return p;
}

/* The tabulated phase's nodes in increasing t = cos: reversed angles, plus t = -1 and t = 1
 * when the table stops short of 180 or 0 degrees (the end value is held there). The table's
 * scale is arbitrary: divided by its largest value first, the trapezoids' sum is within
 * [tiny, 2] even for values near DBL_MAX (whose sum would be infinite and the normalised
 * table 0: a black medium) or near the smallest doubles. */
static void table_nodes(phase *p, int n, const double *angle_deg, const double *value, int extra_lo, int extra_hi)
{
    double vmax = 0.0;
    for (int i = 0; i < n; i++)
        vmax = fmax(vmax, value[i]);
    if (!(vmax > 0.0))
        vmax = 1.0; /* every value 0: refused by the caller */
    int j = 0;
    if (extra_lo) {
        p->t[j] = -1.0;
        p->pt[j++] = value[n - 1] / vmax;
    }
    for (int i = n - 1; i >= 0; i--) {
        p->t[j] = angle_deg[i] == 180.0 ? -1.0 : (angle_deg[i] == 0.0 ? 1.0 : cos(angle_deg[i] * PI / 180.0));
        p->pt[j++] = value[i] / vmax;
    }
    if (extra_hi) {
        p->t[j] = 1.0;
        p->pt[j++] = value[0] / vmax;
    }
}

phase *phase_new_tabulated(int n, const double *angle_deg, const double *value)
{
    if (n < 2) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "tabulated phase: %d points: need at least 2", n);
        return NULL;
    }
    for (int i = 0; i < n; i++) {
        if (!(angle_deg[i] >= 0.0 && angle_deg[i] <= 180.0)) {
            err_set(BRUME_ERROR_RANGE, "tabulated phase: point %d: angle %g: need [0, 180] degrees",
                    i, angle_deg[i]);
            return NULL;
        }
        if (i > 0 && !(angle_deg[i] > angle_deg[i - 1])) {
            err_set(BRUME_ERROR_RANGE,
                    "tabulated phase: point %d: angle %g after %g: angles must increase strictly",
                    i, angle_deg[i], angle_deg[i - 1]);
            return NULL;
        }
        if (!(value[i] >= 0.0) || !isfinite(value[i])) {
            err_set(BRUME_ERROR_RANGE, "tabulated phase: point %d: value %g: need a finite value >= 0",
                    i, value[i]);
            return NULL;
        }
    }
    phase *p = phase_alloc(PHASE_TABULATED);
    if (!p)
        return NULL;
    /* Nodes in increasing t = cos: reversed angles, plus t = -1 and t = 1 when the table
     * stops short of 180 or 0 degrees (the end value is held there). */
    int extra_lo = angle_deg[n - 1] < 180.0, extra_hi = angle_deg[0] > 0.0;
    int m = n + extra_lo + extra_hi;
    p->t = malloc((size_t)m * sizeof *p->t);
    p->pt = malloc((size_t)m * sizeof *p->pt);
    p->cdf = malloc((size_t)m * sizeof *p->cdf);
    if (!p->t || !p->pt || !p->cdf) {
        phase_release(p);
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "tabulated phase: out of memory");
        return NULL;
    }
    table_nodes(p, n, angle_deg, value, extra_lo, extra_hi);
    p->n = m;
    /* Trapezoids are exact for a function linear in t. */
    double total = 0.0;
    p->cdf[0] = 0.0;
    for (int i = 0; i + 1 < m; i++) {
        total += 0.5 * (p->t[i + 1] - p->t[i]) * (p->pt[i] + p->pt[i + 1]);
        p->cdf[i + 1] = total;
    }
    if (!(total > 0.0)) {
        phase_release(p);
        err_set(BRUME_ERROR_RANGE, "tabulated phase: every value is 0: nothing to normalize");
        return NULL;
    }
    double mean = 0.0;
    for (int i = 0; i < m; i++) {
        p->pt[i] /= 2.0 * PI * total;
        p->cdf[i] /= total;
    }
    for (int i = 0; i + 1 < m; i++) { /* integral of t (a + (b - a) s) over the segment */
        double t0 = p->t[i], t1 = p->t[i + 1];
        mean += (t1 - t0) * (p->pt[i] * (2.0 * t0 + t1) + p->pt[i + 1] * (t0 + 2.0 * t1)) / 6.0;
    }
    p->cdf[m - 1] = 1.0;
    p->mean_cos = 2.0 * PI * mean;
    return p;
}

/* Next number on a line: skips blanks; NULL at the end of the data (end or '#'). */
static const char *next_field(const char *s)
{
    while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n' || *s == ',')
        s++;
    return (*s == '\0' || *s == '#') ? NULL : s;
}

/* One line of a phase table: 1 and its angle (degrees) and value, 0 for a line with no
 * data, -1 after err_set() naming path:lineno. prev: the row before's angle, < 0 if none. */
static int table_row(const char *path, int lineno, const char *line, double prev, double *angle, double *value)
{
    const char *s = next_field(line);
    if (!s)
        return 0;
    char *end;
    double a = num_strtod(s, &end);
    if (end == s) {
        err_set(BRUME_ERROR_PARSE, "%s:%d: expected an angle in degrees, got \"%.32s\"", path, lineno, s);
        return -1;
    }
    s = next_field(end);
    double v = s ? num_strtod(s, &end) : 0.0;
    if (!s || end == s) {
        err_set(BRUME_ERROR_PARSE, "%s:%d: expected a value after the angle %g", path, lineno, a);
        return -1;
    }
    if (next_field(end)) {
        err_set(BRUME_ERROR_PARSE, "%s:%d: unexpected \"%.32s\" after angle %g and value %g", path, lineno,
                next_field(end), a, v);
        return -1;
    }
    if (!(a >= 0.0 && a <= 180.0)) {
        err_set(BRUME_ERROR_RANGE, "%s:%d: angle %g: need [0, 180] degrees", path, lineno, a);
        return -1;
    }
    if (prev >= 0.0 && !(a > prev)) {
        err_set(BRUME_ERROR_RANGE, "%s:%d: angle %g after %g: not a function of angle (angles must increase strictly)",
                path, lineno, a, prev);
        return -1;
    }
    if (!(v >= 0.0) || !isfinite(v)) {
        err_set(BRUME_ERROR_RANGE, "%s:%d: value %g at angle %g: need a finite value >= 0", path, lineno, v, a);
        return -1;
    }
    *angle = a;
    *value = v;
    return 1;
}

phase *phase_load_tabulated(const char *path)
{
    FILE *f = NULL;
    if (io_open_regular(path, &f) != BRUME_OK)
        return NULL;
    double *angle = NULL, *value = NULL;
    int n = 0, cap = 0, lineno = 0;
    char line[PHASE_TABLE_LINE_MAX + 1]; /* lines are bounded: /dev/zero is one endless line */
    phase *p = NULL;
    for (;;) {
        /* one line, byte by byte: a NUL or an overlong line ends the read at once */
        size_t len = 0;
        int c = EOF;
        while ((c = getc(f)) != EOF && c != '\n' && c != '\0' && len < PHASE_TABLE_LINE_MAX)
            line[len++] = (char)c;
        line[len] = '\0';
        if (c == EOF && len == 0)
            break;
        lineno++;
        if (c == '\0') {
            err_set(BRUME_ERROR_PARSE, "%s:%d: contains a NUL byte; not a phase table", path, lineno);
            goto done;
        }
        if (len == PHASE_TABLE_LINE_MAX) {
            err_set(BRUME_ERROR_PARSE, "%s:%d: line longer than %d bytes; not a phase table", path, lineno,
                    PHASE_TABLE_LINE_MAX - 1);
            goto done;
        }
        line[strcspn(line, "\r")] = '\0';
        double a, v;
        int got = table_row(path, lineno, line, n > 0 ? angle[n - 1] : -1.0, &a, &v);
        if (got < 0)
            goto done;
        if (got == 0)
            continue;
        if (n == cap) {
            if (cap >= PHASE_TABLE_MAX / 2) {
                err_set(BRUME_ERROR_RANGE, "%s:%d: more than %d rows", path, lineno, PHASE_TABLE_MAX);
                goto done;
            }
            if (budget_take((size_t)(cap ? cap : 64) * 2 * sizeof(double), path) != BRUME_OK)
                goto done;
            cap = cap ? 2 * cap : 64;
            double *na = realloc(angle, (size_t)cap * sizeof *na);
            if (na)
                angle = na;
            double *nv = na ? (double *)realloc(value, (size_t)cap * sizeof *nv) : NULL;
            if (nv)
                value = nv;
            if (!na || !nv) {
                err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
                goto done;
            }
        }
        angle[n] = a;
        value[n++] = v;
    }
    if (ferror(f)) {
        err_set(BRUME_ERROR_IO, "%s: read error: %s", path, strerror(errno));
        goto done;
    }
    p = phase_new_tabulated(n, angle, value);
    if (!p) {
        char msg[1024];
        snprintf(msg, sizeof msg, "%s", err_message());
        err_set(err_status(), "%s: %.1000s", path, msg);
    }
done:
    /* what budget_take counted stays taken: the phase function keeps a copy as large */
    free(angle);
    free(value);
    fclose(f);
    return p;
}

/* The number after "prefix:" in name, or NAN when name has that prefix but no number. */
static int parse_param(const char *name, const char *prefix, double *out)
{
    size_t len = strlen(prefix);
    if (strncmp(name, prefix, len) != 0)
        return 0;
    char *end;
    errno = 0;
    *out = num_strtod(name + len, &end);
    if (end == name + len || *end != '\0')
        *out = (double)NAN;
    return 1;
}

phase *phase_new_from_name(const char *name)
{
    double v;
    if (strcmp(name, "isotropic") == 0)
        return phase_new_isotropic();
    if (strcmp(name, "rayleigh") == 0)
        return phase_new_rayleigh();
    if (strcmp(name, "hazy") == 0)
        return phase_new_mie_hazy();
    if (strcmp(name, "murky") == 0)
        return phase_new_mie_murky();
    if (parse_param(name, "hg:", &v)) {
        if (isnan(v)) {
            err_set(BRUME_ERROR_PARSE, "phase \"%s\": expected hg:G with a number G", name);
            return NULL;
        }
        return phase_new_hg(v);
    }
    if (parse_param(name, "schlick:", &v)) {
        if (isnan(v)) {
            err_set(BRUME_ERROR_PARSE, "phase \"%s\": expected schlick:K with a number K", name);
            return NULL;
        }
        return phase_new_schlick(v);
    }
    struct stat sb; /* not fopen: opening a FIFO would wait for a writer */
    if (stat(name, &sb) != 0) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT,
                "phase \"%s\": neither isotropic, rayleigh, hazy, murky, hg:G, schlick:K "
                "nor a readable file",
                name);
        return NULL;
    }
    return phase_load_tabulated(name);
}

/* ---- operations: one switch each ----------------------------------------------------------- */

double phase_eval(const phase *p, double cos_theta)
{
    switch (p->kind) {
    case PHASE_ISOTROPIC: return INV_4PI;
    case PHASE_RAYLEIGH: return INV_4PI * 0.75 * (1.0 + cos_theta * cos_theta); /* Blasi Eq. 17 */
    case PHASE_MIE_HAZY:
    case PHASE_MIE_MURKY: return mie_eval(p, cos_theta);
    case PHASE_HENYEY_GREENSTEIN: return hg_eval(p, cos_theta);
    case PHASE_SCHLICK: return schlick_eval(p, cos_theta);
    case PHASE_MIXTURE: { /* Blasi Eq. 20 */
        double s = 0.0;
        for (int i = 0; i < p->n; i++)
            s += p->w[i] * phase_eval(p->lobes[i], cos_theta);
        return s;
    }
    case PHASE_TABULATED: return tabulated_eval(p, cos_theta);
    }
    return 0.0;
}

/* Every sampler below inverts its CDF exactly, and a mixture picks lobe i with
 * probability w_i, so the pdf of every kind is its value. */
double phase_pdf(const phase *p, double cos_theta) { return phase_eval(p, cos_theta); }

double phase_sample_cos(const phase *p, double u)
{
    switch (p->kind) {
    case PHASE_ISOTROPIC: return 1.0 - 2.0 * u;
    case PHASE_RAYLEIGH: return rayleigh_sample_cos(u);
    case PHASE_MIE_HAZY:
    case PHASE_MIE_MURKY: return mie_sample_cos(p, u);
    case PHASE_HENYEY_GREENSTEIN: return hg_sample_cos(p->g, u);
    case PHASE_SCHLICK: return schlick_sample_cos(p->k, u);
    case PHASE_MIXTURE: {
        /* Choose lobe i with probability w_i, then reuse u rescaled to [0, 1) in it. */
        int lo = 0, hi = p->n; /* wsum[lo] <= u < wsum[hi] */
        while (hi - lo > 1) {
            int mid = (lo + hi) / 2;
            if (p->wsum[mid] <= u)
                lo = mid;
            else
                hi = mid;
        }
        while (lo > 0 && p->w[lo] == 0.0) /* never pick a lobe of weight 0 */
            lo--;
        double ur = p->w[lo] > 0.0 ? (u - p->wsum[lo]) / p->w[lo] : u;
        ur = fmin(fmax(ur, 0.0), 0x1.fffffffffffffp-1);
        return phase_sample_cos(p->lobes[lo], ur);
    }
    case PHASE_TABULATED: return tabulated_sample_cos(p, u);
    }
    return 0.0;
}

vec3 phase_sample(const phase *p, vec3 wi, double u1, double u2, double *pdf)
{
    double c = phase_sample_cos(p, u1);
    frame f = frame_from_n(wi);
    vec3 wo = frame_to_world(&f, direction_from_cos(c, u2));
    *pdf = phase_pdf(p, c);
    return wo;
}

double phase_mean_cosine(const phase *p)
{
    switch (p->kind) {
    case PHASE_ISOTROPIC: return 0.0;
    case PHASE_RAYLEIGH: return 0.0;
    case PHASE_HENYEY_GREENSTEIN: return p->g;
    case PHASE_SCHLICK: return schlick_mean_cos(p->k);
    case PHASE_MIE_HAZY:
    case PHASE_MIE_MURKY:
    case PHASE_MIXTURE:
    case PHASE_TABULATED: return p->mean_cos;
    }
    return 0.0;
}

/* ---- Schlick's k and Henyey-Greenstein's g ---------------------------------------------------- */

#define K_MAX (1.0 - 1e-9)

double phase_schlick_k_from_g(double g)
{
    double k = 1.55 * g - 0.55 * g * g * g;
    return fmin(K_MAX, fmax(-K_MAX, k));
}

/* Bisection on [0, g1] where g1 = 0.93808... is the root of 1.55 g - 0.55 g^3 = 1 below 1;
 * the cubic increases there (its derivative vanishes only at 0.969), so the root is unique. */
double phase_hg_g_from_schlick_k(double k)
{
    double ak = fmin(fabs(k), K_MAX);
    double lo = 0.0, hi = (-0.55 + sqrt(0.55 * 0.55 + 4.0 * 0.55)) / 1.1;
    for (int i = 0; i < 200 && hi - lo > 1e-16; i++) {
        double mid = 0.5 * (lo + hi);
        if (1.55 * mid - 0.55 * mid * mid * mid < ak)
            lo = mid;
        else
            hi = mid;
    }
    return copysign(0.5 * (lo + hi), k);
}

size_t phase_device_put(const phase *p, dev_arena *a)
{
    size_t at = arena_put(a, p, sizeof *p);
    if (at == ARENA_NULL)
        return at;
    const size_t n = p->n > 0 ? (size_t)p->n : 0;
    size_t lobes = ARENA_NULL;
    if (p->kind == PHASE_MIXTURE && p->lobes) {
        lobes = arena_alloc(a, n * sizeof(phase *));
        for (size_t i = 0; i < n && lobes != ARENA_NULL; i++)
            arena_ptr(a, lobes + i * sizeof(phase *), phase_device_put(p->lobes[i], a));
    }
    arena_ptr(a, at + offsetof(phase, lobes), lobes);
    const bool mix = p->kind == PHASE_MIXTURE, tab = p->kind == PHASE_TABULATED;
    ARENA_PUT_MEMBER(a, at, phase, w, mix ? p->w : NULL, n * sizeof(double));
    ARENA_PUT_MEMBER(a, at, phase, wsum, mix ? p->wsum : NULL, (n + 1) * sizeof(double));
    ARENA_PUT_MEMBER(a, at, phase, t, tab ? p->t : NULL, n * sizeof(double));
    ARENA_PUT_MEMBER(a, at, phase, pt, tab ? p->pt : NULL, n * sizeof(double));
    ARENA_PUT_MEMBER(a, at, phase, cdf, tab ? p->cdf : NULL, n * sizeof(double));
    return at;
}
