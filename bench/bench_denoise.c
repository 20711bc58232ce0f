/* bench_denoise.c - the denoiser (brume_denoise, docs/denoise.md) at equal time against the
 * raw image, on the default scene, scenes/cloud64.json and scenes/wdas-dense.json, measured
 * against a long reference of another seed.
 *
 * Equal time: the raw image is a render with a time budget of T seconds and no layers; the
 * denoised one a render with the layers the denoiser reads (variance, albedo, normal, depth:
 * they cost a first-vertex walk per sample) and a budget of T less the denoiser's measured
 * time, then brume_denoise. Both budgets include the integrator's preparation.
 *
 * Error: relative MSE, the mean over pixels and channels of (x - r)^2 / (r^2 + 0.01)
 * (Rousselle et al. 2011) against the reference r, with the reference's own variance (its
 * variance layer) subtracted from each term, so a finite reference does not inflate it.
 * Bias, reported apart: the denoised image's mean over the image and over 32 x 32 blocks
 * against the reference's, relative, beside the same figures for the raw image (unbiased: its
 * deviations, mean and block, are the noise floor of those figures).
 *
 * With BENCH_SPP=N in the environment both images have N samples per pixel instead (equal
 * samples: the layers' and the denoiser's time are then printed, not compensated).
 *
 *   bench_denoise [SECONDS [REFERENCE_SPP [SCENES]]]   (default 5 and 1024; references cached in
 *                   the working folder as denoise-ref-NAME-SPP.exr; run from the build
 *                   folder of a checkout (the scenes read the grids in data/), or set
 *                   BRUME_SCENES to the scenes folder)
 *   bench_denoise IMAGE.exr [RUNS [THREADS]]   (the denoiser alone on a render with its layers:
 *                   CPU and wall seconds of each of RUNS calls (default 5) on THREADS threads
 *                   (default 1: the CPU time of one thread is the figure that a loaded machine
 *                   disturbs least), and their minimum) */
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

static void die(brume_context *ctx, const char *what)
{
    fprintf(stderr, "bench_denoise: %s: %s\n", what, brume_context_last_error(ctx));
    exit(1);
}

/* Renders path (NULL: the default scene) with the given budget or spp; *spp the mean samples. */
static brume_image *render(brume_context *ctx, const char *path, double seconds, int spp, uint64_t seed, unsigned aovs,
                           double *spp_mean, double *wall)
{
    brume_scene *s = NULL;
    if ((path ? brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) : brume_scene_load(ctx, NULL, NULL, &s)) != BRUME_OK)
        die(ctx, path ? path : "default scene");
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    rs.spp = seconds > 0.0 ? 1 << 24 : spp;
    rs.time_budget = seconds;
    rs.noise_target = 0.0;
    rs.seed = seed;
    rs.threads = 0;
    rs.aovs = aovs;
    if (brume_scene_set_settings(ctx, s, &rs) != BRUME_OK || brume_scene_commit(ctx, s) != BRUME_OK)
        die(ctx, "settings");
    double t0 = now();
    brume_render_job *job = NULL;
    brume_image *img = NULL;
    if (brume_render_begin(ctx, s, &job) != BRUME_OK || brume_render_job_run(ctx, job) != BRUME_OK ||
        brume_render_job_image(ctx, job, &img) != BRUME_OK)
        die(ctx, "render");
    *wall = now() - t0;
    brume_render_progress p;
    brume_render_job_progress(job, &p);
    *spp_mean = p.spp_mean;
    brume_render_job_release(job);
    brume_scene_release(s);
    return img;
}

/* Relative MSE of img against ref, the reference's variance removed. */
static double rel_mse(const brume_image *img, const brume_image *ref)
{
    int n = brume_image_width(ref) * brume_image_height(ref);
    const float *a = brume_image_pixels(img), *r = brume_image_pixels(ref);
    const float *var = brume_image_layer_pixels(ref, bench_layer(ref, "variance"));
    double sum = 0.0;
    for (int i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            double d = (double)a[4 * i + c] - (double)r[4 * i + c];
            sum += (d * d - (double)var[3 * i + c]) / ((double)r[4 * i + c] * (double)r[4 * i + c] + 0.01);
        }
    return sum / (3.0 * n);
}

/* Bias figures: the relative difference of the image's mean luminance from the reference's
 * over the whole image, and the largest over 32 x 32 blocks with signal (mean reference
 * luminance above 10 % of the image's). */
static void bias(const brume_image *img, const brume_image *ref, double *whole, double *worst)
{
    int w = brume_image_width(ref), h = brume_image_height(ref);
    const float *a = brume_image_pixels(img), *r = brume_image_pixels(ref);
    double sa = 0.0, sr = 0.0;
    for (int i = 0; i < w * h; i++)
        for (int c = 0; c < 3; c++) {
            sa += (double)a[4 * i + c];
            sr += (double)r[4 * i + c];
        }
    *whole = (sa - sr) / sr;
    *worst = 0.0;
    double mean_r = sr / (3.0 * w * h);
    for (int by = 0; by + 32 <= h; by += 32)
        for (int bx = 0; bx + 32 <= w; bx += 32) {
            double ba = 0.0, br = 0.0;
            for (int y = by; y < by + 32; y++)
                for (int x = bx; x < bx + 32; x++)
                    for (int c = 0; c < 3; c++) {
                        ba += (double)a[4 * (y * w + x) + c];
                        br += (double)r[4 * (y * w + x) + c];
                    }
            if (br / (3.0 * 1024) < 0.1 * mean_r)
                continue;
            double rel = (ba - br) / br;
            if (fabs(rel) > fabs(*worst))
                *worst = rel;
        }
}

/* The denoiser alone: `runs` calls of brume_denoise on the image at path, timed. */
static int time_denoiser(const char *path, int runs, int threads)
{
    brume_context *ctx = brume_context_new();
    brume_image *in = NULL;
    if (brume_image_read(ctx, path, &in) != BRUME_OK)
        die(ctx, path);
    bench_machine();
    printf("brume_denoise of %s (%d x %d), %d thread(s)\n", path, brume_image_width(in), brume_image_height(in),
           threads);
    double best_cpu = 1e30, best_wall = 1e30;
    for (int i = 0; i < runs; i++) {
        brume_image *out = NULL;
        clock_t c0 = clock();
        double t0 = now();
        if (brume_denoise(ctx, in, threads, &out) != BRUME_OK)
            die(ctx, "brume_denoise");
        double wall = now() - t0, cpu = (double)(clock() - c0) / CLOCKS_PER_SEC;
        printf("run %d: %.3f CPU s, %.3f s wall\n", i + 1, cpu, wall);
        best_cpu = fmin(best_cpu, cpu);
        best_wall = fmin(best_wall, wall);
        brume_image_release(out);
    }
    printf("minimum: %.3f CPU s, %.3f s wall\n", best_cpu, best_wall);
    brume_image_release(in);
    brume_context_release(ctx);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc > 1 && strstr(argv[1], ".exr"))
        return time_denoiser(argv[1], argc > 2 ? atoi(argv[2]) : 5, argc > 3 ? atoi(argv[3]) : 1);
    double seconds = argc > 1 ? atof(argv[1]) : 5.0;
    int ref_spp = argc > 2 ? atoi(argv[2]) : 1024;
    const char *dir = getenv("BRUME_SCENES") ? getenv("BRUME_SCENES") : "../scenes";
    char p1[4096], p2[4096];
    snprintf(p1, sizeof p1, "%s/cloud64.json", dir);
    snprintf(p2, sizeof p2, "%s/wdas-dense.json", dir);
    const char *names[3] = {"default", "cloud64", "wdas-dense"}, *paths[3] = {NULL, p1, p2};
    bench_machine();
    printf("equal time %.2f s; reference %d spp (seed 2); relMSE = mean (x - r)^2 / (r^2 + 0.01), the reference's "
           "variance removed\n", seconds, ref_spp);
    printf("%-11s %8s %8s %9s %11s %11s %7s %10s %10s %10s %10s\n", "scene", "raw spp", "den spp", "denoise s",
           "relMSE raw", "relMSE den", "ratio", "bias mean", "bias block", "raw mean", "raw block");
    const unsigned feats = BRUME_AOV_VARIANCE | BRUME_AOV_ALBEDO | BRUME_AOV_NORMAL | BRUME_AOV_DEPTH;
    for (int k = 0; k < 3; k++) {
        if (argc > 3 && !strstr(argv[3], names[k]))
            continue;
        brume_context *ctx = brume_context_new();
        char refpath[256];
        snprintf(refpath, sizeof refpath, "denoise-ref-%s-%d.exr", names[k], ref_spp);
        brume_image *ref = NULL;
        double spp, wall;
        if (brume_image_read(ctx, refpath, &ref) != BRUME_OK) {
            ref = render(ctx, paths[k], 0.0, ref_spp, 2, BRUME_AOV_VARIANCE, &spp, &wall);
            if (brume_image_write(ctx, ref, refpath, NULL) != BRUME_OK)
                die(ctx, refpath);
            fprintf(stderr, "bench_denoise: reference %s: %.1f s\n", refpath, wall);
        }
        double spp_raw = 0.0, spp_den = 0.0, w_raw = 0.0, w_den = 0.0;
        char rawpath[256];
        snprintf(rawpath, sizeof rawpath, "denoise-raw-%s.exr", names[k]);
        brume_image *raw = NULL;
        int fixed = getenv("BENCH_SPP") ? atoi(getenv("BENCH_SPP")) : 0; /* equal samples instead */
        if (!getenv("BENCH_REUSE") || brume_image_read(ctx, rawpath, &raw) != BRUME_OK) {
            raw = render(ctx, paths[k], fixed ? 0.0 : seconds, fixed, 1, 0, &spp_raw, &w_raw);
            brume_image_write(ctx, raw, rawpath, NULL);
        }
        /* the denoiser's time, measured on a first short render of the same size */
        double t_dn = 0.0;
        for (int pass = 0; pass < 2; pass++) {
            double budget = seconds - t_dn;
            char inpath[256];
            snprintf(inpath, sizeof inpath, "denoise-in-%s.exr", names[k]);
            brume_image *in = NULL;
            if (!pass || !getenv("BENCH_REUSE") || brume_image_read(ctx, inpath, &in) != BRUME_OK)
                in = render(ctx, paths[k], pass && !fixed ? budget : 0.0, pass && fixed ? fixed : 2, 1, feats, &spp_den,
                            &w_den);
            if (pass && !getenv("BENCH_REUSE"))
                brume_image_write(ctx, in, inpath, NULL);
            brume_image *out = NULL;
            double t0 = now();
            if (brume_denoise(ctx, in, 0, &out) != BRUME_OK)
                die(ctx, "denoise");
            t_dn = now() - t0;
            if (pass) {
                double e_raw = rel_mse(raw, ref), e_den = rel_mse(out, ref), b_whole, b_block, r_whole, r_block;
                bias(out, ref, &b_whole, &b_block);
                bias(raw, ref, &r_whole, &r_block);
                printf("%-11s %8.1f %8.1f %9.3f %11.4g %11.4g %6.1fx %+9.2f%% %+9.2f%% %+9.2f%% %+9.2f%%\n", names[k],
                       spp_raw, spp_den, t_dn, e_raw, e_den, e_raw / e_den, 100.0 * b_whole, 100.0 * b_block,
                       100.0 * r_whole, 100.0 * r_block);
                printf("%-11s raw render %.2f s wall, denoised render %.2f s + denoise %.2f s = %.2f s\n", "", w_raw,
                       w_den, t_dn, w_den + t_dn);
                fflush(stdout);
            }
            brume_image_release(in);
            brume_image_release(out);
        }
        brume_image_release(raw);
        brume_image_release(ref);
        brume_context_release(ctx);
    }
    return 0;
}
