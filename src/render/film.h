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

/* Offset from the pixel centre, in pixels, drawn from the filter. */
void film_sample_filter(brume_filter filter, double width, rng *g, double *dx, double *dy);

#endif
