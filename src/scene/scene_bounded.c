/* scene_bounded.c - media bounded by surfaces (docs/surfaces.md, "How surfaces meet
 * media"): brume_scene_set_surface_media, its resolution at commit, and the camera's
 * starting membership. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_build.h"

/* A path's bounded media are the bits of a uint32_t (surface_media_cross). */
_Static_assert(SCENE_MAX_MEDIA <= 32, "bounded media are a 32-bit set");

/* What brume_scene_set_surface_media was given, until commit resolves the names. */
typedef struct scene_bound {
    int surface;
    char inside[64], outside[64];
    bool interface;
} scene_bound;

brume_status brume_scene_set_surface_media(brume_context *ctx, brume_scene *s, int surface, const char *inside,
                                           const char *outside, bool interface)
{
    static const char fn[] = "brume_scene_set_surface_media";
    err_clear();
    brume_status st = build_check_scene(fn, s);
    if (st)
        return ctx_report(ctx, st);
    int count = brume_scene_surface_count(s);
    if (surface < 0 || surface >= count)
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: surface: %d is not a surface of the scene (it has %d)",
                                       fn, surface, count));
    const char *name[2] = {inside ? inside : "", outside ? outside : ""};
    for (int k = 0; k < 2; k++)
        if (strlen(name[k]) >= sizeof s->bound->inside)
            return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: %s: longer than %zu bytes", fn,
                                           k ? "outside" : "inside", sizeof s->bound->inside - 1));
    if (interface && !name[0][0] && !name[1][0])
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT,
                                       "%s: an interface bounds a medium: name the inside or the outside one", fn));
    scene_bound *b = NULL;
    for (int i = 0; i < s->nbound && !b; i++)
        if (s->bound[i].surface == surface)
            b = &s->bound[i];
    if (!b) {
        scene_bound *nb = realloc(s->bound, sizeof *nb * (size_t)(s->nbound + 1));
        if (!nb)
            return ctx_report(ctx, err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn));
        s->bound = nb;
        b = &s->bound[s->nbound++];
    }
    b->surface = surface;
    snprintf(b->inside, sizeof b->inside, "%s", name[0]);
    snprintf(b->outside, sizeof b->outside, "%s", name[1]);
    b->interface = interface;
    return ctx_report(ctx, BRUME_OK);
}

/* The index of the medium named `name` ("" : -1 in *m), or an error naming the key. */
static brume_status find_medium(const brume_scene *s, const char *surface, const char *key, const char *name, int *m)
{
    *m = -1;
    if (!name[0])
        return BRUME_OK;
    for (int i = 0; i < s->nmedia; i++)
        if (strcmp(s->media[i].name, name) == 0) {
            *m = i;
            return BRUME_OK;
        }
    return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: surface '%s': %s: no medium named \"%s\"", s->source, surface,
                   key, name);
}

brume_status scene_bounded_resolve(brume_scene *s)
{
    s->bounded = 0;
    s->has_interfaces = false;
    s->camera_members = 0;
    for (int i = 0; i < s->nbound; i++) {
        const scene_bound *b = &s->bound[i];
        const char *name = surfaces_name(s->surf, b->surface);
        int in, out;
        brume_status st = find_medium(s, name, "medium_inside", b->inside, &in);
        if (st == BRUME_OK)
            st = find_medium(s, name, "medium_outside", b->outside, &out);
        if (st != BRUME_OK)
            return st;
        if (in < 0 && out < 0)
            continue;
        if (!surfaces_closed(s->surf, b->surface))
            return err_set(BRUME_ERROR_INVALID_ARGUMENT,
                           "%s: surface '%s': medium_inside/medium_outside: the shape is not closed (a mesh bounding "
                           "a medium needs every edge shared by two triangles wound alike)", s->source, name);
        surfaces_set_media(s->surf, b->surface, (surface_media){(signed char)in, (signed char)out, b->interface});
        s->bounded |= (in >= 0 ? 1u << in : 0u) | (out >= 0 ? 1u << out : 0u);
        s->has_interfaces = true;
    }
    for (int i = 0; i < s->nmedia && s->camera_medium[0]; i++)
        if ((s->bounded >> i & 1u) && strcmp(s->media[i].name, s->camera_medium) == 0)
            s->camera_members = 1u << i;
    return BRUME_OK;
}
