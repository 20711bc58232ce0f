/* stam_stats.h - Stam 1994, Sections 5.2 and 6.1, Appendix A: the statistics of the optical
 * depth T_i = integral of rho_i along a ray segment, for one random gaussian blob
 *
 *   rho_i = rho_i_mean + sigma_i Q,   sigma_i^2 = eps F_eta(rho_i_mean),
 *
 * Q of unit variance with correlation exp(-r^2 / (2 alpha^2)) (density/randfield.h).
 *
 *   mean      T_mean = m W-integral in closed form with erf (Appendix A)
 *   variance  T_var  = eps sqrt(2 pi) alpha c(alpha / h) integral of F_eta(rho_i_mean) du,
 *             c = (1 + alpha^2 / (4 h^2))^(-1/2)
 *   sample    T_i = T_mean + sqrt(T_var) Q(x_ui)   (Eq. 13), x_ui the closest ray point
 *
 * The variance departs from Eq. 12 (which has K_Q(0) = (2 pi)^(-3/2) alpha^-3 in place of
 * sqrt(2 pi) alpha c): docs/errata.md, erratum 7, derived in docs/stam.md and checked by Monte
 * Carlo over explicit 3-D realizations in tests/test_stam.c. sqrt(2 pi) alpha is the
 * integral of the correlation along the ray, the leading term as alpha / h -> 0 (Eq. 11);
 * c is the exact correction for an unclamped blob and an unbounded segment.
 *
 * Geometry (Figure 2): a unit-direction ray o + u d over u in [a, b]; u_i = (x_i - o).d and
 * d_i^2 = |x_i - o|^2 - u_i^2. The blob is truncated at radius R (blobs.h), so integrals run
 * over the chord |u - u_i| < sqrt(R^2 - d_i^2) only: exactly the field the other
 * integrators see.
 *
 * With a tabulated kernel W (blob_kernel.h) the mean is Section 6.1's table of line
 * integrals, the clamped region |u - u_i| < h sqrt(s_eta^2 - (d_i/h)^2) where m W(s_eta) / h^3
 * = eta, and the variance the same eps sqrt(2 pi) alpha c I_F (c is the gaussian's
 * next-order factor, kept for every kernel: docs/stam.md). */
#ifndef BRUME_RENDER_STAM_STATS_H
#define BRUME_RENDER_STAM_STATS_H

#include "density/blobs.h"

/* Phi(x) = integral_0^x exp(-t^2 / 2) dt = sqrt(pi / 2) erf(x / sqrt 2) (erratum 8), from a
 * table (|error| < 4e-8); stam_stats_init() must have run once (stam_prepare calls it;
 * it is idempotent and thread-safe). */
void stam_stats_init(void);

/* Phi on [0, STAM_PHI_MAX] at STAM_PHI_N + 1 points, linear in between: |error| < 4e-8 (the
 * second derivative of Phi is bounded by 0.61, the spacing is 7.3e-4); beyond, Phi(6)
 * differs from Phi(inf) by 2e-9 relative. The paper tabulates too (Section 6.1). */
#define STAM_PHI_N 8192
#define STAM_PHI_MAX 6.0
extern double stam_phi_table[STAM_PHI_N + 2];
static inline double stam_Phi(double x)
{
    double a = x < 0.0 ? -x : x, v;
    if (!(a < STAM_PHI_MAX)) {
        v = stam_phi_table[STAM_PHI_N];
    } else {
        double f = a * (STAM_PHI_N / STAM_PHI_MAX);
        int i = (int)f;
        v = stam_phi_table[i] + (f - i) * (stam_phi_table[i + 1] - stam_phi_table[i]);
    }
    return x < 0.0 ? -v : v;
}

/* One blob seen along one ray. */
typedef struct blob_ray {
    double peak;   /* mean density at the ray's closest point: m W(d_i) */
    double h;      /* blob radius */
    double u;      /* u_i */
    double half;   /* half-length of the chord inside the truncation sphere */
    /* a tabulated kernel (blob_kernel.h), NULL for the gaussian: then the integrals are
     * Section 6.1's m (Table[d_i, b - u_i] - Table[d_i, a - u_i]) */
    const blob_kernel *k;
    double peak0;  /* mean density at the centre, m W(0) / h^3 */
    double dh;     /* d_i / h */
} blob_ray;

/* The blob i of f seen along a ray with closest parameter u and squared distance d2. */
blob_ray blob_ray_make(const blob_field *f, int i, double u, double d2);

/* Integral of the blob's mean density over [a, b] (Appendix A, T_mean). */
double blob_T_mean(const blob_ray *br, double a, double b);
/* Integral of F_eta(mean) over [a, b] (Section 6.1): the mean outside [u-, u+], eta inside,
 * u+- = u_i +- h sqrt(2 ln(peak / eta)) when peak > eta, else no clamping (erratum 8). */
double blob_T_clamped(const blob_ray *br, double eta, double a, double b);
/* Variance of T_i over [a, b] (docs/stam.md). */
double blob_T_var(const blob_ray *br, double eps, double eta, double alpha, double a, double b);
/* The factor eps sqrt(2 pi) alpha c(alpha / h) of blob_T_var: T_var = it x blob_T_clamped. */
double blob_T_var_scale(double eps, double alpha, double h);
/* Blob's truncated mean density at ray parameter u. */
double blob_ray_density(const blob_ray *br, double u);
/* Integral over [a, b] of sqrt(F_eta(mean_i) F_eta(mean_j)) along the ray (stam.overlap =
 * joint): in closed form (Phi) for gaussian blobs, piece by piece between the plateaus'
 * ends; by 8-point Gauss-Legendre per piece for a tabulated kernel. Equals blob_T_clamped
 * for i = j. */
double blob_T_cross(const blob_ray *bi, const blob_ray *bj, double eta, double a, double b);
/* Cov(T_i, T_j) over [a, b] of two blobs perturbed by the same Q (docs/stam.md, "Overlapping
 * blobs"): eps sqrt(2 pi) alpha c_ij blob_T_cross, c_ij = sqrt(S / (S + alpha^2))
 * exp((u_i - u_j)^2 alpha^2 / (2 S (S + alpha^2))), S = 2 (h_i^2 + h_j^2); = blob_T_var for
 * i = j. */
double blob_T_cov(const blob_ray *bi, const blob_ray *bj, double eps, double eta, double alpha, double a, double b);
/* Eq. 12 as printed, for comparison: K_Q(0) eps integral F_eta, K_Q(0) = (2 pi)^(-3/2) alpha^-3. */
double blob_T_var_paper(const blob_ray *br, double eps, double eta, double alpha, double a, double b);
/* Eq. 12 and Eq. 13 as printed together: T_i = T_mean + sigma_T Q^(0) with sigma_T^2 from Eq. 12
 * and Q^(0) a realization of Eq. 5's Q, whose variance is K_Q(0): with brume's unit-variance
 * Q, T_i = T_mean + K_Q(0) sqrt(eps I_F) Q. Returns K_Q(0) sqrt(eps), the factor of
 * sqrt(I_F) Q (the variance of T_i is then eps I_F K_Q(0)^2). */
double blob_T_sigma_paper_scale(double eps, double alpha);

#endif
