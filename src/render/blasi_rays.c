/* blasi_rays.c - the light rays of Blasi's first pass (1993, Section 4): a ray's start
 * towards the media and its power, the share of rays each light gets, the check of the work
 * they make, and the units of the stored sums (docs/blasi.md, "Normalization"). */
#include <math.h>
#include <stdlib.h>

#include "core/cancel.h"
#include "core/error.h"
#include "core/fixsum.h"
#include "core/pool.h"
#include "core/progress.h"
#include "core/sampling.h"
#include "render/blasi_state.h"
#include "render/blasi_walk.h"
#include "surface/surfaces.h"
#include "render/blasi_rays.h"

/* Projected area of box b seen along unit d, and a uniform point on it (the faces that d
 * enters through, each chosen in proportion to area |n . d|). */
static double box_projected_area(box3 b, vec3 d)
{
    vec3 e = v3_sub(b.hi, b.lo);
    return e.y * e.z * fabs(d.x) + e.x * e.z * fabs(d.y) + e.x * e.y * fabs(d.z);
}

static vec3 box_entry_point(box3 b, vec3 d, double u0, double u1, double u2)
{
    vec3 e = v3_sub(b.hi, b.lo);
    double a[3] = {e.y * e.z * fabs(d.x), e.x * e.z * fabs(d.y), e.x * e.y * fabs(d.z)};
    double x = u0 * (a[0] + a[1] + a[2]);
    if (x < a[0])
        return v3(d.x > 0.0 ? b.lo.x : b.hi.x, b.lo.y + u1 * e.y, b.lo.z + u2 * e.z);
    if (x < a[0] + a[1])
        return v3(b.lo.x + u1 * e.x, d.y > 0.0 ? b.lo.y : b.hi.y, b.lo.z + u2 * e.z);
    return v3(b.lo.x + u1 * e.x, b.lo.y + u2 * e.y, d.z > 0.0 ? b.lo.z : b.hi.z);
}

/* A direction from y uniform in the cone that holds the media's bounding sphere (the whole
 * sphere of directions when y is inside it); *omega is the cone's solid angle. */
static vec3 towards_media(const blasi_state *st, vec3 y, double u1, double u2, double *omega)
{
    vec3 c = v3_sub(st->centre, y);
    double dist = v3_length(c), cos_max = -1.0;
    if (dist > st->radius * (1.0 + 1e-9))
        cos_max = sqrt(fmax(0.0, 1.0 - st->radius * st->radius / (dist * dist)));
    *omega = 1.0 / sample_cone_pdf(cos_max);
    if (cos_max <= -1.0)
        return sample_sphere(u1, u2);
    frame f = frame_from_n(v3_scale(c, 1.0 / dist));
    return frame_to_world(&f, sample_cone(u1, u2, cos_max));
}

/* Light ray j of the n rays of light l (Section 4.2: each light's surface divided into
 * `sources` elementary sources, rays sent stochastically into the solid angle that holds
 * the media, following the light's goniometric distribution). *W is its power; false
 * when it carries none. */
bool blasi_light_ray(const brume_scene *s, const blasi_state *st, const light *l, uint64_t j, uint64_t n, rng *g,
                     ray *r, color *W)
{
    double u0 = rng_next(g), u1 = rng_next(g), u2 = rng_next(g), u3 = 0.0, u4 = 0.0;
    if (l->kind == LIGHT_DISTANT && !(l->angular_radius > 0.0))
        g->counter += 2; /* a delta sun needs no u3, u4: skipped, so what follows draws the same numbers */
    else
        u3 = rng_next(g), u4 = rng_next(g);
    double inv_n = 1.0 / (double)n, omega;
    r->time = 0.0;
    switch (l->kind) {
    case LIGHT_DISTANT: {
        vec3 d = l->direction;
        color L = l->L; /* irradiance of a delta sun */
        if (l->angular_radius > 0.0) { /* a sun disk: a direction in its cone, radiance L */
            d = v3_neg(frame_to_world(&l->f, sample_cone(u3, u4, l->cos_max)));
            double sn = sin(l->angular_radius);
            L = col_scale(l->L, 1.0 / (PI * sn * sn) / sample_cone_pdf(l->cos_max));
        }
        double area = box_projected_area(st->light_box, d);
        vec3 p = box_entry_point(st->light_box, d, u0, u1, u2);
        *r = (ray){v3_madd(p, d, -1e-6 * st->radius), d, s->time};
        if (s->surf && surfaces_occluded(s->surf, r->o, v3_neg(d), 0.0, INFINITY, s->time))
            return false;
        *W = col_scale(L, area * inv_n);
        return true;
    }
    case LIGHT_POINT:
    case LIGHT_SPOT: {
        vec3 d = towards_media(st, l->position, u0, u1, &omega);
        light_sample ls; /* the intensity towards d: irradiance at distance 1 */
        if (!light_sample_at(l, v3_add(l->position, d), 0.5, 0.5, &ls))
            return false;
        *r = (ray){l->position, d, 0.0};
        *W = col_scale(ls.Li, omega * inv_n);
        return true;
    }
    case LIGHT_SPHERE:
    case LIGHT_DISK: {
        /* elementary source j mod M: a stratum of a k x k grid over the surface's
         * parameter square (both maps preserve area) */
        int k = (int)ceil(sqrt((double)blasi_opts(s)->sources));
        uint64_t cell = j % (uint64_t)(k * k);
        double a = ((double)(cell % (uint64_t)k) + u2) / k, b = ((double)(cell / (uint64_t)k) + u3) / k;
        vec3 y, nrm;
        double area;
        if (l->kind == LIGHT_SPHERE) {
            nrm = sample_sphere(a, b);
            y = v3_madd(l->position, nrm, l->radius);
            area = 4.0 * PI * l->radius * l->radius;
        } else {
            nrm = l->direction;
            y = v3_add(l->position, frame_to_world(&l->f, v3_scale(sample_disk(a, b), l->radius)));
            area = PI * l->radius * l->radius;
        }
        vec3 d = towards_media(st, y, u0, u1, &omega);
        double cos_y = v3_dot(d, nrm);
        if (cos_y <= 0.0)
            return false;
        *r = (ray){v3_madd(y, nrm, 1e-9 * (1.0 + l->radius)), d, 0.0};
        *W = col_scale(l->L, cos_y * area * omega * inv_n);
        return true;
    }
    }
    return false;
}

/* Solid angle of the cone from y that holds the sphere (c, radius): 4 pi from inside it. */
static double cone_solid_angle(vec3 c, double radius, vec3 y)
{
    double dist = v3_length(v3_sub(c, y));
    if (!(dist > radius * (1.0 + 1e-9)))
        return 4.0 * PI;
    return 2.0 * PI * (1.0 - sqrt(fmax(0.0, 1.0 - radius * radius / (dist * dist))));
}

/* The share of light l's rays that the first pass traces: its rays aim at light_box (the
 * non-empty voxels) where the paper's aim at the media's bounds, and a ray that misses
 * light_box crosses no non-empty voxel, so deposits nothing. The traced rays keep the
 * weight the paper's rays have (power / number of rays, over the area or solid angle aimed
 * at), so the count shrinks as that area or solid angle does: by the projected areas along
 * a sun's direction, by the solid angles seen from the centre of any other light
 * (docs/blasi.md, "Rays that cannot deposit"). */
static double light_share(const blasi_state *st, const light *l)
{
    if (l->kind == LIGHT_DISTANT) {
        double a = box_projected_area(st->bounds, l->direction);
        return a > 0.0 ? box_projected_area(st->light_box, l->direction) / a : 1.0;
    }
    vec3 cb = v3_scale(v3_add(st->bounds.lo, st->bounds.hi), 0.5);
    double rb = 0.5 * v3_length(v3_sub(st->bounds.hi, st->bounds.lo));
    return cone_solid_angle(st->centre, st->radius, l->position) / cone_solid_angle(cb, rb, l->position);
}

/* The order of magnitude of the power a ray of light l starts with (light_ray's *W, largest
 * channel), n the rays it traces: the fixed-point unit's reference. An upper bound up to
 * a spot's profile (the projected area is at most half the box's surface, a sun disk's
 * radiance factor at most 2, cos_y at most 1, the solid angle at most 4 pi). */
static double ray_power_ref(const blasi_state *st, const light *l, uint64_t n)
{
    double g = 4.0 * PI; /* point and spot: the intensity over the directions */
    if (l->kind == LIGHT_DISTANT) {
        vec3 e = v3_sub(st->light_box.hi, st->light_box.lo);
        g = 2.0 * (e.x * e.y + e.y * e.z + e.x * e.z);
    } else if (l->kind == LIGHT_SPHERE) {
        g = 16.0 * PI * PI * l->radius * l->radius;
    } else if (l->kind == LIGHT_DISK) {
        g = 4.0 * PI * PI * l->radius * l->radius;
    }
    return col_max(l->L) * g / (double)n;
}

/* Where each light's rays are: light l traces rays [first[l], first[l + 1]) of first[nl].
 * Its nominal rays are [l N / nl, (l + 1) N / nl) of the N; those it traces, its share of
 * them (light_share), at least one when it has any. NULL when out of memory (err_set). */
uint64_t *blasi_rays_per_light(const brume_scene *s, const blasi_state *st, uint64_t nominal)
{
    uint64_t *first = malloc(((size_t)s->nlights + 1) * sizeof *first);
    if (!first) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: blasi: out of memory for the light pass", s->source);
        return NULL;
    }
    uint64_t nl = (uint64_t)s->nlights;
    first[0] = 0;
    for (uint64_t l = 0; l < nl; l++) {
        uint64_t n = (l + 1) * nominal / nl - l * nominal / nl;
        double k = fmin(1.0, light_share(st, &s->lights[l])) * (double)n;
        uint64_t m = n > 0 && k > 0.0 ? (uint64_t)llround(k) : 0;
        first[l + 1] = first[l] + (n > 0 && k > 0.0 && m == 0 ? 1 : m);
    }
    return first;
}

/* The work before it starts (render.max_work): rays x the steps of one across the
 * media's box (a step of blasi.step, or a voxel of the finest medium). */
brume_status blasi_check_work(const brume_scene *s, const blasi_state *st, uint64_t nrays)
{
    double steps = 0.0;
    for (int m = 0; m < st->nm; m++)
        steps = fmax(steps, (double)st->m[m].n[0] + st->m[m].n[1] + st->m[m].n[2]);
    if (st->step > 0.0)
        steps = 2.0 * st->radius / st->step;
    double work = (double)nrays * (steps + 1.0);
    if (work > s->max_work)
        return err_set(BRUME_ERROR_RANGE,
                       "%s: blasi: the light pass's %llu rays of about %.3g steps each are %.3g units of work, over "
                       "render.max_work (%.3g): raise blasi.step or lower blasi.light_rays (or raise render.max_work)",
                       s->source, (unsigned long long)nrays, steps, work, s->max_work);
    return BRUME_OK;
}

/* The sums' unit, in units per watt: 2^-40 of the largest reference power per ray over the
 * lights, a power of two. */
double blasi_units_per_watt(const brume_scene *s, const blasi_state *st, const uint64_t *first)
{
    double W_ref = 0.0;
    for (uint64_t l = 0; l < (uint64_t)s->nlights; l++)
        if (first[l + 1] > first[l])
            W_ref = fmax(W_ref, ray_power_ref(st, &s->lights[l], first[l + 1] - first[l]));
    int e = 0;
    (void)frexp(W_ref > 0.0 && isfinite(W_ref) ? W_ref : 1.0, &e);
    return ldexp(1.0, 40 - (e < -900 ? -900 : e > 900 ? 900 : e));
}
