/* surface_materials.h - what the estimators and the GPU ask of a scene's materials, and a
 * material's textures and mixes resolved at a hit (CPU only). */
#ifndef BRUME_SURFACE_SURFACE_MATERIALS_H
#define BRUME_SURFACE_SURFACE_MATERIALS_H

#include "surface/surfaces.h"

/* The first object (insertion order) whose material is not brume's diffuse one, or -1 (also
 * for s NULL); its name in *name, its type in *type. */
int surfaces_first_bsdf(const surfaces *s, const char **name, material_type *type);

/* Whether m, or a material it mixes, has a texture. */
bool material_textured(const material *m);
/* Whether m must be resolved per hit (material_at): a texture or a mix. */
bool material_varies(const material *m);
/* Bytes m's textures hold (the budget's share), its mixed materials' included. */
size_t material_bytes(const material *m);
/* Frees m's textures and mixed materials (m itself is the caller's). */
void material_release(material *m);
/* The material at a hit: a mix resolved as pbrt-v4's MixMaterial::ChooseMaterial does, by a
 * hash of the point p and the direction wo against the amount at (u, v) (so the image is the
 * amount-weighted mix of the two), then the chosen one's textures evaluated at (u, v) into
 * *out. The emission stays m's: a mix emits as the shape does. */
void material_at(const material *m, vec3 p, vec3 wo, double u, double v, material *out);

#endif
