/* distrib.h - piecewise-constant 1-D and 2-D distributions for importance sampling
 * (pbrt's Distribution1D / Distribution2D, marginal-conditional inversion). */
#ifndef BRUME_CORE_DISTRIB_H
#define BRUME_CORE_DISTRIB_H

#include <stddef.h>

typedef struct distrib1 {
    int n;        /* bins over [0, 1) */
    double *f;    /* n values >= 0 (owned) */
    double *cdf;  /* n + 1 values, cdf[0] = 0, cdf[n] = 1 (owned) */
    double integral; /* sum f / n */
} distrib1;

/* Copies f; false on allocation failure. A zero function becomes uniform. */
int distrib1_init(distrib1 *d, const double *f, int n);
void distrib1_free(distrib1 *d);
/* x in [0, 1) with density f(x) / integral; *pdf receives that density, *bin the bin. */
double distrib1_sample(const distrib1 *d, double u, double *pdf, int *bin);
double distrib1_pdf(const distrib1 *d, double x);

typedef struct distrib2 {
    int nu, nv;
    distrib1 *rows; /* nv conditionals over u (owned) */
    distrib1 marginal; /* over v */
} distrib2;

/* Copy the tables of the distribution d, which the arena holds at offset `at` (a byte copy
 * of it), into the arena (core/arena.h) and point the copy at them. */
struct dev_arena;
void distrib1_device_fix(const distrib1 *d, struct dev_arena *a, size_t at);

/* f is nv rows of nu values (row v, column u). */
int distrib2_init(distrib2 *d, const double *f, int nu, int nv);
void distrib2_free(distrib2 *d);
void distrib2_device_fix(const distrib2 *d, struct dev_arena *a, size_t at);
/* (u, v) in [0, 1)^2 with density f / integral (per unit square); *pdf that density. */
void distrib2_sample(const distrib2 *d, double u1, double u2, double *u, double *v, double *pdf);
double distrib2_pdf(const distrib2 *d, double u, double v);

#endif
