/* bench_grid.c - speed of grid traversal and lookup: DDA voxel steps per second per core
 * on a 256^3 grid (one thread and every core), majorant segments per second, and density
 * lookups per second for dense (nearest, trilinear) and NanoVDB grids. Medians of several
 * runs, ratios from the same process: the DDA is also timed with the previous step, which
 * recomputed every plane crossing from its integer plane (exact_next below), interleaved
 * run by run, so the ratio holds on a loaded machine. Build: cmake --build build --target
 * bench_grid; run: build/bench/bench_grid [runs]. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "core/error.h"
#include "core/pool.h"
#include "core/rng.h"
#include "density/density.h"
#include "io/grid_io.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* ---- DDA -------------------------------------------------------------------------------- */

#define RAYS_PER_TASK 4096
typedef struct dda_job {
    const density *d;
    int mode; /* 0 voxel DDA, 1 majorant segments, 2 the previous exact-crossing DDA step */
    unsigned long long steps[64];
    double checksum[64];
} dda_job;

/* The DDA step brume used before the accumulated crossings (dda.h): the axis picked the
 * same way, each new crossing recomputed as (plane - o) * inv from the integer plane, so
 * that it matched a brute-force slab test bit for bit. Kept here as the baseline. */
static inline bool exact_next(grid_dda *g, grid_dda_step *s)
{
    while (!g->done) {
        const double tx = g->t_next[0], ty = g->t_next[1], tz = g->t_next[2];
        int a = ty < tx;
        double t1 = a ? ty : tx;
        a = tz < t1 ? 2 : a;
        t1 = tz < t1 ? tz : t1;
        const double t0 = g->t;
        s->i = g->ijk[0];
        s->j = g->ijk[1];
        s->k = g->ijk[2];
        s->t0 = t0;
        if (t1 >= g->tmax) {
            t1 = g->tmax;
            g->done = true;
        } else {
            const int step = g->step[a], c = g->ijk[a] + step;
            g->ijk[a] = c;
            if ((unsigned)c >= (unsigned)g->n[a])
                g->done = true;
            else
                g->t_next[a] = ((double)(c + (step > 0)) - g->o[a]) * g->inv[a];
        }
        s->t1 = t1;
        g->t = t1;
        if (t1 > t0)
            return true;
    }
    return false;
}

/* Rays from a sphere around the unit box through a random point inside it. */
static ray random_ray(rng *r)
{
    vec3 target = v3(rng_next(r), rng_next(r), rng_next(r));
    double z = 2 * rng_next(r) - 1, phi = 2 * PI * rng_next(r), s = sqrt(1 - z * z);
    vec3 o = v3_add(target, v3_scale(v3(s * cos(phi), s * sin(phi), z), 2.0));
    return (ray){o, v3_normalize(v3_sub(target, o)), 0};
}

static void dda_task(size_t task, int thread, void *user)
{
    dda_job *j = user;
    rng r = rng_make(1, task, 0);
    unsigned long long steps = 0;
    unsigned chk = 0;
    double sum = 0;
    for (int q = 0; q < RAYS_PER_TASK; q++) {
        ray ry = random_ray(&r);
        if (j->mode == 0) {
            grid_dda g;
            grid_dda_step s;
            if (density_voxel_dda_begin(j->d, ry, 0, INFINITY, &g))
            {
                double last = 0.0;
                while (grid_dda_next(&g, &s)) {
                    steps++;
                    chk += (unsigned)(s.i ^ s.j ^ s.k); /* keep the loop honest */
                    last = s.t1;
                }
                sum += last;
            }
        } else if (j->mode == 2) {
            grid_dda g;
            grid_dda_step s;
            if (density_voxel_dda_begin(j->d, ry, 0, INFINITY, &g))
            {
                double last = 0.0;
                while (exact_next(&g, &s)) {
                    steps++;
                    chk += (unsigned)(s.i ^ s.j ^ s.k);
                    last = s.t1;
                }
                sum += last;
            }
        } else {
            majorant_iter mi;
            majorant_seg s;
            density_majorant_begin(j->d, ry, 0, INFINITY, &mi);
            while (majorant_next(&mi, &s)) {
                steps++;
                sum += s.rho_maj;
            }
        }
    }
    j->steps[thread] += steps;
    j->checksum[thread] += sum + (double)chk;
}

/* Steps per second per core, threads threads. */
static double bench_dda(const density *d, int mode, int threads, size_t tasks)
{
    dda_job j;
    memset(&j, 0, sizeof j);
    j.d = d;
    j.mode = mode;
    double t0 = now();
    int used = pool_run(threads, tasks, dda_task, &j);
    double dt = now() - t0;
    unsigned long long steps = 0;
    for (int i = 0; i < 64; i++)
        steps += j.steps[i];
    return (double)steps / dt / used;
}

/* The machine's own scaling, for the per-core figures above: a loop that touches no memory
 * (four independent xorshift chains, integer only), per thread, with one thread and with
 * every core busy. On a machine whose cores share nothing this ratio is 1; below 1 the
 * cores share execution resources (SMT siblings, or a host that throttles busy vCPUs), and
 * the DDA's per-core rate with every core busy can fall by as much for that reason alone. */
#define ALU_ITERS 50000000ull
static void alu_task(size_t task, int thread, void *user)
{
    dda_job *j = user;
    uint64_t a = 0x9e3779b97f4a7c15ull + task, b = a * 3, c = a * 5, d = a * 7;
    for (unsigned long long q = 0; q < ALU_ITERS; q++) {
        a ^= a << 13, a ^= a >> 7, a ^= a << 17;
        b ^= b << 13, b ^= b >> 7, b ^= b << 17;
        c ^= c << 13, c ^= c >> 7, c ^= c << 17;
        d ^= d << 13, d ^= d >> 7, d ^= d << 17;
    }
    j->steps[thread] += ALU_ITERS;
    j->checksum[thread] += (double)((a ^ b ^ c ^ d) & 0xffff);
}

static double bench_alu(int threads)
{
    dda_job j;
    memset(&j, 0, sizeof j);
    double t0 = now();
    int used = pool_run(threads, (size_t)threads, alu_task, &j);
    double dt = now() - t0;
    unsigned long long n = 0;
    for (int i = 0; i < 64; i++)
        n += j.steps[i];
    return (double)n / dt / used;
}

/* ---- lookups ------------------------------------------------------------------------------ */

static double bench_lookup(const density *d, size_t n)
{
    box3 b = density_bounds(d);
    vec3 e = v3_sub(b.hi, b.lo);
    /* points precomputed so that only the lookup is timed */
    vec3 *p = malloc(n * sizeof *p);
    rng r = rng_make(2, 0, 0);
    for (size_t i = 0; i < n; i++)
        p[i] = v3(b.lo.x + rng_next(&r) * e.x, b.lo.y + rng_next(&r) * e.y, b.lo.z + rng_next(&r) * e.z);
    volatile double sink = 0;
    double t0 = now(), s = 0;
    for (size_t i = 0; i < n; i++)
        s += density_eval(d, p[i]);
    double dt = now() - t0;
    sink = s;
    (void)sink;
    free(p);
    return (double)n / dt;
}

static void cpu_model(char *out, size_t cap)
{
    snprintf(out, cap, "unknown");
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (!f)
        return;
    char line[512];
    while (fgets(line, sizeof line, f))
        if (strncmp(line, "model name", 10) == 0) {
            char *c = strchr(line, ':');
            if (c) {
                snprintf(out, cap, "%s", c + 2);
                out[strcspn(out, "\n")] = '\0';
            }
            break;
        }
    fclose(f);
}

int main(int argc, char **argv)
{
    char *end = NULL;
    long n = argc > 1 ? strtol(argv[1], &end, 10) : 5;
    if (argc > 2 || (argc > 1 && (*end || n < 1 || n > 50))) {
        fprintf(stderr, "usage: bench_grid [RUNS in 1..50]\n");
        return 2;
    }
    int runs = (int)n;
    char cpu[256];
    cpu_model(cpu, sizeof cpu);
    int cores = pool_default_threads();
    printf("machine: %s, %d cores (nproc), %d runs each, medians\n", cpu, cores, runs);

    const int N = 256;
    size_t count = (size_t)N * (size_t)N * (size_t)N;
    float *v = malloc(count * sizeof *v);
    rng r = rng_make(3, 0, 0);
    for (size_t i = 0; i < count; i++)
        v[i] = (float)rng_next(&r);
    density *dn = density_new_grid(N, N, N, v, (box3){v3(0, 0, 0), v3(1, 1, 1)}, GRID_NEAREST);
    float *v2 = malloc(count * sizeof *v2);
    memcpy(v2, v, count * sizeof *v2);
    density *dt = density_new_grid(N, N, N, v2, (box3){v3(0, 0, 0), v3(1, 1, 1)}, GRID_TRILINEAR);
    if (!dn || !dt) {
        fprintf(stderr, "bench: %s\n", err_message());
        return 1;
    }
    double res[50], base[50], ratio[50];
    double one = 0, all = 0, maj = 0;
    for (int k = 0; k < runs; k++) { /* interleaved with the baseline: the ratio survives load */
        res[k] = bench_dda(dn, 0, 1, 8);
        base[k] = bench_dda(dn, 2, 1, 8);
        ratio[k] = res[k] / base[k];
    }
    one = median(res, runs);
    double old = median(base, runs), gain = median(ratio, runs);
    for (int k = 0; k < runs; k++)
        res[k] = bench_dda(dn, 0, cores, 16);
    all = median(res, runs);
    for (int k = 0; k < runs; k++)
        res[k] = bench_dda(dn, 1, 1, 8);
    maj = median(res, runs);
    for (int k = 0; k < runs; k++) /* interleaved: the ratio survives load */
        ratio[k] = bench_alu(cores) / bench_alu(1);
    double alu_scaling = median(ratio, runs);
    printf("DDA, 256^3 voxels, random rays through the box:\n");
    printf("  voxel steps/s/core, 1 thread:   %8.1f M\n", one * 1e-6);
    printf("  previous exact-crossing step:   %8.1f M  (this step / previous, median of run ratios: %.2fx)\n",
           old * 1e-6, gain);
    printf("  voxel steps/s/core, %d threads:  %8.1f M  (total %.1f M/s)\n", cores, all * 1e-6, all * cores * 1e-6);
    density_info din;
    density_get_info(dn, &din);
    printf("  majorant segments/s, 1 thread:  %8.1f M  (%d^3-voxel cells, equal ones merged)\n", maj * 1e-6,
           din.majorant_cell);
    printf("  the machine: a register-only loop per thread, %d threads / 1 thread: %.2fx\n", cores, alu_scaling);

    size_t nl = 4000000;
    double ln, lt;
    for (int k = 0; k < runs; k++)
        res[k] = bench_lookup(dn, nl);
    ln = median(res, runs);
    for (int k = 0; k < runs; k++)
        res[k] = bench_lookup(dt, nl);
    lt = median(res, runs);
    printf("lookups/s, 1 thread, random points (cache-hostile), 256^3 dense:\n");
    printf("  dense nearest:    %8.1f M\n  dense trilinear:  %8.1f M  (%.2fx nearest)\n", ln * 1e-6, lt * 1e-6, lt / ln);

    /* the Disney cloud as NanoVDB (the .vdb through the sandboxed reader, the .nvdb directly):
     * its small box read through the dense copy that loading keeps, and through the tree */
    if (grid_have_openvdb()) {
        char nv[512];
        snprintf(nv, sizeof nv, "/tmp/bench-grid-%ld.nvdb", (long)getpid());
        if (grid_convert_vdb_to_nvdb(BRUME_DATA_DIR "/wdas_cloud_sixteenth.vdb", nv, NULL) != BRUME_OK) {
            fprintf(stderr, "bench: %s\n", err_message());
            return 1;
        }
        printf("lookups/s, 1 thread, random points in the Disney cloud (126 x 86 x 154):\n");
        for (int f = 0; f < 2; f++) {
            density_load_options o;
            density_load_options_default(&o);
            o.filter = f ? GRID_TRILINEAR : GRID_NEAREST;
            density *a = density_load_file(BRUME_DATA_DIR "/wdas_cloud_sixteenth.vdb", &o);
            /* the tree's lookups: without this the small box keeps a dense copy and is read
             * like a dense grid (docs/grids.md, "Small sparse grids") */
            uint64_t limit = nanovdb_set_cell_grid_limit(0);
            density *b = density_load_file(nv, &o);
            nanovdb_set_cell_grid_limit(limit);
            if (!a || !b) {
                fprintf(stderr, "bench: %s\n", err_message());
                return 1;
            }
            double da, db;
            for (int k = 0; k < runs; k++)
                res[k] = bench_lookup(a, nl);
            da = median(res, runs);
            for (int k = 0; k < runs; k++)
                res[k] = bench_lookup(b, nl);
            db = median(res, runs);
            printf("  %-9s dense copy %8.1f M, NanoVDB tree %8.1f M  (tree/copy %.2f)\n", f ? "trilinear" : "nearest", da * 1e-6,
                   db * 1e-6, db / da);
            density_release(a);
            density_release(b);
        }
        remove(nv);
    }
    density_release(dn);
    density_release(dt);
    return 0;
}
