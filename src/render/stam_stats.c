/* stam_stats.c - per-blob mean and variance of the optical depth (stam_stats.h). */
#include "render/stam_stats.h"

#include <pthread.h>

#define SQRT_PI_2 1.2533141373155003   /* sqrt(pi / 2) */
#define SQRT_2PI 2.5066282746310002    /* sqrt(2 pi) */
#define SQRT2 1.4142135623730951
#define TWO_PI_3_2 15.749609945722419  /* (2 pi)^(3/2) */

/* The table of stam_Phi (stam_stats.h). */
double stam_phi_table[STAM_PHI_N + 2];
static pthread_once_t phi_once = PTHREAD_ONCE_INIT;

static void phi_init(void)
{
    for (int i = 0; i <= STAM_PHI_N + 1; i++)
        stam_phi_table[i] = SQRT_PI_2 * erf(i * (STAM_PHI_MAX / STAM_PHI_N) * 0.7071067811865476);
}

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

/* Delta u_i: the mean exceeds eta for |u - u_i| < Delta u_i (within the chord); -1 when the
 * peak along the ray does not exceed eta (nothing is clamped). */
static double clamp_half(const blob_ray *br, double eta)
{
    if (!(br->peak > eta))
        return -1.0; /* the log in Delta u_i is <= 0: nothing is clamped */
    double du;
    if (br->k) { /* W(s_eta) = eta: s_eta >= d / h since the peak along the ray exceeds eta */
        double s = blob_kernel_radius(br->k, eta / br->peak0);
        du = br->h * sqrt(fmax(0.0, s * s - br->dh * br->dh));
    } else {
        du = br->h * sqrt(2.0 * log(br->peak / eta)); /* Appendix A, in units of h there */
    }
    return du > br->half ? br->half : du;
}

double blob_T_clamped(const blob_ray *br, double eta, double a, double b)
{
    double du = clamp_half(br, eta);
    if (du < 0.0)
        return blob_T_mean(br, a, b);
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

double blob_ray_density(const blob_ray *br, double u)
{
    double x = u - br->u;
    if (!(fabs(x) < br->half))
        return 0.0;
    if (br->k)
        return br->peak0 * blob_kernel_eval(br->k, sqrt(br->dh * br->dh + x * x / (br->h * br->h)));
    return br->peak * exp(-x * x / (2.0 * br->h * br->h));
}

/* Gauss-Legendre, 8 points on [-1, 1]. */
static const double gl_x[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
static const double gl_w[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

/* Integral over [p, q] of the gaussian a exp(-(u - mu)^2 / (2 s^2)). */
static double gauss_piece(double a, double mu, double s, double p, double q)
{
    return a * s * (stam_Phi((q - mu) / s) - stam_Phi((p - mu) / s));
}

/* sqrt(F_i F_j) over a piece [p, q] on which each blob is either clamped (F = eta) or not. */
static double cross_piece(const blob_ray *bi, const blob_ray *bj, bool ci, bool cj, double eta, double p, double q)
{
    if (ci && cj)
        return eta * (q - p);
    if (bi->k || bj->k) { /* a tabulated kernel: Gauss-Legendre */
        double m = 0.5 * (p + q), r = 0.5 * (q - p), sum = 0.0;
        for (int k = 0; k < 4; k++)
            for (int sg = -1; sg <= 1; sg += 2) {
                double u = m + sg * r * gl_x[k];
                double fi = ci ? eta : blob_ray_density(bi, u), fj = cj ? eta : blob_ray_density(bj, u);
                sum += gl_w[k] * sqrt(fi * fj);
            }
        return sum * r;
    }
    /* gaussians: sqrt(P exp(-(u - u_i)^2 / 2h^2)) = sqrt(P) exp(-(u - u_i)^2 / 4h^2) */
    if (ci || cj) {
        const blob_ray *g = ci ? bj : bi;
        return gauss_piece(sqrt(eta * g->peak), g->u, SQRT2 * g->h, p, q);
    }
    double ai = 1.0 / (4.0 * bi->h * bi->h), aj = 1.0 / (4.0 * bj->h * bj->h), a = ai + aj;
    double mu = (ai * bi->u + aj * bj->u) / a, du = bi->u - bj->u;
    double amp = sqrt(bi->peak * bj->peak) * exp(-ai * aj / a * du * du);
    return gauss_piece(amp, mu, sqrt(0.5 / a), p, q);
}

double blob_T_cross(const blob_ray *bi, const blob_ray *bj, double eta, double a, double b)
{
    double lo = fmax(fmax(bi->u - bi->half, bj->u - bj->half), a);
    double hi = fmin(fmin(bi->u + bi->half, bj->u + bj->half), b);
    if (!(hi > lo))
        return 0.0;
    double di = clamp_half(bi, eta), dj = clamp_half(bj, eta);
    /* the pieces between the plateaus' ends, in order */
    double cut[6];
    int n = 0;
    cut[n++] = lo;
    const double ends[4] = {bi->u - di, bi->u + di, bj->u - dj, bj->u + dj};
    for (int e = 0; e < 4; e++) {
        if ((e < 2 ? di : dj) < 0.0 || !(ends[e] > lo && ends[e] < hi))
            continue;
        int at = n++;
        while (at > 1 && cut[at - 1] > ends[e]) {
            cut[at] = cut[at - 1];
            at--;
        }
        cut[at] = ends[e];
    }
    cut[n++] = hi;
    double sum = 0.0;
    for (int k = 0; k + 1 < n; k++) {
        double m = 0.5 * (cut[k] + cut[k + 1]);
        bool ci = di >= 0.0 && fabs(m - bi->u) < di, cj = dj >= 0.0 && fabs(m - bj->u) < dj;
        sum += cross_piece(bi, bj, ci, cj, eta, cut[k], cut[k + 1]);
    }
    return sum;
}

double blob_T_cov(const blob_ray *bi, const blob_ray *bj, double eps, double eta, double alpha, double a, double b)
{
    if (!(eps > 0.0))
        return 0.0;
    /* c_ij: the exact ratio of the double integral to its leading term for two unclamped,
     * unbounded gaussian blobs (docs/stam.md); c_ii = c(alpha / h) of blob_T_var_scale */
    double S = 2.0 * (bi->h * bi->h + bj->h * bj->h), du = bi->u - bj->u, A = alpha * alpha;
    double c = sqrt(S / (S + A)) * exp(du * du * A / (2.0 * S * (S + A)));
    return eps * SQRT_2PI * alpha * c * blob_T_cross(bi, bj, eta, a, b);
}
