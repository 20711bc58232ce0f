/* material_hit.h - a material's textures and mixes: what it owns, and the material they make
 * at a hit (CPU only: the GPU refuses textured and mixed materials). */
#ifndef BRUME_SURFACE_MATERIAL_HIT_H
#define BRUME_SURFACE_MATERIAL_HIT_H

#include <stdbool.h>
#include <stddef.h>

#include "core/vec.h"
#include "surface/material_params.h"

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
 * *out (its bump_tex kept for material_bump). The emission stays m's: a mix emits as the
 * shape does. */
void material_at(const material *m, vec3 p, vec3 wo, double u, double v, material *out);
/* The shading normal of pbrt-v4's BumpMap: the displacement texture disp at (u, v) and at
 * (u + 0.0005, v), (u, v + 0.0005) (pbrt-v4's offsets without ray differentials) by finite
 * differences, dp/du' = dp/du + (d(u + du, v) - d) / du ng + d dn/du (and for v), the normal
 * normalize(dp/du' x dp/dv') turned to ng's side. dp and dn: the surface's derivatives. */
struct texture;
vec3 material_bump(const struct texture *disp, double u, double v, const vec3 dp[2], const vec3 dn[2], vec3 ng);

#endif
