/* camera.c - primary rays: pinhole or thin lens, with shutter time. */
#include "render/camera.h"

#include "core/sampling.h"

void camera_init(camera *c, int width, int height)
{
    vec3 fwd = v3_normalize(v3_sub(c->look_at, c->position));
    vec3 right = v3_cross(fwd, c->up);
    if (v3_length(right) < 1e-9) /* up parallel to the view: pick any perpendicular */
        right = frame_from_n(fwd).s;
    right = v3_normalize(right);
    vec3 up = v3_cross(right, fwd);
    c->f.s = right;
    c->f.t = up;
    c->f.n = fwd;
    c->tan_half = tan(0.5 * c->fov * PI / 180.0);
    c->aspect = (double)width / (double)height;
}

ray camera_ray(const camera *c, int width, int height, double px, double py, double u1, double u2, double ut)
{
    double sx = (2.0 * px / width - 1.0) * c->tan_half * c->aspect;
    double sy = (1.0 - 2.0 * py / height) * c->tan_half;
    vec3 d = v3_normalize(v3_add(v3_add(v3_scale(c->f.s, sx), v3_scale(c->f.t, sy)), c->f.n));
    ray r;
    r.time = c->shutter_open + ut * (c->shutter_close - c->shutter_open);
    if (c->aperture_radius <= 0.0) {
        r.o = c->position;
        r.d = d;
        return r;
    }
    /* Thin lens: every ray through the lens meets at the point in focus. */
    vec3 focus = v3_madd(c->position, d, c->focus_distance / v3_dot(d, c->f.n));
    vec3 lens = v3_scale(sample_disk(u1, u2), c->aperture_radius);
    r.o = v3_add(c->position, v3_add(v3_scale(c->f.s, lens.x), v3_scale(c->f.t, lens.y)));
    r.d = v3_normalize(v3_sub(focus, r.o));
    return r;
}
