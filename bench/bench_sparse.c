/* bench_sparse.c - sparse volumes at scale: the Disney cloud (data/, 1/16 resolution)
 * upsampled by `brume gen upres` at factors 1, 2, 4 and 8 (index box up to 1008 x 688 x
 * 1232), each loaded from .vdb through the sandboxed reader into NanoVDB and rendered at
 * the same optical thickness; where it fits, the same grid dense. Per factor, in a fresh
 * child process (peak RSS is per process): load time, peak RSS against the NanoVDB buffer,
 * time per path sample; and NanoVDB against dense lookups, interleaved in one process.
 * Build: cmake --build build --target bench; run: build/bench/bench_sparse [max_factor].
 * The last lines repeat the time-per-sample ratios with factor 1 on the tree's majorants
 * too (it has the cell grid by default).
 * The generated files stay in build/bench/sparse/ (regenerated when missing). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "bench_common.h"
#include "brume.h"
#include "core/error.h"
#include "core/rng.h"
#include "density/density.h"
#include "io/grid_io.h"
#include "scene/scene.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double peak_rss_mib(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)ru.ru_maxrss / 1024.0;
}

typedef struct result {
    double load_s, rss_mib, buffer_mib, sample_us, mean;
    unsigned long long active;
    int ok;
} result;

/* Loads `path` (dense when raw) and renders the cloud: 64 x 48 pixels, 4 samples, one
 * thread, sigma_t 0.4 per unit density (as scenes/wdas-cloud.json), albedo 0.999. */
static result measure(const char *path, int dense)
{
    result r = {0};
    double t0 = now();
    density_load_options o;
    density_load_options_default(&o);
    density *d = density_load_file(path, &o);
    r.load_s = now() - t0;
    if (!d) {
        fprintf(stderr, "%s\n", err_message());
        return r;
    }
    density_info in;
    density_get_info(d, &in);
    r.buffer_mib = (double)(dense ? in.memory_bytes : density_shared_bytes(d)) / 1048576.0;
    r.active = (unsigned long long)in.active_voxels;
    density_release(d);
    char json[2048];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [-120, 30, 1150], \"look_at\": [-10, 70, 0], \"up\": [0, 1, 0], \"fov\": 30},"
             " \"background\": [0.18, 0.3, 0.6],"
             " \"lights\": [{\"type\": \"distant\", \"direction\": [0.55, -0.45, -0.7], \"irradiance\": 3}],"
             " \"media\": [{\"sigma_a\": 0.0004, \"sigma_s\": 0.4, \"phase\": {\"type\": \"hg\", \"g\": 0.8},"
             "   \"density\": {\"type\": \"grid\", \"file\": \"%s\"%s}}],"
             " \"render\": {\"width\": 64, \"height\": 48, \"spp\": 4, \"threads\": 1, \"max_depth\": 256}}",
             path, dense ? ", \"format\": \"raw\"" : "");
    brume_scene *s = NULL;
    if (scene_parse_json(json, "<bench>", &s) != BRUME_OK) {
        fprintf(stderr, "%s\n", err_message());
        return r;
    }
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    if (brume_scene_commit(ctx, s) != BRUME_OK) {
        fprintf(stderr, "%s\n", brume_context_last_error(ctx));
        return r;
    }
    double t1 = now();
    if (brume_render(ctx, s, &img) != BRUME_OK) {
        fprintf(stderr, "%s\n", brume_context_last_error(ctx));
        return r;
    }
    r.sample_us = (now() - t1) / (64.0 * 48.0 * 4.0) * 1e6;
    const float *px = brume_image_pixels(img);
    for (int i = 0; i < 64 * 48; i++)
        r.mean += (double)px[4 * i + 1] / (64.0 * 48.0);
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
    r.rss_mib = peak_rss_mib();
    r.ok = 1;
    return r;
}

static brume_scene *cloud_scene(const char *path)
{
    char json[2048];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [-120, 30, 1150], \"look_at\": [-10, 70, 0], \"up\": [0, 1, 0], \"fov\": 30},"
             " \"background\": [0.18, 0.3, 0.6],"
             " \"lights\": [{\"type\": \"distant\", \"direction\": [0.55, -0.45, -0.7], \"irradiance\": 3}],"
             " \"media\": [{\"sigma_a\": 0.0004, \"sigma_s\": 0.4, \"phase\": {\"type\": \"hg\", \"g\": 0.8},"
             "   \"density\": {\"type\": \"grid\", \"file\": \"%s\"}}],"
             " \"render\": {\"width\": 48, \"height\": 32, \"spp\": 4, \"threads\": 1, \"max_depth\": 256}}",
             path);
    brume_scene *s = NULL;
    brume_context *ctx = brume_context_new();
    if (scene_parse_json(json, "<bench>", &s) != BRUME_OK || brume_scene_commit(ctx, s) != BRUME_OK) {
        fprintf(stderr, "%s\n", err_message());
        brume_scene_release(s);
        s = NULL;
    }
    brume_context_release(ctx);
    return s;
}

/* Time per sample of b over a, both scenes in this process, renders interleaved (5 each),
 * median of the per-pair ratios. */
static double render_ratio(const char *a, const char *b)
{
    brume_scene *sa = cloud_scene(a), *sb = cloud_scene(b);
    double r[5] = {0};
    brume_context *ctx = brume_context_new();
    for (int run = 0; sa && sb && run < 5; run++) {
        brume_image *img = NULL;
        double t0 = now();
        brume_render(ctx, sa, &img);
        double ta = now() - t0;
        brume_image_release(img);
        t0 = now();
        brume_render(ctx, sb, &img);
        r[run] = (now() - t0) / ta;
        brume_image_release(img);
    }
    brume_context_release(ctx);
    brume_scene_release(sa);
    brume_scene_release(sb);
    return bench_median(r, 5);
}

/* measure() in a child: its own peak RSS. */
static result measure_fresh(const char *path, int dense)
{
    int fd[2];
    result r = {0};
    if (pipe(fd) != 0)
        return r;
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        close(fd[0]);
        result c = measure(path, dense);
        _exit(write(fd[1], &c, sizeof c) == (ssize_t)sizeof c ? 0 : 1);
    }
    close(fd[1]);
    if (read(fd[0], &r, sizeof r) != (ssize_t)sizeof r)
        r.ok = 0;
    close(fd[0]);
    waitpid(pid, NULL, 0);
    return r;
}

/* NanoVDB against dense lookups (trilinear) at the same points, interleaved runs, median
 * ratio of lookup rates (nano / dense): out[0] at random points of the cloud's box (every
 * lookup a new leaf: the tree's descent and cache misses), out[1] at steps of 1/4 voxel
 * along random rays through the box (what tracking does: successive lookups mostly share
 * a leaf, so NanoVDB's cached accessor pays). */
static void lookup_ratio(const char *nvdb, const char *raw, double out[2])
{
    out[0] = out[1] = 0.0;
    density *a = density_load_file(nvdb, NULL), *b = density_load_file(raw, NULL);
    if (!a || !b) {
        fprintf(stderr, "%s\n", err_message());
        density_release(a);
        density_release(b);
        return;
    }
    box3 bx = density_bounds(a);
    vec3 ext = v3_sub(bx.hi, bx.lo);
    density_info in;
    density_get_info(a, &in);
    double step = 0.25 * in.voxel_to_world.m[0];
    enum { N = 1 << 20, RUNS = 7 };
    vec3 *p = malloc(N * sizeof *p);
    for (int mode = 0; mode < 2; mode++) {
        rng g = rng_make(1, (uint64_t)mode, 0);
        for (int i = 0; i < N;) {
            vec3 o = v3(bx.lo.x + ext.x * rng_next(&g), bx.lo.y + ext.y * rng_next(&g), bx.lo.z + ext.z * rng_next(&g));
            if (mode == 0) {
                p[i++] = o;
                continue;
            }
            /* a ray from a random point of the box toward its centre, until it leaves the box */
            vec3 d = v3_normalize(v3_sub(v3_scale(v3_add(bx.lo, bx.hi), 0.5), o));
            for (vec3 q = o; i < N && q.x >= bx.lo.x && q.y >= bx.lo.y && q.z >= bx.lo.z && q.x <= bx.hi.x &&
                             q.y <= bx.hi.y && q.z <= bx.hi.z;
                 q = v3_madd(q, d, step))
                p[i++] = q;
        }
        double ratio[RUNS];
        volatile double sink = 0.0;
        for (int run = 0; run < RUNS; run++) {
            double t0 = now();
            for (int i = 0; i < N; i++)
                sink += density_eval(a, p[i]);
            double ta = now() - t0;
            t0 = now();
            for (int i = 0; i < N; i++)
                sink += density_eval(b, p[i]);
            double tb = now() - t0;
            ratio[run] = tb / ta;
        }
        (void)sink;
        out[mode] = bench_median(ratio, RUNS);
    }
    free(p);
    density_release(a);
    density_release(b);
}

static int exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0;
}

int main(int argc, char **argv)
{
    int max_factor = argc > 1 ? atoi(argv[1]) : 8;
    bench_machine();
    printf("bench_sparse: Disney cloud 1/16 upsampled by brume gen upres (detail 0.5), loaded from .vdb (sandboxed "
           "reader -> NanoVDB); 64 x 48 x 4 path samples, one thread, same sigma_t at every factor.\n");
    printf("Ratios are within one process (lookups interleaved, 7 runs, median); absolute times move with the load.\n");
    mkdir("sparse", 0755);
    printf("%-6s %-20s %12s %9s %11s %11s %9s %12s %8s\n", "factor", "index box", "active", "load s", "peak RSS MiB",
           "NanoVDB MiB", "floor ok", "us/sample", "mean G");
    double base_sample = 0.0;
    for (int f = 1; f <= max_factor; f *= 2) {
        char vdb[256], cmd[1024];
        snprintf(vdb, sizeof vdb, "sparse/wdas-x%d.vdb", f);
        if (!exists(vdb)) {
            snprintf(cmd, sizeof cmd, "%s gen upres %s/wdas_cloud_sixteenth.vdb --factor %d -o %s > /dev/null", BRUME_EXE,
                     BRUME_DATA_DIR, f, vdb);
            if (system(cmd) != 0) {
                fprintf(stderr, "bench_sparse: %s failed\n", cmd);
                return 1;
            }
        }
        result r = measure_fresh(vdb, 0);
        if (!r.ok) {
            printf("%-6d failed\n", f);
            continue;
        }
        if (f == 1)
            base_sample = r.sample_us;
        double floor_mib = 1.2 * r.buffer_mib + 64.0;
        char box[64];
        snprintf(box, sizeof box, "%d x %d x %d", 126 * f, 86 * f, 154 * f);
        printf("%-6d %-20s %12llu %9.2f %11.1f %11.1f %9s %12.2f %8.4f   (x%.2f of factor 1 per sample)\n", f, box,
               r.active, r.load_s, r.rss_mib, r.buffer_mib, r.rss_mib <= floor_mib ? "yes" : "NO", r.sample_us, r.mean,
               base_sample > 0 ? r.sample_us / base_sample : 0.0);
        fflush(stdout);
        /* dense where it fits in 1 GiB: the same grid written raw */
        if (f <= 4) {
            char nv[256], raw[256];
            snprintf(nv, sizeof nv, "sparse/wdas-x%d.nvdb", f);
            snprintf(raw, sizeof raw, "sparse/wdas-x%d.raw", f);
            if (!exists(raw) || !exists(nv)) {
                density *d = density_load_file(vdb, NULL);
                if (!d || density_write_file(d, raw, GRID_FORMAT_RAW) != BRUME_OK ||
                    grid_convert_vdb_to_nvdb(vdb, nv, NULL) != BRUME_OK) {
                    fprintf(stderr, "%s\n", err_message());
                    density_release(d);
                    continue;
                }
                density_release(d);
            }
            result dr = measure_fresh(raw, 1);
            double ratio[2];
            lookup_ratio(nv, raw, ratio);
            printf("%-6s %-20s %12s %9.2f %11.1f %11.1f %9s %12.2f %8.4f   dense grid; NanoVDB lookups at %.2f x the "
                   "dense rate (random points), %.2f x (along rays)\n",
                   "", "  (dense)", "", dr.load_s, dr.rss_mib, dr.buffer_mib, "", dr.sample_us, dr.mean, ratio[0],
                   ratio[1]);
            fflush(stdout);
        }
    }
    /* cost per sample against factor 1, in one process, renders interleaved */
    for (int f = 2; f <= max_factor; f *= 2) {
        char a[256], b[256];
        snprintf(a, sizeof a, "sparse/wdas-x1.vdb");
        snprintf(b, sizeof b, "sparse/wdas-x%d.vdb", f);
        printf("time per sample, factor %d over factor 1 (same optical thickness, interleaved, median of 5): %.2f\n", f,
               render_ratio(a, b));
        fflush(stdout);
    }
    /* Factor 1's box is small enough for the cell grid (docs/grids.md, "Small sparse grids"),
     * the others walk the tree: the same ratio with the tree at every factor says what the
     * tree's walk costs as the resolution grows. */
    uint64_t limit = nanovdb_set_cell_grid_limit(0);
    for (int f = 2; f <= max_factor; f *= 2) {
        char a[256], b[256];
        snprintf(a, sizeof a, "sparse/wdas-x1.vdb");
        snprintf(b, sizeof b, "sparse/wdas-x%d.vdb", f);
        printf("the same with the tree's majorants at factor 1 too: %.2f\n", render_ratio(a, b));
        fflush(stdout);
    }
    nanovdb_set_cell_grid_limit(limit);
    return 0;
}
