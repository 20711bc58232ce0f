/* motion.h - keyframed rigid-plus-scale transforms: where an object or a medium is at
 * time t. Each key holds a translation, a rotation (unit quaternion) and a per-axis scale;
 * between keys the translation and the scale are interpolated linearly and the rotation by
 * spherical linear interpolation (slerp, the shorter arc); before the first key and after
 * the last one the end keys hold. The transform at t is translate(rotate(scale(p))), the
 * order of a scene file's "transform" (docs/scene-format.md, docs/animation.md). */
#ifndef BRUME_CORE_MOTION_H
#define BRUME_CORE_MOTION_H

#include <stdbool.h>

#include "core/vec.h"
#include "core/xform.h"

#define MOTION_MAX_KEYS 64

typedef struct motion_key {
    double time;     /* seconds, strictly increasing along the track */
    vec3 translate;  /* world units */
    double q[4];     /* rotation as a unit quaternion (w, x, y, z) */
    vec3 scale;      /* factors > 0 */
} motion_key;

typedef struct motion {
    int n; /* keys in use, 1 .. MOTION_MAX_KEYS */
    motion_key key[MOTION_MAX_KEYS];
} motion;

/* The rotation by angle_deg degrees about axis (any length > 0) as a unit quaternion. */
void motion_quat_axis_angle(vec3 axis, double angle_deg, double q[4]);
/* The transform at time t (object or medium space to world). */
affine3 motion_at(const motion *m, double t);
/* True when every key has the same rotation: points then move linearly between keys, so
 * that linear interpolation between two instants with no key between them is exact. */
bool motion_rotation_constant(const motion *m);
/* True when some key time lies strictly inside (t0, t1). */
bool motion_key_inside(const motion *m, double t0, double t1);

#endif
