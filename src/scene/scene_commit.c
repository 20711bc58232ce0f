/* scene_commit.c - brume_scene_commit, the last step of building a scene: the frame's
 * placements (scene_frame.c), Stam's media at commit (stam_media.c), the moved majorants of
 * velocity-blurred media; and what a committed scene may still change (the camera's time).
 * The builders and readers below it never call it: the scene is built in one direction. */
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/budget.h"
#include "core/context.h"
#include "core/error.h"
#include "method/method.h"
#include "scene/stam_media.h"

static bool world_moves(const brume_scene *s);

/* How far the points of a world box move within the shutter, at most: the velocity's bound
 * there times the shutter's reach (the same product as medium_init's velocity_max times
 * the reach, with the box's own component bounds). */
typedef struct moved_reach {
    const medium *md;
    double reach; /* seconds: max |t - t_f| */
} moved_reach;

static double moved_radius(const void *user, box3 world_box)
{
    const moved_reach *mr = (const moved_reach *)user;
    double u2 = 0.0;
    for (int c = 0; c < 3; c++) {
        double b = density_abs_bound_in_box(mr->md->velocity[c], world_box);
        u2 += b * b;
    }
    return sqrt(u2) * medium_velocity_map_norm(mr->md) * mr->reach;
}

/* A medium blurred by its velocity: the majorants its lookups need over the shutter, rho's
 * moved by up to |v| times the shutter's reach from the frame time, |v| bounded per cell
 * (medium.h, density_new_moved_majorant). */
static brume_status commit_velocity(brume_scene *s, int m)
{
    medium *md = &s->media[m];
    density_release(md->moved);
    md->moved = NULL;
    const double reach = fmax(fabs(s->cam.shutter_open), fabs(s->cam.shutter_close));
    const double radius = md->velocity_max * reach;
    if (!md->velocity[0] || !(radius > 0.0))
        return BRUME_OK;
    const moved_reach mr = {md, reach};
    md->moved = density_new_moved_majorant(md->rho, radius, moved_radius, &mr);
    return md->moved ? BRUME_OK : err_prefix("%s: media[%d].velocity", s->source, m);
}

/* The camera's rays start within aperture_radius of its position, every key's included:
 * each coordinate of that stays within SURFACES_COORD_MAX, what ray tracing accepts. */
static brume_status check_camera_reach(const brume_scene *s)
{
    const camera *c = &s->cam;
    for (int i = -1; i < c->nkeys; i++) {
        vec3 p = i < 0 ? c->position : c->keys[i].position;
        double ap = i < 0 ? c->aperture_radius : c->keys[i].aperture_radius;
        double reach = fmax(fabs(p.x), fmax(fabs(p.y), fabs(p.z))) + ap;
        if (!(reach <= SURFACES_COORD_MAX)) {
            char where[48] = "camera";
            if (i >= 0)
                snprintf(where, sizeof where, "camera.keyframes[%d]", i);
            return err_set(BRUME_ERROR_RANGE,
                           "%s: %s: position (%.17g, %.17g, %.17g) and aperture_radius (.pbrt: lensradius) %.17g "
                           "put ray origins %.3g from the world's origin, beyond the %.17g ray tracing accepts "
                           "(docs/scene-format.md#limits)",
                           s->source, where, p.x, p.y, p.z, ap, reach, SURFACES_COORD_MAX);
        }
    }
    return BRUME_OK;
}

brume_status brume_scene_commit(brume_context *ctx, brume_scene *s)
{
    err_clear();
    if (!s)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_scene_commit: scene: NULL"));
    if (s->committed)
        return ctx_report(ctx, BRUME_OK);
    brume_status st = scene_check_settings(s->source, &s->settings);
    if (st != BRUME_OK)
        return ctx_report(ctx, st);
    if ((st = scene_frame_resolve(s)) != BRUME_OK)
        return ctx_report(ctx, st);
    camera *c = &s->cam;
    vec3 view = v3_sub(c->look_at, c->position);
    if (!(v3_length(view) > 0.0))
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: camera.look_at: equals camera.position", s->source));
    c->time = s->time;
    camera_init(c, s->settings.width, s->settings.height);
    if ((st = check_camera_reach(s)) != BRUME_OK)
        return ctx_report(ctx, st);
    s->world_moves = world_moves(s); /* before voxelization turns moving blobs into grids */
    /* what commit generates counts against the scene's memory budget, after what reading took */
    budget_resume(s->max_memory, s->memory_used);
    budget_set_work_limit(s->max_work);
    budget_hold(s->memory_held);
    st = stam_commit_media(s);
    s->has_emission = false;
    for (int m = 0; m < s->nmedia && st == BRUME_OK; m++) { /* the moved majorants count too */
        medium_init(&s->media[m]);
        if ((st = medium_check_range(&s->media[m], s->source, m)) == BRUME_OK)
            st = commit_velocity(s, m);
        if (medium_emits(&s->media[m]))
            s->has_emission = true;
    }
    if (st == BRUME_OK)
        st = scene_camera_medium_check(s);
    s->memory_used = budget_used();
    budget_hold(0);
    budget_end();
    if (st != BRUME_OK)
        return ctx_report(ctx, st);
    s->memory_held = 0; /* the other scene's bytes counted until now: rendering counts its own */
    for (int i = 0; i < s->nlights; i++)
        light_init(&s->lights[i]);
    if (!background_init(&s->bg))
        return ctx_report(ctx, err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: background: out of memory", s->source));
    if (s->surf)
        surfaces_set_shutter(s->surf, s->time + c->shutter_open, s->time + c->shutter_close);
    if ((st = scene_bounded_resolve(s)) != BRUME_OK)
        return ctx_report(ctx, st);
    if (s->surf && surfaces_commit(s->surf) != BRUME_OK)
        return ctx_report(ctx, err_prefix("%s: surfaces", s->source));
    s->flight_control = scene_flight_control(s);
    s->has_indirect_sources = s->has_emission || !background_is_black(&s->bg) || surfaces_has_emitters(s->surf);
    for (int i = 0; i < s->nlights; i++)
        s->has_indirect_sources |= light_is_area(&s->lights[i]);
    s->committed = true;
    return ctx_report(ctx, BRUME_OK);
}

static bool world_moves(const brume_scene *s)
{
    return s->world_moves || surfaces_moving(s->surf) || stam_media_move(s);
}

bool brume_scene_world_is_static(const brume_scene *s) { return s && !world_moves(s); }

brume_status brume_scene_set_camera_time(brume_context *ctx, brume_scene *s, double time)
{
    err_clear();
    if (!s)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_scene_set_camera_time: scene: NULL"));
    if (!s->committed)
        return ctx_report(ctx, err_set(BRUME_ERROR_STATE, "%s: camera time set before commit", s->source));
    if (world_moves(s))
        return ctx_report(ctx, err_set(BRUME_ERROR_STATE,
                                       "%s: more than the camera moves: load each frame (brume_scene_load with its time)",
                                       s->source));
    if (!isfinite(time))
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: frame time %g is not finite", s->source, time));
    s->time = time;
    s->cam.time = time;
    camera_init(&s->cam, s->settings.width, s->settings.height);
    if (!(v3_length(v3_sub(s->cam.look_at, s->cam.position)) > 0.0))
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: camera.look_at: equals camera.position at time %g",
                                       s->source, time));
    return ctx_report(ctx, BRUME_OK);
}
