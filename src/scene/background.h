/* background.h - radiance arriving from infinity (Blasi's L-infinity): a constant, or an
 * environment image, sampled in proportion to its luminance, in one of two layouts:
 *
 * - latitude-longitude: the image's top row looks along `up`, the bottom row along -up;
 *   column u covers azimuth phi = 2 pi u - pi about up, measured in the frame whose first
 *   axis is frame_from_n(up).s;
 * - equal-area octahedral (pbrt-v4's image infinite light, Clarberg 2008): a square image,
 *   the point (u, v) of the unit square (u to the right, v down from the top row) is the
 *   direction bg_equal_area_to_sphere(u, v) in the map's frame, whose axes are the world
 *   directions f.s, f.t, f.n (a rotation, or a rotation and a mirror: then the frame is
 *   left-handed); every texel covers the same solid angle, 4 pi / texels.
 *
 * Radiance = pixel value * scale, the texel's (no filtering, as pbrt-v4's lookup). */
#ifndef BRUME_SCENE_BACKGROUND_H
#define BRUME_SCENE_BACKGROUND_H

#include <stdbool.h>

#include "brume.h"
#include "core/color.h"
#include "core/distrib.h"
#include "core/vec.h"

typedef enum bg_mapping { BG_LATLONG = 0, BG_EQUAL_AREA = 1 } bg_mapping;

typedef struct background {
    color L;           /* constant radiance, when img is NULL */
    brume_image *img;  /* environment image (owned), or NULL */
    double scale;      /* multiplies the image */
    bg_mapping mapping;
    vec3 up;           /* lat-long: the image's zenith direction (unit) */
    frame f;           /* lat-long: derived, n = up; equal-area: given, the map's axes */
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

/* pbrt-v4's equal-area octahedral map: a point of the unit square to a unit vector, and a
 * unit vector to the point, its inverse (pbrt-v4's EqualAreaSquareToSphere and
 * EqualAreaSphereToSquare, with atan in place of its polynomial). */
vec3 bg_equal_area_to_sphere(double u, double v);
void bg_sphere_to_equal_area(vec3 w, double *u, double *v);

#endif
