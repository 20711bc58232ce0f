/* scene_json_texture.h - a texture in a scene file (docs/scene-format.md, "Textures"): a
 * JSON tree of constant, imagemap, scale, mix and checkerboard objects flattened into the
 * nodes of brume.h's brume_texture. */
#ifndef BRUME_SCENE_SCENE_JSON_TEXTURE_H
#define BRUME_SCENE_SCENE_JSON_TEXTURE_H

#include "brume.h"
#include "io/json.h"

typedef struct json_texture {
    brume_texture tex; /* nodes points into node */
    brume_texture_node node[BRUME_TEXTURE_MAX_NODES];
    char *file[BRUME_TEXTURE_MAX_NODES]; /* the imagemaps' resolved paths, owned */
} json_texture;

/* The texture object j[key] (at names j), a float texture when is_float, into *out
 * (malloc'd: scene_json_texture_free). */
brume_status scene_json_texture(const cJSON *j, jloc at, const char *key, bool is_float, json_texture **out);
void scene_json_texture_free(json_texture *t);

#endif
