/* test_progress.c - progress a person can trust, from a library that prints nothing: the
 * figures' meter (core/progress.h) on a synthetic adaptive render (the fraction never goes
 * back, the ETA within a quarter of the truth from 20 % of the run on), a real adaptive
 * render's fraction as its callback reads it, a program linked to libbrume whose stdout and
 * stderr stay empty, and `brume render`'s log lines and end-of-run reason. */
#include "test.h"

#include <stdbool.h>
#include <stdint.h>
#include <sys/wait.h>
#include <unistd.h>

#include "brume.h"
#include "core/progress.h"
#include "core/rng.h"

/* Runs brume with args, stderr to err_path; returns the exit status. */
static int run(const char *args, const char *err_path)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "%s %s >/dev/null 2>%s", BRUME_EXE, args, err_path);
    return test_system(cmd);
}

static int count_lines(const char *text, const char *needle)
{
    int n = 0;
    for (const char *p = text; (p = strstr(p, needle)) != NULL; p++)
        n++;
    return n;
}

/* A render of about a second or more at a fixed count (the default scene's noise target off),
 * a line every 0.05 s asked: several lines, each with
 * the figures, the ETA never "not known" (a fixed count's total is known) and none at 100 %
 * (the last line comes before the end); --quiet: none. */
TEST(lines_in_a_log)
{
    const char *err = test_tmp_path("err.txt"), *out = test_tmp_path("out.png");
    char args[1024];
    snprintf(args, sizeof args, "render --width 64 --height 40 --spp 48 --set render.noise=0 --progress-every 0.05 -o %s", out);
    ASSERT_EQ_INT(run(args, err), 0);
    size_t n = 0;
    char *text = test_slurp(err, &n);
    int lines = count_lines(text, "brume: render ");
    fprintf(stderr, "%d progress lines; the first: %.120s\n", lines, text);
    ASSERT_TRUE(lines >= 2);
    ASSERT_TRUE(count_lines(text, " spp, ") >= lines); /* the summary line has one too */
    ASSERT_EQ_INT(count_lines(text, " elapsed, ETA "), lines);
    ASSERT_EQ_INT(count_lines(text, "not known"), 0);
    ASSERT_EQ_INT(count_lines(text, "brume: render 100%"), 0);
    ASSERT_TRUE(strchr(text, '\r') == NULL); /* no bar drawn in place in a log */
    free(text);
    snprintf(args, sizeof args, "render --width 64 --height 40 --spp 48 --set render.noise=0 --progress-every 0.05 --quiet -o %s", out);
    ASSERT_EQ_INT(run(args, err), 0);
    text = test_slurp(err, &n);
    ASSERT_EQ_INT((int)n, 0);
    free(text);
    remove(out);
    remove(err);
}

/* ---- the meter on a synthetic adaptive render ----------------------------------------------
 *
 * A 64 x 64 image in tiles of 8 x 8: sky (no noise: it stops at min_spp, and cheap), a
 * cloud (noisy, heavy-tailed, and costly in proportion to its noise) and ground. Passes as
 * job/render.c schedules them under a noise target (min_spp, then a quarter more each pass,
 * up to spp); at the end of a pass a pixel stops once its estimated error meets the target.
 * The estimated error at n samples is the true sigma / sqrt(n) times a factor that starts low
 * and scattered (the sample variance of heavy-tailed samples is mostly under the truth with
 * few samples) and converges as n grows. Time is the samples' cost. A reading follows each
 * tile, with the estimate of the time left as the job makes it (job_refresh, job_figures):
 * the samples each pixel still needs (progress_samples_needed) at its tile's cost per sample
 * in the last pass it was sampled; before the first pass ends, not known. */
enum { SIM_W = 64, SIM_TILE = 8, SIM_NPIX = SIM_W * SIM_W, SIM_MIN_SPP = 16, SIM_SPP = 1024, SIM_MAX = 8192 };
#define SIM_TARGET 0.03
#define SIM_PASSES ((progress_passes){4, 16}) /* job/render.c's: a quarter more, at most 16 */
#define SIM_LOW 1.0     /* the first estimates' bias: exp(-SIM_LOW / sqrt(n)) */
#define SIM_SCATTER 1.5 /* their scatter: SIM_SCATTER x a chi-square's at n samples */

typedef struct sim_run {
    int n;                                  /* readings */
    double t[SIM_MAX], left[SIM_MAX];       /* elapsed, the job's estimate of the time left */
    double left_mean[SIM_MAX];              /* the same at the last pass's mean cost per sample */
    double end;                             /* the elapsed time at the end */
    double first_total, samples;            /* the first estimate of the samples, and the count */
} sim_run;

static double sim_gauss(uint64_t stream, uint64_t k)
{
    rng g = rng_make(47, stream, k);
    double u = rng_next(&g), v = rng_next(&g);
    return sqrt(-2.0 * log(1.0 - u)) * cos(6.283185307179586 * v);
}

/* Per pixel: relative standard deviation of a sample (sigma), cost of a sample, and the
 * persistent part of its estimate's scatter. */
static void sim_pixels(double *sigma, double *cost, double *z)
{
    for (int i = 0; i < SIM_NPIX; i++) {
        double x = i % SIM_W, y = i / SIM_W, dx = (x - 32.0) / 24.0, dy = (y - 26.0) / 14.0;
        if (dx * dx + dy * dy < 1.0) { /* the cloud: lognormal noise, cost rising with it */
            sigma[i] = 0.6 * exp(0.6 * sim_gauss((uint64_t)i, 1));
            cost[i] = 2.0 + 4.0 * sigma[i];
        } else if (y >= 40) { /* ground */
            sigma[i] = 0.25 + 0.25 * (0.5 + 0.5 * tanh(sim_gauss((uint64_t)i, 2)));
            cost[i] = 1.0;
        } else { /* sky */
            sigma[i] = 0.0;
            cost[i] = 0.2;
        }
        z[i] = sim_gauss((uint64_t)i, 3);
    }
}

/* The tile of pixel i, and pixel k of tile t. */
static int sim_tile_of(int i) { return (i / SIM_W / SIM_TILE) * (SIM_W / SIM_TILE) + (i % SIM_W) / SIM_TILE; }
static int sim_pixel(int t, int k)
{
    int tx = t % (SIM_W / SIM_TILE), ty = t / (SIM_W / SIM_TILE);
    return (ty * SIM_TILE + k / SIM_TILE) * SIM_W + tx * SIM_TILE + k % SIM_TILE;
}

/* Runs the render; a time budget > 0 stops it after the first tile past it. */
static void simulate(double budget, sim_run *out)
{
    static double sigma[SIM_NPIX], cost[SIM_NPIX], z[SIM_NPIX], est[SIM_NPIX], tile_cost[SIM_NPIX];
    static int n[SIM_NPIX];
    static bool active[SIM_NPIX];
    sim_pixels(sigma, cost, z);
    for (int i = 0; i < SIM_NPIX; i++) {
        n[i] = 0;
        active[i] = true;
        tile_cost[i] = 0.0;
    }
    double t = 0.0, left_cost = -1.0, mean_rate = -1.0, total = 0.0, done = 0.0, left_samples = 0.0;
    int spp_done = 0, pass = 0;
    out->n = 0;
    for (;;) {
        int k = spp_done == 0 ? SIM_MIN_SPP : spp_done / 4 > 1 ? spp_done / 4 : 1, nactive = 0;
        k = spp_done > 0 && k > SIM_PASSES.max_step ? SIM_PASSES.max_step : k;
        k = k < SIM_SPP - spp_done ? k : SIM_SPP - spp_done;
        for (int i = 0; i < SIM_NPIX; i++)
            nactive += active[i];
        if (k <= 0 || nactive == 0 || (budget > 0.0 && t >= budget))
            break;
        double t0 = t, d0 = done;
        for (int tile = 0; tile < SIM_NPIX / (SIM_TILE * SIM_TILE) && !(budget > 0.0 && t >= budget); tile++) {
            double c = 0.0, m = 0.0;
            for (int q = 0; q < SIM_TILE * SIM_TILE; q++) {
                int i = sim_pixel(tile, q);
                if (active[i]) {
                    c += k * cost[i];
                    m += k;
                    n[i] += k;
                }
            }
            if (m > 0.0)
                tile_cost[tile] = c / m;
            t += c;
            done += m;
            ASSERT_TRUE(out->n < SIM_MAX);
            double rest = fmax(total - done, 0.0);
            out->t[out->n] = t;
            out->left[out->n] = left_cost < 0.0 ? -1.0 : rest * left_cost / fmax(left_samples, 1.0);
            out->left_mean[out->n] = mean_rate < 0.0 ? -1.0 : rest * mean_rate;
            out->n++;
        }
        if (budget > 0.0 && t >= budget)
            break;
        mean_rate = (t - t0) / (done - d0);
        spp_done += k;
        pass++;
        total = 0.0;
        left_cost = 0.0;
        for (int i = 0; i < SIM_NPIX; i++) {
            if (active[i]) { /* the pass's estimate of the pixel's error, and the stop */
                double w = (z[i] + sim_gauss((uint64_t)i, 100 + (uint64_t)pass)) / sqrt(2.0);
                double f = exp(SIM_SCATTER * sqrt(2.0 / (n[i] - 1.0)) * w - SIM_LOW / sqrt(n[i]));
                est[i] = sigma[i] * sqrt(f / n[i]);
                active[i] = !(est[i] <= SIM_TARGET);
            }
            double want = active[i] ? progress_samples_needed(n[i], est[i], SIM_TARGET, spp_done, SIM_PASSES, SIM_SPP)
                                    : n[i];
            total += want;
            left_cost += (want - n[i]) * tile_cost[sim_tile_of(i)];
        }
        left_samples = total - done;
        if (pass == 1)
            out->first_total = total;
    }
    out->end = t;
    out->samples = done;
}

/* Feeds the readings to a meter: how often the fraction fell, and the largest relative
 * error of the ETA (of `left` itself when raw) between 20 % and 90 % of the run. */
static void meter_errors(const sim_run *r, const double *left, double budget, bool raw, int *falls, double *worst)
{
    progress_meter m;
    progress_meter_init(&m);
    double last = -1.0;
    *falls = 0;
    *worst = 0.0;
    for (int i = 0; i < r->n; i++) {
        double frac, eta, budget_left = budget > 0.0 ? fmax(budget - r->t[i], 0.0) : -1.0;
        bool finished = i == r->n - 1;
        progress_meter_read(&m, &(progress_reading){r->t[i], left[i], budget_left, finished}, &frac, &eta);
        if (raw)
            eta = left[i];
        ASSERT_TRUE(finished ? frac == 1.0 && eta == 0.0 : frac <= PROGRESS_FRAC_MAX);
        if (budget > 0.0 && !raw)
            ASSERT_TRUE(eta <= budget_left + 1e-9);
        if (frac >= 0.0) {
            *falls += frac < last;
            last = frac;
        } else {
            ASSERT_TRUE(last < 0.0); /* once known, the fraction stays known */
        }
        double u = r->t[i] / r->end, truth = r->end - r->t[i];
        if (u >= 0.2 && u <= 0.9)
            *worst = fmax(*worst, eta < 0.0 ? HUGE_VAL : fabs(eta - truth) / truth);
    }
}

/* The adaptive render above: the fraction never falls, and the ETA is within 25 % of the
 * time really left from 20 % to 90 % of the run. Weighing the samples left by the last
 * pass's mean cost instead of their tiles' (what the job did before) is printed: it misses
 * by about half, the cloud's pixels being both the ones left and the costly ones. */
TEST(eta_within_a_quarter_of_the_truth)
{
    static sim_run r;
    simulate(0.0, &r);
    int falls, falls_mean;
    double worst, worst_raw, worst_mean;
    meter_errors(&r, r.left, 0.0, false, &falls, &worst);
    meter_errors(&r, r.left, 0.0, true, &falls_mean, &worst_raw);
    meter_errors(&r, r.left_mean, 0.0, false, &falls_mean, &worst_mean);
    fprintf(stderr, "%d readings; ETA error from 20 %% to 90 %% of the run: at most %.1f %% (the raw estimate "
                    "%.1f %%; at the last pass's mean cost %.1f %%)\n", r.n, 100.0 * worst, 100.0 * worst_raw,
            100.0 * worst_mean);
    ASSERT_EQ_INT(falls, 0);
    ASSERT_TRUE(worst <= 0.25);
    ASSERT_TRUE(worst_mean > 0.25); /* the simulation is one the mean cost gets wrong */
}

/* A time budget and a noise target together: the run stops at the budget (half of what the
 * noise target would take), the ETA never promises more than the budget leaves, and the
 * fraction never falls, however the two estimates cross. */
TEST(fraction_never_falls_under_a_budget_and_a_target)
{
    static sim_run full, r;
    simulate(0.0, &full);
    double budget = 0.5 * full.end;
    simulate(budget, &r);
    ASSERT_TRUE(r.end >= budget && r.end < full.end);
    int falls;
    double worst;
    meter_errors(&r, r.left, budget, false, &falls, &worst);
    ASSERT_EQ_INT(falls, 0);
}

/* The meter alone: an estimate that jumps up shows over time, not at once; the fraction
 * holds where a smaller estimate would lower it; a budget's end caps the ETA. */
TEST(meter_smooths_and_holds)
{
    progress_meter m;
    progress_meter_init(&m);
    double frac, eta;
    progress_meter_read(&m, &(progress_reading){10.0, -1.0, -1.0, false}, &frac, &eta);
    ASSERT_TRUE(frac < 0.0 && eta < 0.0);
    progress_meter_read(&m, &(progress_reading){10.0, 30.0, -1.0, false}, &frac, &eta);
    ASSERT_NEAR(eta, 30.0, 1e-9);
    ASSERT_NEAR(frac, 0.25, 1e-9);
    /* the estimate doubles 1 s later: the end moves by 1 - exp(-1 / (0.25 x 11)) of the jump */
    progress_meter_read(&m, &(progress_reading){11.0, 60.0, -1.0, false}, &frac, &eta);
    double moved = 1.0 - exp(-1.0 / (PROGRESS_SMOOTHING * 11.0));
    ASSERT_NEAR(eta, 40.0 + moved * (71.0 - 40.0) - 11.0, 1e-9);
    ASSERT_NEAR(frac, 0.25, 1e-12); /* 11 / (11 + eta) is below 0.25: held */
    progress_meter_read(&m, &(progress_reading){12.0, 60.0, 5.0, false}, &frac, &eta);
    ASSERT_NEAR(eta, 5.0, 1e-9);
    ASSERT_NEAR(frac, 12.0 / 17.0, 1e-9);
    progress_meter_read(&m, &(progress_reading){13.0, 0.0, -1.0, true}, &frac, &eta);
    ASSERT_TRUE(frac == 1.0 && eta == 0.0);
}

/* ---- a real adaptive render ------------------------------------------------------------------ */

typedef struct watch {
    brume_render_job *job; /* NULL until brume_render_begin returned */
    int calls, falls, known_then_unknown, full_early;
    double last;
} watch;

/* The callback reads the job's figures at every tile, as a display would. */
static bool watch_cb(void *user, uint64_t done, uint64_t total)
{
    (void)done;
    (void)total;
    watch *w = user;
    if (!w->job)
        return true;
    brume_render_progress p;
    brume_render_job_progress(w->job, &p);
    w->calls++;
    if (p.fraction >= 0.0) {
        w->falls += p.fraction < w->last;
        w->last = p.fraction;
    } else {
        w->known_then_unknown += w->last >= 0.0;
    }
    w->full_early += p.fraction >= 1.0 && !p.finished;
    return true;
}

/* Renders the default scene, small, with the settings fn makes; the figures at the end. */
static void watched_render(void (*fn)(brume_render_settings *), watch *w, brume_render_progress *end)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    ASSERT_EQ_INT(brume_scene_load(ctx, NULL, NULL, &s), BRUME_OK);
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    rs.width = 48;
    rs.height = 32;
    rs.threads = 2;
    rs.progress_fn = watch_cb;
    rs.progress_user = w;
    fn(&rs);
    *w = (watch){.last = -1.0};
    brume_render_job *job = NULL;
    if (brume_scene_set_settings(ctx, s, &rs) != BRUME_OK || brume_scene_commit(ctx, s) != BRUME_OK ||
        brume_render_begin(ctx, s, &job) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    w->job = job;
    if (brume_render_job_run(ctx, job) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    brume_render_job_progress(job, end);
    brume_render_job_release(job);
    brume_scene_release(s);
    brume_context_release(ctx);
}

static void adaptive(brume_render_settings *rs)
{
    rs->noise_target = 0.1;
    rs->min_spp = 4;
    rs->spp = 4096;
}

static void adaptive_capped(brume_render_settings *rs)
{
    rs->noise_target = 0.01;
    rs->min_spp = 4;
    rs->spp = 24;
    rs->time_budget = 60.0;
}

/* A small adaptive render of the default scene: its callback reads a fraction that never
 * falls and never reaches 1 before the end; the end says why it stopped. Then a target it
 * cannot meet within its spp, under a budget it does not reach: stopped at the spp. */
TEST(fraction_never_falls_in_an_adaptive_render)
{
    watch w;
    brume_render_progress p;
    watched_render(adaptive, &w, &p);
    fprintf(stderr, "%d readings, %.1f spp on average, %.0f %% of the pixels converged\n", w.calls, p.spp_mean,
            100.0 * p.converged);
    ASSERT_TRUE(w.calls >= 10);
    ASSERT_EQ_INT(w.falls, 0);
    ASSERT_EQ_INT(w.known_then_unknown, 0);
    ASSERT_EQ_INT(w.full_early, 0);
    ASSERT_TRUE(p.finished && p.fraction == 1.0 && p.eta == 0.0);
    ASSERT_EQ_INT(p.stopped, p.converged == 1.0 ? BRUME_STOP_NOISE : BRUME_STOP_SPP);
    watched_render(adaptive_capped, &w, &p);
    ASSERT_EQ_INT(w.falls, 0);
    ASSERT_TRUE(p.finished && p.spp_max == 24);
    ASSERT_EQ_INT(p.stopped, BRUME_STOP_SPP);
}

/* ---- a library that prints nothing ------------------------------------------------------------ */

/* The default scene, small, committed with the settings; NULL on failure. */
static brume_scene *quiet_scene(brume_context *ctx, double noise, double time_budget)
{
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, NULL, NULL, &s) != BRUME_OK)
        return NULL;
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    rs.width = 24;
    rs.height = 16;
    rs.spp = 8;
    rs.aovs = BRUME_AOV_DEPTH | BRUME_AOV_VARIANCE | BRUME_AOV_SAMPLES;
    rs.noise_target = noise;
    rs.time_budget = time_budget;
    if (brume_scene_set_settings(ctx, s, &rs) != BRUME_OK || brume_scene_commit(ctx, s) != BRUME_OK) {
        brume_scene_release(s);
        return NULL;
    }
    return s;
}

/* In the child: each failure exits with its own status. */
static void quiet_renders(void)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    /* a failed load: the message goes to the context */
    if (brume_scene_load(ctx, &(brume_source){.path = "bad.json", .text = "{\"render\": {\"spp\": -1}}"}, NULL, &s) ==
        BRUME_OK)
        _exit(3);
    brume_image *img = NULL;
    if (!(s = quiet_scene(ctx, 0.0, 0.0)) || brume_render(ctx, s, &img) != BRUME_OK)
        _exit(4);
    brume_image_release(img);
    brume_scene_release(s);
    /* a watched job: passes, figures, adaptive sampling under a budget */
    brume_render_job *job = NULL;
    if (!(s = quiet_scene(ctx, 0.2, 30.0)) || brume_render_begin(ctx, s, &job) != BRUME_OK ||
        brume_render_job_run(ctx, job) != BRUME_OK)
        _exit(5);
    brume_render_progress p;
    brume_render_job_progress(job, &p);
    brume_render_job_release(job);
    brume_scene_release(s);
    brume_context_release(ctx);
    _exit(p.finished ? 0 : 6);
}

/* A program linked to libbrume renders, with no callback, through brume_render and through
 * a job with a noise target and a time budget, and fails a load: its stdout and stderr,
 * one pipe, stay empty. */
TEST(library_prints_nothing)
{
    int fd[2];
    ASSERT_EQ_INT(pipe(fd), 0);
    fflush(NULL);
    pid_t pid = fork();
    ASSERT_TRUE(pid >= 0);
    if (pid == 0) {
        close(fd[0]);
        if (dup2(fd[1], STDOUT_FILENO) < 0 || dup2(fd[1], STDERR_FILENO) < 0)
            _exit(2);
        close(fd[1]);
        quiet_renders();
    }
    close(fd[1]);
    char buf[4096];
    size_t got = 0;
    ssize_t k;
    while ((k = read(fd[0], buf + got, sizeof buf - 1 - got)) > 0 && got + (size_t)k < sizeof buf - 1)
        got += (size_t)k;
    if (k > 0)
        got += (size_t)k;
    close(fd[0]);
    buf[got] = '\0';
    int status = 0;
    ASSERT_EQ_INT(waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status));
    ASSERT_EQ_INT(WEXITSTATUS(status), 0);
    ASSERT_EQ_STR(buf, "");
}

/* ---- brume render's end-of-run reason ------------------------------------------------------- */

/* `--time 20` on a render whose spp is reached first says so; a noise target met says so. */
TEST(summary_says_why_it_stopped)
{
    const char *err = test_tmp_path("err.txt"), *out = test_tmp_path("out.png");
    char args[1024];
    snprintf(args, sizeof args, "render --width 32 --height 24 --spp 4 --time 20 --set render.noise=0 -o %s", out);
    ASSERT_EQ_INT(run(args, err), 0);
    size_t n = 0;
    char *text = test_slurp(err, &n);
    ASSERT_CONTAINS(text, "; stopped: the sample maximum, 4 spp (render.spp or --spp), before the time budget\n");
    free(text);
    snprintf(args, sizeof args, "render --width 32 --height 24 --spp 4096 --noise 0.2 --min-spp 4 -o %s", out);
    ASSERT_EQ_INT(run(args, err), 0);
    text = test_slurp(err, &n);
    ASSERT_CONTAINS(text, "; stopped: every pixel met the 20% noise target\n");
    free(text);
    remove(out);
    remove(err);
}

TEST_MAIN(lines_in_a_log, eta_within_a_quarter_of_the_truth, fraction_never_falls_under_a_budget_and_a_target,
          meter_smooths_and_holds, fraction_never_falls_in_an_adaptive_render, library_prints_nothing,
          summary_says_why_it_stopped)
