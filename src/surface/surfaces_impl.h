/* surfaces_impl.h - the solid objects' state, shared by their construction (surfaces.c:
 * objects, motion steps, emitters, Embree's scene, the device's copy) and their queries
 * (surface_query.c, compiled for the CPU and the GPU). Private to src/surface. */
#ifndef BRUME_SURFACE_SURFACES_IMPL_H
#define BRUME_SURFACE_SURFACES_IMPL_H

#include "core/bvh.h"
#include "core/distrib.h"
#include "core/sampling.h"
#include "surface/surfaces.h"

typedef struct surface_object {
    char name[64];
    material mat;
    surface_media media;
    bool is_sphere;
    vec3 center; /* sphere */
    double radius;
    int nv, ntri;   /* mesh */
    double *pos;    /* 3 nv, owned */
    int *idx;       /* 3 ntri, owned */
    double *uv;     /* 2 nv texture coordinates, owned; NULL: (0, 0), (1, 0), (1, 1) per triangle */
    motion *mo;     /* owned; NULL = fixed */
    int nsteps;     /* with mo: Embree time steps over the shutter (1 = closed shutter) */
    double *step;   /* with mo: per step, 3 nv positions (mesh) or centre and radius (sphere) */
} surface_object;

/* Linear motion between two steps is exact; else this many steps over the shutter. */
#define SURFACES_MOTION_STEPS 17

/* One emissive primitive: a triangle of a mesh, or a whole sphere. */
typedef struct emitter {
    int object, prim;
    double area;
} emitter;

/* One primitive of the device's hierarchy: a triangle of a mesh, or a whole sphere. */
typedef struct surface_ref {
    int object, prim;
} surface_ref;

struct surfaces {
    struct RTCDeviceTy *device; /* Embree's (host only; NULL in the device's copy) */
    struct RTCSceneTy *scene;   /* Embree's BVH (host only; NULL in the device's copy) */
    surface_object *obj;
    int n, cap;
    bool committed;
    emitter *em;
    int nem;
    int *em_first;    /* per object: index of its first emitter record, or -1 */
    distrib1 em_dist; /* over emitters, in proportion to area x average radiance */
    double em_total;  /* sum of area x average radiance */
    double t0, t1;    /* shutter interval, absolute seconds; Embree's ray time 0..1 spans it */
    bvh hier;         /* the device's hierarchy over ref (empty on the host: Embree's is used) */
    surface_ref *ref; /* hier.nitems primitives */
};

/* Absolute time -> Embree's ray time in [0, 1] over the shutter. */
static inline double shutter_time(const surfaces *s, double t)
{
    if (!(s->t1 > s->t0))
        return 0.0;
    double u = (t - s->t0) / (s->t1 - s->t0);
    return u < 0.0 ? 0.0 : (u > 1.0 ? 1.0 : u);
}

/* The two steps around shutter time u and the weight of the second, as Embree does. */
static inline void step_at(const surface_object *o, double u, int *i, double *w)
{
    *i = 0;
    *w = 0.0;
    if (o->nsteps <= 1)
        return;
    double x = u * (o->nsteps - 1);
    int k = (int)floor(x);
    if (k > o->nsteps - 2)
        k = o->nsteps - 2;
    *i = k;
    *w = x - k;
}

static inline vec3 mesh_vertex(const surface_object *o, int v, double u)
{
    if (!o->mo) {
        const double *p = o->pos + 3 * (size_t)v;
        return v3(p[0], p[1], p[2]);
    }
    int i;
    double w;
    step_at(o, u, &i, &w);
    const double *a = o->step + 3 * ((size_t)i * (size_t)o->nv + (size_t)v);
    if (w == 0.0)
        return v3(a[0], a[1], a[2]);
    const double *b = a + 3 * (size_t)o->nv;
    return v3(a[0] + (b[0] - a[0]) * w, a[1] + (b[1] - a[1]) * w, a[2] + (b[2] - a[2]) * w);
}

static inline void sphere_at(const surface_object *o, double u, vec3 *c, double *r)
{
    if (!o->mo) {
        *c = o->center;
        *r = o->radius;
        return;
    }
    int i;
    double w;
    step_at(o, u, &i, &w);
    const double *a = o->step + 4 * (size_t)i, *b = o->nsteps > 1 ? a + 4 : a;
    *c = v3(a[0] + (b[0] - a[0]) * w, a[1] + (b[1] - a[1]) * w, a[2] + (b[2] - a[2]) * w);
    *r = a[3] + (b[3] - a[3]) * w;
}

static inline vec3 tri_vertex(const surface_object *o, int prim, int k, double u)
{
    return mesh_vertex(o, o->idx[3 * prim + k], u);
}

static inline double tri_area(const surface_object *o, int prim, double u)
{
    vec3 a = tri_vertex(o, prim, 0, u), b = tri_vertex(o, prim, 1, u), c = tri_vertex(o, prim, 2, u);
    return 0.5 * v3_length(v3_cross(v3_sub(b, a), v3_sub(c, a)));
}

/* An emitter's area at shutter time u (moving objects may scale). */
static inline double emitter_area(const surface_object *o, const emitter *e, double u)
{
    if (!o->mo)
        return e->area;
    if (o->is_sphere) {
        vec3 c;
        double r;
        sphere_at(o, u, &c, &r);
        return 4.0 * PI * r * r;
    }
    return tri_area(o, e->prim, u);
}

/* The nearest root t in (tmin, tmax) of sphere object o at shutter time u along r (unit
 * direction), in double precision; *center is its centre at u, hit or not. */
static inline bool sphere_hit(const surface_object *o, double u, ray r, double tmin, double tmax, double *t,
                              vec3 *center)
{
    double radius;
    sphere_at(o, u, center, &radius);
    vec3 oc = v3_sub(r.o, *center);
    double b = v3_dot(oc, r.d), c = v3_dot(oc, oc) - radius * radius, disc = b * b - c;
    if (disc < 0.0)
        return false;
    double sq = sqrt(disc), th = -b - sq;
    if (th <= tmin)
        th = -b + sq;
    if (!(th > tmin && th < tmax))
        return false;
    *t = th;
    return true;
}

/* Embree's queries (surfaces.c, host only): what surfaces_intersect and surfaces_occluded
 * use on the CPU when no hierarchy of brume's own was built. A ray whose origin has a
 * coordinate beyond SURFACES_COORD_MAX meets no surface there (Embree accepts up to 1.844e18). */
bool surfaces_embree_intersect(const surfaces *s, ray r, double tmin, double tmax, surface_hit *h);
bool surfaces_embree_occluded(const surfaces *s, vec3 o, vec3 d, double tmin, double tmax, double time);

#endif
