/* device_scene.c - what of a scene the GPU renders, and the scene's copy for it
 * (gpu/device_scene.h). */
#include "gpu/device_scene.h"

#include <stddef.h>
#include <string.h>

#include "core/error.h"
#include "render/integrator.h"
#include "surface/surface_materials.h"
#include "surface/surfaces.h"

brume_status device_scene_check(const brume_scene *s, int kind)
{
    if (kind != INTEGRATOR_PATH && kind != INTEGRATOR_SINGLE)
        return err_set(BRUME_ERROR_UNSUPPORTED,
                       "%s: render.method '%s' runs on the CPU only: the GPU renders path and single (--device cpu)",
                       s->source, brume_method_name(s->settings.method));
    if (s->bounded)
        return err_set(BRUME_ERROR_UNSUPPORTED,
                       "%s: media bounded by surfaces (medium_inside/medium_outside) render on the CPU only "
                       "(--device cpu)", s->source);
    const char *textured = surfaces_textured(s->surf);
    if (textured)
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: textures render on the CPU only (surface '%s') (--device cpu)",
                       s->source, textured);
    {   /* pbrt-v4's BSDFs compile for the GPU but have not been checked there */
        const char *name = NULL;
        material_type t = MATERIAL_DIFFUSE;
        if (surfaces_first_bsdf(s->surf, &name, &t) >= 0)
            return err_set(BRUME_ERROR_UNSUPPORTED, "%s: %s: material '%s' renders on the CPU only (--device cpu)",
                           s->source, name, material_type_name(t));
    }
    return BRUME_OK;
}

/* Host objects already copied, so that objects shared on the host stay shared (and equal
 * as pointers) in the copy. */
typedef struct put_memo {
    const void *host[4 * SCENE_MAX_MEDIA * 8];
    size_t at[4 * SCENE_MAX_MEDIA * 8];
    int n;
} put_memo;

static size_t memo_find(const put_memo *pm, const void *p)
{
    for (int i = 0; i < pm->n; i++)
        if (pm->host[i] == p)
            return pm->at[i];
    return ARENA_NULL;
}

static size_t memo_add(put_memo *pm, const void *p, size_t at)
{
    if (pm->n < (int)(sizeof pm->host / sizeof pm->host[0])) {
        pm->host[pm->n] = p;
        pm->at[pm->n++] = at;
    }
    return at;
}

static size_t put_density(const density *d, dev_arena *a, put_memo *pm)
{
    if (!d)
        return ARENA_NULL;
    size_t at = memo_find(pm, d);
    return at != ARENA_NULL ? at : memo_add(pm, d, density_device_put(d, a));
}

static size_t put_phase(const phase *p, dev_arena *a, put_memo *pm)
{
    if (!p)
        return ARENA_NULL;
    size_t at = memo_find(pm, p);
    return at != ARENA_NULL ? at : memo_add(pm, p, phase_device_put(p, a));
}

size_t device_scene_put(const brume_scene *s, const void *state, dev_arena *a, size_t *state_at)
{
    put_memo pm = {.n = 0};
    size_t at = arena_put(a, s, sizeof *s);
    if (at == ARENA_NULL)
        return at;
    ARENA_PUT_MEMBER(a, at, brume_scene, lights, s->lights, (size_t)s->nlights * sizeof(light));
    for (int m = 0; m < s->nmedia; m++) {
        const medium *md = &s->media[m];
        size_t mat = at + offsetof(brume_scene, media) + (size_t)m * sizeof(medium);
        arena_ptr(a, mat + offsetof(medium, rho), put_density(md->rho, a, &pm));
        arena_ptr(a, mat + offsetof(medium, ph), put_phase(md->ph, a, &pm));
        for (int c = 0; c < 3; c++) {
            arena_ptr(a, mat + offsetof(medium, albedo) + (size_t)c * sizeof(density *), put_density(md->albedo[c], a, &pm));
            arena_ptr(a, mat + offsetof(medium, emission) + (size_t)c * sizeof(density *),
                      put_density(md->emission[c], a, &pm));
        }
        arena_ptr(a, mat + offsetof(medium, temperature), put_density(md->temperature, a, &pm));
        for (int c = 0; c < 3; c++)
            arena_ptr(a, mat + offsetof(medium, velocity) + (size_t)c * sizeof(density *),
                      put_density(md->velocity[c], a, &pm));
        arena_ptr(a, mat + offsetof(medium, moved), put_density(md->moved, a, &pm));
        ARENA_PUT_MEMBER(a, mat, medium, motion, md->motion, sizeof(motion));
    }
    arena_ptr(a, at + offsetof(brume_scene, surf), surfaces_device_put(s->surf, a));
    /* what rendering does not read on the device: the host's alone */
    for (int i = 0; i < METHOD_OPTIONS_COUNT; i++)
        arena_ptr(a, at + offsetof(brume_scene, options) + (size_t)i * sizeof(void *), ARENA_NULL);
    arena_ptr(a, at + offsetof(brume_scene, prepared), ARENA_NULL);
    arena_ptr(a, at + offsetof(brume_scene, settings) + offsetof(brume_render_settings, progress_fn), ARENA_NULL);
    arena_ptr(a, at + offsetof(brume_scene, settings) + offsetof(brume_render_settings, progress_user), ARENA_NULL);
    background_device_fix(&s->bg, a, at + offsetof(brume_scene, bg));
    *state_at = path_state_device_put(state, a);
    return at;
}
