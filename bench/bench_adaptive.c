/* bench_adaptive.c - adaptive sampling (a noise target) against uniform sampling at equal
 * time, on the default scene and on scenes/cloud64.json: the error of each against a long
 * uniform reference, and the time uniform sampling needs to reach adaptive's error.
 *
 * Error: the RMS over pixels of the relative error of the pixel's channel mean y against
 * the reference, (y - y_ref) / max(y_ref, 1e-3), with the reference's own variance (from its
 * variance layer) subtracted, so a finite reference does not inflate it. Uniform sampling's
 * error falls as 1 / sqrt(samples), so at a measured (time t_u, error e_u) it reaches error
 * e in t_u (e_u / e)^2; the ratio (adaptive's time) / (uniform's time to adaptive's error) is
 * the figure (floor for the default scene: 0.7). Runs alternate uniform, adaptive, three
 * times, and the medians are reported: the machine is shared.
 *
 * Two more figures explain the first. The cost of a sample, adaptive's over uniform's
 * (seconds per sample): adaptive sampling spends its samples where the noise is, and when
 * those are the costly pixels (a cloud's interior against the sky) each of its samples
 * costs more. And the same ratio for the 95th percentile of the per-pixel relative error
 * |y - y_ref| / max(y_ref, 1e-3) instead of the RMS: what a noise target bounds is each
 * pixel's error, the visible noise of the worst regions (docs/render-jobs.md derives why
 * a per-pixel target cannot beat uniform sampling on the RMS when cost and variance go
 * together).
 *
 *   bench_adaptive [REFERENCE_SPP]   (default 1024; references are cached in the working
 *                                     folder as adaptive-ref-*.exr) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_common.h"
#include "brume.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct setup {
    const char *name, *path; /* path NULL: the default scene */
    int width, height;
    double noise;            /* adaptive sampling's target */
} setup;

static brume_scene *scene_for(brume_context *ctx, const setup *su, int spp, double noise, unsigned aovs)
{
    brume_scene *s = NULL;
    brume_status st = su->path ? brume_scene_load(ctx, &(brume_source){.path = su->path}, NULL, &s) : brume_scene_load(ctx, NULL, NULL, &s);
    if (st != BRUME_OK) {
        fprintf(stderr, "bench_adaptive: %s\n", brume_context_last_error(ctx));
        exit(1);
    }
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    rs.width = su->width;
    rs.height = su->height;
    rs.spp = spp;
    rs.noise_target = noise;
    rs.time_budget = 0.0;
    rs.min_spp = 16;
    rs.threads = 0;
    rs.aovs = aovs;
    if (brume_scene_set_settings(ctx, s, &rs) != BRUME_OK || brume_scene_commit(ctx, s) != BRUME_OK) {
        fprintf(stderr, "bench_adaptive: %s\n", brume_context_last_error(ctx));
        exit(1);
    }
    return s;
}

/* Renders; returns the image, the seconds of the render (the integrator's preparation
 * excluded: it is done by a first render of the same scene object) and the samples taken. */
static brume_image *render(brume_context *ctx, brume_scene *s, double *seconds, double *samples)
{
    brume_render_job *job = NULL;
    if (brume_render_begin(ctx, s, &job) != BRUME_OK) {
        fprintf(stderr, "bench_adaptive: %s\n", brume_context_last_error(ctx));
        exit(1);
    }
    double t0 = now();
    brume_image *img = NULL;
    if (brume_render_job_run(ctx, job) != BRUME_OK || brume_render_job_image(ctx, job, &img) != BRUME_OK) {
        fprintf(stderr, "bench_adaptive: %s\n", brume_context_last_error(ctx));
        exit(1);
    }
    *seconds = now() - t0;
    brume_render_progress p;
    brume_render_job_progress(job, &p);
    *samples = (double)p.done;
    brume_render_job_release(job);
    return img;
}

/* RMS relative error of img's channel mean against ref (bias of the reference removed). */
static double rel_error(const brume_image *img, const brume_image *ref)
{
    int n = brume_image_width(ref) * brume_image_height(ref);
    const float *a = brume_image_pixels(img), *r = brume_image_pixels(ref);
    int v = bench_layer(ref, "variance");
    const float *var = v >= 0 ? brume_image_layer_pixels(ref, v) : NULL;
    double sum = 0.0;
    for (int i = 0; i < n; i++) {
        double y = ((double)a[4 * i] + (double)a[4 * i + 1] + (double)a[4 * i + 2]) / 3.0;
        double yr = ((double)r[4 * i] + (double)r[4 * i + 1] + (double)r[4 * i + 2]) / 3.0;
        double sd = var ? (sqrt((double)var[3 * i]) + sqrt((double)var[3 * i + 1]) + sqrt((double)var[3 * i + 2])) / 3.0 : 0.0;
        double d = fmax(yr, 1e-3);
        sum += ((y - yr) * (y - yr) - sd * sd) / (d * d);
    }
    return sqrt(fmax(sum / n, 0.0));
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The q-quantile over pixels of img's relative error against ref. */
static double rel_error_quantile(const brume_image *img, const brume_image *ref, double q)
{
    int n = brume_image_width(ref) * brume_image_height(ref);
    const float *a = brume_image_pixels(img), *r = brume_image_pixels(ref);
    double *e = malloc((size_t)n * sizeof *e);
    if (!e) {
        fprintf(stderr, "bench_adaptive: out of memory\n");
        exit(1);
    }
    for (int i = 0; i < n; i++) {
        double y = ((double)a[4 * i] + (double)a[4 * i + 1] + (double)a[4 * i + 2]) / 3.0;
        double yr = ((double)r[4 * i] + (double)r[4 * i + 1] + (double)r[4 * i + 2]) / 3.0;
        e[i] = fabs(y - yr) / fmax(yr, 1e-3);
    }
    qsort(e, (size_t)n, sizeof *e, cmp_double);
    double v = e[(int)(q * (n - 1))];
    free(e);
    return v;
}

static void bench(const setup *su, int ref_spp)
{
    brume_context *ctx = brume_context_new();
    char ref_path[256];
    snprintf(ref_path, sizeof ref_path, "adaptive-ref-%s-%dx%d-%d.exr", su->name, su->width, su->height, ref_spp);
    brume_image *ref = NULL;
    if (brume_image_read(ctx, ref_path, &ref) != BRUME_OK || bench_layer(ref, "variance") < 0) {
        brume_image_release(ref);
        brume_scene *s = scene_for(ctx, su, ref_spp, 0.0, BRUME_AOV_VARIANCE);
        double secs, samples;
        ref = render(ctx, s, &secs, &samples);
        printf("%s: reference %d spp at %d x %d in %.1f s\n", su->name, ref_spp, su->width, su->height, secs);
        brume_image_write(ctx, ref, ref_path, NULL);
        brume_scene_release(s);
    }
    /* warm: the scenes' integrator preparation (nothing for path) and the caches */
    brume_scene *uni = scene_for(ctx, su, 64, 0.0, 0), *ada = scene_for(ctx, su, 4096, su->noise, 0);
    enum { RUNS = 3 };
    double t_u[RUNS], e_u[RUNS], t_a[RUNS], e_a[RUNS], ratio[RUNS], eq[RUNS], work[RUNS], cost[RUNS], ratio95[RUNS];
    for (int k = 0; k < RUNS; k++) {
        double su_samples, sa_samples;
        brume_image *iu = render(ctx, uni, &t_u[k], &su_samples);
        brume_image *ia = render(ctx, ada, &t_a[k], &sa_samples);
        e_u[k] = rel_error(iu, ref);
        e_a[k] = rel_error(ia, ref);
        /* uniform's time to adaptive's error, and uniform's error at adaptive's time */
        double t_needed = t_u[k] * (e_u[k] / e_a[k]) * (e_u[k] / e_a[k]);
        ratio[k] = t_a[k] / t_needed;
        eq[k] = e_a[k] / (e_u[k] * sqrt(t_u[k] / t_a[k]));
        work[k] = sa_samples / (su_samples * (e_u[k] / e_a[k]) * (e_u[k] / e_a[k]));
        cost[k] = (t_a[k] / sa_samples) / (t_u[k] / su_samples);
        double p_u = rel_error_quantile(iu, ref, 0.95), p_a = rel_error_quantile(ia, ref, 0.95);
        ratio95[k] = t_a[k] / (t_u[k] * (p_u / p_a) * (p_u / p_a));
        printf("%s run %d: uniform 64 spp %.2f s error %.4f | adaptive (target %.3g) %.2f s, %.1f spp mean, "
               "error %.4f | time to uniform's error %.2f x, error at equal time %.2f x, samples %.2f x, "
               "cost of a sample %.2f x | 95th percentile error %.4f vs %.4f: time to uniform's %.2f x\n",
               su->name, k, t_u[k], e_u[k], su->noise, t_a[k], sa_samples / (su->width * su->height), e_a[k],
               ratio[k], eq[k], work[k], cost[k], p_u, p_a, ratio95[k]);
        brume_image_release(iu);
        brume_image_release(ia);
        fflush(stdout);
    }
    printf("%s: median time to reach uniform's error %.2f x uniform's time; median error at equal time %.2f x "
           "uniform's; samples %.2f x; cost of a sample %.2f x; time to uniform's 95th-percentile error %.2f x\n",
           su->name, bench_median(ratio, RUNS), bench_median(eq, RUNS), bench_median(work, RUNS),
           bench_median(cost, RUNS), bench_median(ratio95, RUNS));
    brume_scene_release(uni);
    brume_scene_release(ada);
    brume_image_release(ref);
    brume_context_release(ctx);
}

int main(int argc, char **argv)
{
    int ref_spp = argc > 1 ? atoi(argv[1]) : 1024;
    if (ref_spp < 16) {
        fprintf(stderr, "usage: bench_adaptive [REFERENCE_SPP >= 16]\n");
        return 2;
    }
    bench_machine();
    const setup setups[2] = {{"default", NULL, 240, 160, 0.05},
                             {"cloud64", BRUME_SOURCE_DIR "/scenes/cloud64.json", 128, 128, 0.05}};
    for (int i = 0; i < 2; i++)
        bench(&setups[i], ref_spp);
    return 0;
}
