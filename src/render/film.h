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
#include "scene/film_sensor.h" /* the film's sensor and white balance */

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
