/* scene_build.h - what the public scene builders (scene_build.c, scene_media.c,
 * scene_shapes.c) share: argument checks whose messages name the function and the
 * argument, and the public density and phase handles. */
#ifndef BRUME_SCENE_SCENE_BUILD_H
#define BRUME_SCENE_SCENE_BUILD_H

#include "brume.h"
#include "core/color.h"
#include "core/motion.h"
#include "core/vec.h"
#include "density/density.h"
#include "phase/phase.h"

struct brume_density {
    density *d;   /* owned */
    bool evolves; /* generated at a time with a time-dependent recipe (the world is not static) */
};

/* The most numbers an inline array of a scene file may hold (a density's `data`, a mesh's
 * `positions` or `indices`): 2^21 voxels is 128^3, 8 MiB as floats, and about 130 MiB of
 * parsed JSON nodes; larger data belongs in a file (docs/scene-format.md, "Limits"). */
#define SCENE_INLINE_MAX_VALUES (1 << 21)
#define SCENE_MAX_IGNORED 1000 /* entries of a scene file's "ignored" list (brume_scene_ignored) */

struct brume_phase {
    phase *p; /* owned */
};

/* Each returns BRUME_OK or err_set()s "FN: ARG: what is wrong". */
brume_status build_check_scene(const char *fn, const brume_scene *s); /* not NULL, not committed */
brume_status build_null(const char *fn, const char *arg);
/* The first NULL of n (name, pointer) pairs, as build_null; BRUME_OK when none is NULL. */
brume_status build_need(const char *fn, int n, ...);
brume_status build_number(const char *fn, const char *arg, double v, double lo, double hi);
brume_status build_point(const char *fn, const char *arg, const double *p, vec3 *out);     /* finite */
brume_status build_direction(const char *fn, const char *arg, const double *p, vec3 *out); /* normalized */
brume_status build_color(const char *fn, const char *arg, const double *c, double hi, color *out);
brume_status build_box(const char *fn, const char *arg, const double *b, box3 *out);
brume_status build_motion(const char *fn, const brume_transform_key *keys, int n, motion *out);

#endif
