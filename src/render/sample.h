/* sample.h - one camera sample of a pixel, shared by the CPU's tiles (render.c) and the
 * GPU's kernel (gpu/kernel.cu): its numbers and ray (sample_camera), its radiance, alpha
 * and first-vertex layers (sample_eval), and what it adds to the pixel's sums
 * (sample_add). The CPU makes a tile's camera rays in batches with the same calls
 * (render.c, camera_samples), so a sample's numbers are the same on both. */
#ifndef BRUME_RENDER_SAMPLE_H
#define BRUME_RENDER_SAMPLE_H

#include "core/rng.h"
#include "core/stats.h"
#include "render/film.h"
#include "render/integrator.h"
#include "render/job.h"

#define RENDER_SOBOL_DIMS 8 /* dimensions of a camera sample drawn from Sobol points */
#define AOV_DIMENSION (1ULL << 40) /* the first-vertex walk draws from this dimension on, so
                                      it never shares a number with the sample's path */

/* What a sample needs to know of the render, the same for every sample of a job. */
typedef struct sample_params {
    int kind;              /* integrator_kind */
    int width, height;     /* pixels */
    uint64_t seed;
    brume_filter filter;
    double filter_width;   /* pixels */
    double max_component;  /* 0, or the clamp of a sample's largest sensor value (sample_clamp) */
    double sensor[9];      /* the sensor's values from linear Rec. 709, row-major (film_sensor_maps) */
    bool film_map;         /* film applies (a camera sensor or render.white_balance) */
    double film[9];        /* film_sensor_maps' output RGB from linear Rec. 709, after the clamp */
    uint32_t qmc_dims;     /* RENDER_SOBOL_DIMS with the Sobol sampler, else 0 */
    bool lens, shutter;    /* the camera has a lens aperture, a shutter interval */
    bool trace_aovs;       /* depth, albedo or normal layers */
    bool squares;          /* keep the sums of squares (noise estimates) */
} sample_params;

/* What one sample adds to its pixel. */
typedef struct sample_value {
    color L;                /* radiance (0 when the estimator returned a non-finite value) */
    bool nonfinite;         /* the estimator returned NaN or infinity (counted, added as 0) */
    double alpha;           /* 1 - transmittance, or 1 on a surface; counted when sidx < JOB_ALPHA_SAMPLES */
    double aov[JOB_AOVS];   /* depth, hit, albedo RGB, normal XYZ of the first vertex */
} sample_value;

/* Sample sidx of pixel (x, y), index i: its random sequence, positioned after the camera's
 * numbers, and its ray. Dimensions: the filter's offset takes the first pair, then the lens
 * (two) and the shutter (one) when the camera has them; the path the rest. */
static inline void sample_camera(const camera *cam, const sample_params *sp, size_t i, int x, int y, uint32_t sidx,
                                 rng *g, ray *r)
{
    *g = rng_make_qmc(sp->seed, (uint64_t)i, sidx, sp->qmc_dims);
    double dx, dy, u1 = 0.5, u2 = 0.5, ut = 0.5;
    film_sample_filter(sp->filter, sp->filter_width, g, &dx, &dy);
    if (sp->lens) {
        u1 = rng_next(g);
        u2 = rng_next(g);
    }
    if (sp->shutter)
        ut = rng_next(g);
    *r = camera_ray(cam, sp->width, sp->height, x + 0.5 + dx, y + 0.5 + dy, u1, u2, ut);
}

/* With sp->trace_aovs, the first vertex along r (its own dimensions of g, from
 * AOV_DIMENSION on) into v's layers; else the layers are zero. */
static inline void sample_aovs(const brume_scene *s, const sample_params *sp, ray r, rng g, sample_value *v)
{
    if (sp->trace_aovs) {
        rng ga = g;
        ga.counter += AOV_DIMENSION;
        first_vertex fv;
        integrator_first_vertex(s, r, &ga, &fv);
        v->aov[0] = fv.hit ? fv.depth : 0.0;
        v->aov[1] = fv.hit ? 1.0 : 0.0;
        for (int c = 0; c < 3; c++)
            v->aov[2 + c] = fv.albedo.c[c];
        v->aov[5] = fv.normal.x;
        v->aov[6] = fv.normal.y;
        v->aov[7] = fv.normal.z;
    } else {
        for (int a = 0; a < JOB_AOVS; a++) /* not added (sample_add), but defined */
            v->aov[a] = 0.0;
    }
}

/* pbrt-v4's maxcomponentvalue (RGBFilm::AddSample): a sample whose largest sensor value
 * exceeds max_component is scaled down to it, before the pixel filter's weight. The sensor's
 * values are sensor (3 x 3, row-major) times brume's linear Rec. 709: CIE X, Y, Z for pbrt-v4's
 * default cie1931 sensor, a camera's raw r, g, b for a named one (render/film_sensor.c); the
 * whole colour is scaled alike. A clamp: it lowers the mean of every pixel whose samples exceed
 * it (a bias), in exchange for the fireflies. A NaN or an infinity stays non-finite (sample_set
 * counts it). */
static inline color sample_clamp(color L, double max_component, const double sensor[9])
{
    if (!(max_component > 0.0))
        return L;
    double r = L.c[0], g = L.c[1], b = L.c[2], m = -INFINITY;
    for (int k = 0; k < 3; k++)
        m = fmax(m, sensor[3 * k] * r + sensor[3 * k + 1] * g + sensor[3 * k + 2] * b);
    return m > max_component ? col_scale(L, max_component / m) : L;
}

/* The estimator's radiance L, clamped and mapped by the film as sp says, whether the camera
 * ray ended on a surface (opaque) and its transmittance T, as the sample's value. */
static inline void sample_set(sample_value *v, const sample_params *sp, color L, bool opaque, color T)
{
    L = sample_clamp(L, sp->max_component, sp->sensor);
    if (sp->film_map) /* pbrt-v4 maps the sensor's values to its output after clamping them */
        L = col_rgb(sp->film[0] * L.c[0] + sp->film[1] * L.c[1] + sp->film[2] * L.c[2],
                    sp->film[3] * L.c[0] + sp->film[4] * L.c[1] + sp->film[5] * L.c[2],
                    sp->film[6] * L.c[0] + sp->film[7] * L.c[1] + sp->film[8] * L.c[2]);
    v->nonfinite = !col_isfinite(L);
    v->L = v->nonfinite ? col(0.0) : L; /* a failed sample counts as black */
    v->alpha = opaque ? 1.0 : 1.0 - col_avg(T);
}

/* The sample's radiance along r with the sequence g (from sample_camera), its alpha (on
 * the first JOB_ALPHA_SAMPLES samples only: a smooth estimator that needs few samples, and
 * no cost for the others) and, with sp->trace_aovs, its first vertex. */
static inline void sample_eval(const brume_scene *s, const void *state, const sample_params *sp, ray r, rng g,
                               uint32_t sidx, sample_value *v)
{
    sample_aovs(s, sp, r, g, v);
    bool opaque = false;
    stats_counters *sc = stats_tls;
    double t0 = sc ? stats_now() : 0.0;
    color T = col(1.0);
    color L = integrator_Li((integrator_kind)sp->kind, s, state, r, &g, &opaque, sidx < JOB_ALPHA_SAMPLES ? &T : NULL);
    if (sc) {
        sc->t_li += stats_now() - t0;
        sc->camera_rays++;
    }
    sample_set(v, sp, L, opaque, T);
}

/* Adds sample sidx's value to its pixel's sums (JOB_SUMS), squares (JOB_SQS, with
 * sp->squares) and layers (JOB_AOVS, with sp->trace_aovs). */
static inline void sample_add(const sample_params *sp, const sample_value *v, uint32_t sidx, double *sum, double *sq,
                              double *aov)
{
    for (int c = 0; c < 3; c++)
        sum[c] += v->L.c[c];
    if (sp->squares) {
        for (int c = 0; c < 3; c++)
            sq[c] += v->L.c[c] * v->L.c[c];
        double yv = (v->L.c[0] + v->L.c[1] + v->L.c[2]) / 3.0;
        sq[3] += yv * yv;
    }
    if (sidx < JOB_ALPHA_SAMPLES)
        sum[3] += v->alpha;
    if (sp->trace_aovs)
        for (int a = 0; a < JOB_AOVS; a++)
            aov[a] += v->aov[a];
}

#endif
