/* blob_kernel.c - tabulated radial kernels of blob fields (blob_kernel.h): the file reader
 * with its validation, the normalisation, and the line-integral table of Stam's Section 6.1. */
#include "density/blob_kernel.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/number.h"
#include "core/regular_file.h"

#define FOUR_PI 12.566370614359172

/* 4 pi integral_0^s_max w(s) s^2 ds for w linear on each [k ds, (k + 1) ds]: exact. */
static double kernel_mass(const double *w, int n, double ds)
{
    double sum = 0.0;
    for (int k = 0; k < n; k++) {
        double a = k * ds, b = (k + 1) * ds, slope = (w[k + 1] - w[k]) / ds;
        double c3 = (b * b * b - a * a * a) / 3.0, c4 = (b * b * b * b - a * a * a * a) / 4.0;
        sum += w[k] * c3 + slope * (c4 - a * c3);
    }
    return FOUR_PI * sum;
}

/* w(r) of the normalised table for the line integrals: 0 beyond s_max. */
static double w_at(const blob_kernel *k, double r) { return r > k->s_max ? 0.0 : blob_kernel_eval(k, r); }

/* G(d, x) on the grid by Simpson's rule, 16 intervals per grid cell (the kinks of the
 * piecewise-linear w make it second order there: error below 1e-7 of G for s_max <= 10). */
static void build_line_table(blob_kernel *k)
{
    enum { SUB = 16 };
    int ng = BLOB_KERNEL_G;
    for (int i = 0; i <= ng; i++) {
        double d = i * k->gs, run = 0.0, hs = k->gs / SUB;
        double *row = k->g + (size_t)i * (size_t)(ng + 1);
        row[0] = 0.0;
        for (int j = 0; j < ng; j++) {
            double x0 = j * k->gs, s = 0.0;
            for (int q = 0; q <= SUB; q++) {
                double t = x0 + q * hs;
                s += (q == 0 || q == SUB ? 1.0 : (q % 2 ? 4.0 : 2.0)) * w_at(k, sqrt(d * d + t * t));
            }
            run += s * hs / 3.0;
            row[j + 1] = run;
        }
    }
}

blob_kernel *blob_kernel_new(const double *w, int n, double ds, const char *who)
{
    if (n < 1 || n > BLOB_KERNEL_MAX_POINTS || !(ds > 0.0 && isfinite(ds) && isfinite(n * ds))) {
        err_set(BRUME_ERROR_RANGE, "%s: need 2 to %d points with a spacing > 0", who, BLOB_KERNEL_MAX_POINTS + 1);
        return NULL;
    }
    for (int i = 0; i <= n; i++)
        if (!(isfinite(w[i]) && w[i] >= 0.0) || (i > 0 && w[i] > w[i - 1]) || !(w[0] > 0.0)) {
            err_set(BRUME_ERROR_RANGE, "%s: W at point %d is %g: need finite W >= 0, W(0) > 0, not increasing with r",
                    who, i, w[i]);
            return NULL;
        }
    blob_kernel *k = calloc(1, sizeof *k);
    if (k) {
        k->w = malloc((size_t)(n + 2) * sizeof *k->w);
        k->g = malloc((size_t)(BLOB_KERNEL_G + 1) * (BLOB_KERNEL_G + 1) * sizeof *k->g);
    }
    if (!k || !k->w || !k->g) {
        if (k) {
            free(k->w);
            free(k->g);
        }
        free(k);
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for the kernel table", who);
        return NULL;
    }
    k->n = n;
    k->ds = ds;
    k->inv_ds = 1.0 / ds;
    k->s_max = n * ds;
    k->w0 = w[0] / kernel_mass(w, n, ds);
    for (int i = 0; i <= n; i++)
        k->w[i] = w[i] / w[0];
    k->w[n + 1] = k->w[n];
    k->gs = k->s_max / BLOB_KERNEL_G;
    k->inv_gs = 1.0 / k->gs;
    k->refs = 1;
    build_line_table(k);
    return k;
}

/* One data line "s W": two finite numbers and nothing else. */
static bool parse_pair(const char *line, double *s, double *w)
{
    char *end;
    errno = 0;
    *s = num_strtod(line, &end);
    if (end == line)
        return false;
    const char *p = end;
    *w = num_strtod(p, &end);
    if (end == p || errno == ERANGE)
        return false;
    while (*end == ' ' || *end == '\t' || *end == '\r' || *end == '\n')
        end++;
    return *end == '\0';
}

blob_kernel *blob_kernel_read(const char *path, const char *field)
{
    FILE *fp = NULL;
    if (io_open_input(path, field, &fp) != BRUME_OK)
        return NULL;
    /* every line a point or a comment: the points' lines and as many again of comments */
    if (io_check_size(fp, path, field, 2LL * (BLOB_KERNEL_MAX_POINTS + 1) * 512) != BRUME_OK) {
        fclose(fp);
        return NULL;
    }
    double *w = malloc((size_t)(BLOB_KERNEL_MAX_POINTS + 1) * sizeof *w), ds = 0.0;
    if (!w) {
        fclose(fp);
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: %s: out of memory", path, field);
        return NULL;
    }
    char line[512];
    int n = 0, lineno = 0;
    brume_status st = BRUME_OK;
    while (st == BRUME_OK && fgets(line, sizeof line, fp)) {
        lineno++;
        size_t len = strlen(line);
        if (len == sizeof line - 1 && line[len - 1] != '\n') {
            st = err_set(BRUME_ERROR_PARSE, "%s: %s: line %d: longer than %zu characters", path, field, lineno,
                         sizeof line - 2);
            break;
        }
        const char *p = line + strspn(line, " \t\r\n");
        if (*p == '\0' || *p == '#')
            continue;
        double s = 0.0, v = 0.0;
        if (!parse_pair(p, &s, &v))
            st = err_set(BRUME_ERROR_PARSE, "%s: %s: line %d: expected two numbers, r/h and W", path, field, lineno);
        else if (n > BLOB_KERNEL_MAX_POINTS)
            st = err_set(BRUME_ERROR_RANGE, "%s: %s: line %d: more than %d points", path, field, lineno,
                         BLOB_KERNEL_MAX_POINTS + 1);
        else if (!isfinite(s) || !isfinite(v))
            st = err_set(BRUME_ERROR_RANGE, "%s: %s: line %d: r/h and W must be finite", path, field, lineno);
        else if (v < 0.0)
            st = err_set(BRUME_ERROR_RANGE, "%s: %s: line %d: W = %g is negative (need W >= 0)", path, field, lineno, v);
        else if (n == 0 && s != 0.0)
            st = err_set(BRUME_ERROR_RANGE, "%s: %s: line %d: the first r/h must be 0, got %g", path, field, lineno, s);
        else if (n == 0 && !(v > 0.0))
            st = err_set(BRUME_ERROR_RANGE, "%s: %s: line %d: W(0) must be > 0", path, field, lineno);
        else if (n > 0 && v > w[n - 1])
            st = err_set(BRUME_ERROR_RANGE, "%s: %s: line %d: W = %g increases (after %g): W must not increase with r",
                         path, field, lineno, v, w[n - 1]);
        else if (n == 1 && !(s > 0.0))
            st = err_set(BRUME_ERROR_RANGE, "%s: %s: line %d: r/h must increase", path, field, lineno);
        else if (n > 1 && !(fabs(s - n * ds) <= 1e-6 * ds))
            st = err_set(BRUME_ERROR_RANGE, "%s: %s: line %d: r/h = %.9g, expected %.9g: the points must be evenly spaced",
                         path, field, lineno, s, n * ds);
        if (st != BRUME_OK)
            break;
        if (n == 1)
            ds = s;
        w[n++] = v;
    }
    if (st == BRUME_OK && ferror(fp))
        st = err_set(BRUME_ERROR_IO, "%s: %s: read error", path, field);
    fclose(fp);
    if (st == BRUME_OK && n < 2)
        st = err_set(BRUME_ERROR_PARSE, "%s: %s: need at least two points (r/h, W), found %d", path, field, n);
    blob_kernel *k = NULL;
    if (st == BRUME_OK) {
        char who[1100];
        snprintf(who, sizeof who, "%s: %s", path, field);
        k = blob_kernel_new(w, n - 1, ds, who);
    }
    free(w);
    return k;
}

blob_kernel *blob_kernel_retain(blob_kernel *k)
{
    if (k)
        k->refs++;
    return k;
}

void blob_kernel_release(blob_kernel *k)
{
    if (!k || --k->refs > 0)
        return;
    free(k->w);
    free(k->g);
    free(k);
}

double blob_kernel_line(const blob_kernel *k, double d, double x)
{
    double sign = x < 0.0 ? -1.0 : 1.0;
    double fd = d * k->inv_gs, fx = fabs(x) * k->inv_gs;
    int ng = BLOB_KERNEL_G;
    if (!(fd < ng))
        return 0.0;
    fx = fx < ng ? fx : ng;
    int i = (int)fd, j = (int)fx;
    j = j < ng ? j : ng - 1;
    double td = fd - i, tx = fx - j;
    const double *r0 = k->g + (size_t)i * (size_t)(ng + 1), *r1 = r0 + ng + 1;
    double g0 = r0[j] + tx * (r0[j + 1] - r0[j]), g1 = r1[j] + tx * (r1[j + 1] - r1[j]);
    return sign * (g0 + td * (g1 - g0));
}

double blob_kernel_radius(const blob_kernel *k, double level)
{
    if (!(k->w[0] >= level))
        return 0.0;
    if (k->w[k->n] >= level)
        return k->s_max;
    int lo = 0, hi = k->n; /* w[lo] >= level > w[hi] */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (k->w[mid] >= level)
            lo = mid;
        else
            hi = mid;
    }
    return (lo + (k->w[lo] - level) / (k->w[lo] - k->w[hi])) * k->ds;
}
