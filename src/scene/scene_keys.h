/* scene_keys.h - "keyframes" in scene files: camera poses, transforms of surfaces and
 * media, and per-frame values of lights (docs/animation.md, docs/scene-format.md).
 *
 * Every "keyframes" value is an array of objects, each with a "time" (seconds, strictly
 * increasing) and the keyed properties. A property is interpolated linearly between the
 * keys that give it, rotations by slerp; before its first key and after its last one it
 * holds. */
#ifndef BRUME_SCENE_SCENE_KEYS_H
#define BRUME_SCENE_SCENE_KEYS_H

#include "core/motion.h"
#include "io/json.h"
#include "scene/camera.h"

/* keys: [{"time": t, "transform": {translate, rotate, scale}}, ...] into out[0 .. *n)
 * (room for MOTION_MAX_KEYS), for brume_scene_set_medium_motion / _surface_motion. */
brume_status keys_parse_motion(const cJSON *keys, jloc at, brume_transform_key *out, int *n);

/* keys: [{"time": t, "position", "look_at", "up", "fov", "aperture_radius",
 * "focus_distance"}, ...] into c->keys, completing each key from the other keys, or from
 * the camera's own fields for a property no key gives. focus_given says whether the camera
 * object named focus_distance; when neither it nor any key does, each key focuses at its
 * look_at. */
brume_status keys_parse_camera(const cJSON *keys, jloc at, camera *c, bool focus_given);

/* A copy of object j whose keyed properties (numbers and arrays of numbers) take their
 * values at time t, without the "keyframes" key: what a reader that evaluates once per
 * frame (lights) parses. The caller cJSON_Delete()s *out. */
brume_status keys_object_at(const cJSON *j, jloc at, double t, cJSON **out);

#endif
