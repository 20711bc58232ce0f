/* path_impl.h - the path tracer's private parts, shared by render/path.c (the estimator)
 * and render/path_state.c (what it prepares once per scene) only. */
#ifndef BRUME_RENDER_PATH_IMPL_H
#define BRUME_RENDER_PATH_IMPL_H

#include "render/path.h"
#include "surface/surfaces.h"

/* Crossing a surface (docs/surfaces.md, "How surfaces meet media"): the bounded media absent
 * (bit m: s->media[m] is not there, track_collisions') on the far side of the surface hit
 * sh for a ray leaving it along d, from those absent on the near side. Every crossing goes
 * through it: the flights and shadow rays that pass interfaces (path.c), and a material
 * whose sampled direction wi goes through its surface (a refraction): there, the path's
 * next flight starts with w->f.absent = path_cross_surface(sh, wi, w->f.absent), and the
 * new ray from the offset point on wi's side (surface_offset(sh, wi)). A reflection
 * keeps w->f.absent as it is. */
uint32_t path_cross_surface(const surface_hit *sh, vec3 d, uint32_t absent);

/* Power heuristic with exponent 2. */
static inline double mis_weight(double pdf_this, double pdf_other)
{
    double a = pdf_this * pdf_this, b = pdf_other * pdf_other;
    return a > 0.0 ? a / (a + b) : 0.0;
}


#define LOBE_TABLE 33  /* S(c) at c = -1 + 2 i / (LOBE_TABLE - 1) */
#define LOBE_MAX_SUNS 4 /* delta suns that get lobe samples (the first ones of the scene) */

/* What integrator_prepare keeps for `path` and `single`: the delta suns; for lobe samples
 * (path), per medium (its phase function), the table of S(c), the relative size of phase
 * sampling's error on a sun's light scattered once more, as a function of the cosine c
 * between the arriving direction and the direction to the sun (lobe_table); the camera
 * rays' cull; and the sun roulette's predictions. */
typedef struct path_state {
    double kappa;                  /* path.sun_lobe */
    int nsuns;                     /* delta suns (lobe samples when kappa > 0; the sun roulette) */
    int split;                     /* path.split: continuations from the camera vertex (path only) */
    int sun[LOBE_MAX_SUNS];        /* indices into s->lights */
    float S[SCENE_MAX_MEDIA][LOBE_TABLE]; /* per medium (its phase function) */
    /* A camera ray that misses `reach`, the world box of every medium's walks
     * (density_reach_bounds), meets nothing but what lies past the media, when the scene has
     * no surfaces, no area lights and no moving media (`cull`): path_Li_alpha then returns
     * the escaped radiance at once, the value the whole path would have come to. */
    bool cull;
    box3 reach;
    /* Sun roulette (docs/path-tracer.md, "Sun rays deep in a cloud"): for each sun j (a
     * delta sun, sun[j]), tau[j] holds the optical depth towards it predicted at a grid of
     * tn nodes spanning `reach` (sun_tau_build), or is NULL (no prediction: sun_roulette 0,
     * moving media, or too little of the media deep enough for it to act). */
    double tau0;               /* -log(path.sun_roulette) */
    int tn[3];                 /* nodes per axis, >= 2 */
    vec3 tscale;               /* (tn - 1) / reach's size, per axis [1 / world unit] */
    float *tau[LOBE_MAX_SUNS]; /* per cell of the grid (tn - 1 per axis, x fastest): the least
                                  tau of its 8 nodes; in tau_data */
    float tau_data[];
} path_state;

/* The state of `path` and `single`: the camera rays' cull, the delta suns with, for each, the
 * sun roulette's predicted optical depths (when path.sun_roulette > 0 and no medium moves),
 * and with `lobes` (path) sun-lobe tables when path.sun_lobe > 0. */
brume_status path_prepare(const brume_scene *s, bool lobes, path_state **out);

#endif
