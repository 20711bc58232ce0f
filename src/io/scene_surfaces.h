/* scene_surfaces.h - reads a scene file's "surfaces" array (docs/scene-format.md). */
#ifndef BRUME_IO_SCENE_SURFACES_H
#define BRUME_IO_SCENE_SURFACES_H

#include <cjson/cJSON.h>

#include "surface/surfaces.h"

/* A new uncommitted surfaces object, or NULL in *out for an empty array. */
brume_status scene_parse_surfaces(const cJSON *arr, const char *file, surfaces **out);

#endif
