/* randfield.h - the homogeneous gaussian random field Q of Stam 1994 (Sections 4 and 7):
 * zero mean, unit variance, gaussian correlation exp(-|r|^2 / (2 alpha^2)), made by inverse
 * spectral synthesis with FFTW on a periodic lattice and read by trilinear interpolation.
 *
 * Normalization (a departure from Stam's Eq. 5, see docs/stam.md): Q has unit variance, so
 * its covariance is the correlation function r(x) = exp(-|x|^2 / (2 alpha^2)), r(0) = 1, and
 * a field g Q has variance g^2 as Eq. 2 says. Eq. 5's normalized gaussian would give Q the
 * variance (2 pi)^(-3/2) alpha^-3, which is not dimensionless.
 *
 * Synthesis: with lattice spacing `cell` and wave vectors k = 2 pi m / (n cell),
 *   Z(x, t) = sum_k c_k xi_k exp(i omega_k t) exp(i k.x),   c_k^2 = g_k / sum g,
 *   g_k = exp(-alpha^2 |k|^2 / 2),   xi_k = a_k + i b_k,   a_k, b_k ~ N(0, 1) independent,
 * one complex FFT. Re Z and Im Z are two independent real fields, each with covariance
 * sum_k c_k^2 cos(k.r) (= 1 at r = 0 exactly, ~ exp(-r^2 / 2 alpha^2) when cell << alpha <<
 * n cell). Time: each mode turns at omega_k = rate (1 + alpha |k|) (fine detail changes
 * faster, after Stam and Fiume 1993), so every frame has the same spatial statistics and
 * consecutive frames are correlated by sum_k c_k^2 cos(omega_k dt): the field evolves
 * smoothly (Section 6.1). */
#ifndef BRUME_DENSITY_RANDFIELD_H
#define BRUME_DENSITY_RANDFIELD_H

#include <stdint.h>

#include "brume.h"
#include "core/vec.h"

typedef struct randfield_params {
    int n[3];      /* lattice points per axis, each in [2, 512] */
    double cell;   /* lattice spacing, world units, > 0 */
    double alpha;  /* correlation length (standard deviation of the gaussian), world units, > 0 */
    uint64_t seed; /* the realization */
    double time;   /* t */
    double rate;   /* omega_0, radians per unit time, >= 0 */
} randfield_params;

/* Two independent realizations (Re Z and Im Z) of the lattice values, n0 n1 n2 floats each,
 * x fastest; `index` selects an independent pair for the same seed. im may be NULL.
 * BRUME_OK, or an error with err_set() on bad parameters or no memory. */
brume_status randfield_synthesize(const randfield_params *p, uint64_t index, float *re, float *im);

/* Q over all space: the lattice repeats with period n cell, node (0, 0, 0) at the world origin. */
typedef struct randfield {
    int n[3];
    double inv_cell;
    float *q; /* owned, n0 n1 n2 values */
} randfield;

/* A new field (realization index 0 of p), or NULL with err_set(). */
randfield *randfield_new(const randfield_params *p);
void randfield_release(randfield *q);
/* Q(p): trilinear between the periodic lattice values. */
double randfield_eval(const randfield *q, vec3 p);

#endif
