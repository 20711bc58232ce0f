/* pass.c - a pass's samples on the CPU: one tile's pixels on the calling thread (render/pass.h). */
#include "render/pass.h"

#include "render/watch.h"
#include "scene/scene.h"

#define CAMERA_BATCH 8 /* camera rays made together before their radiance (pass_render_cpu) */

/* Camera samples s0 .. s0 + nb - 1 (nb <= CAMERA_BATCH) of pixel (x, y), index i: their
 * rays, and in g their random sequences positioned after the camera's numbers.
 * Dimensions: the filter's offset takes the first pair; the lens and the shutter take the
 * next ones only when the camera has them (lens, shutter); the path the rest. The first
 * qmc_dims dimensions are Sobol points (render.sampler, docs/sampling.md).
 * Made stage by stage over the batch (the sequences, then the filter's offsets, then the
 * lens and shutter numbers, then the rays): each stage is a chain of hashes, or of
 * divisions and a square root, longer than the processor can look ahead past, and the
 * samples' chains are independent, so a stage's iterations overlap where one sample's
 * whole chain at a time would leave the processor waiting. Each sample's numbers are
 * those it would draw alone (sample_camera, the GPU's). */
static void camera_samples(const camera *cam, const sample_params *sp, size_t i, int x, int y, uint32_t s0,
                           uint32_t nb, rng g[CAMERA_BATCH], ray r[CAMERA_BATCH])
{
    double dx[CAMERA_BATCH], dy[CAMERA_BATCH], u1[CAMERA_BATCH], u2[CAMERA_BATCH], ut[CAMERA_BATCH];
    for (uint32_t b = 0; b < nb; b++)
        g[b] = rng_make_qmc(sp->seed, (uint64_t)i, s0 + b, sp->qmc_dims);
    for (uint32_t b = 0; b < nb; b++)
        film_sample_filter(sp->filter, sp->filter_width, &g[b], &dx[b], &dy[b]);
    for (uint32_t b = 0; b < nb; b++) {
        u1[b] = u2[b] = ut[b] = 0.5;
        if (sp->lens) {
            u1[b] = rng_next(&g[b]);
            u2[b] = rng_next(&g[b]);
        }
        if (sp->shutter)
            ut[b] = rng_next(&g[b]);
    }
    if (camera_is_pinhole(cam)) { /* the rays made in place in the batch */
        for (uint32_t b = 0; b < nb; b++)
            camera_pinhole_ray(cam, sp->width, sp->height, x + 0.5 + dx[b], y + 0.5 + dy[b], ut[b], &r[b]);
        return;
    }
    for (uint32_t b = 0; b < nb; b++)
        r[b] = camera_ray(cam, sp->width, sp->height, x + 0.5 + dx[b], y + 0.5 + dy[b], u1[b], u2[b], ut[b]);
}

/* The samples listed pixel j still lacks up to the target, added into its count and sums,
 * until p->cut or the watch stops them (the next pixel is asked again). In batches: first the
 * batch's camera rays (camera_samples), then their radiance. With p->cut (a time budget) the
 * clock is read before every sample (some tens of nanoseconds against microseconds a sample
 * at least): the budget ends within one sample per thread, however slow a sample is. Between
 * batches the watch's poll is asked too (the job's: a slow tile's stop), so that samples
 * without collisions (a sky in a pass of 2^30) stop on a signal as the others do. */
static void pixel_samples(render_pass *p, size_t j)
{
    const sample_params *sp = &p->sp;
    const size_t i = p->pixels[j];
    const int x = (int)(i % (size_t)sp->width), y = (int)(i / (size_t)sp->width);
    double *sq = p->sq ? p->sq[j] : NULL, *aov = p->aov ? p->aov[j] : NULL;
    sample_watch *w = watch_tls;
    for (uint32_t s0 = p->n[j], s1 = p->n[j]; s0 < p->target && !(s0 > s1 && w && w->poll && w->poll(w->user));
         s0 += CAMERA_BATCH) {
        uint32_t nb = p->target - s0 < CAMERA_BATCH ? p->target - s0 : CAMERA_BATCH;
        rng gb[CAMERA_BATCH];
        ray rb[CAMERA_BATCH];
        camera_samples(&p->s->cam, sp, i, x, y, s0, nb, gb, rb);
        for (uint32_t b = 0; b < nb; b++) {
            const uint32_t sidx = s0 + b;
            if (p->cut && p->cut(p->user))
                return;
            sample_value v;
            if (w)
                watch_sample(w);
            sample_eval(p->s, p->state, sp, rb[b], gb[b], sidx, &v);
            if (w && w->stopped) /* stopped within the sample: it is not kept */
                return;
            if (w)
                w->ncut += w->cut;
            sample_add(sp, &v, sidx, p->sum[j], sq, aov);
            p->nonfinite += v.nonfinite;
            p->taken++;
            p->n[j] = sidx + 1;
        }
    }
}

void pass_render_cpu(render_pass *p)
{
    for (size_t j = 0; j < p->npixels; j++)
        pixel_samples(p, j);
}
