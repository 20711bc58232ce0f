/* scene_build.c - the public scene builders (brume.h, "building a scene in memory"):
 * camera, lights, background, media, motion. Every description of a scene reaches a
 * brume_scene through these functions; the scene file reader is one client of them.
 * Each checks its arguments and on failure changes nothing and names itself and the
 * argument. Densities and phase functions are in scene_media.c, surfaces in
 * scene_shapes.c. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/error.h"
#include "image/image.h"
#include "scene/scene.h"
#include "scene/scene_build.h"

brume_status build_check_scene(const char *fn, const brume_scene *s)
{
    if (!s)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: scene: NULL", fn);
    if (s->committed)
        return err_set(BRUME_ERROR_STATE, "%s: %s: the scene is committed; build before brume_scene_commit", fn,
                       s->source);
    return BRUME_OK;
}

brume_status build_null(const char *fn, const char *arg)
{
    return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s: NULL", fn, arg);
}

brume_status build_need(const char *fn, int n, ...)
{
    va_list ap;
    va_start(ap, n);
    brume_status st = BRUME_OK;
    for (int i = 0; i < n && st == BRUME_OK; i++) {
        const char *name = va_arg(ap, const char *);
        const void *p = va_arg(ap, const void *);
        if (!p)
            st = build_null(fn, name);
    }
    va_end(ap);
    return st;
}

brume_status build_number(const char *fn, const char *arg, double v, double lo, double hi)
{
    if (!(v >= lo && v <= hi))
        return err_set(BRUME_ERROR_RANGE, "%s: %s: %.17g outside [%.17g, %.17g]", fn, arg, v, lo, hi);
    return BRUME_OK;
}

brume_status build_point(const char *fn, const char *arg, const double *p, vec3 *out)
{
    if (!p)
        return build_null(fn, arg);
    if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
        return err_set(BRUME_ERROR_RANGE, "%s: %s: (%g, %g, %g) is not finite", fn, arg, p[0], p[1], p[2]);
    *out = v3(p[0], p[1], p[2]);
    return BRUME_OK;
}

brume_status build_direction(const char *fn, const char *arg, const double *p, vec3 *out)
{
    brume_status st = build_point(fn, arg, p, out);
    if (st)
        return st;
    if (!(v3_length(*out) > 0.0))
        return err_set(BRUME_ERROR_RANGE, "%s: %s: must not be the zero vector", fn, arg);
    *out = v3_normalize(*out);
    return BRUME_OK;
}

brume_status build_color(const char *fn, const char *arg, const double *c, double hi, color *out)
{
    if (!c)
        return build_null(fn, arg);
    for (int i = 0; i < 3; i++)
        if (!(c[i] >= 0.0 && c[i] <= hi))
            return err_set(BRUME_ERROR_RANGE, "%s: %s[%d]: %.17g outside [0, %.17g]", fn, arg, i, c[i], hi);
    *out = col_rgb(c[0], c[1], c[2]);
    return BRUME_OK;
}

brume_status build_box(const char *fn, const char *arg, const double *b, box3 *out)
{
    if (!b)
        return build_null(fn, arg);
    for (int i = 0; i < 6; i++)
        if (!isfinite(b[i]))
            return err_set(BRUME_ERROR_RANGE, "%s: %s[%d]: %g is not finite", fn, arg, i, b[i]);
    if (!(b[0] < b[3] && b[1] < b[4] && b[2] < b[5]))
        return err_set(BRUME_ERROR_RANGE, "%s: %s: need min < max on every axis", fn, arg);
    *out = (box3){v3(b[0], b[1], b[2]), v3(b[3], b[4], b[5])};
    return BRUME_OK;
}

brume_status build_motion(const char *fn, const brume_transform_key *keys, int n, motion *out)
{
    if (!keys)
        return build_null(fn, "keys");
    if (n < 1 || n > MOTION_MAX_KEYS)
        return err_set(BRUME_ERROR_RANGE, "%s: n: %d keys, need 1 to %d", fn, n, MOTION_MAX_KEYS);
    out->n = 0;
    for (int i = 0; i < n; i++) {
        const brume_transform_key *k = &keys[i];
        char arg[64];
        if (!isfinite(k->time) || (i > 0 && !(k->time > keys[i - 1].time)))
            return err_set(BRUME_ERROR_RANGE, "%s: keys[%d].time: %g must be finite and greater than the previous key's",
                           fn, i, k->time);
        vec3 t, axis, sc;
        brume_status st;
        snprintf(arg, sizeof arg, "keys[%d].translate", i);
        if ((st = build_point(fn, arg, k->translate, &t))) return st;
        snprintf(arg, sizeof arg, "keys[%d].axis", i);
        if ((st = build_direction(fn, arg, k->axis, &axis))) return st;
        snprintf(arg, sizeof arg, "keys[%d].angle", i);
        if ((st = build_number(fn, arg, k->angle, -1e9, 1e9))) return st;
        snprintf(arg, sizeof arg, "keys[%d].scale", i);
        if ((st = build_point(fn, arg, k->scale, &sc))) return st;
        if (!(sc.x > 0.0 && sc.y > 0.0 && sc.z > 0.0))
            return err_set(BRUME_ERROR_RANGE, "%s: keys[%d].scale: every factor must be > 0", fn, i);
        motion_key *mk = &out->key[out->n++];
        mk->time = k->time;
        mk->translate = t;
        motion_quat_axis_angle(axis, k->angle, mk->q);
        mk->scale = sc;
    }
    return BRUME_OK;
}

/* ---- the scene ---------------------------------------------------------------------------- */

brume_status brume_scene_new(brume_context *ctx, const char *name, brume_scene **out)
{
    err_clear();
    if (!out)
        return ctx_report(ctx, build_null("brume_scene_new", "out"));
    *out = scene_new(name ? name : "<scene>");
    return ctx_report(ctx, *out ? BRUME_OK : err_status());
}

brume_status brume_scene_set_time(brume_context *ctx, brume_scene *s, double time)
{
    err_clear();
    brume_status st = build_check_scene("brume_scene_set_time", s);
    if (!st && !isfinite(time))
        st = err_set(BRUME_ERROR_RANGE, "brume_scene_set_time: time: %g is not finite", time);
    if (!st)
        s->time = time;
    return ctx_report(ctx, st);
}

brume_status brume_scene_set_animated(brume_context *ctx, brume_scene *s)
{
    err_clear();
    brume_status st = build_check_scene("brume_scene_set_animated", s);
    if (!st)
        s->world_moves = true;
    return ctx_report(ctx, st);
}

/* ---- camera ------------------------------------------------------------------------------- */

void brume_camera_default(brume_camera *c)
{
    if (!c)
        return;
    *c = (brume_camera){.position = {0, 0, 5}, .look_at = {0, 0, 0}, .up = {0, 1, 0}, .fov = 40.0};
}

brume_status brume_scene_set_camera(brume_context *ctx, brume_scene *s, const brume_camera *c)
{
    static const char fn[] = "brume_scene_set_camera";
    err_clear();
    brume_status st = build_check_scene(fn, s);
    if (st)
        return ctx_report(ctx, st);
    if (!c)
        return ctx_report(ctx, build_null(fn, "camera"));
    camera n = s->cam;
    if ((st = build_point(fn, "position", c->position, &n.position)) ||
        (st = build_point(fn, "look_at", c->look_at, &n.look_at)) || (st = build_point(fn, "up", c->up, &n.up)) ||
        (st = build_number(fn, "fov", c->fov, 1e-3, 179.0)) ||
        (st = build_number(fn, "aperture_radius", c->aperture_radius, 0.0, 1e30)))
        return ctx_report(ctx, st);
    if (!(v3_length(n.up) > 0.0))
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: up: must not be the zero vector", fn));
    if (c->focus_distance != 0.0 && (st = build_number(fn, "focus_distance", c->focus_distance, 1e-9, 1e30)))
        return ctx_report(ctx, st);
    if (!isfinite(c->shutter_open) || !isfinite(c->shutter_close) || c->shutter_close < c->shutter_open)
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: shutter: need finite open <= close, got [%.17g, %.17g]", fn,
                                       c->shutter_open, c->shutter_close));
    n.fov = c->fov;
    n.aperture_radius = c->aperture_radius;
    n.focus_distance = c->focus_distance != 0.0 ? c->focus_distance : v3_length(v3_sub(n.look_at, n.position));
    n.shutter_open = c->shutter_open;
    n.shutter_close = c->shutter_close;
    s->cam = n;
    return ctx_report(ctx, BRUME_OK);
}

brume_status brume_scene_set_camera_keys(brume_context *ctx, brume_scene *s, const brume_camera_key *keys, int n)
{
    static const char fn[] = "brume_scene_set_camera_keys";
    err_clear();
    brume_status st = build_check_scene(fn, s);
    if (st)
        return ctx_report(ctx, st);
    if (!keys)
        return ctx_report(ctx, build_null(fn, "keys"));
    if (n < 1 || n > CAMERA_MAX_KEYS)
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: n: %d keys, need 1 to %d", fn, n, CAMERA_MAX_KEYS));
    camera_key *k = calloc((size_t)n, sizeof *k);
    if (!k)
        return ctx_report(ctx, err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn));
    for (int i = 0; i < n && !st; i++) {
        const brume_camera_key *in = &keys[i];
        char arg[64];
        if (!isfinite(in->time) || (i > 0 && !(in->time > keys[i - 1].time))) {
            st = err_set(BRUME_ERROR_RANGE, "%s: keys[%d].time: %g must be finite and greater than the previous key's",
                         fn, i, in->time);
            break;
        }
        k[i].time = in->time;
        snprintf(arg, sizeof arg, "keys[%d].position", i);
        if ((st = build_point(fn, arg, in->position, &k[i].position))) break;
        snprintf(arg, sizeof arg, "keys[%d].look_at", i);
        if ((st = build_point(fn, arg, in->look_at, &k[i].look_at))) break;
        snprintf(arg, sizeof arg, "keys[%d].up", i);
        if ((st = build_point(fn, arg, in->up, &k[i].up))) break;
        k[i].fov = in->fov;
        k[i].aperture_radius = in->aperture_radius;
        k[i].focus_distance = in->focus_distance;
        if (!(in->fov >= 1e-3 && in->fov <= 179.0))
            st = err_set(BRUME_ERROR_RANGE, "%s: keys[%d]: fov %.17g outside [0.001, 179]", fn, i, in->fov);
        else if (!(in->aperture_radius >= 0.0 && in->aperture_radius <= 1e30) ||
                 !(in->focus_distance > 0.0 && in->focus_distance <= 1e30))
            st = err_set(BRUME_ERROR_RANGE, "%s: keys[%d]: need aperture_radius >= 0 and focus_distance > 0", fn, i);
        else if (!(v3_length(v3_sub(k[i].look_at, k[i].position)) > 0.0) || !(v3_length(k[i].up) > 0.0))
            st = err_set(BRUME_ERROR_RANGE, "%s: keys[%d]: look_at equals position, or up is zero", fn, i);
    }
    if (!st) {
        memcpy(s->cam.keys, k, sizeof *k * (size_t)n);
        s->cam.nkeys = n;
    }
    free(k);
    return ctx_report(ctx, st);
}

/* ---- lights ------------------------------------------------------------------------------- */

static brume_status add_light(const char *fn, brume_scene *s, const light *l)
{
    if (s->nlights >= SCENE_MAX_LIGHTS)
        return err_set(BRUME_ERROR_RANGE, "%s: %s: already %d lights, at most %d", fn, s->source, s->nlights,
                       SCENE_MAX_LIGHTS);
    if (s->nlights == s->lights_cap) {
        int cap = s->lights_cap ? 2 * s->lights_cap : 8;
        light *nl = realloc(s->lights, sizeof *nl * (size_t)cap);
        if (!nl)
            return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn);
        s->lights = nl;
        s->lights_cap = cap;
    }
    s->lights[s->nlights++] = *l;
    return BRUME_OK;
}

static const double BIG = 1e30;

brume_status brume_scene_add_distant_light(brume_context *ctx, brume_scene *s, const double direction[3],
                                           const double irradiance[3], double angular_radius)
{
    static const char fn[] = "brume_scene_add_distant_light";
    err_clear();
    light l = {.kind = LIGHT_DISTANT};
    brume_status st = build_check_scene(fn, s);
    if (!st)
        st = build_need(fn, 2, "direction", (const void *)direction, "irradiance", (const void *)irradiance);
    if (!st && !(st = build_direction(fn, "direction", direction, &l.direction)) &&
        !(st = build_color(fn, "irradiance", irradiance, BIG, &l.L)) &&
        !(st = build_number(fn, "angular_radius", angular_radius, 0.0, 90.0))) {
        l.angular_radius = angular_radius * PI / 180.0;
        st = add_light(fn, s, &l);
    }
    return ctx_report(ctx, st);
}

brume_status brume_scene_add_point_light(brume_context *ctx, brume_scene *s, const double position[3],
                                         const double intensity[3])
{
    static const char fn[] = "brume_scene_add_point_light";
    err_clear();
    light l = {.kind = LIGHT_POINT};
    brume_status st = build_check_scene(fn, s);
    if (!st)
        st = build_need(fn, 2, "position", (const void *)position, "intensity", (const void *)intensity);
    if (!st && !(st = build_point(fn, "position", position, &l.position)) &&
        !(st = build_color(fn, "intensity", intensity, BIG, &l.L)))
        st = add_light(fn, s, &l);
    return ctx_report(ctx, st);
}

brume_status brume_scene_add_spot_light(brume_context *ctx, brume_scene *s, const double position[3],
                                        const double direction[3], const double intensity[3], double cone_angle,
                                        double falloff_start)
{
    static const char fn[] = "brume_scene_add_spot_light";
    err_clear();
    light l = {.kind = LIGHT_SPOT};
    brume_status st = build_check_scene(fn, s);
    if (!st)
        st = build_need(fn, 3, "position", (const void *)position, "direction", (const void *)direction, "intensity",
                        (const void *)intensity);
    if (!st && !(st = build_point(fn, "position", position, &l.position)) &&
        !(st = build_direction(fn, "direction", direction, &l.direction)) &&
        !(st = build_color(fn, "intensity", intensity, BIG, &l.L)) &&
        !(st = build_number(fn, "cone_angle", cone_angle, 0.01, 180.0)) &&
        !(st = build_number(fn, "falloff_start", falloff_start, 0.0, cone_angle))) {
        l.cos_outer = cos(cone_angle * PI / 180.0);
        l.cos_inner = cos(falloff_start * PI / 180.0);
        if (l.cos_inner <= l.cos_outer)
            l.cos_inner = l.cos_outer + 1e-9;
        st = add_light(fn, s, &l);
    }
    return ctx_report(ctx, st);
}

brume_status brume_scene_add_spot_light_profile(brume_context *ctx, brume_scene *s, const double position[3],
                                                const double direction[3], const double intensity[3],
                                                const double *angle, const double *factor, int n)
{
    static const char fn[] = "brume_scene_add_spot_light_profile";
    err_clear();
    light *l = calloc(1, sizeof *l);
    if (!l)
        return ctx_report(ctx, err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn));
    l->kind = LIGHT_SPOT;
    brume_status st = build_check_scene(fn, s);
    if (!st)
        st = build_need(fn, 5, "position", (const void *)position, "direction", (const void *)direction, "intensity",
                        (const void *)intensity, "angle", (const void *)angle, "factor", (const void *)factor);
    if (!st && !(st = build_point(fn, "position", position, &l->position)) &&
        !(st = build_direction(fn, "direction", direction, &l->direction)) &&
        !(st = build_color(fn, "intensity", intensity, BIG, &l->L))) {
        if (!angle)
            st = build_null(fn, "angle");
        else if (!factor)
            st = build_null(fn, "factor");
        else if (n < 2 || n > LIGHT_PROFILE_MAX)
            st = err_set(BRUME_ERROR_RANGE, "%s: n: %d pairs, need 2 to %d", fn, n, LIGHT_PROFILE_MAX);
        for (int i = 0; !st && i < n; i++) {
            if (!(angle[i] >= 0.0 && angle[i] <= 180.0) || (i > 0 && !(angle[i] > angle[i - 1])))
                st = err_set(BRUME_ERROR_RANGE, "%s: angle[%d]: %g must increase within [0, 180]", fn, i, angle[i]);
            else if (!(factor[i] >= 0.0 && factor[i] <= BIG))
                st = err_set(BRUME_ERROR_RANGE, "%s: factor[%d]: %g must be finite and >= 0", fn, i, factor[i]);
            l->profile_angle[i] = angle[i];
            l->profile_value[i] = factor[i];
        }
        l->profile_n = n;
        if (!st)
            st = add_light(fn, s, l);
    }
    free(l);
    return ctx_report(ctx, st);
}

brume_status brume_scene_add_sphere_light(brume_context *ctx, brume_scene *s, const double position[3],
                                          double radius, const double radiance[3])
{
    static const char fn[] = "brume_scene_add_sphere_light";
    err_clear();
    light l = {.kind = LIGHT_SPHERE};
    brume_status st = build_check_scene(fn, s);
    if (!st)
        st = build_need(fn, 2, "position", (const void *)position, "radiance", (const void *)radiance);
    if (!st && !(st = build_point(fn, "position", position, &l.position)) &&
        !(st = build_number(fn, "radius", radius, 1e-9, BIG)) && !(st = build_color(fn, "radiance", radiance, BIG, &l.L))) {
        l.radius = radius;
        st = add_light(fn, s, &l);
    }
    return ctx_report(ctx, st);
}

brume_status brume_scene_add_disk_light(brume_context *ctx, brume_scene *s, const double position[3],
                                        const double normal[3], double radius, const double radiance[3])
{
    static const char fn[] = "brume_scene_add_disk_light";
    err_clear();
    light l = {.kind = LIGHT_DISK};
    brume_status st = build_check_scene(fn, s);
    if (!st)
        st = build_need(fn, 3, "position", (const void *)position, "normal", (const void *)normal, "radiance",
                        (const void *)radiance);
    if (!st && !(st = build_point(fn, "position", position, &l.position)) &&
        !(st = build_direction(fn, "normal", normal, &l.direction)) &&
        !(st = build_number(fn, "radius", radius, 1e-9, BIG)) && !(st = build_color(fn, "radiance", radiance, BIG, &l.L))) {
        l.radius = radius;
        st = add_light(fn, s, &l);
    }
    return ctx_report(ctx, st);
}

/* ---- background --------------------------------------------------------------------------- */

brume_status brume_scene_set_background_color(brume_context *ctx, brume_scene *s, const double radiance[3])
{
    static const char fn[] = "brume_scene_set_background_color";
    err_clear();
    color L;
    brume_status st = build_check_scene(fn, s);
    if (!st && !(st = build_color(fn, "radiance", radiance, BIG, &L))) {
        brume_image_release(s->bg.img);
        s->bg.img = NULL;
        s->bg.L = L;
    }
    return ctx_report(ctx, st);
}

/* The image, checked and copied, as the background (either mapping). */
static brume_status set_background_map(const char *fn, brume_scene *s, const brume_image *image, double scale,
                                       bg_mapping mapping, vec3 up, frame f)
{
    brume_status st = BRUME_OK;
    if (!image)
        st = build_null(fn, "image");
    if (!st)
        st = build_number(fn, "scale", scale, 0.0, BIG);
    if (!st && mapping == BG_EQUAL_AREA && image->width != image->height)
        st = err_set(BRUME_ERROR_RANGE, "%s: image: %d x %d pixels: an equal-area map is square", fn, image->width,
                     image->height);
    /* radiance, as a grid's density: a negative value would render negative light, and a
     * NaN or an infinity poisons every pixel that sees it (checked like grids) */
    for (size_t i = 0, n = st ? 0 : (size_t)image->width * (size_t)image->height; !st && i < n; i++)
        for (int c = 0; c < 3 && !st; c++) {
            float v = image->rgba[4 * i + (size_t)c];
            if (!isfinite(v) || v < 0.0f)
                st = err_set(BRUME_ERROR_RANGE, "%s: image: pixel (%zu, %zu) %c is %g: radiance must be finite and >= 0",
                             fn, i % (size_t)image->width, i / (size_t)image->width, "RGB"[c], (double)v);
        }
    if (st)
        return st;
    brume_image *copy = image_new(image->width, image->height);
    if (!copy)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn);
    memcpy(copy->rgba, image->rgba, sizeof *copy->rgba * 4 * (size_t)image->width * (size_t)image->height);
    brume_image_release(s->bg.img);
    s->bg.img = copy;
    s->bg.L = col(0.0);
    s->bg.scale = scale;
    s->bg.mapping = mapping;
    s->bg.up = up;
    s->bg.f = f;
    return BRUME_OK;
}

brume_status brume_scene_set_background_image(brume_context *ctx, brume_scene *s, const brume_image *image,
                                              double scale, const double up[3])
{
    static const char fn[] = "brume_scene_set_background_image";
    err_clear();
    vec3 u = v3(0, 1, 0);
    brume_status st = build_check_scene(fn, s);
    if (!st && !image)
        st = build_null(fn, "image");
    if (!st && up)
        st = build_direction(fn, "up", up, &u);
    if (!st)
        st = set_background_map(fn, s, image, scale, BG_LATLONG, u, frame_from_n(u));
    return ctx_report(ctx, st);
}

brume_status brume_scene_set_background_equal_area(brume_context *ctx, brume_scene *s, const brume_image *image,
                                                   double scale, const double world_from_map[9])
{
    static const char fn[] = "brume_scene_set_background_equal_area";
    err_clear();
    frame f = {v3(1, 0, 0), v3(0, 1, 0), v3(0, 0, 1)};
    brume_status st = build_check_scene(fn, s);
    if (!st && !image)
        st = build_null(fn, "image");
    if (!st && world_from_map) {
        vec3 c[3];
        for (int j = 0; j < 3; j++)
            c[j] = v3(world_from_map[j], world_from_map[3 + j], world_from_map[6 + j]);
        double n0 = v3_length(c[0]);
        bool ok = isfinite(n0) && n0 > 0.0 && n0 < BIG;
        for (int i = 0; i < 3 && ok; i++)
            for (int j = i; j < 3 && ok; j++)
                ok = fabs(v3_dot(c[i], c[j]) - (i == j ? n0 * n0 : 0.0)) <= 1e-6 * n0 * n0;
        if (!ok)
            st = err_set(BRUME_ERROR_RANGE, "%s: world_from_map: not a rotation (and mirror) times a uniform scale", fn);
        else
            f = (frame){v3_scale(c[0], 1.0 / n0), v3_scale(c[1], 1.0 / n0), v3_scale(c[2], 1.0 / n0)};
    }
    if (!st)
        st = set_background_map(fn, s, image, scale, BG_EQUAL_AREA, v3(0, 0, 1), f);
    return ctx_report(ctx, st);
}

/* ---- media -------------------------------------------------------------------------------- */

brume_status brume_scene_add_medium(brume_context *ctx, brume_scene *s, const brume_medium *m, brume_density *rho,
                                    brume_phase *ph)
{
    static const char fn[] = "brume_scene_add_medium";
    err_clear();
    brume_status st = build_check_scene(fn, s);
    if (st)
        return ctx_report(ctx, st);
    if (!m)
        return ctx_report(ctx, build_null(fn, "medium"));
    if (!rho)
        return ctx_report(ctx, build_null(fn, "density"));
    if (s->nmedia >= SCENE_MAX_MEDIA)
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: %s: already %d media, at most %d", fn, s->source,
                                       s->nmedia, SCENE_MAX_MEDIA));
    if (!memchr(m->name, '\0', sizeof m->name))
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: medium.name: not NUL-terminated within 64 bytes", fn));
    medium md = {0};
    if ((st = build_color(fn, "medium.sigma_a", m->sigma_a, 1e12, &md.sigma_a)) ||
        (st = build_color(fn, "medium.sigma_s", m->sigma_s, 1e12, &md.sigma_s)) ||
        (st = build_color(fn, "medium.emission", m->emission, BIG, &md.Le)))
        return ctx_report(ctx, st);
    if (m->emission_units != BRUME_EMISSION_RADIANCE && m->emission_units != BRUME_EMISSION_PER_LENGTH)
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: medium.emission_units: %d is not a "
                                       "brume_emission_units", fn, m->emission_units));
    md.emit_per_length = m->emission_units == BRUME_EMISSION_PER_LENGTH;
    if (!ph) {
        md.ph = phase_new_isotropic();
        if (!md.ph)
            return ctx_report(ctx, err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn));
    } else {
        md.ph = ph->p;
        free(ph);
    }
    snprintf(md.name, sizeof md.name, "%s", m->name);
    md.rho = rho->d;
    if (rho->evolves)
        s->world_moves = true;
    free(rho);
    s->media[s->nmedia++] = md;
    return ctx_report(ctx, BRUME_OK);
}

int brume_scene_medium_count(const brume_scene *s) { return s ? s->nmedia : 0; }

brume_status brume_scene_set_medium_motion(brume_context *ctx, brume_scene *s, int index,
                                           const brume_transform_key *keys, int n)
{
    static const char fn[] = "brume_scene_set_medium_motion";
    err_clear();
    brume_status st = build_check_scene(fn, s);
    if (!st && !keys)
        st = build_null(fn, "keys");
    if (st)
        return ctx_report(ctx, st);
    if (index < 0 || index >= s->nmedia)
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: medium: %d is not a medium of the scene (it has %d)",
                                       fn, index, s->nmedia));
    motion *mo = malloc(sizeof *mo);
    if (!mo)
        return ctx_report(ctx, err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn));
    if ((st = build_motion(fn, keys, n, mo))) {
        free(mo);
        return ctx_report(ctx, st);
    }
    free(s->media[index].motion);
    s->media[index].motion = mo;
    s->world_moves = true;
    return ctx_report(ctx, BRUME_OK);
}

brume_status brume_scene_set_medium_density(brume_context *ctx, brume_scene *s, int index, brume_density *rho)
{
    static const char fn[] = "brume_scene_set_medium_density";
    err_clear();
    brume_status st = build_check_scene(fn, s);
    if (st)
        return ctx_report(ctx, st);
    if (!rho)
        return ctx_report(ctx, build_null(fn, "density"));
    if (index < 0 || index >= s->nmedia)
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: medium: %d is not a medium of the scene (it has %d)",
                                       fn, index, s->nmedia));
    density_release(s->media[index].rho);
    s->media[index].rho = rho->d;
    if (rho->evolves)
        s->world_moves = true;
    free(rho);
    return ctx_report(ctx, BRUME_OK);
}
