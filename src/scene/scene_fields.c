/* scene_fields.c - the public builders of a medium's optional fields (brume.h): albedo,
 * temperature with blackbody emission, emission, velocity (medium/medium.h says how they
 * act). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_build.h"

static brume_status check_medium(const char *fn, const brume_scene *s, int index)
{
    brume_status st = build_check_scene(fn, s);
    if (st)
        return st;
    if (index < 0 || index >= s->nmedia)
        return err_set(BRUME_ERROR_RANGE, "%s: medium: %d is not a medium of the scene (it has %d)", fn, index,
                       s->nmedia);
    return BRUME_OK;
}

/* The fields' values must be usable: finite and >= 0 is checked by every loader; a field
 * that is all 0 is allowed (it does nothing). */
static void take(brume_scene *s, density **slot, brume_density *h)
{
    if (h->evolves) /* a field read per frame (a grid sequence): the world is not static */
        s->world_moves = true;
    density_release(*slot);
    *slot = h->d;
    free(h);
}

brume_status brume_scene_set_medium_albedo(brume_context *ctx, brume_scene *s, int index, brume_density *const *albedo)
{
    static const char fn[] = "brume_scene_set_medium_albedo";
    err_clear();
    if (!albedo)
        return ctx_report(ctx, build_null(fn, "albedo"));
    brume_status st = check_medium(fn, s, index);
    if (st)
        return ctx_report(ctx, st);
    for (int c = 0; c < 3; c++)
        if (!albedo[c])
            return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: albedo[%d]: NULL", fn, c));
    for (int c = 0; c < 3; c++)
        take(s, &s->media[index].albedo[c], albedo[c]);
    return ctx_report(ctx, BRUME_OK);
}

void brume_blackbody_default(brume_blackbody *bb)
{
    if (!bb)
        return;
    bb->scale = 1.0;
    bb->temperature_scale = 1.0;
    bb->temperature_offset = 0.0;
    bb->cutoff = 100.0;
    bb->model = BRUME_BLACKBODY_PBRT;
    bb->intensity = 1.0;
    for (int c = 0; c < 3; c++)
        bb->tint[c] = 1.0;
}

brume_status brume_scene_set_medium_temperature(brume_context *ctx, brume_scene *s, int index,
                                                brume_density *temperature, const brume_blackbody *bb)
{
    static const char fn[] = "brume_scene_set_medium_temperature";
    err_clear();
    if (!temperature)
        return ctx_report(ctx, build_null(fn, "temperature"));
    brume_status st = check_medium(fn, s, index);
    if (st)
        return ctx_report(ctx, st);
    brume_blackbody def;
    brume_blackbody_default(&def);
    if (!bb)
        bb = &def;
    if ((st = build_number(fn, "blackbody.scale", bb->scale, 1e-30, 1e30)) ||
        (st = build_number(fn, "blackbody.temperature_scale", bb->temperature_scale, 1e-30, 1e30)) ||
        (st = build_number(fn, "blackbody.temperature_offset", bb->temperature_offset, -1e30, 1e30)) ||
        (st = build_number(fn, "blackbody.cutoff", bb->cutoff, 0.0, 1e30)) ||
        (st = build_number(fn, "blackbody.intensity", bb->intensity, 0.0, 1.0)))
        return ctx_report(ctx, st);
    color tint;
    if ((st = build_color(fn, "blackbody.tint", bb->tint, 1e30, &tint)))
        return ctx_report(ctx, st);
    if (bb->model != BRUME_BLACKBODY_PBRT && bb->model != BRUME_BLACKBODY_BLENDER)
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: blackbody.model: %d is not a brume_blackbody_model",
                                       fn, bb->model));
    medium *m = &s->media[index];
    take(s, &m->temperature, temperature);
    m->bb_blender = bb->model == BRUME_BLACKBODY_BLENDER;
    m->bb_intensity = bb->intensity;
    m->bb_tint = tint;
    m->bb_scale = bb->scale;
    m->bb_tscale = bb->temperature_scale;
    m->bb_offset = bb->temperature_offset;
    m->bb_cutoff = bb->cutoff;
    return ctx_report(ctx, BRUME_OK);
}

brume_status brume_scene_set_medium_emission_field(brume_context *ctx, brume_scene *s, int index,
                                                   brume_density *const *fields, int n, const double rgb[3])
{
    static const char fn[] = "brume_scene_set_medium_emission_field";
    err_clear();
    if (!fields)
        return ctx_report(ctx, build_null(fn, "fields"));
    if (!rgb)
        return ctx_report(ctx, build_null(fn, "color"));
    brume_status st = check_medium(fn, s, index);
    if (st)
        return ctx_report(ctx, st);
    if (n != 1 && n != 3)
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: n: %d fields, need 1 or 3", fn, n));
    for (int c = 0; c < n; c++)
        if (!fields[c])
            return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: fields[%d]: NULL", fn, c));
    color col_e;
    if ((st = build_color(fn, "color", rgb, 1e30, &col_e)))
        return ctx_report(ctx, st);
    medium *m = &s->media[index];
    for (int c = 0; c < 3; c++) {
        density_release(m->emission[c]);
        m->emission[c] = NULL;
    }
    for (int c = 0; c < n; c++)
        take(s, &m->emission[c], fields[c]);
    m->emission_color = col_e;
    return ctx_report(ctx, BRUME_OK);
}

brume_status brume_scene_set_medium_velocity(brume_context *ctx, brume_scene *s, int index,
                                             brume_density *const *velocity, const double map[9])
{
    static const char fn[] = "brume_scene_set_medium_velocity";
    err_clear();
    if (!velocity)
        return ctx_report(ctx, build_null(fn, "velocity"));
    brume_status st = check_medium(fn, s, index);
    if (st)
        return ctx_report(ctx, st);
    for (int c = 0; c < 3; c++)
        if (!velocity[c])
            return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: velocity[%d]: NULL", fn, c));
    for (int c = 0; c < 3; c++) {
        density_info in;
        density_get_info(velocity[c]->d, &in);
        if (!isfinite(in.rho_min) || !isfinite(in.rho_max))
            return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: velocity[%d]: values not finite", fn, c));
    }
    const double id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    if (!map)
        map = id;
    for (int k = 0; k < 9; k++)
        if (!isfinite(map[k]) || fabs(map[k]) > 1e30)
            return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: map[%d]: %g is not a finite number", fn, k, map[k]));
    medium *m = &s->media[index];
    for (int c = 0; c < 3; c++)
        take(s, &m->velocity[c], velocity[c]);
    memcpy(m->velocity_map, map, sizeof m->velocity_map);
    return ctx_report(ctx, BRUME_OK);
}
