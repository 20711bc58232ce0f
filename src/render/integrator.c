/* integrator.c - the estimators by kind (integrator_kind): what each prepares once per
 * scene, releases, and estimates along a camera ray. The estimators themselves live in
 * path.c (path and single), blasi_setup.c (blasi_view.c for the gather) and stam.c. */
#include "render/integrator.h"

#include <stdlib.h>

#include "core/error.h"
#include "render/blasi.h"
#include "render/path_impl.h"
#include "render/stam.h"
#include "surface/surface_materials.h"

brume_status integrator_prepare(integrator_kind kind, const brume_scene *s, void **state)
{
    *state = NULL;
    /* albedo, temperature and emission grids are rendered by path and single only */
    for (int m = 0; (kind == INTEGRATOR_BLASI || kind == INTEGRATOR_STAM) && m < s->nmedia; m++)
        if (medium_has_fields(&s->media[m]))
            return err_set(BRUME_ERROR_UNSUPPORTED,
                           "%s: media[%d]: albedo, temperature and emission grids need the path or single method",
                           s->source, m);
    if ((kind == INTEGRATOR_BLASI || kind == INTEGRATOR_STAM) && s->bounded)
        for (int m = 0; m < s->nmedia; m++)
            if (s->bounded >> m & 1u)
                return err_set(BRUME_ERROR_UNSUPPORTED,
                               "%s: media[%d] '%s': a medium bounded by a surface (medium_inside/medium_outside) "
                               "renders with path and single only", s->source, m, s->media[m].name);
    /* blasi and stam gather direct light at surfaces through brume's diffuse material only */
    const char *name = NULL;
    material_type t = MATERIAL_DIFFUSE;
    if ((kind == INTEGRATOR_BLASI || kind == INTEGRATOR_STAM) && surfaces_first_bsdf(s->surf, &name, &t) >= 0)
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: %s: material '%s' needs the path or single method", s->source,
                       name, material_type_name(t));
    switch (kind) {
    case INTEGRATOR_PATH:
    case INTEGRATOR_SINGLE: {
        path_state *st = NULL;
        brume_status rc = path_prepare(s, kind == INTEGRATOR_PATH, &st);
        *state = st;
        return rc;
    }
    case INTEGRATOR_BLASI: {
        blasi_state *st = NULL;
        brume_status rc = blasi_prepare(s, &st);
        *state = st;
        return rc;
    }
    case INTEGRATOR_STAM: return stam_prepare(s, state);
    }
    return BRUME_OK;
}

void integrator_finish(integrator_kind kind, void *state)
{
    switch (kind) {
    case INTEGRATOR_PATH:
    case INTEGRATOR_SINGLE: free(state); break;
    case INTEGRATOR_BLASI: blasi_finish((blasi_state *)state); break;
    case INTEGRATOR_STAM: stam_finish(state); break;
    }
}

color integrator_Li(integrator_kind kind, const brume_scene *s, const void *state, ray r, rng *g,
                    bool *hit_surface, color *Tr)
{
    color L = col(0.0);
    switch (kind) {
    case INTEGRATOR_PATH: return path_Li_alpha(s, state, r, s->settings.max_depth, g, hit_surface, Tr);
    case INTEGRATOR_SINGLE: return path_Li_alpha(s, state, r, 1, g, hit_surface, Tr);
#if !defined(__CUDA_ARCH__) /* CPU-only methods: the GPU renders path and single (gpu/device_scene.c) */
    case INTEGRATOR_BLASI:
        L = blasi_Li(s, (const blasi_state *)state, r, g, hit_surface);
        if (Tr)
            *Tr = blasi_transmittance(s, (const blasi_state *)state, r); /* its voxels, exact: no tracking */
        return L;
    case INTEGRATOR_STAM:
        L = stam_Li(state, r, g, hit_surface);
        if (Tr)
            *Tr = stam_transmittance(state, r.o, r.d, INFINITY);
        return L;
#else
    default: break;
#endif
    }
    return L;
}
