/* scene_stam.h - the scene file's blob densities (type "blobs", docs/scene-format.md), built
 * with brume_density_new_blobs. Stam's options (the "stam" object) are read as method
 * options (scene/scene_methods.c). */
#ifndef BRUME_SCENE_SCENE_STAM_H
#define BRUME_SCENE_SCENE_STAM_H

#include <cjson/cJSON.h>

#include "io/json.h"

/* A density object of type "blobs": explicit blobs and/or generators. */
brume_status scene_parse_blobs(const cJSON *j, jloc at, brume_density **out);

#endif
