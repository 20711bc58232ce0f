/* scene_material_build.h - brume.h's brume_material checked and built into the surfaces'
 * material (scene_material_build.c). */
#ifndef BRUME_SCENE_SCENE_MATERIAL_BUILD_H
#define BRUME_SCENE_SCENE_MATERIAL_BUILD_H

#include "brume.h"

/* bm checked and built into *m (its textures' images read, its mixed materials allocated:
 * surface/material_hit.h's material_release frees them); depth counts the mixes above it, what
 * names it in messages ("material", "material.materials[1]"). On failure nothing is kept. */
struct material;
brume_status material_build(const char *fn, const char *what, const brume_material *bm, int depth,
                            struct material *m);

#endif
