/* surfaces.h - solid objects traced with Embree 3 on the CPU and with brume's own
 * hierarchy on the GPU: spheres and triangle meshes (boxes,
 * quads and OBJ meshes become triangles) in world space, each with a material; emissive
 * objects are area lights of any shape.
 *
 * Lifecycle: surfaces_new, add objects (and their motion), surfaces_set_shutter,
 * surfaces_commit (builds the Embree BVH and the emitter table), then queries from any
 * number of threads, then surfaces_release.
 *
 * Motion: an object with a motion (core/motion.h) is placed at time t by motion_at(t)
 * applied after its world placement. Over the shutter [t0, t1] it becomes an Embree
 * motion-blurred geometry with time steps at equal intervals (2 when its points move
 * linearly over the interval, else SURFACES_MOTION_STEPS); between steps Embree and every
 * query here interpolate linearly. Queries take the absolute time of the ray. */
#ifndef BRUME_SURFACE_SURFACES_H
#define BRUME_SURFACE_SURFACES_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "brume.h"
#include "core/color.h"
#include "core/motion.h"
#include "core/vec.h"
#include "surface/material.h"

typedef struct surfaces surfaces;

/* The largest coordinate of a ray origin or direction the queries trace: Embree aborts the
 * process on a ray beyond its FLT_LARGE (1.844e18), so the camera's rays stay within this
 * (checked at commit) and a ray starting farther out meets no surface. */
#define SURFACES_COORD_MAX 1e18

/* How a surface bounds media (docs/surfaces.md, "How surfaces meet media"): the indices in
 * the scene's media of the medium behind its front side (`inside`: a sphere's, a closed
 * mesh's interior) and of the one before it (`outside`), -1 for none. An `interface` has no
 * material: paths and shadow rays cross it (render/path.c, path_cross_surface). */
typedef struct surface_media {
    signed char inside, outside;
    bool interface;
} surface_media;

/* The bounded media absent (bit i: the scene's medium i is not where the ray is) after a ray
 * along d crosses a surface of geometric normal ng that bounds m: going in (against ng) it
 * leaves the outside medium and enters the inside one; coming out, the reverse. The one
 * membership rule: paths, shadow rays and the camera's start all cross by it. */
static inline uint32_t surface_media_cross(surface_media m, vec3 ng, vec3 d, uint32_t absent)
{
    const bool in = v3_dot(d, ng) < 0.0;
    const int leave = in ? m.outside : m.inside, enter = in ? m.inside : m.outside;
    if (leave >= 0)
        absent |= 1u << leave;
    if (enter >= 0)
        absent &= ~(1u << enter);
    return absent;
}

/* NULL when out of memory or Embree cannot start (err_set says which). */
surfaces *surfaces_new(void);
void surfaces_release(surfaces *s);
/* The adds below take over m->albedo_tex on success (surfaces_release frees it); on failure
 * the caller keeps it. */
/* A sphere of `radius` (world units) at `center`. */
brume_status surfaces_add_sphere(surfaces *s, vec3 center, double radius, const material *m, const char *name);
/* A triangle mesh in world coordinates: nv vertices (x, y, z), ntri triangles of three
 * vertex indices, counter-clockwise seen from the front. The arrays are copied. Vertices
 * must be finite and indices in range (err_set names the object). */
brume_status surfaces_add_mesh(surfaces *s, const double *pos, int nv, const int *idx, int ntri, const material *m,
                               const char *name);
/* Texture coordinates (u, v) per vertex for mesh `index` of nv vertices (copied, finite).
 * Before commit. */
brume_status surfaces_set_uv(surfaces *s, int index, const double *uv, int nv);
/* Gives object `index` (insertion order) a motion (copied). A sphere's keys must scale
 * uniformly. Before commit. */
brume_status surfaces_set_motion(surfaces *s, int index, const motion *m);
/* The shutter interval in absolute seconds, t0 <= t1 (default [0, 0]). Before commit. */
void surfaces_set_shutter(surfaces *s, double t0, double t1);
/* Gives object `index` (insertion order) the media it bounds (default: none, not an
 * interface); an interface's material becomes black, emitting nothing. Before commit. */
void surfaces_set_media(surfaces *s, int index, surface_media m);
/* Whether object `index` is closed: a sphere, or a mesh whose every edge is shared by
 * exactly two triangles that run along it in opposite directions (a consistently wound,
 * watertight mesh: its inside is well defined). */
bool surfaces_closed(const surfaces *s, int index);
/* The object's name (insertion order). */
const char *surfaces_name(const surfaces *s, int index);
/* The name of the first object with a texture, or NULL when none has one. */
const char *surfaces_textured(const surfaces *s);
/* True when some object has a motion. */
bool surfaces_moving(const surfaces *s);
brume_status surfaces_commit(surfaces *s);
int surfaces_count(const surfaces *s);
long surfaces_triangle_count(const surfaces *s);

typedef struct surface_hit {
    double t;    /* ray parameter of the hit */
    vec3 p;      /* world position */
    vec3 ng;     /* unit geometric normal (front side: counter-clockwise, or outward) */
    vec3 ns;     /* unit shading normal on ng's side: ng, or bump-mapped by the material (CPU) */
    const material *mat; /* the object's, or &shade when it has a texture */
    material shade;      /* a textured object's material at this hit (CPU only) */
    double uv[2];        /* texture coordinates at the hit (set for textured objects only) */
    int object;  /* index in insertion order */
    int prim;    /* triangle index, 0 for spheres */
    double time; /* the ray's time, absolute seconds */
    surface_media media; /* the object's */
} surface_hit;

/* brume's own hierarchy (core/bvh.h) for the queries instead of Embree's: what the GPU
 * traverses, and on the CPU what the tests compare with Embree. After commit. */
brume_status surfaces_use_bvh(surfaces *s);
struct dev_arena;
/* Copies s for the GPU (core/arena.h), with brume's hierarchy (built for the copy when
 * s has none); its offset, or ARENA_NULL (a->failed set) when out of memory. */
size_t surfaces_device_put(const surfaces *s, struct dev_arena *a);

/* Nearest hit of r (unit direction) in (tmin, tmax) at time r.time. */
bool surfaces_intersect(const surfaces *s, ray r, double tmin, double tmax, surface_hit *h);
/* Any hit of the segment o + t d, t in (tmin, tmax), at `time`. */
bool surfaces_occluded(const surfaces *s, vec3 o, vec3 d, double tmin, double tmax, double time);

/* A point slightly off the surface on the side of direction d, for spawning rays. */
vec3 surface_offset(const surface_hit *h, vec3 d);
/* Where a ray that crossed a surface at p, and goes on from p itself, starts its next
 * surface query (ray parameter): the scale surface_offset moves spawned rays by, so that
 * the surface crossed is not met again. The media are tracked from p on, none skipped;
 * a second surface closer than this to the first is not seen. */
static inline double surface_cross_tmin(vec3 p)
{
    return 1e-4 * (1.0 + fmax(fabs(p.x), fmax(fabs(p.y), fabs(p.z))));
}

/* ---- emitters --------------------------------------------------------------------------- */
bool surfaces_has_emitters(const surfaces *s);
/* Emitted radiance leaving the hit point towards direction w (unit, away from surface). */
color surface_emission(const surface_hit *h, vec3 w);
/* Samples a point on an emitter (where it is at `time`) as seen from p: unit direction
 * *wi, distance *dist, the radiance *Le arriving from it and the solid-angle pdf *pdf.
 * False if nothing is sent. */
bool surfaces_sample_emitter(const surfaces *s, vec3 p, double time, double u0, double u1, double u2, vec3 *wi,
                             double *dist, color *Le, double *pdf);
/* The solid-angle pdf with which surfaces_sample_emitter would pick the hit h from p (at
 * the hit's time). */
double surfaces_emitter_pdf(const surfaces *s, const surface_hit *h, vec3 p);

#endif
