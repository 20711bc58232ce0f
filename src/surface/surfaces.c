/* surfaces.c - solid objects: spheres and triangle meshes (fixed or motion-blurred), their
 * Embree 3 scene and queries on the CPU, their emitter table, and their copy for the GPU
 * with brume's own hierarchy (the queries themselves: surface_query.c).
 *
 * libembree3 is opened by its SONAME (BRUME_EMBREE_SONAME, read from the library CMake found)
 * when the first scene with surfaces is built, not linked: its static constructors and those
 * of TBB and libstdc++ that it brings took 7 ms of every brume process's start on the
 * project's machine, and most scenes have no surface (docs/performance.md, "Start-up"). The
 * functions keep the header's types (the table rtc). */
#include "surface/surfaces.h"

#include <embree3/rtcore.h>
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/arena.h"
#include "core/error.h"
#include "core/lazylib.h"
#include "surface/surfaces_impl.h"
#include "surface/material_hit.h"
#include "surface/texture.h"

#ifndef BRUME_EMBREE_SONAME
#define BRUME_EMBREE_SONAME "libembree3.so.3"
#endif

#define EMBREE_FUNCTIONS(X)                                                                             \
    X(rtcNewDevice) X(rtcSetDeviceErrorFunction) X(rtcReleaseDevice) X(rtcNewScene) X(rtcReleaseScene)  \
    X(rtcSetSceneBuildQuality) X(rtcCommitScene) X(rtcNewGeometry) X(rtcSetGeometryTimeStepCount)       \
    X(rtcSetNewGeometryBuffer) X(rtcCommitGeometry) X(rtcAttachGeometryByID) X(rtcReleaseGeometry)      \
    X(rtcIntersect1) X(rtcOccluded1)

static struct {
    EMBREE_FUNCTIONS(LAZYLIB_POINTER)
} rtc;
static const char *const rtc_names[] = {EMBREE_FUNCTIONS(LAZYLIB_NAME) NULL};
static const char *const rtc_sonames[] = {BRUME_EMBREE_SONAME, NULL};
static lazylib rtc_lib = LAZYLIB("Embree", rtc_sonames, rtc_names, &rtc, sizeof rtc);

static void on_embree_error(void *user, enum RTCError code, const char *msg)
{
    (void)user;
    err_set(BRUME_ERROR_UNSUPPORTED, "embree: error %d: %s", (int)code, msg ? msg : "");
}

surfaces *surfaces_new(void)
{
    surfaces *s = calloc(1, sizeof *s);
    if (!s) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "surfaces: out of memory");
        return NULL;
    }
    if (!lazylib_open(&rtc_lib)) {
        free(s);
        err_set(BRUME_ERROR_UNSUPPORTED, "surfaces: %s", rtc_lib.error);
        return NULL;
    }
    s->device = rtc.rtcNewDevice("threads=1,set_affinity=0");
    if (!s->device) {
        free(s);
        err_set(BRUME_ERROR_UNSUPPORTED, "surfaces: Embree could not start (rtcNewDevice failed)");
        return NULL;
    }
    rtc.rtcSetDeviceErrorFunction(s->device, on_embree_error, NULL);
    return s;
}

void surfaces_release(surfaces *s)
{
    if (!s)
        return;
    for (int i = 0; i < s->n; i++) {
        free(s->obj[i].pos);
        free(s->obj[i].idx);
        free(s->obj[i].mo);
        free(s->obj[i].step);
        free(s->obj[i].uv);
        material_release(&s->obj[i].mat);
    }
    free(s->obj);
    free(s->em);
    free(s->em_first);
    if (s->nem)
        distrib1_free(&s->em_dist);
    bvh_free(&s->hier);
    free(s->ref);
    if (s->scene)
        rtc.rtcReleaseScene(s->scene);
    rtc.rtcReleaseDevice(s->device);
    free(s);
}

static surface_object *surfaces_push(surfaces *s, const material *m, const char *name)
{
    if (s->committed) {
        err_set(BRUME_ERROR_STATE, "surfaces: object '%s' added after commit", name);
        return NULL;
    }
    if (s->n == s->cap) {
        int cap = s->cap ? 2 * s->cap : 8;
        surface_object *o = realloc(s->obj, sizeof *o * (size_t)cap);
        if (!o) {
            err_set(BRUME_ERROR_OUT_OF_MEMORY, "surfaces: out of memory");
            return NULL;
        }
        s->obj = o;
        s->cap = cap;
    }
    surface_object *o = &s->obj[s->n];
    memset(o, 0, sizeof *o);
    snprintf(o->name, sizeof o->name, "%s", name ? name : "");
    o->mat = *m;
    o->media = (surface_media){-1, -1, false};
    return o;
}

brume_status surfaces_add_sphere(surfaces *s, vec3 center, double radius, const material *m, const char *name)
{
    if (!v3_isfinite(center) || !(radius > 0.0) || !isfinite(radius))
        return err_set(BRUME_ERROR_RANGE, "surface '%s': sphere needs a finite centre and radius > 0", name);
    surface_object *o = surfaces_push(s, m, name);
    if (!o)
        return err_status();
    o->is_sphere = true;
    o->center = center;
    o->radius = radius;
    s->n++;
    return BRUME_OK;
}

brume_status surfaces_add_mesh(surfaces *s, const double *pos, int nv, const int *idx, int ntri, const material *m,
                               const char *name)
{
    if (nv < 3 || ntri < 1)
        return err_set(BRUME_ERROR_PARSE, "surface '%s': a mesh needs at least 3 vertices and 1 triangle", name);
    for (int i = 0; i < 3 * nv; i++)
        if (!isfinite(pos[i]) || fabs(pos[i]) > 1e18)
            return err_set(BRUME_ERROR_RANGE, "surface '%s': vertex %d has a non-finite coordinate", name, i / 3);
    for (int i = 0; i < 3 * ntri; i++)
        if (idx[i] < 0 || idx[i] >= nv)
            return err_set(BRUME_ERROR_RANGE, "surface '%s': triangle %d names vertex %d of %d", name, i / 3, idx[i],
                           nv);
    surface_object *o = surfaces_push(s, m, name);
    if (!o)
        return err_status();
    o->pos = malloc(sizeof *o->pos * 3 * (size_t)nv);
    o->idx = malloc(sizeof *o->idx * 3 * (size_t)ntri);
    if (!o->pos || !o->idx) {
        free(o->pos);
        free(o->idx);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "surface '%s': out of memory for %d triangles", name, ntri);
    }
    memcpy(o->pos, pos, sizeof *o->pos * 3 * (size_t)nv);
    memcpy(o->idx, idx, sizeof *o->idx * 3 * (size_t)ntri);
    o->nv = nv;
    o->ntri = ntri;
    s->n++;
    return BRUME_OK;
}

const char *surfaces_textured(const surfaces *s)
{
    for (int i = 0; s && i < s->n; i++)
        if (material_textured(&s->obj[i].mat))
            return s->obj[i].name;
    return NULL;
}

brume_status surfaces_set_uv(surfaces *s, int index, const double *uv, int nv)
{
    if (s->committed || index < 0 || index >= s->n || s->obj[index].is_sphere || s->obj[index].nv != nv)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "surfaces: uv for object %d: not a mesh of %d vertices before "
                       "commit", index, nv);
    for (int i = 0; i < 2 * nv; i++)
        if (!isfinite(uv[i]))
            return err_set(BRUME_ERROR_RANGE, "surface '%s': uv of vertex %d is not finite", s->obj[index].name, i / 2);
    double *c = malloc(sizeof *c * 2 * (size_t)nv);
    if (!c)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "surface '%s': out of memory", s->obj[index].name);
    memcpy(c, uv, sizeof *c * 2 * (size_t)nv);
    free(s->obj[index].uv);
    s->obj[index].uv = c;
    return BRUME_OK;
}

brume_status surfaces_set_motion(surfaces *s, int index, const motion *m)
{
    if (s->committed || index < 0 || index >= s->n || m->n < 1)
        return err_set(BRUME_ERROR_STATE, "surfaces: motion for object %d set after commit or out of range", index);
    surface_object *o = &s->obj[index];
    if (o->is_sphere)
        for (int k = 0; k < m->n; k++) {
            vec3 sc = m->key[k].scale;
            if (fabs(sc.x - sc.y) > 1e-9 * sc.x || fabs(sc.x - sc.z) > 1e-9 * sc.x)
                return err_set(BRUME_ERROR_UNSUPPORTED,
                               "surface '%s': a sphere's keyframes take a uniform scale only", o->name);
        }
    motion *c = malloc(sizeof *c);
    if (!c)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "surface '%s': out of memory", o->name);
    *c = *m;
    free(o->mo);
    o->mo = c;
    return BRUME_OK;
}

void surfaces_set_shutter(surfaces *s, double t0, double t1)
{
    s->t0 = t0;
    s->t1 = t1 > t0 ? t1 : t0;
}

bool surfaces_moving(const surfaces *s)
{
    for (int i = 0; s && i < s->n; i++)
        if (s->obj[i].mo)
            return true;
    return false;
}

/* The positions of a moving object at each of its time steps over the shutter. */
static brume_status build_steps(const surfaces *s, surface_object *o)
{
    bool linear = motion_rotation_constant(o->mo) && !motion_key_inside(o->mo, s->t0, s->t1);
    o->nsteps = !(s->t1 > s->t0) ? 1 : (linear ? 2 : SURFACES_MOTION_STEPS);
    size_t per = o->is_sphere ? 4 : 3 * (size_t)o->nv;
    free(o->step);
    o->step = malloc(sizeof *o->step * per * (size_t)o->nsteps);
    if (!o->step)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "surface '%s': out of memory for motion steps", o->name);
    for (int k = 0; k < o->nsteps; k++) {
        double t = o->nsteps > 1 ? s->t0 + (s->t1 - s->t0) * k / (o->nsteps - 1) : s->t0;
        affine3 a = motion_at(o->mo, t);
        double *dst = o->step + per * (size_t)k;
        if (o->is_sphere) {
            vec3 c = affine3_apply(&a, o->center);
            dst[0] = c.x;
            dst[1] = c.y;
            dst[2] = c.z;
            dst[3] = o->radius * v3_length(affine3_apply_dir(&a, v3(1, 0, 0)));
        } else {
            for (int v = 0; v < o->nv; v++) {
                vec3 p = affine3_apply(&a, v3(o->pos[3 * v], o->pos[3 * v + 1], o->pos[3 * v + 2]));
                dst[3 * v] = p.x;
                dst[3 * v + 1] = p.y;
                dst[3 * v + 2] = p.z;
            }
        }
    }
    return BRUME_OK;
}

static brume_status build_emitters(surfaces *s)
{
    int count = 0;
    for (int i = 0; i < s->n; i++)
        if (!col_is_black(s->obj[i].mat.emission))
            count += s->obj[i].is_sphere ? 1 : s->obj[i].ntri;
    if (!count)
        return BRUME_OK;
    s->em = malloc(sizeof *s->em * (size_t)count);
    s->em_first = malloc(sizeof *s->em_first * (size_t)s->n);
    double *w = malloc(sizeof *w * (size_t)count);
    if (!s->em || !w || !s->em_first) {
        free(w);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "surfaces: out of memory for emitters");
    }
    int k = 0;
    s->em_total = 0.0;
    for (int i = 0; i < s->n; i++) {
        const surface_object *o = &s->obj[i];
        s->em_first[i] = -1;
        if (col_is_black(o->mat.emission))
            continue;
        s->em_first[i] = k;
        int prims = o->is_sphere ? 1 : o->ntri;
        for (int p = 0; p < prims; p++) {
            /* a moving emitter: its area at shutter open weighs the choice; pdfs use the
             * area at the ray's time */
            emitter e = {i, p, 0.0};
            double area = o->mo ? emitter_area(o, &e, 0.0)
                                : (o->is_sphere ? 4.0 * PI * o->radius * o->radius : tri_area(o, p, 0.0));
            s->em[k] = (emitter){i, p, area};
            w[k] = area * col_avg(o->mat.emission);
            s->em_total += w[k];
            k++;
        }
    }
    int ok = distrib1_init(&s->em_dist, w, count);
    free(w);
    if (!ok)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "surfaces: out of memory for emitters");
    s->nem = count;
    return BRUME_OK;
}

brume_status surfaces_commit(surfaces *s)
{
    if (s->committed)
        return BRUME_OK;
    err_clear();
    s->scene = rtc.rtcNewScene(s->device);
    if (!s->scene)
        return err_set(BRUME_ERROR_UNSUPPORTED, "surfaces: Embree could not create a scene");
    rtc.rtcSetSceneBuildQuality(s->scene, RTC_BUILD_QUALITY_HIGH);
    for (int i = 0; i < s->n; i++) {
        surface_object *o = &s->obj[i];
        o->nsteps = 1;
        if (o->mo) {
            brume_status st = build_steps(s, o);
            if (st)
                return st;
        }
        RTCGeometry g = rtc.rtcNewGeometry(s->device, o->is_sphere ? RTC_GEOMETRY_TYPE_SPHERE_POINT
                                                               : RTC_GEOMETRY_TYPE_TRIANGLE);
        rtc.rtcSetGeometryTimeStepCount(g, (unsigned)o->nsteps);
        for (int k = 0; k < o->nsteps; k++) {
            if (o->is_sphere) {
                float *v = rtc.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, (unsigned)k, RTC_FORMAT_FLOAT4,
                                                   4 * sizeof(float), 1);
                if (!v) {
                    rtc.rtcReleaseGeometry(g);
                    return err_set(BRUME_ERROR_OUT_OF_MEMORY, "surface '%s': Embree buffer allocation failed", o->name);
                }
                vec3 c;
                double r;
                sphere_at(o, o->nsteps > 1 ? (double)k / (o->nsteps - 1) : 0.0, &c, &r);
                v[0] = (float)c.x;
                v[1] = (float)c.y;
                v[2] = (float)c.z;
                v[3] = (float)r;
            } else {
                float *v = rtc.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, (unsigned)k, RTC_FORMAT_FLOAT3,
                                                   3 * sizeof(float), (size_t)o->nv);
                if (!v) {
                    rtc.rtcReleaseGeometry(g);
                    return err_set(BRUME_ERROR_OUT_OF_MEMORY, "surface '%s': Embree buffer allocation failed", o->name);
                }
                const double *src = o->mo ? o->step + 3 * (size_t)k * (size_t)o->nv : o->pos;
                for (size_t j = 0; j < 3 * (size_t)o->nv; j++)
                    v[j] = (float)src[j];
            }
        }
        if (!o->is_sphere) {
            unsigned *ix = rtc.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                   3 * sizeof(unsigned), (size_t)o->ntri);
            if (!ix) {
                rtc.rtcReleaseGeometry(g);
                return err_set(BRUME_ERROR_OUT_OF_MEMORY, "surface '%s': Embree buffer allocation failed", o->name);
            }
            for (size_t j = 0; j < 3 * (size_t)o->ntri; j++)
                ix[j] = (unsigned)o->idx[j];
        }
        rtc.rtcCommitGeometry(g);
        rtc.rtcAttachGeometryByID(s->scene, g, (unsigned)i);
        rtc.rtcReleaseGeometry(g);
    }
    rtc.rtcCommitScene(s->scene);
    if (err_status() != BRUME_OK)
        return err_status();
    brume_status st = build_emitters(s);
    if (st)
        return st;
    s->committed = true;
    return BRUME_OK;
}

int surfaces_count(const surfaces *s) { return s->n; }

const char *surfaces_name(const surfaces *s, int index) { return s->obj[index].name; }

void surfaces_set_media(surfaces *s, int index, surface_media m)
{
    if (index < 0 || index >= s->n)
        return;
    s->obj[index].media = m;
    if (m.interface) { /* no material: nothing reflects or emits there */
        material_release(&s->obj[index].mat);
        s->obj[index].mat = (material){.albedo = {{0}}, .albedo_tex = NULL};
    }
}

/* A directed edge a -> b of a mesh, as the ordered pair (lo, hi) and the direction. */
typedef struct mesh_edge {
    int lo, hi, dir; /* dir: +1 when a < b */
} mesh_edge;

static int edge_cmp(const void *pa, const void *pb)
{
    const mesh_edge *a = (const mesh_edge *)pa, *b = (const mesh_edge *)pb;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi)
        return a->hi < b->hi ? -1 : 1;
    return a->dir - b->dir;
}

/* Vertex indices ordered by position (x, then y, then z), for surfaces_closed. */
static _Thread_local const double *closed_pos;

static int vertex_cmp(const void *pa, const void *pb)
{
    const double *a = closed_pos + 3 * (size_t)*(const int *)pa, *b = closed_pos + 3 * (size_t)*(const int *)pb;
    for (int k = 0; k < 3; k++)
        if (a[k] != b[k])
            return a[k] < b[k] ? -1 : 1;
    return 0;
}

bool surfaces_closed(const surfaces *s, int index)
{
    const surface_object *o = &s->obj[index];
    if (o->is_sphere)
        return true;
    /* vertices at one position are one vertex (a file's faces may each have their own) */
    size_t ne = 3 * (size_t)o->ntri;
    int *order = malloc((size_t)o->nv * sizeof *order), *id = malloc((size_t)o->nv * sizeof *id);
    mesh_edge *e = malloc(ne * sizeof *e);
    if (!order || !id || !e) {
        free(order);
        free(id);
        free(e);
        return false;
    }
    for (int v = 0; v < o->nv; v++)
        order[v] = v;
    closed_pos = o->pos; /* qsort has no user pointer: this thread's */
    qsort(order, (size_t)o->nv, sizeof *order, vertex_cmp);
    for (int v = 0; v < o->nv; v++)
        id[order[v]] = v > 0 && vertex_cmp(&order[v - 1], &order[v]) == 0 ? id[order[v - 1]] : v;
    for (size_t t = 0; t < (size_t)o->ntri; t++)
        for (size_t k = 0; k < 3; k++) {
            int a = id[(size_t)o->idx[3 * t + k]], b = id[(size_t)o->idx[3 * t + (k + 1) % 3]];
            e[3 * t + k] = (mesh_edge){a < b ? a : b, a < b ? b : a, a < b ? 1 : -1};
        }
    free(order);
    free(id);
    qsort(e, ne, sizeof *e, edge_cmp);
    /* sorted, each undirected edge must be exactly one pair (-1, +1) */
    bool closed = ne % 2 == 0;
    for (size_t i = 0; closed && i < ne; i += 2)
        closed = e[i].lo == e[i + 1].lo && e[i].hi == e[i + 1].hi && e[i].dir == -1 && e[i + 1].dir == 1 &&
                 (i + 2 >= ne || e[i + 2].lo != e[i].lo || e[i + 2].hi != e[i].hi);
    free(e);
    return closed;
}

long surfaces_triangle_count(const surfaces *s)
{
    long n = 0;
    for (int i = 0; i < s->n; i++)
        n += s->obj[i].ntri;
    return n;
}

/* Embree asserts (aborts the process) on a ray whose origin or direction has a coordinate
 * beyond its FLT_LARGE, 1.844e18: the camera is kept within SURFACES_COORD_MAX at commit
 * (scene.c), and a ray that starts farther out (scattered in a medium whose bounds reach
 * beyond it) is not given to Embree and meets no surface: a float origin there is off by
 * 1e11 units anyway. */
static bool embree_accepts(vec3 o, vec3 d)
{
    return fabs(o.x) <= SURFACES_COORD_MAX && fabs(o.y) <= SURFACES_COORD_MAX && fabs(o.z) <= SURFACES_COORD_MAX &&
           fabs(d.x) <= SURFACES_COORD_MAX && fabs(d.y) <= SURFACES_COORD_MAX && fabs(d.z) <= SURFACES_COORD_MAX;
}

static void embree_ray(struct RTCRay *rr, vec3 o, vec3 d, double tmin, double tmax, double time)
{
    rr->org_x = (float)o.x;
    rr->org_y = (float)o.y;
    rr->org_z = (float)o.z;
    rr->dir_x = (float)d.x;
    rr->dir_y = (float)d.y;
    rr->dir_z = (float)d.z;
    rr->tnear = (float)tmin;
    rr->tfar = tmax < (double)FLT_MAX ? (float)tmax : FLT_MAX;
    rr->time = (float)time;
    rr->mask = 0xffffffffu;
    rr->id = 0;
    rr->flags = 0;
}

bool surfaces_embree_intersect(const surfaces *s, ray r, double tmin, double tmax, surface_hit *h)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRayHit rh;
    if (!embree_accepts(r.o, r.d))
        return false;
    double u = shutter_time(s, r.time);
    embree_ray(&rh.ray, r.o, r.d, tmin, tmax, u);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtc.rtcIntersect1(s->scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
        return false;
    const surface_object *o = &s->obj[rh.hit.geomID];
    h->t = (double)rh.ray.tfar;
    h->p = ray_at(r, h->t);
    h->object = (int)rh.hit.geomID;
    h->prim = (int)rh.hit.primID;
    h->mat = &o->mat;
    h->media = o->media;
    h->time = r.time;
    if (o->is_sphere) {
        /* recompute the hit in double precision from the sphere itself (where it is at u) */
        vec3 center;
        double t;
        if (sphere_hit(o, u, r, tmin, tmax, &t, &center)) {
            h->t = t;
            h->p = ray_at(r, t);
        }
        h->ng = v3_normalize(v3_sub(h->p, center));
    } else {
        /* Embree's unnormalized Ng points like (v1 - v0) x (v2 - v0), our counter-clockwise
         * front (checked by surfaces.emitter_front_side); it is computed at the ray's time
         * and costs no vertex fetch, which dominated the hit cost on large meshes */
        vec3 ng = v3((double)rh.hit.Ng_x, (double)rh.hit.Ng_y, (double)rh.hit.Ng_z);
        double len = v3_length(ng);
        if (len > 0.0 && isfinite(len)) {
            h->ng = v3_scale(ng, 1.0 / len);
        } else { /* degenerate in float: fall back to the vertices in double */
            vec3 a = tri_vertex(o, h->prim, 0, u), b = tri_vertex(o, h->prim, 1, u), c = tri_vertex(o, h->prim, 2, u);
            h->ng = v3_normalize(v3_cross(v3_sub(b, a), v3_sub(c, a)));
        }
    }
    return true;
}

bool surfaces_embree_occluded(const surfaces *s, vec3 o, vec3 d, double tmin, double tmax, double time)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRay rr;
    if (!embree_accepts(o, d))
        return false;
    embree_ray(&rr, o, d, tmin, tmax, shutter_time(s, time));
    rtc.rtcOccluded1(s->scene, &ctx, &rr);
    return rr.tfar < 0.0f;
}


/* ---- brume's own hierarchy and the device's copy --------------------------------------- */

/* A box that holds the primitive at every time of the shutter: the union of its boxes at
 * the motion steps (between steps it moves linearly, inside their hull), padded by a few
 * ulps of its coordinates so that interpolated positions stay inside. */
static box3 prim_box(const surface_object *o, int prim)
{
    box3 b = box3_empty();
    int steps = o->mo ? o->nsteps : 1;
    for (int k = 0; k < steps; k++) {
        double u = steps > 1 ? (double)k / (steps - 1) : 0.0;
        if (o->is_sphere) {
            vec3 c;
            double r;
            sphere_at(o, u, &c, &r);
            b.lo = v3_min(b.lo, v3_sub(c, v3(r, r, r)));
            b.hi = v3_max(b.hi, v3_add(c, v3(r, r, r)));
        } else {
            for (int v = 0; v < 3; v++) {
                vec3 p = tri_vertex(o, prim, v, u);
                b.lo = v3_min(b.lo, p);
                b.hi = v3_max(b.hi, p);
            }
        }
    }
    double m = fmax(fmax(fabs(b.lo.x), fabs(b.hi.x)), fmax(fmax(fabs(b.lo.y), fabs(b.hi.y)), fmax(fabs(b.lo.z), fabs(b.hi.z))));
    double pad = 1e-12 * (1.0 + m);
    b.lo = v3_sub(b.lo, v3(pad, pad, pad));
    b.hi = v3_add(b.hi, v3(pad, pad, pad));
    return b;
}

/* The hierarchy over every primitive of s, and its primitive table. */
static brume_status build_hierarchy(const surfaces *s, bvh *h, surface_ref **ref)
{
    long count = 0;
    for (int i = 0; i < s->n; i++)
        count += s->obj[i].is_sphere ? 1 : s->obj[i].ntri;
    if (count > 0x7fffffff)
        return err_set(BRUME_ERROR_RANGE, "surfaces: %ld primitives are more than the GPU's hierarchy holds", count);
    *ref = malloc(sizeof **ref * (size_t)(count ? count : 1));
    box3 *boxes = malloc(sizeof *boxes * (size_t)(count ? count : 1));
    if (!*ref || !boxes) {
        free(*ref);
        free(boxes);
        *ref = NULL;
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "surfaces: out of memory for the hierarchy of %ld primitives", count);
    }
    int k = 0;
    for (int i = 0; i < s->n; i++) {
        const surface_object *o = &s->obj[i];
        for (int p = 0; p < (o->is_sphere ? 1 : o->ntri); p++, k++) {
            (*ref)[k] = (surface_ref){i, p};
            boxes[k] = prim_box(o, p);
        }
    }
    brume_status st = bvh_build(h, boxes, NULL, (int)count);
    free(boxes);
    if (st) {
        free(*ref);
        *ref = NULL;
    }
    return st;
}

brume_status surfaces_use_bvh(surfaces *s)
{
    if (!s->committed)
        return err_set(BRUME_ERROR_STATE, "surfaces: brume's hierarchy asked for before commit");
    if (s->hier.nnodes)
        return BRUME_OK;
    return build_hierarchy(s, &s->hier, &s->ref);
}

size_t surfaces_device_put(const surfaces *s, dev_arena *a)
{
    if (!s)
        return ARENA_NULL;
    bvh h = s->hier;
    surface_ref *ref = s->ref;
    if (!h.nnodes && build_hierarchy(s, &h, &ref) != BRUME_OK) {
        a->failed = true;
        return ARENA_NULL;
    }
    size_t at = arena_put(a, s, sizeof *s);
    if (at != ARENA_NULL) {
        arena_ptr(a, at + offsetof(surfaces, device), ARENA_NULL);
        arena_ptr(a, at + offsetof(surfaces, scene), ARENA_NULL);
        size_t objs = arena_put(a, s->obj, sizeof *s->obj * (size_t)s->n);
        arena_ptr(a, at + offsetof(surfaces, obj), objs);
        for (int i = 0; i < s->n && objs != ARENA_NULL; i++) {
            const surface_object *o = &s->obj[i];
            size_t oat = objs + (size_t)i * sizeof *o, per = o->is_sphere ? 4 : 3 * (size_t)o->nv;
            ARENA_PUT_MEMBER(a, oat, surface_object, pos, o->pos, sizeof *o->pos * 3 * (size_t)o->nv);
            ARENA_PUT_MEMBER(a, oat, surface_object, idx, o->idx, sizeof *o->idx * 3 * (size_t)o->ntri);
            ARENA_PUT_MEMBER(a, oat, surface_object, mo, o->mo, sizeof *o->mo);
            ARENA_PUT_MEMBER(a, oat, surface_object, step, o->step, sizeof *o->step * per * (size_t)o->nsteps);
        }
        ARENA_PUT_MEMBER(a, at, surfaces, em, s->em, sizeof *s->em * (size_t)s->nem);
        ARENA_PUT_MEMBER(a, at, surfaces, em_first, s->em_first, sizeof *s->em_first * (size_t)(s->nem ? s->n : 0));
        if (s->nem)
            distrib1_device_fix(&s->em_dist, a, at + offsetof(surfaces, em_dist));
        size_t hat = at + offsetof(surfaces, hier);
        ARENA_PUT_MEMBER(a, hat, bvh, nodes, h.nodes, sizeof *h.nodes * (size_t)h.nnodes);
        ARENA_PUT_MEMBER(a, hat, bvh, item, h.item, sizeof *h.item * (size_t)h.nitems);
        bvh *ch = (bvh *)arena_at(a, hat);
        ch->nnodes = h.nnodes;
        ch->nitems = h.nitems;
        ARENA_PUT_MEMBER(a, at, surfaces, ref, ref, sizeof *ref * (size_t)h.nitems);
    }
    if (!s->hier.nnodes) {
        bvh_free(&h);
        free(ref);
    }
    return at;
}
