/* film.h - pixel filters and per-pixel accumulation.
 *
 * Pixel filters are importance-sampled (pbrt-v4): a sample's film position is drawn from
 * the filter itself, so every sample has weight 1 and a pixel is the plain mean of its
 * samples. Each pixel is owned by one tile task, so accumulation needs no locks and the
 * result does not depend on the thread count. */
#ifndef BRUME_RENDER_FILM_H
#define BRUME_RENDER_FILM_H

#include "brume.h"
#include "core/rng.h"

/* pbrt-v4's white balance of its cie1931 sensor (film_white.c): the chromaticity (x, y) of
 * its source white at `kelvin`, and the 3 x 3 (row-major) that maps linear Rec. 709 colours
 * from that white to D65's. */
void film_daylight_xy(double kelvin, double xy[2]);
void film_white_balance(double kelvin, double m[9]);

/* film_sample_filter's Gaussian filter (film.c). */
void film_sample_gaussian(double width, rng *g, double *dx, double *dy);

/* Offset from the pixel centre, in pixels, drawn from the filter. Inline: the box filter,
 * the usual one, is two numbers, and the renderer draws it for every sample. */
static inline void film_sample_filter(brume_filter filter, double width, rng *g, double *dx, double *dy)
{
    switch (filter) {
    case BRUME_FILTER_BOX:
        *dx = (rng_next(g) - 0.5) * width;
        *dy = (rng_next(g) - 0.5) * width;
        return;
    case BRUME_FILTER_GAUSSIAN: film_sample_gaussian(width, g, dx, dy); return;
    }
    *dx = *dy = 0.0;
}

#endif
