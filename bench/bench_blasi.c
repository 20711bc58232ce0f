/* bench_blasi.c - the blasi integrator's two passes timed, and its time to equal error
 * against the path tracer (docs/blasi.md).
 *
 *   build/bench/bench_blasi [SCENE.json] [--runs N] [--threads T] [--passes-only] [--cmp-size W] [--ref-spp N]
 *                           [--ref OUT.exr] [--against OTHER_BRUME]
 *
 * SCENE defaults to scenes/blasi-picture1.json (the paper's configuration: 65 x 65 x 10
 * grid, 2^21 light rays, 400 x 400 x 10 view rays).
 *   1. a fresh scene rendered twice through the public API, median of N runs (default 5),
 *      threads 1 and 2 (or T only): the first render runs both passes (the whole brume_render call);
 *      the second reuses the light pass the scene keeps between renders, so it is the
 *      view pass alone. The last line gives the two medians on 2 threads (issue 18's
 *      figures). Interleaved with the 2-thread runs, the command a user runs, timed whole
 *      process (start, scene, both passes, the PNG written, exit): `brume render SCENE -o
 *      TMP.png` (with --threads 2 where the machine has another count of cores), and `brume
 *      --version` (the process's start alone); the command's wall and CPU medians, and its
 *      ratio to both passes through the API; with --against, another brume's command in the
 *      same rounds too (an older build: before and after). --passes-only stops here.
 *   2. time to equal error: at W x W (default 200) a path-traced reference with --ref-spp
 *      spp (default 512); blasi's relative RMSE against it (both passes, 2 threads); then
 *      path at 1, 2, 4, ... spp with other seeds: the time at which path's relative RMSE
 *      (reference noise removed) falls to blasi's, interpolated as err ~ 1 / sqrt(spp). */
#include "bench_common.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "brume.h"
#include "core/progress.h"
#include "render/blasi.h"
#include "scene/scene.h"

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
    if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK)
        die(ctx);
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    if (brume_method_from_name(ctx, method, &rs.method) != BRUME_OK)
        die(ctx);
    rs.threads = threads;
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

/* CPU time of the calling thread: with one render thread the pool runs every task on the
 * caller, so this is the render's CPU time, which a loaded machine inflates far less than
 * the wall time */
static double thread_cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double last_cpu; /* CPU seconds of the calling thread in the last render() */

static brume_image *render(brume_scene *s, double *secs)
{
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    double t0 = progress_now(), c0 = thread_cpu();
    if (brume_render(ctx, s, &img) != BRUME_OK)
        die(ctx);
    *secs = progress_now() - t0;
    last_cpu = thread_cpu() - c0;
    brume_context_release(ctx);
    return img;
}

#define MAX_RUNS 15

static double seconds(struct timeval t) { return (double)t.tv_sec + 1e-6 * (double)t.tv_usec; }

/* Runs argv (stdout and stderr to /dev/null) and waits: its wall-clock seconds, from before
 * the fork to its end, and in *cpu its user + system CPU seconds. Exits on failure. */
static double run_process(char *const argv[], double *cpu)
{
    fflush(stdout); /* the child must not print this process's buffered lines again */
    double t0 = progress_now();
    pid_t pid = fork();
    if (pid < 0) {
        perror("bench_blasi: fork");
        exit(1);
    }
    if (pid == 0) {
        FILE *null = freopen("/dev/null", "w", stdout);
        if (!null || dup2(fileno(stdout), 2) < 0)
            _exit(127);
        execv(argv[0], argv);
        _exit(127);
    }
    int status = 0;
    struct rusage before, after; /* the children's totals: this one's is the difference */
    getrusage(RUSAGE_CHILDREN, &before);
    if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        fprintf(stderr, "bench_blasi: %s %s failed (status %d)\n", argv[0], argv[1], status);
        exit(1);
    }
    double wall = progress_now() - t0;
    getrusage(RUSAGE_CHILDREN, &after);
    *cpu = seconds(after.ru_utime) + seconds(after.ru_stime) - seconds(before.ru_utime) - seconds(before.ru_stime);
    return wall;
}

int main(int argc, char **argv)
{
    const char *scene = NULL, *ref_out = NULL, *against = NULL;
    int runs = 5, cmp_size = 200, ref_spp = 512, only_threads = 0;
    bool passes_only = false;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--runs") && i + 1 < argc) runs = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc) only_threads = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--cmp-size") && i + 1 < argc) cmp_size = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--ref-spp") && i + 1 < argc) ref_spp = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--ref") && i + 1 < argc) ref_out = argv[++i];
        else if (!strcmp(argv[i], "--against") && i + 1 < argc) against = argv[++i];
        else if (!strcmp(argv[i], "--passes-only")) passes_only = true;
        else if (argv[i][0] != '-') scene = argv[i];
        else {
            fprintf(stderr, "bench_blasi: unknown argument %s\n", argv[i]);
            return 2;
        }
    }
    if (only_threads < 0 || only_threads > 64) {
        fprintf(stderr, "bench_blasi: --threads must be in 1..64\n");
        return 2;
    }
    if (runs < 1 || runs > MAX_RUNS) {
        fprintf(stderr, "bench_blasi: --runs must be in 1..%d\n", MAX_RUNS);
        return 2;
    }
    if (!scene)
        scene = BRUME_SOURCE_DIR "/scenes/blasi-picture1.json";
    bench_machine();
    brume_scene *s0 = load(scene, "blasi", 0, 0, 0, 1, NULL, NULL);
    printf("scene: %s, %d x %d, %d spp (%.2f M view rays), %llu light rays, variant: exit %s, view %s\n", scene,
           s0->settings.width, s0->settings.height, s0->settings.spp,
           (double)s0->settings.width * s0->settings.height * s0->settings.spp * 1e-6,
           (unsigned long long)((const blasi_options *)scene_options(s0, METHOD_OPTIONS_BLASI))->light_rays, ((const blasi_options *)scene_options(s0, METHOD_OPTIONS_BLASI))->exit_deposit == BLASI_EXIT_PAPER ? "paper" : "none",
           ((const blasi_options *)scene_options(s0, METHOD_OPTIONS_BLASI))->view_attenuation == BLASI_VIEW_ABSORPTION ? "absorption" : "extinction");
    brume_scene_release(s0);

    /* 1: both passes (the scene's first render) and the view pass alone (a second render of
     * the same committed scene, which keeps its light pass: the library's saved light pass),
     * through the public API, as an application dragging a slider would call it */
    printf("%8s %16s %16s %14s %14s\n", "threads", "both passes (s)", "view only (s)", "M light rays/s",
           "M view rays/s");
    double both2 = 0.0, view2 = 0.0;
    uint64_t inter = 0, nrays = 0, traced = 0;
    /* the user's command: as typed on a 2-core machine (the argument list ends before
     * --threads); elsewhere with --threads 2. Its PNG goes to a fresh folder, mkdtemp's
     * (the template's six X's are mkdtemp's to fill) */
    char out_dir[] = "/tmp/bench_blasi_XXXXXX", out_png[64], threads_arg[] = "2";
    if (!mkdtemp(out_dir)) {
        perror("bench_blasi: mkdtemp");
        return 1;
    }
    snprintf(out_png, sizeof out_png, "%s/p.png", out_dir);
    const bool two_cores = sysconf(_SC_NPROCESSORS_ONLN) == 2;
    char *cli[] = {BRUME_EXE, "render", (char *)scene, "-o", out_png, two_cores ? NULL : "--threads", threads_arg, NULL};
    char *version[] = {BRUME_EXE, "--version", NULL};
    char *other[] = {(char *)against, "render", (char *)scene, "-o", out_png, two_cores ? NULL : "--threads", threads_arg, NULL};
    double cli_wall[MAX_RUNS], cli_cpu[MAX_RUNS], ver_wall[MAX_RUNS], ver_cpu[MAX_RUNS], oth_wall[MAX_RUNS], oth_cpu[MAX_RUNS];
    for (int threads = only_threads ? only_threads : 1; threads <= (only_threads ? only_threads : 2); threads++) {
        double tb[MAX_RUNS], tv[MAX_RUNS], tl[MAX_RUNS], cb[MAX_RUNS], cv[MAX_RUNS];
        int w = 0, h = 0, spp = 0;
        const bool with_cli = threads == 2;
        for (int r = 0; r < runs; r++) {
            if (with_cli) { /* interleaved: the command, then the API's renders of the same round */
                cli_wall[r] = run_process(cli, &cli_cpu[r]);
                ver_wall[r] = run_process(version, &ver_cpu[r]);
                if (against)
                    oth_wall[r] = run_process(other, &oth_cpu[r]);
            }
            brume_scene *s = load(scene, "blasi", threads, 0, 0, 1, NULL, NULL);
            brume_image *img = render(s, &tb[r]);
            cb[r] = last_cpu;
            brume_image_release(img);
            blasi_stats bs;
            blasi_get_stats(s->prepared->state, &bs);
            tl[r] = bs.light_seconds;
            nrays = bs.light_rays;
            traced = bs.traced_rays;
            inter = bs.interceptions;
            img = render(s, &tv[r]);
            cv[r] = last_cpu;
            brume_image_release(img);
            w = s->settings.width;
            h = s->settings.height;
            spp = s->settings.spp;
            brume_scene_release(s);
        }
        double both = bench_median(tb, runs), view = bench_median(tv, runs), t_light = bench_median(tl, runs);
        printf("%8d %16.3f %16.3f %14.2f %14.2f", threads, both, view, (double)nrays / t_light * 1e-6,
               (double)w * h * spp / view * 1e-6);
        if (threads == 1) /* one thread: the CPU time too, robust to load */
            printf("   CPU s: both %.3f, view %.3f", bench_median(cb, runs), bench_median(cv, runs));
        printf("\n");
        if (threads == 2 || only_threads) {
            both2 = both;
            view2 = view;
        }
    }
    printf("first pass: %llu of the %llu light rays traced (the others cannot reach a non-empty voxel), %llu "
           "interceptions (%.2f per light ray)\n",
           (unsigned long long)traced, (unsigned long long)nrays, (unsigned long long)inter,
           (double)inter / (double)nrays);
    printf("on %d threads, medians of %d: both passes %.3f s (issue 18: <= 0.25), view pass alone with the light "
           "pass kept %.3f s (<= 0.1)\n",
           only_threads ? only_threads : 2, runs, both2, view2);
    if (only_threads == 0 || only_threads == 2) {
        double cw = bench_median(cli_wall, runs), cc = bench_median(cli_cpu, runs);
        printf("the user's command, whole process, medians of %d interleaved with the 2-thread runs:\n", runs);
        printf("  %s render %s -o %s%s: %.3f s wall (issue 37: <= 0.3), %.3f CPU s; %.2f x both passes "
               "through the API\n",
               BRUME_EXE, scene, out_png, two_cores ? "" : " --threads 2", cw, cc, cw / both2);
        printf("  %s --version (the process's start alone): %.1f ms wall, %.1f CPU ms\n", BRUME_EXE,
               1e3 * bench_median(ver_wall, runs), 1e3 * bench_median(ver_cpu, runs));
        if (against) {
            double ow = bench_median(oth_wall, runs);
            printf("  %s render %s -o %s: %.3f s wall, %.3f CPU s; this brume's / that one's: %.3f\n", against, scene,
                   out_png, ow, bench_median(oth_cpu, runs), cw / ow);
        }
    }
    unlink(out_png);
    rmdir(out_dir);
    if (passes_only)
        return 0;

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
        double err = bench_error_without_reference(st.rel_rmse, spp, ref_spp);
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
