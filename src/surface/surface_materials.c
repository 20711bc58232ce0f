/* surface_materials.c - a scene's materials, as the estimators and the GPU ask for them. */
#include "surface/surface_materials.h"

#include "surface/surfaces_impl.h"

int surfaces_first_bsdf(const surfaces *s, const char **name, material_type *type)
{
    for (int i = 0; s && i < s->n; i++)
        if (s->obj[i].mat.type != MATERIAL_DIFFUSE) {
            *name = s->obj[i].name;
            *type = s->obj[i].mat.type;
            return i;
        }
    return -1;
}
