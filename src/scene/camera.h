/* camera.h - look-at perspective camera with a thin lens and a shutter (Blasi Eq. 1).
 * A pixel's value is the mean over pixel area (through the pixel filter), lens disk and
 * shutter interval of the radiance along the generated rays.
 *
 * Time: `time` is the frame's time (seconds); the shutter interval is relative to it, so a
 * ray's time lies in [time + shutter_open, time + shutter_close]. A keyframed camera
 * (nkeys > 0) takes its pose from the keys: at the frame time for the fields below, and at
 * each ray's own time while the shutter is open (docs/animation.md). */
#ifndef BRUME_SCENE_CAMERA_H
#define BRUME_SCENE_CAMERA_H

#include "core/vec.h"

#define CAMERA_MAX_KEYS 64

/* One keyframe: the complete pose at `time` (the scene reader fills the fields a key does
 * not give from the other keys). Between keys every field is interpolated linearly. */
typedef struct camera_key {
    double time;
    vec3 position, look_at, up;
    double fov, aperture_radius, focus_distance;
} camera_key;

typedef struct camera {
    vec3 position;          /* world units */
    vec3 look_at;           /* world point at the image centre */
    vec3 up;                /* approximate up direction (default +y) */
    double fov;             /* vertical field of view, degrees, in (0, 180) */
    double aperture_radius; /* lens radius, world units; 0 = pinhole */
    double focus_distance;  /* distance to the plane in focus, world units, > 0 */
    double shutter_open, shutter_close; /* seconds, relative to `time` */
    double time;            /* the frame's time, seconds */
    int nkeys;              /* 0 = a fixed camera */
    camera_key keys[CAMERA_MAX_KEYS]; /* increasing times */
    /* derived by camera_init */
    frame f;          /* s = right, t = up, n = forward */
    double tan_half;  /* tan(fov / 2) */
    double aspect;    /* width / height */
} camera;

/* Sets the pose from the keys at c->time (when keyed) and derives the frame. */
void camera_init(camera *c, int width, int height);
/* The interpolated pose at time t (keys clamp at both ends); requires nkeys > 0. */
camera_key camera_pose_at(const camera *c, double t);
/* True when rays must take the pose at their own time: keyed, with an open shutter. */
static inline bool camera_moving(const camera *c) { return c->nkeys > 1 && c->shutter_close > c->shutter_open; }

/* The unit direction through film point (px, py) of c's pose, from its centre. */
static inline vec3 camera_pinhole_dir(const camera *c, int width, int height, double px, double py)
{
    double sx = (2.0 * px / width - 1.0) * c->tan_half * c->aspect;
    double sy = (1.0 - 2.0 * py / height) * c->tan_half;
    return v3_normalize(v3_add(v3_add(v3_scale(c->f.s, sx), v3_scale(c->f.t, sy)), c->f.n));
}

/* camera_ray for a moving or thin-lens camera (camera.c). */
ray camera_ray_general(const camera *c, int width, int height, double px, double py, double u1, double u2, double ut);

/* True for a fixed pinhole (no lens, no keyed pose while the shutter is open): the camera
 * whose rays camera_pinhole_ray makes. */
static inline bool camera_is_pinhole(const camera *c) { return !(c->aperture_radius > 0.0) && !camera_moving(c); }

/* camera_ray of a fixed pinhole, written into *r field by field, so that a batch of rays
 * can be made in place (a ray built on the stack and copied into the batch costs a
 * store-forwarding stall per ray: the copy's 16-byte loads straddle the 8-byte stores). */
static inline void camera_pinhole_ray(const camera *c, int width, int height, double px, double py, double ut, ray *r)
{
    const vec3 d = camera_pinhole_dir(c, width, height, px, py);
    r->o.x = c->position.x;
    r->o.y = c->position.y;
    r->o.z = c->position.z;
    r->d.x = d.x;
    r->d.y = d.y;
    r->d.z = d.z;
    r->time = c->time + c->shutter_open + ut * (c->shutter_close - c->shutter_open);
}

/* Ray through film point (px, py) in pixels (0,0 = top-left corner), lens sample
 * (u1, u2), time sample ut in [0, 1) over the shutter. The direction is unit length.
 * Inline for a fixed pinhole (the usual camera), else camera_ray_general; both give the
 * same ray for a fixed pinhole. */
static inline ray camera_ray(const camera *c, int width, int height, double px, double py, double u1, double u2,
                             double ut)
{
    if (!camera_is_pinhole(c))
        return camera_ray_general(c, width, height, px, py, u1, u2, ut);
    ray r;
    camera_pinhole_ray(c, width, height, px, py, ut, &r);
    return r;
}

#endif
