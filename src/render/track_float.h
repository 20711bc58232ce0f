/* track_float.h - the estimator's flight and shadow stages in single precision, for the
 * GPU (docs/gpu.md, "Single precision"), from the same source as the CPU's double ones:
 * render/track_body.h, track_loop.h, track_steps.h and flight_body.h instantiated in float
 * (flightf, flight_runf, track_transmittancef ...) over a float view of a scene of the
 * specialised shape: one medium whose density is a trilinear dense grid (or a NanoVDB
 * grid's dense copy), no motion, no velocity, no fields but rho. The flights ignore surfaces; the caller stops them there.
 * Header-only, so that the GPU's stage kernels (gpu/stages.cu) include it and nothing else
 * of the estimator; scenef_make (track_float.c) builds the view on the host. */
#ifndef BRUME_RENDER_TRACK_FLOAT_H
#define BRUME_RENDER_TRACK_FLOAT_H

#include <stdbool.h>
#include <stdint.h>

#include "core/color.h"
#include "core/rng.h"
#include "core/stats.h"
#include "density/dense_float.h"
#include "render/watch.h"

/* A medium in float: medium.h's fields that the stages read (same names), its density the
 * float view of a dense grid. */
typedef struct mediumf {
    colorf sigma_a, sigma_s, Le; /* per unit length per unit density [1 / world unit]; Le radiance */
    bool emit_per_length;
    float sigma_t_max, sigma_flight, sigma_t_min; /* [1 / world unit], as medium.h's */
    densityf rho;
} mediumf;

/* The scene as the float stages see it: one medium. */
typedef struct scenef {
    int nmedia; /* 1 */
    bool flight_control;
    mediumf media[1];
} scenef;

struct brume_scene;
/* The float view of s into *v; NULL when s has that shape, else the first thing that keeps
 * it off the float stages, a phrase ("2 media", "a NanoVDB density" ...). Reads s, whose
 * grids the view points into: s outlives v. */
const char *scenef_make(const struct brume_scene *s, scenef *v);

/* the medium's majorant walk (medium_majorant_begin's, in float) */
static inline __attribute__((always_inline)) bool medium_majorant_beginf(const mediumf *md, rayf r, float tmax,
                                                                         majorant_iterf *it)
{
    densityf_majorant_begin(&md->rho, r, tmax, it);
    return true;
}

#define REAL_F 1
#define TRACK_MAX_MEDIA 1
#include "render/track_body.h"
#undef TRACK_MAX_MEDIA

/* The medium at p (media_at's, in float: one medium, no fields); absent and time are the
 * double signature's, unused. */
static inline __attribute__((always_inline)) void media_atf(const scenef *s, uint32_t absent, vec3f p, float time,
                                                            medium_samplef *ms)
{
    (void)absent;
    (void)time;
    const mediumf *md = &s->media[0];
    ms->sigma_a = colf(0.0f);
    ms->sigma_s = colf(0.0f);
    ms->emission = colf(0.0f);
    ms->n = 0;
    if (stats_tls)
        stats_tls->density_lookups++;
    const float rho = densityf_eval(&md->rho, p);
    if (rho <= 0.0f)
        return;
    ms->sigma_a = col_scalef(md->sigma_a, rho);
    ms->sigma_s = col_scalef(md->sigma_s, rho);
    ms->emission = md->emit_per_length ? md->Le : col_mulf(ms->sigma_a, md->Le);
    ms->index[0] = 0;
    ms->weight[0] = col_avgf(ms->sigma_s);
    ms->n = 1;
}

#define TRACK_SCENE scenef
#define TRACK_NAME track_collisions_1f
#define TRACK_NMAX 1
#define TRACK_INLINE __attribute__((always_inline))
#include "render/track_loop.h"
static inline __attribute__((always_inline)) bool track_collisionsf(const scenef *s, uint32_t absent, rayf r,
                                                                    float tmax, rng *g, bool residual, track_fnf fn,
                                                                    void *user, float *tau_c_end)
{
    return track_collisions_1f(s, 1, absent, r, tmax, g, residual, fn, user, tau_c_end);
}
#define TRACK_API static inline
#include "render/track_steps.h"
#undef TRACK_API
#undef TRACK_SCENE

#define FLIGHT_SCENE scenef
#define FLIGHT_MEDIUM mediumf
#define FLIGHT_API static inline
#include "render/flight_type.h"
#include "render/flight_body.h"
#undef FLIGHT_API
#undef FLIGHT_MEDIUM
#undef FLIGHT_SCENE
#undef REAL_F

#endif
