/* scene_frame.c - auto-framing: brume_scene_frame_camera records a request, and commit moves
 * the camera so that the media it names are whole in view (docs/scene-format.md, camera
 * "frame"). Resolved at commit, so that the image's aspect is the final one (the command
 * line's --width/--height come after the scene file). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/context.h"
#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_build.h"

brume_status brume_scene_frame_camera(brume_context *ctx, brume_scene *scene, const char *media, double margin)
{
    static const char fn[] = "brume_scene_frame_camera";
    err_clear();
    brume_status st = build_check_scene(fn, scene);
    if (st == BRUME_OK)
        st = build_number(fn, "margin", margin, 0.0, 0.9);
    if (st == BRUME_OK && media && strlen(media) >= sizeof scene->frame.media)
        st = err_set(BRUME_ERROR_RANGE, "%s: media: longer than %zu bytes", fn, sizeof scene->frame.media - 1);
    if (st != BRUME_OK)
        return ctx_report(ctx, st);
    scene->frame.on = true;
    scene->frame.box = false;
    snprintf(scene->frame.media, sizeof scene->frame.media, "%s", media && media[0] ? media : "media");
    scene->frame.margin = margin;
    return ctx_report(ctx, BRUME_OK);
}

brume_status brume_scene_frame_camera_box(brume_context *ctx, brume_scene *scene, const double box[6], double margin)
{
    static const char fn[] = "brume_scene_frame_camera_box";
    err_clear();
    brume_status st = build_check_scene(fn, scene);
    if (st == BRUME_OK && !box)
        st = err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: box: NULL", fn);
    if (st == BRUME_OK)
        st = build_number(fn, "margin", margin, 0.0, 0.9);
    for (int a = 0; st == BRUME_OK && a < 3; a++)
        if (!isfinite(box[a]) || !isfinite(box[a + 3]) || !(box[a] <= box[a + 3]))
            st = err_set(BRUME_ERROR_RANGE, "%s: box: need finite lo <= hi on axis %d, got [%.17g, %.17g]", fn, a, box[a],
                         box[a + 3]);
    if (st != BRUME_OK)
        return ctx_report(ctx, st);
    scene->frame.on = true;
    scene->frame.box = true;
    scene->frame.bounds = (box3){v3(box[0], box[1], box[2]), v3(box[3], box[4], box[5])};
    snprintf(scene->frame.media, sizeof scene->frame.media, "media");
    scene->frame.margin = margin;
    return ctx_report(ctx, BRUME_OK);
}

box3 scene_density_box(const density *d)
{
    box3 a = density_bounds(d), r = density_reach_bounds(d);
    return (box3){v3_max(a.lo, r.lo), v3_min(a.hi, r.hi)};
}

/* Camera placement for a box: looking along the camera's own view direction at the box's
 * centre c, from the distance D at which every corner projects inside the frame shrunk by
 * the margin. With the corner's offsets x (right), y (up) and z (towards the eye) from c, its
 * depth is D - z, and it is inside when |x| <= t_h (D - z) and |y| <= t_v (D - z): D is the
 * largest of |x| / t_h + z and |y| / t_v + z over the eight corners. */
brume_status scene_frame_resolve(brume_scene *s)
{
    if (!s->frame.on)
        return BRUME_OK;
    camera *c = &s->cam;
    if (c->nkeys > 0)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: camera.frame: not with camera keyframes (frame a pose, then key it)",
                       s->source);
    bool all = strcmp(s->frame.media, "media") == 0;
    box3 b = box3_empty();
    int found = 0;
    if (s->frame.box) {
        b = s->frame.bounds;
        found = 1;
    }
    for (int i = 0; i < s->nmedia && !s->frame.box; i++) {
        if (!all && strcmp(s->media[i].name, s->frame.media) != 0)
            continue;
        found++;
        box3 m = scene_density_box(s->media[i].rho); /* at rest: keyframed motion is not followed */
        b.lo = v3_min(b.lo, m.lo);
        b.hi = v3_max(b.hi, m.hi);
    }
    if (!found)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: camera.frame: %s", s->source,
                       all ? "the scene has no media to frame" : "no medium of that name");
    if (!(b.lo.x <= b.hi.x && b.lo.y <= b.hi.y && b.lo.z <= b.hi.z))
        return err_set(BRUME_ERROR_RANGE, "%s: camera.frame: the media framed are empty (every density is 0)", s->source);
    vec3 centre = v3_scale(v3_add(b.lo, b.hi), 0.5);
    vec3 w = v3_normalize(v3_sub(c->position, c->look_at)); /* towards the eye */
    vec3 right = v3_cross(c->up, w);
    if (!(v3_length(right) > 1e-9))
        return err_set(BRUME_ERROR_RANGE, "%s: camera.frame: the view direction is parallel to camera.up", s->source);
    right = v3_normalize(right);
    vec3 up = v3_cross(w, right);
    double tv = tan(0.5 * c->fov * PI / 180.0) * (1.0 - s->frame.margin);
    double th = tv * (double)s->settings.width / (double)s->settings.height;
    double D = 0.0;
    for (int k = 0; k < 8; k++) {
        vec3 p = v3(k & 1 ? b.hi.x : b.lo.x, k & 2 ? b.hi.y : b.lo.y, k & 4 ? b.hi.z : b.lo.z);
        vec3 d = v3_sub(p, centre);
        double x = fabs(v3_dot(d, right)), y = fabs(v3_dot(d, up)), z = v3_dot(d, w);
        D = fmax(D, fmax(x / th + z, y / tv + z));
    }
    double focus_ratio = c->focus_distance / v3_length(v3_sub(c->look_at, c->position));
    c->look_at = centre;
    c->position = v3_add(centre, v3_scale(w, D));
    c->focus_distance = focus_ratio * D; /* the focus keeps its place relative to the look-at point */
    return BRUME_OK;
}

brume_status brume_scene_set_camera_medium(brume_context *ctx, brume_scene *scene, const char *name)
{
    static const char fn[] = "brume_scene_set_camera_medium";
    err_clear();
    brume_status st = build_check_scene(fn, scene);
    if (st == BRUME_OK && name && strlen(name) >= sizeof scene->camera_medium)
        st = err_set(BRUME_ERROR_RANGE, "%s: name: longer than %zu bytes", fn, sizeof scene->camera_medium - 1);
    if (st != BRUME_OK)
        return ctx_report(ctx, st);
    snprintf(scene->camera_medium, sizeof scene->camera_medium, "%s", name ? name : "");
    return ctx_report(ctx, BRUME_OK);
}

/* Whether the box holds the ball of radius r around p (the lens's points around it). */
static bool box_holds(box3 b, vec3 p, double r)
{
    return p.x - r >= b.lo.x && p.x + r <= b.hi.x && p.y - r >= b.lo.y && p.y + r <= b.hi.y && p.z - r >= b.lo.z &&
           p.z + r <= b.hi.z;
}

brume_status scene_camera_medium_check(const brume_scene *s)
{
    if (!s->camera_medium[0])
        return BRUME_OK;
    const medium *md = NULL;
    for (int i = 0; i < s->nmedia && !md; i++)
        if (strcmp(s->media[i].name, s->camera_medium) == 0)
            md = &s->media[i];
    if (!md)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: camera.medium: no medium named \"%s\"", s->source,
                       s->camera_medium);
    if (md->motion)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: camera.medium: \"%s\" moves (keyframes); the camera's "
                       "medium must be at rest", s->source, s->camera_medium);
    const camera *c = &s->cam;
    box3 b = density_bounds(md->rho);
    for (int i = -1; i < c->nkeys; i++) {
        vec3 p = i < 0 ? c->position : c->keys[i].position;
        double r = i < 0 ? c->aperture_radius : c->keys[i].aperture_radius;
        if (!box_holds(b, p, r))
            return err_set(BRUME_ERROR_RANGE, "%s: camera.medium: the camera%s at (%g, %g, %g) (lens radius %g) is not "
                           "inside \"%s\", whose field spans [%g, %g] x [%g, %g] x [%g, %g]", s->source,
                           i < 0 ? "" : " key", p.x, p.y, p.z, r, s->camera_medium, b.lo.x, b.hi.x, b.lo.y, b.hi.y,
                           b.lo.z, b.hi.z);
    }
    return BRUME_OK;
}
