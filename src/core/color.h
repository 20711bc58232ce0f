/* color.h - linear RGB (Rec. 709 primaries), BRUME_NSAMPLES samples per ray.
 * Every radiometric quantity (radiance, sigma_a, albedo, path weights) is a color.
 * Keep loops over BRUME_NSAMPLES rather than naming r, g, b, so a spectral build stays possible. */
#ifndef BRUME_CORE_COLOR_H
#define BRUME_CORE_COLOR_H

#include <math.h>
#include <stdbool.h>

#define BRUME_NSAMPLES 3

/* color, col_add ... in double; colorf, col_addf ... in float (the GPU's single-precision
 * stages): one body (core/color_body.h), two instantiations. */
#define REAL_F 0
#include "core/color_body.h"
#undef REAL_F
#define REAL_F 1
#include "core/color_body.h"
#undef REAL_F

#endif
