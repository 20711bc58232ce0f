/* first_vertex.c - what the first vertex of a camera ray is, for the image's extra layers
 * (AOVs), by a walk of its own (integrator_first_vertex): the estimators are untouched. */
#include "render/integrator.h"

#include <string.h>

#include "surface/surfaces.h"

/* Delta tracking to the first real collision (integrator_first_vertex). */
typedef struct first_walk {
    const brume_scene *s;
    ray r;
    rng *g;
    bool hit;
    double t;
    medium_sample ms;
} first_walk;

static bool first_step(const track_event *e, void *user)
{
    first_walk *w = (first_walk *)user;
    media_at(w->s, ray_at(w->r, e->t), w->r.time, &w->ms);
    double sigma_t = col_avg(col_add(w->ms.sigma_a, w->ms.sigma_s));
    if (rng_next(w->g) * e->sigma_maj < sigma_t) {
        w->hit = true;
        w->t = e->t;
        return false;
    }
    return true;
}

void integrator_first_vertex(const brume_scene *s, ray r, rng *g, first_vertex *v)
{
    memset(v, 0, sizeof *v);
    surface_hit sh;
    bool on_surface = s->surf && surfaces_intersect(s->surf, r, 0.0, INFINITY, &sh);
    first_walk w = {.s = s, .r = r, .g = g, .hit = false};
    track_collisions(s, r, on_surface ? sh.t : (double)INFINITY, g, false, first_step, &w, NULL);
    if (w.hit) {
        v->hit = true;
        v->depth = w.t;
        for (int c = 0; c < BRUME_NSAMPLES; c++) {
            double st = w.ms.sigma_a.c[c] + w.ms.sigma_s.c[c];
            v->albedo.c[c] = st > 0.0 ? w.ms.sigma_s.c[c] / st : 0.0;
        }
    } else if (on_surface) {
        v->hit = true;
        v->depth = sh.t;
        v->albedo = sh.mat ? sh.mat->albedo : col(0.0);
        v->normal = v3_dot(sh.ng, r.d) < 0.0 ? sh.ng : v3_neg(sh.ng);
    }
}
