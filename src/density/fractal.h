/* fractal.h - fractal density grids for clouds, after Blasi et al. 1993, section 4.1:
 * "grids of fractal densities" from an extension of Peitgen and Saupe (The Science of
 * Fractal Images, 1988, ch. 2), shaped by a solid texture (Perlin 1985; Perlin and Hoffert
 * 1989), animated by a varying threshold combined with a turbulence function (Ebert and
 * Parent 1990). Derivations and pictures: docs/grids.md.
 *
 * The three fractal bases, each fractional Brownian motion (fBm) with Hurst exponent H in
 * (0, 1) (H near 1 smooth, near 0 rough; the fractal dimension of a level surface is 4 - H):
 *   midpoint  random midpoint displacement on a (2^L + 1)^3 lattice (the paper's 65 = 2^6 + 1)
 *   spectral  spectral synthesis: gaussian Fourier coefficients with amplitude |f|^-(H + 3/2),
 *             inverse FFT with FFTW (periodic)
 *   perlin    a sum of octaves of Perlin's gradient noise with gain 2^-H per octave */
#ifndef BRUME_DENSITY_FRACTAL_H
#define BRUME_DENSITY_FRACTAL_H

#include <stdint.h>

#include "brume.h"
#include "density/density.h"

typedef enum fractal_method { FRACTAL_MIDPOINT, FRACTAL_SPECTRAL, FRACTAL_PERLIN } fractal_method;
typedef enum fractal_shape { FRACTAL_SHAPE_NONE, FRACTAL_SHAPE_ELLIPSOID, FRACTAL_SHAPE_SLAB } fractal_shape;

/* rho(x, t) = density * max(0, (s(x) g(x, t) - theta(t)) / (1 - theta(t))), where
 *   g = f(x) + turbulence * (turb(turbulence_frequency x + t wind) - mean), f the fBm base
 *       normalized to [0, 1] over the grid, turb Perlin's turbulence;
 *   s = the solid texture: 1 inside, falling smoothly to 0 over `falloff` (a fraction of
 *       the half-extent) at the ellipsoid inscribed in the grid box, or at the slab's top
 *       and bottom and side walls;
 *   theta(t) = clamp(threshold + threshold_rate t, 0, 0.99).
 * Coordinates x are normalized: [-1, 1] across each axis of the grid. */
typedef struct fractal_params {
    int n[3];              /* voxels per axis, each in [1, 1024] */
    uint64_t seed;
    fractal_method method;
    double hurst;          /* H in (0, 1) */
    int octaves;           /* perlin base and turbulence: octaves, >= 1 */
    double frequency;      /* perlin base: cycles across the grid's largest axis */
    fractal_shape shape;
    double falloff;        /* in (0, 1] */
    double threshold;      /* theta at time 0, in [0, 1) */
    double threshold_rate; /* d theta / dt, per unit time */
    double turbulence;     /* amplitude of the turbulence term, >= 0 */
    double turbulence_frequency; /* cycles across the grid's largest axis */
    vec3 wind;             /* turbulence drift, normalized units per unit time */
    double time;           /* t */
    double density;        /* the largest possible rho, > 0 */
} fractal_params;

/* Defaults (chosen by eye on docs/images/gen-cloud.png): midpoint, H = 0.5, slab with
 * falloff 0.6, threshold 0.4, no turbulence,
 * 6 octaves at frequency 2, density 1, time 0, 65 x 65 x 10 voxels, seed 1. */
void fractal_params_default(fractal_params *p);
/* The parameters of brume.h's brume_fractal (all but its bounds and filter), copied as they
 * are: the caller checked them (brume_density_new_fractal, `brume gen cloud`). */
void fractal_params_from_api(const brume_fractal *f, fractal_params *p);

/* The cloud's voxels (n0 n1 n2 floats, x fastest), malloc'd for the caller; NULL with
 * err_set() on bad parameters or no memory. */
float *fractal_cloud_voxels(const fractal_params *p);
/* The same as a density placed on `bounds`. */
density *fractal_cloud(const fractal_params *p, box3 bounds, grid_filter filter);

/* Building blocks, each returning BRUME_OK or an error. out must hold the stated count. */
/* (2^level + 1)^3 values, zero mean at the corners' scale sigma = 1, level in [1, 10]; only
 * the planes k < planes (in [1, 2^level + 1]) are filled, each as in the whole lattice, and
 * the others hold what they held. */
brume_status fractal_midpoint(int level, double hurst, uint64_t seed, int planes, float *out);
/* n0 n1 n2 values (x fastest), periodic, normalized to zero mean and unit variance. */
brume_status fractal_spectral(const int n[3], double hurst, uint64_t seed, float *out);

/* Perlin's improved gradient noise (Perlin 2002) in [-1, 1] with a permutation from seed. */
typedef struct perlin_table {
    uint8_t p[512];
} perlin_table;
void perlin_init(perlin_table *t, uint64_t seed);
double perlin_noise(const perlin_table *t, vec3 x);
/* Perlin 1985: sum over octaves o of |noise(2^o x)| / 2^o. */
double perlin_turbulence(const perlin_table *t, vec3 x, int octaves);

#endif
