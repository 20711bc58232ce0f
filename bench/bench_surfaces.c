/* bench_surfaces.c - Embree surface rays per second per core (closest hit and occlusion),
 * single thread and both cores, medians of 5 runs, ratio against one thread in the same
 * process, on two 500k-triangle scenes:
 *   terrain  a height field plus spheres, rays from above it in all downward directions
 *            (many long grazing rays that cross the BVH boxes of the whole relief: the
 *            hard case);
 *   ball     a closed tessellated sphere, rays from a sphere of radius 3 around it aimed
 *            at random points near its centre (incoherent, every ray hits: the usual
 *            case of a camera or light looking at an object).
 * For the ball, the same rays are also traced by a few lines that call Embree directly
 * (own device, scene and rays in float, no brume code): the baseline that separates
 * brume's wrapper from Embree itself.
 *   build/bench/bench_surfaces */
#include <embree3/rtcore.h>
#include <float.h>
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
    int ball; /* 0: terrain rays, 1: rays at the ball */
    long hits[TASKS];
} job;

static void trace_task(size_t task, int thread, void *user)
{
    (void)thread;
    job *j = user;
    rng g = rng_make(1, task, 0);
    long hits = 0;
    for (int i = 0; i < RAYS_PER_TASK; i++) {
        vec3 o, d;
        if (j->ball) {
            o = v3_scale(sample_sphere(rng_next(&g), rng_next(&g)), 3.0);
            vec3 target = v3_scale(sample_sphere(rng_next(&g), rng_next(&g)), 0.5 * rng_next(&g));
            d = v3_normalize(v3_sub(target, o));
        } else {
            o = v3(4.0 * rng_next(&g) - 2.0, 1.0 + rng_next(&g), 4.0 * rng_next(&g) - 2.0);
            d = sample_sphere(rng_next(&g), rng_next(&g));
            if (d.y > 0)
                d.y = -d.y;
        }
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

static void report(job *j, const char *name)
{
    j->occlusion = 0;
    double c1 = measure(j, 1), c2 = measure(j, 2);
    j->occlusion = 1;
    double o1 = measure(j, 1), o2 = measure(j, 2);
    printf("%s closest hit: %.2f M rays/s on 1 thread, %.2f M rays/s on 2 (x%.2f)\n", name, c1 * 1e-6, c2 * 1e-6,
           c2 / c1);
    printf("%s occlusion:   %.2f M rays/s on 1 thread, %.2f M rays/s on 2 (x%.2f)\n", name, o1 * 1e-6, o2 * 1e-6,
           o2 / o1);
}

/* A closed sphere of radius 1 as a GRID x GRID/2 latitude-longitude mesh (poles collapsed):
 * malloc'd positions (xyz) and triangles (3 vertex indices each). */
static void ball_mesh(double **pos_out, int *np_out, int **idx_out, int *ntri_out)
{
    int nu = GRID, nv = GRID / 2, np = (nu + 1) * (nv + 1), ntri = 2 * nu * nv;
    double *pos = malloc(sizeof *pos * 3 * (size_t)np);
    int *idx = malloc(sizeof *idx * 3 * (size_t)ntri);
    for (int j = 0; j <= nv; j++)
        for (int i = 0; i <= nu; i++) {
            double th = PI * j / nv, ph = 2 * PI * i / nu;
            double *p = pos + 3 * (j * (nu + 1) + i);
            p[0] = sin(th) * cos(ph);
            p[1] = cos(th);
            p[2] = sin(th) * sin(ph);
        }
    for (int j = 0, t = 0; j < nv; j++)
        for (int i = 0; i < nu; i++, t += 2) {
            int a = j * (nu + 1) + i, b = a + 1, c = a + nu + 1, d = c + 1;
            int tri[6] = {a, c, b, b, c, d};
            memcpy(idx + 3 * t, tri, sizeof tri);
        }
    *pos_out = pos;
    *np_out = np;
    *idx_out = idx;
    *ntri_out = ntri;
}

static surfaces *ball_scene(int *ntri_out)
{
    surfaces *S = surfaces_new();
    double *pos;
    int *idx, np;
    ball_mesh(&pos, &np, &idx, ntri_out);
    material m = {col(0.5), col(0.0), 1.0, col(0.0), false};
    surfaces_add_mesh(S, pos, np, idx, *ntri_out, &m, "ball");
    free(pos);
    free(idx);
    return S;
}

/* The ball's rays traced by Embree alone, one thread: rays per second. */
static double raw_embree_ball(void)
{
    RTCDevice dev = rtcNewDevice("threads=1,set_affinity=0");
    RTCScene sc = rtcNewScene(dev);
    double *pos;
    int *idx, np, ntri;
    ball_mesh(&pos, &np, &idx, &ntri);
    RTCGeometry geo = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(geo, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), (size_t)np);
    unsigned *ix = rtcSetNewGeometryBuffer(geo, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                           (size_t)ntri);
    for (size_t k = 0; k < 3 * (size_t)np; k++)
        v[k] = (float)pos[k];
    for (size_t k = 0; k < 3 * (size_t)ntri; k++)
        ix[k] = (unsigned)idx[k];
    free(pos);
    free(idx);
    rtcCommitGeometry(geo);
    rtcAttachGeometry(sc, geo);
    rtcReleaseGeometry(geo);
    rtcCommitScene(sc);
    double t[5];
    long hits = 0;
    for (int run = 0; run < 5; run++) {
        double t0 = progress_now();
        for (int task = 0; task < TASKS; task++) {
            rng g = rng_make(1, (uint64_t)task, 0);
            for (int i = 0; i < RAYS_PER_TASK; i++) {
                vec3 o = v3_scale(sample_sphere(rng_next(&g), rng_next(&g)), 3.0);
                vec3 target = v3_scale(sample_sphere(rng_next(&g), rng_next(&g)), 0.5 * rng_next(&g));
                vec3 d = v3_normalize(v3_sub(target, o));
                struct RTCIntersectContext ctx;
                rtcInitIntersectContext(&ctx);
                struct RTCRayHit rh;
                memset(&rh, 0, sizeof rh);
                rh.ray.org_x = (float)o.x;
                rh.ray.org_y = (float)o.y;
                rh.ray.org_z = (float)o.z;
                rh.ray.dir_x = (float)d.x;
                rh.ray.dir_y = (float)d.y;
                rh.ray.dir_z = (float)d.z;
                rh.ray.tfar = FLT_MAX;
                rh.ray.mask = 0xffffffffu;
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(sc, &ctx, &rh);
                hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            }
        }
        t[run] = progress_now() - t0;
    }
    rtcReleaseScene(sc);
    rtcReleaseDevice(dev);
    if (hits != 5L * TASKS * RAYS_PER_TASK)
        fprintf(stderr, "raw Embree: %ld of the rays missed the ball\n", 5L * TASKS * RAYS_PER_TASK - hits);
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
    job j = {S, 0, 0, {0}};
    report(&j, "terrain");
    surfaces_release(S);
    int nball;
    surfaces *B = ball_scene(&nball);
    t0 = progress_now();
    if (surfaces_commit(B) != BRUME_OK) {
        fprintf(stderr, "commit failed\n");
        return 1;
    }
    printf("scene: ball of %d triangles, BVH build %.3f s\n", nball, progress_now() - t0);
    job jb = {B, 0, 1, {0}};
    report(&jb, "ball");
    jb.occlusion = 0;
    double b1 = measure(&jb, 1), raw = raw_embree_ball();
    printf("ball closest hit, 1 thread: brume %.2f M rays/s, Embree called directly %.2f M rays/s (brume / direct %.2f)\n",
           b1 * 1e-6, raw * 1e-6, b1 / raw);
    surfaces_release(B);
    free(pos);
    free(idx);
    return 0;
}
