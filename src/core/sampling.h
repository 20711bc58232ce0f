/* sampling.h - warps from uniform numbers in [0,1) to distributions, each with its pdf.
 * Solid-angle pdfs are per steradian; area pdfs per unit area; distances per unit length. */
#ifndef BRUME_CORE_SAMPLING_H
#define BRUME_CORE_SAMPLING_H

#include <math.h>

#include "core/vec.h"

/* Uniform direction on the unit sphere; pdf 1 / (4 pi). */
vec3 sample_sphere(double u1, double u2);
/* Uniform direction in the cone of half-angle acos(cos_max) around +z; pdf 1 / (2 pi (1 - cos_max)). */
vec3 sample_cone(double u1, double u2, double cos_max);
double sample_cone_pdf(double cos_max);
/* Uniform point on the unit disk (concentric map, Shirley and Chiu 1997), z = 0; pdf 1 / pi. */
vec3 sample_disk(double u1, double u2);
/* Cosine-weighted direction on the +z hemisphere; pdf cos(theta) / pi. */
vec3 sample_cosine_hemisphere(double u1, double u2);
/* Distance with density sigma exp(-sigma t) on [0, inf): t = -ln(1 - u) / sigma. */
static inline double sample_exponential(double u, double sigma)
{
    /* 1 - u is exact for u >= 1/2 and rounds by less than 2^-53 below: log, not the
     * slower log1p, is accurate enough for a sample */
    return -log(1.0 - u) / sigma;
}
/* Direction from a cosine about +z and an azimuth from u: (sin cos phi, sin sin phi, cos). */
vec3 direction_from_cos(double cos_theta, double u_phi);

#endif
