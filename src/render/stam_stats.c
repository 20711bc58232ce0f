/* stam_stats.c - per-blob mean and variance of the optical depth (stam_stats.h). */
#include "render/stam_stats.h"

#define SQRT_PI_2 1.2533141373155003   /* sqrt(pi / 2) */
#define SQRT_2PI 2.5066282746310002    /* sqrt(2 pi) */
#define TWO_PI_3_2 15.749609945722419  /* (2 pi)^(3/2) */

double stam_Phi(double x) { return SQRT_PI_2 * erf(x * 0.7071067811865476); }

blob_ray blob_ray_make(const blob_field *f, int i, double u, double d2)
{
    blob_ray br;
    br.h = f->b[i].h;
    br.u = u;
    br.peak = f->peak[i] * exp(-d2 * f->inv2h2[i]);
    br.half = sqrt(fmax(0.0, f->R2[i] - d2));
    return br;
}

double blob_T_mean(const blob_ray *br, double a, double b)
{
    a = fmax(a, br->u - br->half);
    b = fmin(b, br->u + br->half);
    if (!(b > a))
        return 0.0;
    /* m / ((2 pi)^(3/2) h^3) exp(-d^2 / 2h^2) h (Phi((b - u) / h) - Phi((a - u) / h)) */
    double inv = 1.0 / br->h;
    return br->peak * br->h * (stam_Phi((b - br->u) * inv) - stam_Phi((a - br->u) * inv));
}

double blob_T_clamped(const blob_ray *br, double eta, double a, double b)
{
    if (!(br->peak > eta))
        return blob_T_mean(br, a, b); /* the log in Delta u_i is <= 0: nothing is clamped */
    double du = br->h * sqrt(2.0 * log(br->peak / eta)); /* Appendix A, in units of h there */
    double lo = fmax(br->u - du, br->u - br->half), hi = fmin(br->u + du, br->u + br->half);
    double plateau = fmax(0.0, fmin(b, hi) - fmax(a, lo));
    return blob_T_mean(br, a, fmin(b, lo)) + eta * plateau + blob_T_mean(br, fmax(a, hi), b);
}

double blob_T_var(const blob_ray *br, double eps, double eta, double alpha, double a, double b)
{
    if (!(eps > 0.0))
        return 0.0;
    double c = 1.0 / sqrt(1.0 + alpha * alpha / (4.0 * br->h * br->h));
    return eps * SQRT_2PI * alpha * c * blob_T_clamped(br, eta, a, b);
}

double blob_T_var_paper(const blob_ray *br, double eps, double eta, double alpha, double a, double b)
{
    return eps * blob_T_clamped(br, eta, a, b) / (TWO_PI_3_2 * alpha * alpha * alpha);
}
