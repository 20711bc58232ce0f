/* device_scene.h - what of a scene the GPU renders, and the scene's copy for it.
 *
 * The GPU runs the path tracer's own source (gpu/kernel.cu) on a copy of the scene's object
 * graph in device memory (core/arena.h). What the GPU cannot render yet is refused with one
 * line naming the feature (device_scene_check), never rendered wrong. */
#ifndef BRUME_GPU_DEVICE_SCENE_H
#define BRUME_GPU_DEVICE_SCENE_H

#include "brume.h"
#include "core/arena.h"
#include "scene/scene.h"

/* BRUME_OK when the GPU can render s with method `kind` (integrator_kind); else
 * BRUME_ERROR_UNSUPPORTED with err_set() naming the scene and the feature. */
brume_status device_scene_check(const brume_scene *s, int kind);
/* Copies s (checked) and the integrator state into a: returns the scene copy's offset and
 * sets *state_at to the state copy's (ARENA_NULL for none). a->failed on failure. */
size_t device_scene_put(const brume_scene *s, const void *state, dev_arena *a, size_t *state_at);

#endif
