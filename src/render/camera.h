/* camera.h - look-at perspective camera with a thin lens and a shutter (Blasi Eq. 1).
 * A pixel's value is the mean over pixel area (through the pixel filter), lens disk and
 * shutter interval of the radiance along the generated rays. */
#ifndef BRUME_RENDER_CAMERA_H
#define BRUME_RENDER_CAMERA_H

#include "core/vec.h"

typedef struct camera {
    vec3 position;          /* world units */
    vec3 look_at;           /* world point at the image centre */
    vec3 up;                /* approximate up direction (default +y) */
    double fov;             /* vertical field of view, degrees, in (0, 180) */
    double aperture_radius; /* lens radius, world units; 0 = pinhole */
    double focus_distance;  /* distance to the plane in focus, world units, > 0 */
    double shutter_open, shutter_close; /* seconds */
    /* derived by camera_init */
    frame f;          /* s = right, t = up, n = forward */
    double tan_half;  /* tan(fov / 2) */
    double aspect;    /* width / height */
} camera;

void camera_init(camera *c, int width, int height);
/* Ray through film point (px, py) in pixels (0,0 = top-left corner), lens sample
 * (u1, u2), time sample ut. The direction is unit length. */
ray camera_ray(const camera *c, int width, int height, double px, double py, double u1, double u2, double ut);

#endif
