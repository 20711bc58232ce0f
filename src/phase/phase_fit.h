/* phase_fit.h - fitting Blasi's two-lobe Schlick mixture (Eq. 22) to any phase function.
 *
 * The model is phi(t) = r phi_k(t) + (1 - r) phi_k'(t) with Schlick lobes (Eq. 21),
 * r in [0, 1], |k|, |k'| < 1. The result is reported with k <= k', so that, as in the
 * paper's Figure 7, k is the backward (or less forward) lobe and r its weight.
 *
 * The error norms (docs/phase-functions.md) compare phi = 4 pi p of the model and of the
 * target; each is relative, so 0.01 means a 1 % root-mean-square difference. */
#ifndef BRUME_PHASE_PHASE_FIT_H
#define BRUME_PHASE_PHASE_FIT_H

#include "brume.h"
#include "phase/phase.h"

typedef enum phase_fit_norm {
    /* sqrt( int (phi_fit - phi)^2 dt / int phi^2 dt ), t = cos in [-1, 1]: the L2 norm
     * over the sphere (uniform in solid angle). */
    PHASE_FIT_NORM_COS,
    /* The same with d(theta) in [0, pi] in place of dt: the L2 norm of the cartesian plot
     * of phi against the angle, weighting back and side scattering more than the sphere.
     * The default: of the three norms, the paper's Figure 7 parameters come closest to
     * its minimum (docs/phase-functions.md). */
    PHASE_FIT_NORM_ANGLE,
    /* sqrt( int (ln phi_fit - ln phi)^2 dt / 2 ): root-mean-square relative (log) error
     * over the sphere; needs a target without zeros. */
    PHASE_FIT_NORM_LOG
} phase_fit_norm;

typedef struct phase_fit_result {
    double r, k, kprime; /* Blasi Eq. 22, k <= kprime */
    double error;        /* the norm at (r, k, kprime) */
} phase_fit_result;

/* "cos", "angle", "log" to a norm; returns false for any other name. */
bool phase_fit_norm_from_name(const char *name, phase_fit_norm *out);
const char *phase_fit_norm_name(phase_fit_norm norm);

/* The error of the mixture (r, k, kprime) against target in the given norm, computed by
 * composite Gauss-Legendre quadrature over the angle (fine near both poles, where the
 * peaks are). Returns NAN for parameters outside the domain of Eq. 22. */
double phase_fit_error(const phase *target, phase_fit_norm norm, double r, double k, double kprime);

/* Minimizes phase_fit_error over (r, k, kprime): a coarse grid search over the whole
 * domain, then Nelder-Mead from the best grid points in unconstrained coordinates
 * (r = sin^2 a, k = K sin b). Deterministic. Fails (err_set) only when out of memory or
 * when the log norm meets a target that is 0 somewhere. */
brume_status phase_fit_schlick_mix(const phase *target, phase_fit_norm norm, phase_fit_result *out);

#endif
