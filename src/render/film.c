/* film.c - pixel filter sampling. */
#include "render/film.h"

#include <math.h>

void film_sample_gaussian(double width, rng *g, double *dx, double *dy)
{
    /* Gaussian of standard deviation width / 4 truncated to a disk of radius width / 2:
     * Box-Muller with the radius drawn from the truncated distribution by inversion. */
    double sigma = 0.25 * width, rmax = 0.5 * width;
    double cut = 1.0 - exp(-0.5 * rmax * rmax / (sigma * sigma));
    double r = sigma * sqrt(-2.0 * log1p(-rng_next(g) * cut));
    double phi = 2.0 * 3.14159265358979323846 * rng_next(g);
    *dx = r * cos(phi);
    *dy = r * sin(phi);
}
