/* bench_surfaces.c - Embree surface rays per second per core (closest hit and occlusion)
 * on a 500k-triangle height field plus spheres, single thread and both cores, medians
 * of 5 runs, ratio against one thread in the same process.
 *   build/bench/bench_surfaces */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_common.h"
#include "core/pool.h"
#include "core/progress.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "surface/surfaces.h"

enum { GRID = 500, RAYS_PER_TASK = 1 << 16, TASKS = 64 };

typedef struct job {
    const surfaces *S;
    int occlusion;
    long hits[TASKS];
} job;

static void trace_task(size_t task, int thread, void *user)
{
    (void)thread;
    job *j = user;
    rng g = rng_make(1, task, 0);
    long hits = 0;
    for (int i = 0; i < RAYS_PER_TASK; i++) {
        vec3 o = v3(4.0 * rng_next(&g) - 2.0, 1.0 + rng_next(&g), 4.0 * rng_next(&g) - 2.0);
        vec3 d = sample_sphere(rng_next(&g), rng_next(&g));
        if (d.y > 0)
            d.y = -d.y;
        ray r = {o, d, 0};
        if (j->occlusion) {
            hits += surfaces_occluded(j->S, o, d, 0.0, 10.0, 0.0);
        } else {
            surface_hit h;
            hits += surfaces_intersect(j->S, r, 0.0, INFINITY, &h);
        }
    }
    j->hits[task] = hits;
}

static double measure(job *j, int threads)
{
    double t[5];
    for (int r = 0; r < 5; r++) {
        double t0 = progress_now();
        pool_run(threads, TASKS, trace_task, j);
        t[r] = progress_now() - t0;
    }
    return (double)TASKS * RAYS_PER_TASK / bench_median(t, 5);
}

int main(void)
{
    bench_machine();
    surfaces *S = surfaces_new();
    int nv = (GRID + 1) * (GRID + 1), ntri = 2 * GRID * GRID;
    double *pos = malloc(sizeof *pos * 3 * (size_t)nv);
    int *idx = malloc(sizeof *idx * 3 * (size_t)ntri);
    for (int j = 0; j <= GRID; j++)
        for (int i = 0; i <= GRID; i++) {
            double x = 4.0 * i / GRID - 2.0, z = 4.0 * j / GRID - 2.0;
            double *p = pos + 3 * (j * (GRID + 1) + i);
            p[0] = x;
            p[1] = 0.2 * sin(5 * x) * cos(4 * z);
            p[2] = z;
        }
    int t = 0;
    for (int j = 0; j < GRID; j++)
        for (int i = 0; i < GRID; i++) {
            int a = j * (GRID + 1) + i, b = a + 1, c = a + GRID + 1, d = c + 1;
            int tri[6] = {a, c, b, b, c, d};
            memcpy(idx + 3 * t, tri, sizeof tri);
            t += 2;
        }
    material m = {col(0.5), col(0.0), 1.0, col(0.0), false};
    surfaces_add_mesh(S, pos, nv, idx, ntri, &m, "terrain");
    for (int k = 0; k < 20; k++)
        surfaces_add_sphere(S, v3(-1.8 + 0.19 * k, 0.5, 0.3 * sin(k)), 0.08, &m, "ball");
    double t0 = progress_now();
    if (surfaces_commit(S) != BRUME_OK) {
        fprintf(stderr, "commit failed\n");
        return 1;
    }
    printf("scene: %d triangles + 20 spheres, BVH build %.3f s\n", ntri, progress_now() - t0);
    job j = {S, 0, {0}};
    double c1 = measure(&j, 1), c2 = measure(&j, 2);
    j.occlusion = 1;
    double o1 = measure(&j, 1), o2 = measure(&j, 2);
    printf("closest hit: %.2f M rays/s on 1 thread, %.2f M rays/s on 2 (x%.2f)\n", c1 * 1e-6, c2 * 1e-6, c2 / c1);
    printf("occlusion:   %.2f M rays/s on 1 thread, %.2f M rays/s on 2 (x%.2f)\n", o1 * 1e-6, o2 * 1e-6, o2 / o1);
    surfaces_release(S);
    free(pos);
    free(idx);
    return 0;
}
