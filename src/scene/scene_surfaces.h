/* scene_surfaces.h - reads a scene file's "surfaces" array (docs/scene-format.md) into the
 * scene through the public surface builders. */
#ifndef BRUME_SCENE_SCENE_SURFACES_H
#define BRUME_SCENE_SCENE_SURFACES_H

#include <cjson/cJSON.h>

#include "brume.h"
#include "io/json.h"

brume_status scene_parse_surfaces(const cJSON *arr, const char *file, brume_scene *s);

#endif
