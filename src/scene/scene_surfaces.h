/* scene_surfaces.h - reads a scene file's "surfaces" array (docs/scene-format.md) into the
 * scene through the public surface builders. */
#ifndef BRUME_SCENE_SCENE_SURFACES_H
#define BRUME_SCENE_SCENE_SURFACES_H

#include <cjson/cJSON.h>

#include "brume.h"
#include "io/json.h"

/* A surface's "material" object j (NULL: the default) into *m (scene_material.c); an "albedo"
 * texture object into *tex (the caller frees it: scene_json_texture_free), which
 * m->albedo_texture then points to. */
struct json_texture;
brume_status scene_parse_material(const cJSON *j, jloc at, brume_material *m, struct json_texture **tex);
brume_status scene_parse_surfaces(const cJSON *arr, const char *file, brume_scene *s);

#endif
