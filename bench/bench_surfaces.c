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
 * brume's wrapper from Embree itself. Then where the limit is (docs/performance.md,
 * "Embree"): the ISA Embree dispatches and the CPU flags; Embree alone on balls of 800 to
 * 1,000,000 triangles (rays/s against the size of the scene: cache-resident or not); the
 * 250k ball with coherent rays (a camera's, in pixel order) against incoherent ones, on one
 * thread and as packets of 8; and this machine's memory latency (a random pointer chase
 * over 1 to 256 MiB), which bounds incoherent rays once the BVH leaves the cache.
 *   build/bench/bench_surfaces        (prints "ball closest hit ... M rays/s on 2")
 *   build/bench/bench_surfaces quick  (skips the terrain) */
#include <embree3/rtcore.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

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

/* ---- where the limit is: Embree alone -------------------------------------------------- */

/* This thread's CPU time in seconds: the single-thread figures below count the time the
 * thread ran, not the time other processes held the core (the machine is shared). */
static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Ray sets in float (origin, direction) for Embree alone. */
enum { RAW_RAYS = 1 << 20 };

/* The ball's rays (as trace_task makes them: incoherent) or a camera's at (0, 0, 3) looking
 * at the ball through a 1024 x 1024 grid in pixel order (coherent: neighbours share nodes). */
static float *raw_rays(int camera)
{
    float *R = malloc(sizeof *R * 6 * RAW_RAYS);
    rng g = rng_make(1, 0, 0);
    for (int i = 0; i < RAW_RAYS; i++) {
        vec3 o, d;
        if (camera) {
            int px = i % 1024, py = i / 1024;
            o = v3(0, 0, 3);
            d = v3_normalize(v3((px + 0.5) / 1024 * 0.8 - 0.4, (py + 0.5) / 1024 * 0.8 - 0.4, -1));
        } else {
            o = v3_scale(sample_sphere(rng_next(&g), rng_next(&g)), 3.0);
            vec3 target = v3_scale(sample_sphere(rng_next(&g), rng_next(&g)), 0.5 * rng_next(&g));
            d = v3_normalize(v3_sub(target, o));
        }
        float *r = R + 6 * i;
        r[0] = (float)o.x, r[1] = (float)o.y, r[2] = (float)o.z;
        r[3] = (float)d.x, r[4] = (float)d.y, r[5] = (float)d.z;
    }
    return R;
}

static size_t rss_bytes(void)
{
    long pages = 0, rss = 0;
    FILE *fp = fopen("/proc/self/statm", "r");
    if (fp && fscanf(fp, "%ld %ld", &pages, &rss) != 2)
        rss = 0;
    if (fp)
        fclose(fp);
    return (size_t)rss * 4096u;
}

/* A ball of 2 grid (grid / 2) triangles in Embree alone (medium build quality, as Embree's
 * tutorials), one thread; the memory the build took (resident set growth) in *mib. */
static RTCScene raw_ball(RTCDevice dev, int grid, double *mib)
{
    size_t r0 = rss_bytes();
    RTCScene sc = rtcNewScene(dev);
    int nu = grid, nv = grid / 2, np = (nu + 1) * (nv + 1), ntri = 2 * nu * nv;
    RTCGeometry geo = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(geo, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), (size_t)np);
    unsigned *ix =
        rtcSetNewGeometryBuffer(geo, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), (size_t)ntri);
    for (int j = 0; j <= nv; j++)
        for (int i = 0; i <= nu; i++) {
            double th = PI * j / nv, ph = 2 * PI * i / nu;
            float *q = v + 3 * (j * (nu + 1) + i);
            q[0] = (float)(sin(th) * cos(ph)), q[1] = (float)cos(th), q[2] = (float)(sin(th) * sin(ph));
        }
    for (int j = 0, t = 0; j < nv; j++)
        for (int i = 0; i < nu; i++, t += 2) {
            unsigned a = (unsigned)(j * (nu + 1) + i), b = a + 1, c = a + (unsigned)nu + 1, d = c + 1;
            unsigned tri[6] = {a, c, b, b, c, d};
            memcpy(ix + 3 * t, tri, sizeof tri);
        }
    rtcCommitGeometry(geo);
    rtcAttachGeometry(sc, geo);
    rtcReleaseGeometry(geo);
    rtcCommitScene(sc);
    *mib = (double)(rss_bytes() - r0) / 1048576.0;
    return sc;
}

/* Rays per second of Embree alone over the ray set R, one thread, median of 3 runs:
 * rtcIntersect1 per ray (packet 0) or rtcIntersect8 per 8 consecutive rays (packet 8). */
static double raw_trace(RTCScene sc, const float *R, int packet)
{
    double t[3];
    long hits = 0;
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (int run = 0; run < 3; run++) {
        double t0 = cpu_now();
        if (!packet) {
            for (int i = 0; i < RAW_RAYS; i++) {
                const float *r = R + 6 * i;
                struct RTCRayHit rh;
                memset(&rh, 0, sizeof rh);
                rh.ray.org_x = r[0], rh.ray.org_y = r[1], rh.ray.org_z = r[2];
                rh.ray.dir_x = r[3], rh.ray.dir_y = r[4], rh.ray.dir_z = r[5];
                rh.ray.tfar = FLT_MAX;
                rh.ray.mask = 0xffffffffu;
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(sc, &ctx, &rh);
                hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            }
        } else {
            for (int i = 0; i < RAW_RAYS; i += 8) {
                struct RTCRayHit8 rh __attribute__((aligned(32)));
                int valid[8] __attribute__((aligned(32)));
                memset(&rh, 0, sizeof rh);
                for (int k = 0; k < 8; k++) {
                    const float *r = R + 6 * (i + k);
                    valid[k] = -1;
                    rh.ray.org_x[k] = r[0], rh.ray.org_y[k] = r[1], rh.ray.org_z[k] = r[2];
                    rh.ray.dir_x[k] = r[3], rh.ray.dir_y[k] = r[4], rh.ray.dir_z[k] = r[5];
                    rh.ray.tfar[k] = FLT_MAX;
                    rh.ray.mask[k] = 0xffffffffu;
                    rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                }
                rtcIntersect8(valid, sc, &ctx, &rh);
                for (int k = 0; k < 8; k++)
                    hits += rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
            }
        }
        t[run] = cpu_now() - t0;
    }
    if (hits == 0)
        fprintf(stderr, "raw Embree: no ray hit the ball\n");
    return RAW_RAYS / bench_median(t, 3);
}

/* Nanoseconds per load of a random pointer chase over `mib` MiB (one cache line a node). */
static double chase_ns(size_t mib)
{
    size_t n = mib * 1048576 / 64, bytes = n * 64;
    char *b = aligned_alloc(64, bytes);
    size_t *perm = malloc(n * sizeof *perm);
    if (!b || !perm) {
        free(b);
        free(perm);
        return 0.0;
    }
    rng g = rng_make(3, mib, 0);
    for (size_t i = 0; i < n; i++)
        perm[i] = i;
    for (size_t i = n - 1; i > 0; i--) {
        size_t j = (size_t)(rng_next(&g) * (double)(i + 1)) % (i + 1), t = perm[i];
        perm[i] = perm[j];
        perm[j] = t;
    }
    for (size_t i = 0; i < n; i++)
        *(char **)(void *)(b + perm[i] * 64) = b + perm[(i + 1) % n] * 64;
    free(perm);
    char *p = b;
    enum { LOADS = 1 << 23 };
    double t0 = cpu_now();
    for (long i = 0; i < LOADS; i++)
        p = *(char **)(void *)p;
    double ns = (cpu_now() - t0) / LOADS * 1e9;
    if (p == NULL) /* keeps the chase */
        ns = -1.0;
    free(b);
    return ns;
}

/* Where the limit is: ISA, scene size, coherence, memory latency. Returns the rays/s of
 * Embree alone on the 250k ball with the incoherent rays (the baseline for brume's). */
static double roofline(void)
{
    FILE *fp = fopen("/proc/cpuinfo", "r");
    char line[4096];
    while (fp && fgets(line, sizeof line, fp))
        if (strncmp(line, "flags", 5) == 0) {
            printf("CPU flags: avx2 %s, avx512f %s, fma %s (what the VM exposes)\n", strstr(line, " avx2") ? "yes" : "no",
                   strstr(line, " avx512f") ? "yes" : "no", strstr(line, " fma") ? "yes" : "no");
            break;
        }
    if (fp)
        fclose(fp);
    RTCDevice dev = rtcNewDevice("threads=1,set_affinity=0");
    printf("Embree %ld (Debian build); the ISA it dispatches is in its verbose banner: "
           "build/bench/bench_surfaces roofline-verbose\n",
           (long)rtcGetDeviceProperty(dev, RTC_DEVICE_PROPERTY_VERSION));
    float *inc = raw_rays(0), *cam = raw_rays(1);
    double base = 0.0;
    printf("Embree alone, one thread (M rays per CPU second), incoherent rays at a ball, against its size:\n");
    const int grids[] = {20, 50, 100, 200, 500, 1000};
    for (int q = 0; q < 6; q++) {
        double mib;
        RTCScene sc = raw_ball(dev, grids[q], &mib);
        double r1 = raw_trace(sc, inc, 0);
        printf("  %8d triangles, scene %6.1f MiB: %6.2f M rays/s", grids[q] * grids[q], mib, r1 * 1e-6);
        if (grids[q] == GRID) {
            base = r1;
            printf("; packets of 8: %.2f; coherent camera rays: %.2f, packets of 8: %.2f",
                   raw_trace(sc, inc, 8) * 1e-6, raw_trace(sc, cam, 0) * 1e-6, raw_trace(sc, cam, 8) * 1e-6);
        }
        printf("\n");
        fflush(stdout);
        rtcReleaseScene(sc);
    }
    rtcReleaseDevice(dev);
    free(inc);
    free(cam);
    printf("memory latency (random pointer chase, ns per load, CPU time):");
    for (size_t mib = 1; mib <= 256; mib *= 4)
        printf(" %zu MiB %.0f%s", mib, chase_ns(mib), mib < 256 ? "," : "\n");
    return base;
}

int main(int argc, char **argv)
{
    bench_machine();
    if (argc > 1 && strcmp(argv[1], "roofline-verbose") == 0) {
        rtcReleaseDevice(rtcNewDevice("verbose=1"));
        return 0;
    }
    int quick = argc > 1 && strcmp(argv[1], "quick") == 0;
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
    if (!quick)
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
    /* brume's ball rays on this thread in CPU time, as Embree alone is measured */
    double tb[3];
    for (int run = 0; run < 3; run++) {
        double c0 = cpu_now();
        for (int task = 0; task < TASKS; task++)
            trace_task((size_t)task, 0, &jb);
        tb[run] = cpu_now() - c0;
    }
    double b1 = (double)TASKS * RAYS_PER_TASK / bench_median(tb, 3), raw = roofline();
    printf("ball closest hit, 1 thread, M rays per CPU second: brume %.2f, Embree called directly %.2f (brume / direct "
           "%.2f)\n",
           b1 * 1e-6, raw * 1e-6, b1 / raw);
    surfaces_release(B);
    free(pos);
    free(idx);
    return 0;
}
