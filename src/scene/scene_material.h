/* scene_material.h - a scene file's material object (docs/scene-format.md, "surfaces"). */
#ifndef BRUME_SCENE_SCENE_MATERIAL_H
#define BRUME_SCENE_SCENE_MATERIAL_H

#include <cjson/cJSON.h>

#include "brume.h"
#include "io/json.h"

/* What a material object's textures and mixed materials are kept in while its brume_material
 * is used (brume_material points into it). */
#define SCENE_MATERIAL_MAX_TEXTURES 32
#define SCENE_MATERIAL_MAX_PARTS 32
struct json_texture;
typedef struct scene_material_store {
    struct json_texture *tex[SCENE_MATERIAL_MAX_TEXTURES];
    int ntex;
    brume_material mat[SCENE_MATERIAL_MAX_PARTS];
    int nmat;
} scene_material_store;

/* A surface's "material" object j (NULL: the default) into *m (scene_material.c), its texture
 * objects and mixed materials into *sm (the caller frees it, on failure too:
 * scene_material_store_free). */
brume_status scene_parse_material(const cJSON *j, jloc at, brume_material *m, scene_material_store *sm);
void scene_material_store_free(scene_material_store *sm);

#endif
