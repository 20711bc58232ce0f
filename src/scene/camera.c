/* camera.c - primary rays: pinhole or thin lens, with shutter time and keyframed poses. */
#include "scene/camera.h"

#include "core/sampling.h"

/* The look-at frame and the field-of-view scale from the pose fields. */
static void camera_derive(camera *c)
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
}

camera_key camera_pose_at(const camera *c, double t)
{
    const camera_key *k = c->keys;
    int n = c->nkeys;
    if (n == 1 || t <= k[0].time)
        return k[0];
    if (t >= k[n - 1].time)
        return k[n - 1];
    int i = 0;
    while (i + 2 < n && t >= k[i + 1].time)
        i++;
    double u = (t - k[i].time) / (k[i + 1].time - k[i].time);
    const camera_key *a = &k[i], *b = &k[i + 1];
    camera_key p;
    p.time = t;
    p.position = v3_add(a->position, v3_scale(v3_sub(b->position, a->position), u));
    p.look_at = v3_add(a->look_at, v3_scale(v3_sub(b->look_at, a->look_at), u));
    p.up = v3_add(a->up, v3_scale(v3_sub(b->up, a->up), u));
    p.fov = a->fov + (b->fov - a->fov) * u;
    p.aperture_radius = a->aperture_radius + (b->aperture_radius - a->aperture_radius) * u;
    p.focus_distance = a->focus_distance + (b->focus_distance - a->focus_distance) * u;
    return p;
}

static void camera_set_pose(camera *c, const camera_key *p)
{
    c->position = p->position;
    c->look_at = p->look_at;
    c->up = p->up;
    c->fov = p->fov;
    c->aperture_radius = p->aperture_radius;
    c->focus_distance = p->focus_distance;
}

void camera_init(camera *c, int width, int height)
{
    if (c->nkeys > 0) {
        camera_key p = camera_pose_at(c, c->time);
        camera_set_pose(c, &p);
    }
    camera_derive(c);
    c->aspect = (double)width / (double)height;
}

ray camera_ray_general(const camera *c, int width, int height, double px, double py, double u1, double u2, double ut)
{
    double time = c->time + c->shutter_open + ut * (c->shutter_close - c->shutter_open);
    camera moved;
    if (camera_moving(c)) {
        /* the pose at this ray's instant: motion blur of the camera itself */
        camera_key p = camera_pose_at(c, time);
        moved.aspect = c->aspect;
        camera_set_pose(&moved, &p);
        camera_derive(&moved);
        c = &moved;
    }
    vec3 d = camera_pinhole_dir(c, width, height, px, py);
    ray r;
    r.time = time;
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
