/* bench_render.c - path-tracer throughput and time to a given error on a scene.
 *
 *   build/bench/bench_render [SCENE.json] [--width W --height H] [--ref-spp N] [--target E]
 *                            [--method NAME] [--threads N] [--ref OUT.exr]
 *
 * Renders a reference with N spp (default 1024), then the same scene at 1, 2, 4, ... spp
 * with other seeds, each timed (median of 3 runs for the short ones) and compared with the
 * reference: relative RMSE (rmse / mean of the reference), with the reference's own noise
 * removed (the two are independent: measured^2 = err^2 (1 + n / N)). The time to relative RMSE E
 * (default 0.01) follows from err ~ 1/sqrt(spp) fitted on the last point. Prints samples
 * per second, and the machine. */
#include "bench_common.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brume.h"
#include "core/progress.h"

static brume_image *render(const char *path, const brume_render_settings *base, int spp, uint64_t seed, double *secs)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    brume_image *img = NULL;
    if ((path ? brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) : brume_scene_load(ctx, NULL, NULL, &s)) != BRUME_OK) {
        fprintf(stderr, "bench_render: %s\n", brume_context_last_error(ctx));
        exit(1);
    }
    brume_render_settings rs = *base;
    rs.spp = spp;
    rs.seed = seed;
    if (brume_scene_set_settings(ctx, s, &rs) != BRUME_OK || brume_scene_commit(ctx, s) != BRUME_OK) {
        fprintf(stderr, "bench_render: %s\n", brume_context_last_error(ctx));
        exit(1);
    }
    double t0 = progress_now();
    if (brume_render(ctx, s, &img) != BRUME_OK) {
        fprintf(stderr, "bench_render: %s\n", brume_context_last_error(ctx));
        exit(1);
    }
    *secs = progress_now() - t0;
    brume_scene_release(s);
    brume_context_release(ctx);
    return img;
}

int main(int argc, char **argv)
{
    const char *scene = NULL, *ref_out = NULL, *method = NULL;
    int width = 0, height = 0, ref_spp = 1024, threads = 0;
    double target = 0.01;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--width") && i + 1 < argc) width = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--height") && i + 1 < argc) height = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--ref-spp") && i + 1 < argc) ref_spp = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc) threads = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--target") && i + 1 < argc) target = atof(argv[++i]);
        else if (!strcmp(argv[i], "--ref") && i + 1 < argc) ref_out = argv[++i];
        else if (!strcmp(argv[i], "--method") && i + 1 < argc) method = argv[++i];
        else if (argv[i][0] != '-') scene = argv[i];
        else {
            fprintf(stderr, "bench_render: unknown argument %s\n", argv[i]);
            return 2;
        }
    }
    bench_machine();
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if ((scene ? brume_scene_load(ctx, &(brume_source){.path = scene}, NULL, &s) : brume_scene_load(ctx, NULL, NULL, &s)) != BRUME_OK) {
        fprintf(stderr, "bench_render: %s\n", brume_context_last_error(ctx));
        return 1;
    }
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    brume_scene_release(s);
    if (width) rs.width = width;
    if (height) rs.height = height;
    if (method && brume_method_from_name(ctx, method, &rs.method) != BRUME_OK) {
        fprintf(stderr, "bench_render: %s\n", brume_context_last_error(ctx));
        return 1;
    }
    rs.threads = threads;
    printf("scene: %s, %d x %d, method %s, threads %d\n", scene ? scene : "(default)", rs.width, rs.height,
           brume_method_name(rs.method), threads);

    double t_ref;
    brume_image *ref = render(scene, &rs, ref_spp, 1000003, &t_ref);
    double pix = (double)rs.width * rs.height;
    printf("reference: %d spp in %.2f s (%.3f M samples/s)\n", ref_spp, t_ref, pix * ref_spp / t_ref * 1e-6);
    if (ref_out)
        brume_image_write(ctx, ref, ref_out, NULL);
    printf("%6s %10s %10s %12s\n", "spp", "seconds", "rel_rmse", "Msamples/s");
    double last_err = 0.0, last_t = 0.0;
    int last_spp = 0;
    for (int spp = 1; spp <= ref_spp / 16; spp *= 2) {
        double times[3];
        int runs = spp <= 16 ? 3 : 1;
        brume_image *img = NULL;
        for (int r = 0; r < runs; r++) {
            brume_image_release(img);
            img = render(scene, &rs, spp, 7 + (uint64_t)spp, &times[r]);
        }
        double t = bench_median(times, runs);
        image_diff_stats st;
        image_compare(img, ref, &st);
        double err = bench_error_without_reference(st.rel_rmse, spp, ref_spp);
        printf("%6d %10.3f %10.4f %12.3f\n", spp, t, err, pix * spp / t * 1e-6);
        last_err = err;
        last_t = t;
        last_spp = spp;
        brume_image_release(img);
    }
    double spp_needed = last_spp * (last_err / target) * (last_err / target);
    printf("time to relative RMSE %.3g: %.2f s (about %.0f spp, from %d spp at %.4f)\n", target,
           last_t * spp_needed / last_spp, spp_needed, last_spp, last_err);
    brume_image_release(ref);
    brume_context_release(ctx);
    return 0;
}
