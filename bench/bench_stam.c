/* bench_stam.c - Stam's stochastic renderer: time of a 640 x 480 frame (1 sample per pixel)
 * against the number of blobs (the paper claims O(n)), against the resolution N^3 of the
 * random field Q (the paper claims independence), with and without the blob hierarchy, on
 * 1 and 2 threads. Medians of `reps` runs (default 3). Built by `cmake --build build
 * --target bench`; run as build/bench/bench_stam [reps]. Results: docs/stam.md.
 * build/bench/bench_stam --scene N prints the frame's scene with N blobs (2 threads = every
 * core here), which bench/cli_times.py renders as a user would. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "brume.h"
#include "core/error.h"
#include "scene/scene.h"

static double clock_s(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Wall time (median) and CPU time of all threads (median) of a frame. On a machine shared
 * with other jobs the CPU time is the robust figure: wall = CPU / threads on idle cores. */
typedef struct timing {
    double wall, cpu;
} timing;

/* The Figure 5 cloud with n blobs: the total mass is kept (peak density 0.15 x 200 / n), so
 * the cloud's optical depth stays the same while the blobs per ray grow with n. threads 0:
 * one per core (as `brume render` runs it). */
static void frame_json(char *json, size_t size, int n, int lattice, bool bvh, int threads)
{
    snprintf(json, size,
             "{\"camera\": {\"position\": [0.0, 0.3, 6.0], \"look_at\": [0, 0, 0], \"fov\": 40},"
             " \"background\": [0.32, 0.48, 0.78],"
             " \"lights\": [{\"type\": \"distant\", \"direction\": [-0.6, -0.55, -0.58], \"irradiance\": 3.0}],"
             " \"media\": [{\"sigma_a\": 0.05, \"sigma_s\": 8.0, \"density\": {\"type\": \"blobs\", \"generators\": ["
             "   {\"type\": \"cloud\", \"center\": [0, 0, 0], \"radii\": [1.6, 0.75, 1.0], \"count\": %d,"
             "    \"h\": [0.12, 0.35], \"density\": %g, \"seed\": 5}]}}],"
             " \"stam\": {\"eps\": 0.4, \"eta\": 0.15, \"alpha\": 0.06, \"lattice\": %d, \"bvh\": %s,"
             "   \"ambient\": [0.35, 0.4, 0.5]},"
             " \"render\": {\"width\": 640, \"height\": 480, \"spp\": 1, \"method\": \"stam\", \"threads\": %d}}",
             n, 0.15 * 200.0 / n, lattice, bvh ? "true" : "false", threads);
}

static timing time_frame(int n, int lattice, bool bvh, int threads, int reps)
{
    char json[2048];
    frame_json(json, sizeof json, n, lattice, bvh, threads);
    double t[16], c[16];
    for (int r = 0; r < reps; r++) {
        brume_context *ctx = brume_context_new();
        brume_scene *s = NULL;
        brume_image *img = NULL;
        if (scene_parse_json(json, "<bench>", &s) != BRUME_OK) {
            fprintf(stderr, "bench_stam: %s\n", err_message());
            exit(1);
        }
        double t0 = clock_s(CLOCK_MONOTONIC), c0 = clock_s(CLOCK_PROCESS_CPUTIME_ID);
        /* commit is part of the frame: Q and the light cache are built per render */
        if (brume_scene_commit(ctx, s) != BRUME_OK || brume_render(ctx, s, &img) != BRUME_OK) {
            fprintf(stderr, "bench_stam: %s\n", brume_context_last_error(ctx));
            exit(1);
        }
        t[r] = clock_s(CLOCK_MONOTONIC) - t0;
        c[r] = clock_s(CLOCK_PROCESS_CPUTIME_ID) - c0;
        brume_image_release(img);
        brume_scene_release(s);
        brume_context_release(ctx);
    }
    qsort(t, (size_t)reps, sizeof t[0], cmp_double);
    qsort(c, (size_t)reps, sizeof c[0], cmp_double);
    return (timing){t[reps / 2], c[reps / 2]};
}

int main(int argc, char **argv)
{
    if (argc > 2 && strcmp(argv[1], "--scene") == 0) { /* the frame's scene, for the command's figure */
        char json[2048];
        frame_json(json, sizeof json, atoi(argv[2]), 32, true, 0);
        printf("%s\n", json);
        return 0;
    }
    int reps = argc > 1 ? atoi(argv[1]) : 3;
    reps = reps < 1 ? 1 : (reps > 16 ? 16 : reps);
    printf("640 x 480, 1 spp, Figure 5 cloud (total mass fixed); median of %d; seconds per frame\n"
           "(scene commit + render) as wall / CPU of all threads\n\n", reps);
    printf("| blobs | BVH, 1 thread | BVH, 2 threads | no BVH, 1 thread | no BVH, 2 threads |\n");
    printf("| --- | --- | --- | --- | --- |\n");
    const int counts[] = {10, 30, 100, 300, 1000, 3000, 10000};
    for (int i = 0; i < 7; i++) {
        int n = counts[i], r = n >= 10000 ? 1 : reps; /* the largest frame is long: one run */
        timing a = time_frame(n, 32, true, 1, r), b = time_frame(n, 32, true, 2, r);
        printf("| %d | %.3f / %.3f | %.3f / %.3f |", n, a.wall, a.cpu, b.wall, b.cpu);
        if (n <= 1000) {
            timing c = time_frame(n, 32, false, 1, reps), d = time_frame(n, 32, false, 2, reps);
            printf(" %.3f / %.3f | %.3f / %.3f |\n", c.wall, c.cpu, d.wall, d.cpu);
        } else {
            printf(" - | - |\n");
        }
        fflush(stdout);
    }
    printf("\n| Q lattice N (N^3 points) | 1 thread | 2 threads |\n| --- | --- | --- |\n");
    const int lattices[] = {16, 32, 64, 128};
    for (int i = 0; i < 4; i++) {
        timing a = time_frame(200, lattices[i], true, 1, reps), b = time_frame(200, lattices[i], true, 2, reps);
        printf("| %d | %.3f / %.3f | %.3f / %.3f |\n", lattices[i], a.wall, a.cpu, b.wall, b.cpu);
        fflush(stdout);
    }
    return 0;
}
