/* first_vertex.c - what the first vertex of a camera ray is, for the image's extra layers
 * (AOVs), by a walk of its own (integrator_first_vertex): the estimators are untouched. */
#include "render/integrator.h"

#include <string.h>

#include "render/path.h"

#include "surface/surfaces.h"

/* Delta tracking to the first real collision (integrator_first_vertex). */
typedef struct first_walk {
    const brume_scene *s;
    uint32_t absent; /* the bounded media the walk is not in */
    ray r;
    rng *g;
    bool hit;
    double t;
    medium_sample ms;
} first_walk;

static bool first_step(const track_event *e, void *user)
{
    first_walk *w = (first_walk *)user;
    media_at(w->s, w->absent, ray_at(w->r, e->t), w->r.time, &w->ms);
    double sigma_t = col_avg(col_add(w->ms.sigma_a, w->ms.sigma_s));
    if (rng_next(w->g) * e->sigma_maj < sigma_t) {
        w->hit = true;
        w->t = e->t;
        return false;
    }
    return true;
}

/* Interfaces a first-vertex walk crosses at most (as a path's flight, render/path.c). */
#define FIRST_MAX_CROSSINGS 64

void integrator_first_vertex(const brume_scene *s, ray r, rng *g, first_vertex *v)
{
    memset(v, 0, sizeof *v);
    surface_hit sh;
    first_walk w = {.s = s, .absent = path_camera_absent(s, r), .r = r, .g = g, .hit = false};
    bool on_surface = false;
    double t0 = 0.0, tmin = 0.0; /* where w.r starts along r: on the last interface crossed */
    for (int k = 0; k <= FIRST_MAX_CROSSINGS; k++) {
        on_surface = s->surf && surfaces_intersect(s->surf, w.r, tmin, INFINITY, &sh);
        track_collisions(s, w.absent, w.r, on_surface ? sh.t : (double)INFINITY, g, false, first_step, &w, NULL);
        if (w.hit || !on_surface || !sh.media.interface || k == FIRST_MAX_CROSSINGS)
            break;
        w.absent = surface_media_cross(sh.media, sh.ng, r.d, w.absent);
        t0 += sh.t;
        w.r.o = sh.p;
        tmin = surface_cross_tmin(w.r.o);
    }
    if (w.hit) {
        v->hit = true;
        v->depth = t0 + w.t;
        for (int c = 0; c < BRUME_NSAMPLES; c++) {
            double st = w.ms.sigma_a.c[c] + w.ms.sigma_s.c[c];
            v->albedo.c[c] = st > 0.0 ? w.ms.sigma_s.c[c] / st : 0.0;
        }
    } else if (on_surface && !sh.media.interface) {
        v->hit = true;
        v->depth = t0 + sh.t;
        v->albedo = sh.mat ? sh.mat->albedo : col(0.0);
        v->normal = v3_dot(sh.ng, r.d) < 0.0 ? sh.ng : v3_neg(sh.ng);
    }
}
