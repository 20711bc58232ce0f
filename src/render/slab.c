/* slab.c - Rd and Tt of a plane-parallel slab by the renderer's own random walk. */
#include "render/slab.h"

#include <stdlib.h>

#include "core/error.h"
#include "core/pool.h"
#include "render/integrator.h"
#include "scene/scene.h"

#define SLAB_BATCH 4096
#define SLAB_HALF_WIDTH 1e9     /* lateral extent: photons never leave sideways */
#define SLAB_SEMI_INFINITE 1e9  /* depth standing for tau = 0 */
#define SLAB_SOBOL_DIMS 8       /* as the renderer's camera samples (render.c) */

typedef struct slab_sums {
    double r, r2, t, t2;
} slab_sums;

typedef struct slab_job {
    const brume_scene *s;
    const slab_params *p;
    slab_sums *sums; /* one per batch */
} slab_job;

static void slab_batch(size_t batch, int thread, void *user)
{
    (void)thread;
    slab_job *job = user;
    const slab_params *p = job->p;
    uint64_t first = (uint64_t)batch * SLAB_BATCH;
    uint64_t last = first + SLAB_BATCH < p->samples ? first + SLAB_BATCH : p->samples;
    slab_sums acc = {0, 0, 0, 0};
    for (uint64_t i = first; i < last; i++) {
        rng g = p->sampler == BRUME_SAMPLER_SOBOL ? rng_make_qmc(p->seed, i >> 32, (uint32_t)i, SLAB_SOBOL_DIMS)
                                                  : rng_make(p->seed, i, 0);
        flight f = {.s = job->s, .g = &g, .beta = col(1.0), .L = col(0.0)};
        ray r = {v3(0, 0, 0), v3(0, 0, -1), 0.0}; /* enters the lit face z = 0 going down */
        double rd = 0.0, td = 0.0; /* this photon's reflected and transmitted weight */
        for (int depth = 0;; depth++) {
            f.tail_Tr = depth > 0 ? FLIGHT_TAIL_TR : 0.0; /* as the path tracer's flights */
            bool scattered = flight_run(&f, r, INFINITY, &g);
            double w = col_avg(col_mul(f.beta, f.Tr)); /* the part that leaves the slab */
            if (r.d.z > 0.0)
                rd += w;
            else
                td += w;
            if (!scattered || depth >= p->max_depth)
                break;
            f.beta = f.beta_s;
            double pdf;
            vec3 wo = phase_sample(p->ph, r.d, rng_next(&g), rng_next(&g), &pdf);
            r = (ray){ray_at(r, f.t), wo, 0.0};
            if (!path_roulette(&f.beta, depth, &g))
                break;
        }
        acc.r += rd;
        acc.r2 += rd * rd;
        acc.t += td;
        acc.t2 += td * td;
    }
    job->sums[batch] = acc;
}

brume_status slab_run(const slab_params *p, slab_result *out)
{
    if (!(p->albedo >= 0.0 && p->albedo <= 1.0))
        return err_set(BRUME_ERROR_RANGE, "slab: albedo %.17g outside [0, 1]", p->albedo);
    if (!(p->tau >= 0.0 && p->tau < 1e6))
        return err_set(BRUME_ERROR_RANGE, "slab: tau %.17g outside [0, 1e6) (0 = semi-infinite)", p->tau);
    if (p->tau == 0.0 && p->albedo >= 1.0 && p->max_depth > 1000)
        return err_set(BRUME_ERROR_RANGE, "slab: a semi-infinite medium of albedo 1 never absorbs; give tau > 0");
    if (p->samples < 1 || p->samples > (1ULL << 40))
        return err_set(BRUME_ERROR_RANGE, "slab: samples %llu outside [1, 2^40]", (unsigned long long)p->samples);
    if (p->max_depth < 1)
        return err_set(BRUME_ERROR_RANGE, "slab: max_depth %d must be >= 1", p->max_depth);

    brume_scene *s = scene_new("<slab>");
    if (!s)
        return err_status();
    double depth = p->tau > 0.0 ? p->tau : SLAB_SEMI_INFINITE;
    float *one = malloc(sizeof *one);
    if (!one) {
        brume_scene_release(s);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "slab: out of memory");
    }
    one[0] = 1.0f;
    box3 b = {v3(-SLAB_HALF_WIDTH, -SLAB_HALF_WIDTH, -depth), v3(SLAB_HALF_WIDTH, SLAB_HALF_WIDTH, 0.0)};
    medium *m = &s->media[0];
    m->rho = density_new_grid(1, 1, 1, one, b, GRID_NEAREST);
    if (!m->rho) {
        free(one);
        brume_scene_release(s);
        return err_status();
    }
    m->sigma_s = col(p->albedo);
    m->sigma_a = col(1.0 - p->albedo);
    m->Le = col(0.0);
    m->ph = (phase *)p->ph; /* borrowed: detached before release */
    s->nmedia = 1;
    medium_init(m);
    s->flight_control = scene_flight_control(s);
    s->committed = true;

    size_t nbatch = (size_t)((p->samples + SLAB_BATCH - 1) / SLAB_BATCH);
    slab_sums *sums = calloc(nbatch, sizeof *sums);
    brume_status st = BRUME_OK;
    if (!sums) {
        st = err_set(BRUME_ERROR_OUT_OF_MEMORY, "slab: out of memory");
    } else {
        slab_job job = {s, p, sums};
        pool_run(p->threads, nbatch, slab_batch, &job);
        slab_sums tot = {0, 0, 0, 0};
        for (size_t i = 0; i < nbatch; i++) { /* fixed order: same sums for any thread count */
            tot.r += sums[i].r;
            tot.r2 += sums[i].r2;
            tot.t += sums[i].t;
            tot.t2 += sums[i].t2;
        }
        double n = (double)p->samples;
        out->Rd = tot.r / n;
        out->Tt = tot.t / n;
        out->Rd_stderr = sqrt(fmax(0.0, tot.r2 / n - out->Rd * out->Rd) / n);
        out->Tt_stderr = sqrt(fmax(0.0, tot.t2 / n - out->Tt * out->Tt) / n);
        out->Tc = p->tau > 0.0 ? exp(-p->tau) : 0.0;
    }
    free(sums);
    m->ph = NULL;
    brume_scene_release(s);
    return st;
}
