/* bench_blasi.c - the blasi integrator's two passes timed, and its time to equal error
 * against the path tracer (docs/blasi.md).
 *
 *   build/bench/bench_blasi [SCENE.json] [--runs N] [--cmp-size W] [--ref-spp N] [--ref OUT.exr]
 *
 * SCENE defaults to scenes/blasi-picture1.json (the paper's configuration: 65 x 65 x 10
 * grid, 2^21 light rays, 400 x 400 x 10 view rays).
 *   1. first pass: blasi_prepare alone, median of N runs (default 5), threads 1 and 2;
 *   2. second pass: the render with the first pass loaded from a file (--load-light), minus
 *      the median time of loading it, threads 1 and 2;
 *   3. time to equal error: at W x W (default 200) a path-traced reference with --ref-spp
 *      spp (default 512); blasi's relative RMSE against it (both passes, 2 threads); then
 *      path at 1, 2, 4, ... spp with other seeds: the time at which path's relative RMSE
 *      (reference noise removed) falls to blasi's, interpolated as err ~ 1 / sqrt(spp). */
#include "bench_common.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "brume.h"
#include "core/progress.h"
#include "io/compare.h"
#include "render/blasi.h"
#include "render/scene.h"

static void die(brume_context *ctx)
{
    fprintf(stderr, "bench_blasi: %s\n", brume_context_last_error(ctx));
    exit(1);
}

/* A committed scene with settings and options changed. */
static brume_scene *load(const char *path, const char *method, int threads, int size, int spp, uint64_t seed,
                         const char *opt_key, const char *opt_value)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, path, &s) != BRUME_OK)
        die(ctx);
    brume_render_settings rs;
    brume_scene_get_settings(s, &rs);
    snprintf(rs.method, sizeof rs.method, "%s", method);
    rs.threads = threads;
    rs.progress = false;
    if (size) rs.width = rs.height = size;
    if (spp) rs.spp = spp;
    rs.seed = seed;
    if (brume_scene_set_settings(ctx, s, &rs) != BRUME_OK)
        die(ctx);
    if (opt_key && brume_scene_set_option(ctx, s, opt_key, opt_value) != BRUME_OK)
        die(ctx);
    if (brume_scene_commit(ctx, s) != BRUME_OK)
        die(ctx);
    brume_context_release(ctx);
    return s;
}

static brume_image *render(brume_scene *s, double *secs)
{
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    double t0 = progress_now();
    if (brume_render(ctx, s, &img) != BRUME_OK)
        die(ctx);
    *secs = progress_now() - t0;
    brume_context_release(ctx);
    return img;
}

#define MAX_RUNS 15

int main(int argc, char **argv)
{
    const char *scene = NULL, *ref_out = NULL;
    int runs = 5, cmp_size = 200, ref_spp = 512;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--runs") && i + 1 < argc) runs = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--cmp-size") && i + 1 < argc) cmp_size = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--ref-spp") && i + 1 < argc) ref_spp = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--ref") && i + 1 < argc) ref_out = argv[++i];
        else if (argv[i][0] != '-') scene = argv[i];
        else {
            fprintf(stderr, "bench_blasi: unknown argument %s\n", argv[i]);
            return 2;
        }
    }
    if (runs < 1 || runs > MAX_RUNS)
        runs = 5;
    /* BRUME_DATA_DIR is <source>/../shared/data: the scene is under the source tree */
    char def[1024];
    snprintf(def, sizeof def, "%s", BRUME_DATA_DIR);
    char *cut = strstr(def, "/../shared/data");
    if (cut)
        *cut = '\0';
    strncat(def, "/scenes/blasi-picture1.json", sizeof def - strlen(def) - 1);
    if (!scene)
        scene = def;
    bench_machine();
    brume_scene *s0 = load(scene, "blasi", 0, 0, 0, 1, NULL, NULL);
    printf("scene: %s, %d x %d, %d spp (%.2f M view rays), %llu light rays, variant: exit %s, view %s\n", scene,
           s0->settings.width, s0->settings.height, s0->settings.spp,
           (double)s0->settings.width * s0->settings.height * s0->settings.spp * 1e-6,
           (unsigned long long)((const blasi_options *)scene_options(s0, METHOD_OPTIONS_BLASI))->light_rays, ((const blasi_options *)scene_options(s0, METHOD_OPTIONS_BLASI))->exit_deposit == BLASI_EXIT_PAPER ? "paper" : "none",
           ((const blasi_options *)scene_options(s0, METHOD_OPTIONS_BLASI))->view_attenuation == BLASI_VIEW_ABSORPTION ? "absorption" : "extinction");
    brume_scene_release(s0);

    /* 1 and 2: the two passes */
    char light_file[512];
    snprintf(light_file, sizeof light_file, "/tmp/bench_blasi_%d.light", (int)getpid());
    printf("%8s %14s %14s %14s %14s\n", "threads", "pass 1 (s)", "M light rays/s", "pass 2 (s)", "M view rays/s");
    for (int threads = 1; threads <= 2; threads++) {
        double t1[MAX_RUNS], tl[MAX_RUNS], tr[MAX_RUNS];
        blasi_stats bs = {0};
        for (int r = 0; r < runs; r++) {
            brume_scene *s = load(scene, "blasi", threads, 0, 0, 1, r == 0 ? "blasi.save_light" : NULL, light_file);
            blasi_state *st = NULL;
            if (blasi_prepare(s, &st) != BRUME_OK) {
                fprintf(stderr, "bench_blasi: first pass failed\n");
                return 1;
            }
            blasi_get_stats(st, &bs);
            t1[r] = bs.light_seconds;
            blasi_finish(st);
            brume_scene_release(s);
        }
        uint64_t nrays = bs.light_rays, inter = bs.interceptions;
        int w = 0, h = 0, spp = 0;
        for (int r = 0; r < runs; r++) {
            brume_scene *s = load(scene, "blasi", threads, 0, 0, 1, "blasi.load_light", light_file);
            blasi_state *st = NULL;
            if (blasi_prepare(s, &st) != BRUME_OK) {
                fprintf(stderr, "bench_blasi: loading failed\n");
                return 1;
            }
            blasi_get_stats(st, &bs);
            tl[r] = bs.light_seconds;
            blasi_finish(st);
            brume_image *img = render(s, &tr[r]);
            w = s->settings.width;
            h = s->settings.height;
            spp = s->settings.spp;
            brume_image_release(img);
            brume_scene_release(s);
        }
        double p1 = bench_median(t1, runs), p2 = bench_median(tr, runs) - bench_median(tl, runs);
        printf("%8d %14.3f %14.3f %14.3f %14.3f\n", threads, p1, (double)nrays / p1 * 1e-6, p2,
               (double)w * h * spp / p2 * 1e-6);
        if (threads == 2)
            printf("first pass: %llu interceptions (%.1f per light ray); both passes on 2 threads: %.3f s\n",
                   (unsigned long long)inter, (double)inter / (double)nrays, p1 + p2);
    }
    remove(light_file);

    /* 3: time to equal error against path on the same scene */
    double t_ref;
    brume_scene *sr = load(scene, "path", 0, cmp_size, ref_spp, 1000003, NULL, NULL);
    brume_image *ref = render(sr, &t_ref);
    brume_scene_release(sr);
    if (ref_out) {
        brume_context *ctx = brume_context_new();
        brume_image_write(ctx, ref, ref_out, NULL);
        brume_context_release(ctx);
    }
    printf("\nat %d x %d: path reference %d spp in %.2f s\n", cmp_size, cmp_size, ref_spp, t_ref);
    double tb;
    brume_scene *sb = load(scene, "blasi", 2, cmp_size, 0, 1, NULL, NULL);
    brume_image *bimg = render(sb, &tb);
    brume_scene_release(sb);
    image_diff_stats bst;
    image_compare(bimg, ref, &bst);
    printf("blasi (both passes): %.3f s, relative RMSE %.4f, mean %.5f vs %.5f (%+.1f %%), mean |rel| %.3f, max |rel| "
           "%.3f\n",
           tb, bst.rel_rmse, bst.mean_img, bst.mean_ref, 100.0 * (bst.mean_img / bst.mean_ref - 1.0), bst.mean_rel,
           bst.max_rel);
    printf("%6s %10s %10s\n", "spp", "seconds", "rel_rmse");
    double prev_err = 0.0, prev_t = 0.0, found = -1.0;
    for (int spp = 1; spp <= ref_spp / 8; spp *= 2) {
        double t;
        brume_scene *sp = load(scene, "path", 2, cmp_size, spp, 7 + (uint64_t)spp, NULL, NULL);
        brume_image *img = render(sp, &t);
        brume_scene_release(sp);
        image_diff_stats st;
        image_compare(img, ref, &st);
        double err = sqrt(fmax(0.0, st.rel_rmse * st.rel_rmse * (1.0 - (double)spp / ref_spp)));
        printf("%6d %10.3f %10.4f\n", spp, t, err);
        brume_image_release(img);
        if (err <= bst.rel_rmse) {
            /* err ~ c / sqrt(t): the time at which the error crosses blasi's */
            double t_cross = spp == 1 ? t * (err / bst.rel_rmse) * (err / bst.rel_rmse)
                                      : prev_t * (prev_err / bst.rel_rmse) * (prev_err / bst.rel_rmse);
            found = t_cross;
            break;
        }
        prev_err = err;
        prev_t = t;
    }
    if (found >= 0.0)
        printf("time to blasi's error: path %.3f s, blasi %.3f s (ratio %.2f)\n", found, tb, tb / found);
    else
        printf("path did not reach blasi's error by %d spp: blasi is faster to this error\n", ref_spp / 8);
    brume_image_release(bimg);
    brume_image_release(ref);
    return 0;
}
