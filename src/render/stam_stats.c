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
    br.peak = blob_density_r2(f, i, d2);
    br.half = sqrt(fmax(0.0, f->R2[i] - d2));
    br.k = f->kernel;
    br.peak0 = f->peak[i];
    br.dh = br.k ? sqrt(d2) / br.h : 0.0;
    return br;
}

double blob_T_mean(const blob_ray *br, double a, double b)
{
    double lo = br->u - br->half, hi = br->u + br->half;
    a = a > lo ? a : lo;
    b = b < hi ? b : hi;
    if (!(b > a))
        return 0.0;
    double inv = 1.0 / br->h;
    if (br->k) /* Section 6.1: m W(0) / h^3 h (G(d / h, (b - u) / h) - G(d / h, (a - u) / h)) */
        return br->peak0 * br->h *
               (blob_kernel_line(br->k, br->dh, (b - br->u) * inv) - blob_kernel_line(br->k, br->dh, (a - br->u) * inv));
    /* m / ((2 pi)^(3/2) h^3) exp(-d^2 / 2h^2) h (Phi((b - u) / h) - Phi((a - u) / h)) */
    return br->peak * br->h * (stam_Phi((b - br->u) * inv) - stam_Phi((a - br->u) * inv));
}

double blob_T_clamped(const blob_ray *br, double eta, double a, double b)
{
    if (!(br->peak > eta))
        return blob_T_mean(br, a, b); /* the log in Delta u_i is <= 0: nothing is clamped */
    double du;
    if (br->k) { /* W(s_eta) = eta: s_eta >= d / h since the peak along the ray exceeds eta */
        double s = blob_kernel_radius(br->k, eta / br->peak0);
        du = br->h * sqrt(fmax(0.0, s * s - br->dh * br->dh));
    } else {
        du = br->h * sqrt(2.0 * log(br->peak / eta)); /* Appendix A, in units of h there */
    }
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
