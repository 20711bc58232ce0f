/* scene_material.h - a scene file's material object (docs/scene-format.md, "surfaces"). */
#ifndef BRUME_SCENE_SCENE_MATERIAL_H
#define BRUME_SCENE_SCENE_MATERIAL_H

#include <cjson/cJSON.h>

#include "brume.h"
#include "io/json.h"

/* A surface's "material" object j (NULL: the default) into *m (scene_material.c); an "albedo"
 * texture object into *tex (the caller frees it: scene_json_texture_free), which
 * m->albedo_texture then points to. */
struct json_texture;
brume_status scene_parse_material(const cJSON *j, jloc at, brume_material *m, struct json_texture **tex);

#endif
