/* quadrature.h - Gauss-Legendre rules shared by the phase module (normalization, fitting). */
#ifndef BRUME_PHASE_QUADRATURE_H
#define BRUME_PHASE_QUADRATURE_H

/* The n-point Gauss-Legendre rule on [-1, 1] (n >= 1): nodes x[0..n) in increasing order
 * and weights w[0..n). Exact for polynomials of degree <= 2n - 1. Nodes are found by
 * Newton's method on the Legendre polynomial P_n, to machine precision. */
void quad_gauss_legendre(int n, double *x, double *w);

#endif
