/* stam_stats.c - per-blob mean and variance of the optical depth (stam_stats.h). */
#include "render/stam_stats.h"

#include <pthread.h>

#define SQRT_PI_2 1.2533141373155003   /* sqrt(pi / 2) */
#define SQRT_2PI 2.5066282746310002    /* sqrt(2 pi) */
#define TWO_PI_3_2 15.749609945722419  /* (2 pi)^(3/2) */

/* The table of stam_Phi (stam_stats.h). */
double stam_phi_table[STAM_PHI_N + 2];
static pthread_once_t phi_once = PTHREAD_ONCE_INIT;

static void phi_init(void)
{
    for (int i = 0; i <= STAM_PHI_N + 1; i++)
        stam_phi_table[i] = SQRT_PI_2 * erf(i * (STAM_PHI_MAX / STAM_PHI_N) * 0.7071067811865476);
}

double stam_Phi_exact(double x) { return SQRT_PI_2 * erf(x * 0.7071067811865476); }

void stam_stats_init(void) { pthread_once(&phi_once, phi_init); }

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
    double lo = br->u - br->half, hi = br->u + br->half;
    a = a > lo ? a : lo;
    b = b < hi ? b : hi;
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
    if (du > br->half)
        du = br->half;
    double lo = br->u - du, hi = br->u + du;
    double pa = a > lo ? a : lo, pb = b < hi ? b : hi;
    double plateau = pb > pa ? pb - pa : 0.0;
    return blob_T_mean(br, a, b < lo ? b : lo) + eta * plateau + blob_T_mean(br, a > hi ? a : hi, b);
}

double blob_T_var_scale(double eps, double alpha, double h)
{
    return eps * SQRT_2PI * alpha / sqrt(1.0 + alpha * alpha / (4.0 * h * h));
}

double blob_T_var(const blob_ray *br, double eps, double eta, double alpha, double a, double b)
{
    if (!(eps > 0.0))
        return 0.0;
    return blob_T_var_scale(eps, alpha, br->h) * blob_T_clamped(br, eta, a, b);
}

double blob_T_var_paper(const blob_ray *br, double eps, double eta, double alpha, double a, double b)
{
    return eps * blob_T_clamped(br, eta, a, b) / (TWO_PI_3_2 * alpha * alpha * alpha);
}

double blob_T_sigma_paper_scale(double eps, double alpha)
{
    /* sigma_T Q^(0) = sqrt(K_Q(0) eps I_F) sqrt(K_Q(0)) Q = K_Q(0) sqrt(eps I_F) Q, Q of unit variance */
    return sqrt(eps) / (TWO_PI_3_2 * alpha * alpha * alpha);
}
