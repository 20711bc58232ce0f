/* vec.h - 3-vectors, rays, axis-aligned boxes and orthonormal frames (world units). */
#ifndef BRUME_CORE_VEC_H
#define BRUME_CORE_VEC_H

#include <math.h>

/* glibc's INFINITY is a float constant, and clang's -Wdouble-promotion flags each use of it
 * in double arithmetic; brume computes in double, so its infinity is a double. */
#if defined(__clang__)
#undef INFINITY
#define INFINITY (__builtin_inf())
#endif
#include <stdbool.h>

#define PI 3.14159265358979323846
#define INV_PI 0.31830988618379067154
#define INV_4PI 0.07957747154594766788

/* vec3, ray, v3_add ... in double; vec3f, rayf, v3_addf ... in float (the GPU's
 * single-precision stages): one body (core/vec_body.h), two instantiations. */
#define REAL_F 0
#include "core/vec_body.h"
#undef REAL_F
#define REAL_F 1
#include "core/vec_body.h"
#undef REAL_F

/* Axis-aligned box [lo, hi]; empty when any lo > hi. */
typedef struct box3 {
    vec3 lo, hi;
} box3;

/* Right-handed orthonormal frame: s x t = n. */
typedef struct frame {
    vec3 s, t, n;
} frame;

static inline vec3 v3_min(vec3 a, vec3 b) { return v3(fmin(a.x, b.x), fmin(a.y, b.y), fmin(a.z, b.z)); }
static inline vec3 v3_max(vec3 a, vec3 b) { return v3(fmax(a.x, b.x), fmax(a.y, b.y), fmax(a.z, b.z)); }
static inline double v3_get(vec3 a, int axis) { return axis == 0 ? a.x : (axis == 1 ? a.y : a.z); }
static inline void v3_to_array(vec3 a, double out[3])
{
    out[0] = a.x;
    out[1] = a.y;
    out[2] = a.z;
}
static inline bool v3_isfinite(vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

/* Frame with n as its third axis (Duff et al. 2017, branchless; n must be unit length). */
static inline frame frame_from_n(vec3 n)
{
    double sign = copysign(1.0, n.z);
    double a = -1.0 / (sign + n.z);
    double b = n.x * n.y * a;
    frame f;
    f.s = v3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    f.t = v3(b, sign + n.y * n.y * a, -n.y);
    f.n = n;
    return f;
}
/* Local (frame) coordinates to world. */
static inline vec3 frame_to_world(const frame *f, vec3 l)
{
    return v3_add(v3_add(v3_scale(f->s, l.x), v3_scale(f->t, l.y)), v3_scale(f->n, l.z));
}
static inline vec3 frame_to_local(const frame *f, vec3 w)
{
    return v3(v3_dot(w, f->s), v3_dot(w, f->t), v3_dot(w, f->n));
}

static inline box3 box3_empty(void) { return (box3){v3(INFINITY, INFINITY, INFINITY), v3(-INFINITY, -INFINITY, -INFINITY)}; }
static inline box3 box3_union(box3 a, box3 b) { return (box3){v3_min(a.lo, b.lo), v3_max(a.hi, b.hi)}; }
static inline bool box3_contains(box3 b, vec3 p)
{
    return p.x >= b.lo.x && p.x <= b.hi.x && p.y >= b.lo.y && p.y <= b.hi.y && p.z >= b.lo.z && p.z <= b.hi.z;
}
/* Slab test. On a hit, [*t0, *t1] is the parametric overlap of the ray with the box,
 * clipped to [tmin, tmax]. Robust for axis-parallel rays (IEEE infinities). */
static inline bool box3_intersect(box3 b, ray r, double tmin, double tmax, double *t0, double *t1)
{
    const double o[3] = {r.o.x, r.o.y, r.o.z}, d[3] = {r.d.x, r.d.y, r.d.z};
    const double lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
    for (int a = 0; a < 3; a++) {
        double inv = 1.0 / d[a];
        double tn = (lo[a] - o[a]) * inv, tf = (hi[a] - o[a]) * inv;
        if (tn > tf) {
            double s = tn;
            tn = tf;
            tf = s;
        }
        if (isnan(tn) || isnan(tf)) /* d = 0 and origin on a slab plane: treat as inside */
            continue;
        tmin = tn > tmin ? tn : tmin;
        tmax = tf < tmax ? tf : tmax;
        if (tmin > tmax)
            return false;
    }
    *t0 = tmin;
    *t1 = tmax;
    return true;
}

#endif
