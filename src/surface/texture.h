/* texture.h - values that vary over a surface with its texture coordinates (u, v): the
 * trees of brume.h's brume_texture (constant, imagemap, scale, mix, checkerboard), built
 * once with their images decoded, then evaluated from any number of threads (CPU only: the GPU
 * refuses textured surfaces, gpu/device_scene.c). */
#ifndef BRUME_SURFACE_TEXTURE_H
#define BRUME_SURFACE_TEXTURE_H

#include "brume.h"
#include "core/color.h"

typedef struct texture texture;

/* The tree t checked and built; images[i] is node i's image when it is an imagemap (read by
 * the caller, who keeps it: the scene layer reads files), NULL otherwise. fn and what name
 * the caller and the field in messages ("brume_scene_add_mesh: material.albedo_texture").
 * NULL after err_set. */
texture *texture_build(const brume_texture *t, brume_image *const *images, const char *fn, const char *what);
void texture_free(texture *t);
/* The value at texture coordinates (u, v). */
color texture_eval(const texture *t, double u, double v);
/* Bytes the tree holds (its images). */
size_t texture_bytes(const texture *t);

#endif
