/* background.h - radiance arriving from infinity (Blasi's L-infinity): a constant, or an
 * environment image in latitude-longitude layout, sampled in proportion to its luminance.
 *
 * Image layout: the image's top row looks along `up`, the bottom row along -up; column u
 * covers azimuth phi = 2 pi u - pi about up, measured in the frame whose first axis is
 * frame_from_n(up).s. Radiance = pixel value * scale. */
#ifndef BRUME_SCENE_BACKGROUND_H
#define BRUME_SCENE_BACKGROUND_H

#include <stdbool.h>

#include "brume.h"
#include "core/color.h"
#include "core/distrib.h"
#include "core/vec.h"

typedef struct background {
    color L;           /* constant radiance, when img is NULL */
    brume_image *img;  /* lat-long environment (owned), or NULL */
    double scale;      /* multiplies the image */
    vec3 up;           /* the image's zenith direction (unit) */
    frame f;           /* derived: n = up */
    distrib2 dist;     /* derived: luminance * sin(theta) per pixel */
    bool has_dist;
} background;

/* Copies the image and tables of b, which the arena holds at offset `at` (a byte copy of
 * it), into the arena (core/arena.h) for the GPU, and points the copy at them. */
struct dev_arena;
void background_device_fix(const background *b, struct dev_arena *a, size_t at);

/* Builds the sampling tables; false when out of memory. */
bool background_init(background *b);
void background_release(background *b);
bool background_is_black(const background *b);
/* Radiance arriving along -w, i.e. seen when looking along w. */
color background_eval(const background *b, vec3 w);
/* A direction w (towards the background) with solid-angle *pdf and the radiance *L. */
vec3 background_sample(const background *b, double u1, double u2, double *pdf, color *L);
double background_pdf(const background *b, vec3 w);

#endif
