/* surface_materials.h - what the estimators and the GPU ask of a scene's materials. */
#ifndef BRUME_SURFACE_SURFACE_MATERIALS_H
#define BRUME_SURFACE_SURFACE_MATERIALS_H

#include "surface/surfaces.h"

/* The first object (insertion order) whose material is not brume's diffuse one, or -1 (also
 * for s NULL); its name in *name, its type in *type. */
int surfaces_first_bsdf(const surfaces *s, const char **name, material_type *type);

#endif
