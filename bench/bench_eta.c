/* bench_eta.c - how far a render's progress figures can be trusted: renders a scene through
 * the public API, reads brume_render_job_progress ten times a second (as `brume render`'s bar
 * does), and once the render has ended compares each reading's ETA with the time that was
 * really left. Prints the number of times the fraction went down (0 expected), the ETA's
 * relative error |ETA - left| / left at the first reading past 20 % of the run, and the
 * largest such error over the readings between 20 % and 90 % of the run (a person's bound:
 * 25 %); docs/render-jobs.md gives the figures. With --csv FILE every reading is written
 * out: elapsed, done, total, fraction, ETA, the time really left, spp_mean, noise, converged.
 *
 *   bench_eta [--width W --height H] [--threads N] [--noise X] [--time S] [--csv FILE] [SCENE]
 *   (SCENE: a scene file; none: the built-in default scene, 480 x 320 to a 3 % noise target) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_common.h"
#include "brume.h"

typedef struct reading {
    double elapsed, fraction, eta, spp_mean, noise, converged;
    unsigned long long done, total;
} reading;

typedef struct recorder {
    brume_render_job *job; /* NULL until brume_render_begin returned */
    double t_last;
    reading *r;
    size_t n, cap;
} recorder;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void record(recorder *rec)
{
    brume_render_progress p;
    brume_render_job_progress(rec->job, &p);
    if (rec->n == rec->cap) {
        rec->cap = rec->cap ? 2 * rec->cap : 1024;
        if (!(rec->r = realloc(rec->r, rec->cap * sizeof *rec->r))) {
            fprintf(stderr, "bench_eta: out of memory\n");
            exit(1);
        }
    }
    rec->r[rec->n++] = (reading){p.elapsed, p.fraction, p.eta, p.spp_mean, p.noise, p.converged,
                                 (unsigned long long)p.done, (unsigned long long)p.total};
}

static bool on_progress(void *user, uint64_t done, uint64_t total)
{
    (void)done;
    (void)total;
    recorder *rec = user;
    double t = now();
    if (rec->job && t - rec->t_last >= 0.1) {
        rec->t_last = t;
        record(rec);
    }
    return true;
}

int main(int argc, char **argv)
{
    int width = 0, height = 0, threads = -1;
    double noise = -1.0, time_budget = -1.0;
    const char *csv = NULL, *path = NULL;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "--width") == 0 && v)
            width = atoi(argv[++i]);
        else if (strcmp(a, "--height") == 0 && v)
            height = atoi(argv[++i]);
        else if (strcmp(a, "--threads") == 0 && v)
            threads = atoi(argv[++i]);
        else if (strcmp(a, "--noise") == 0 && v)
            noise = atof(argv[++i]);
        else if (strcmp(a, "--time") == 0 && v)
            time_budget = atof(argv[++i]);
        else if (strcmp(a, "--csv") == 0 && v)
            csv = argv[++i];
        else if (a[0] != '-')
            path = a;
        else {
            fprintf(stderr, "usage: bench_eta [--width W --height H] [--threads N] [--noise X] [--time S] "
                            "[--csv FILE] [SCENE]\n");
            return 2;
        }
    }
    bench_machine();
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    recorder rec = {0};
    if (brume_scene_load(ctx, path ? &(brume_source){.path = path} : NULL, NULL, &s) != BRUME_OK) {
        fprintf(stderr, "bench_eta: %s\n", brume_context_last_error(ctx));
        return 1;
    }
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    if (width > 0)
        rs.width = width;
    if (height > 0)
        rs.height = height;
    if (threads >= 0)
        rs.threads = threads;
    if (noise >= 0.0)
        rs.noise_target = noise;
    if (time_budget >= 0.0)
        rs.time_budget = time_budget;
    rs.progress_fn = on_progress;
    rs.progress_user = &rec;
    brume_render_job *job = NULL;
    if (brume_scene_set_settings(ctx, s, &rs) != BRUME_OK || brume_scene_commit(ctx, s) != BRUME_OK ||
        brume_render_begin(ctx, s, &job) != BRUME_OK) {
        fprintf(stderr, "bench_eta: %s\n", brume_context_last_error(ctx));
        return 1;
    }
    printf("scene: %s, %d x %d, spp %d, noise target %g, time budget %g s, threads %d\n",
           path ? path : "the default scene", rs.width, rs.height, rs.spp, rs.noise_target, rs.time_budget, rs.threads);
    rec.job = job;
    rec.t_last = now();
    if (brume_render_job_run(ctx, job) != BRUME_OK) {
        fprintf(stderr, "bench_eta: %s\n", brume_context_last_error(ctx));
        return 1;
    }
    record(&rec);
    const reading *end = &rec.r[rec.n - 1];
    const double T = end->elapsed;
    int falls = 0;
    double at20 = -1.0, worst = 0.0, last = -1.0;
    FILE *fp = csv ? fopen(csv, "w") : NULL;
    if (fp)
        fprintf(fp, "elapsed,done,total,fraction,eta,left,spp_mean,noise,converged\n");
    for (size_t i = 0; i < rec.n; i++) {
        const reading *r = &rec.r[i];
        double left = T - r->elapsed, u = r->elapsed / T;
        if (fp)
            fprintf(fp, "%.3f,%llu,%llu,%.5f,%.3f,%.3f,%.3f,%.5f,%.4f\n", r->elapsed, r->done, r->total, r->fraction,
                    r->eta, left, r->spp_mean, r->noise, r->converged);
        if (r->fraction >= 0.0) {
            falls += r->fraction < last;
            last = r->fraction;
        }
        if (u < 0.2 || u > 0.9 || i + 1 == rec.n)
            continue;
        double err = r->eta < 0.0 ? HUGE_VAL : fabs(r->eta - left) / left;
        if (at20 < 0.0)
            at20 = err;
        worst = fmax(worst, err);
    }
    if (fp)
        fclose(fp);
    printf("render: %.2f s, %.1f spp on average, %zu readings\n", T, end->spp_mean, rec.n);
    printf("fraction: went down %d times\n", falls);
    printf("ETA error at 20 %% of the run: %.1f %%; largest between 20 %% and 90 %%: %.1f %%\n", 100.0 * at20,
           100.0 * worst);
    brume_render_job_release(job);
    brume_scene_release(s);
    brume_context_release(ctx);
    free(rec.r);
    return 0;
}
