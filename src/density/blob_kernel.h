/* blob_kernel.h - a tabulated radial kernel W for blob fields (Stam 1994, Section 6.1): the
 * general "smooth blending function" of Eq. 3 with W(x) = W(|x|), read from a file in place
 * of the gaussian of Appendix A (`stam.kernel = "table"`, `stam.kernel_file`).
 *
 * The file gives W at s = r / h = 0, ds, 2 ds, ... s_max (docs/scene-format.md, "Radial
 * kernel files"); between the points W is linear in s, beyond s_max it is 0. brume
 * normalises it: W(s) = w(s) / (4 pi integral_0^s_max w(s) s^2 ds), the integral of the
 * piecewise-linear w taken exactly, so that a blob of mass m and radius h,
 *
 *   rho(x) = m W(|x - x_i| / h) / h^3,
 *
 * holds mass m before truncation, as the gaussian does. The blob is truncated at
 * min(cutoff, s_max) h. W must be finite, >= 0, nonincreasing (so that the clamped region
 * of Section 6.1 is one interval and the majorant's bound at the nearest point holds) and
 * W(0) > 0.
 *
 * The kernel is immutable once built and shared (reference counted) by the blob fields of a
 * scene. blob_kernel_eval is device code (blob_mean_at calls it): the GPU needs `w` (n + 2
 * doubles) copied with the struct. The line-integral table `g` is host only (stam). */
#ifndef BRUME_DENSITY_BLOB_KERNEL_H
#define BRUME_DENSITY_BLOB_KERNEL_H

#include "brume.h"

/* At most this many intervals in a kernel file (the table is n + 1 doubles). */
#define BLOB_KERNEL_MAX_POINTS 65536
/* The line-integral table: BLOB_KERNEL_G + 1 points per axis over [0, s_max]^2. */
#define BLOB_KERNEL_G 256

typedef struct blob_kernel {
    int n;            /* intervals: W at s_k = k ds, k = 0..n */
    double ds, inv_ds, s_max; /* in units of h */
    double w0;        /* the normalised W(0): a blob's peak density is m w0 / h^3 */
    double *w;        /* n + 2 values W(s_k) / W(0) (w[0] = 1, nonincreasing; w[n + 1] = w[n]) */
    /* host only: G(d, x) = integral_0^x w(sqrt(d^2 + t^2)) dt at d = i gs, x = j gs
     * (i, j = 0..BLOB_KERNEL_G, gs = s_max / BLOB_KERNEL_G), g[i (BLOB_KERNEL_G + 1) + j] */
    double gs, inv_gs;
    double *g;
    int refs;
} blob_kernel;

/* W(s) / W(0) for s >= 0 (s in units of h), linear between the table's points, w[n] from
 * s_max on (the truncation, not this function, ends the blob). */
static inline double blob_kernel_eval(const blob_kernel *k, double s)
{
    double f = s * k->inv_ds;
    if (!(f < (double)k->n))
        return k->w[k->n];
    int i = (int)f;
    return k->w[i] + (f - i) * (k->w[i + 1] - k->w[i]);
}

/* A kernel from n + 1 samples w[k] of W at s = k ds (copied): NULL with err_set() naming
 * `who` when they are not finite, >= 0, nonincreasing with w[0] > 0, or on no memory. */
blob_kernel *blob_kernel_new(const double *w, int n, double ds, const char *who);
/* Reads a kernel file (docs/scene-format.md): NULL with a one-line error naming the file, the
 * line and `field` (the option that named it). */
blob_kernel *blob_kernel_read(const char *path, const char *field);
blob_kernel *blob_kernel_retain(blob_kernel *k);
void blob_kernel_release(blob_kernel *k);

/* Integral of w(sqrt(d^2 + t^2)) dt over t in [0, x] (x may be negative: odd in x), d >= 0,
 * both in units of h, from the table G (bilinear). */
double blob_kernel_line(const blob_kernel *k, double d, double x);
/* The largest s with w(s) >= level (0 < level <= 1), i.e. where m W(s) / h^3 falls to
 * level times the peak; 0 when w(0+) < level. */
double blob_kernel_radius(const blob_kernel *k, double level);

#endif
