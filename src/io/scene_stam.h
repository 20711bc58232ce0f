/* scene_stam.h - the scene file's blob densities (type "blobs") and its "stam" object
 * (docs/scene-format.md). */
#ifndef BRUME_IO_SCENE_STAM_H
#define BRUME_IO_SCENE_STAM_H

#include <cjson/cJSON.h>

#include "io/json.h"
#include "render/scene.h"

/* A density object of type "blobs": explicit blobs and/or generators. */
brume_status scene_parse_blobs(const cJSON *j, jloc at, density **out);
/* The top-level "stam" object (may be absent), read after the media: fills s->stam, moves
 * drifting blob fields to stam.time, and with stam.voxelize replaces every blob field by a
 * dense grid of its mean or of one explicit realization. */
brume_status scene_parse_stam(const cJSON *root, brume_scene *s);

#endif
