/* cli_job.c - how `brume render` runs a render job: signals that stop it and keep the work,
 * checkpoints every few seconds and on interruption, resume, and the checks of output paths
 * made before any work. */
#include "cli_job.h"

#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "cli_progress.h"
#include "commands.h"

/* ---- signals ------------------------------------------------------------------------------ */

static volatile sig_atomic_t g_signal; /* the first SIGINT, SIGTERM or SIGHUP, 0 before */
static volatile sig_atomic_t g_keep;   /* 1 while a phase runs whose work a signal keeps */
static brume_context *_Atomic g_cancel; /* the denoiser's context: a kept signal cancels it */

/* While a render job runs (cli_signals_keep), the first signal asks it to stop (the progress
 * callback sees it within a tile) and its samples are kept; while a finished image is
 * written or denoised, the write goes on and the denoiser is cancelled (its context,
 * cli_signals_cancel), so that the image before denoising is written. In any other phase
 * (loading a scene, generating a grid, Blasi's light pass) there is nothing partial to keep,
 * so the first signal ends the process at once, as a second one always does: temporary
 * files of writes under way are removed, finished files stay (a signal answered after the
 * phase would come minutes later). */
static void on_signal(int sig)
{
    if (g_signal || !g_keep) {
        brume_remove_all_temporaries();
        static const char msg[] = "brume: interrupted: the work in progress is not kept\n";
        if (!g_signal)
            (void)!write(2, msg, sizeof msg - 1);
        _exit(128 + sig);
    }
    g_signal = sig;
    brume_context *c = atomic_load(&g_cancel);
    if (c)
        brume_context_cancel_loads(c); /* async-signal-safe (brume.h) */
}

void cli_signals_keep(bool keep) { g_keep = keep ? 1 : 0; }

void cli_signals_cancel(brume_context *ctx) { atomic_store(&g_cancel, ctx); }

void cli_signals_raise(int sig)
{
    static atomic_flag raised = ATOMIC_FLAG_INIT; /* two stops at once on two threads: one signal */
    if (!g_signal && !atomic_flag_test_and_set(&raised))
        (void)kill(getpid(), sig);
}

void cli_signals_install(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGHUP, &sa, NULL);
}

int cli_signal(void) { return (int)g_signal; }

const char *cli_signal_name(int sig)
{
    switch (sig) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    }
    return "a signal";
}

/* ---- outputs -------------------------------------------------------------------------------- */

static bool ext_is(const char *path, const char *want)
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    const char *dot = strrchr(base, '.');
    if (!dot || dot == base)
        return false;
    for (; *dot && *want; dot++, want++) {
        char c = *dot;
        if (c >= 'A' && c <= 'Z')
            c = (char)(c - 'A' + 'a');
        if (c != *want)
            return false;
    }
    return *dot == *want;
}

int cli_check_image_name(const char *flag, const char *path, bool need_exr)
{
    const char *slash = strrchr(path, '/');
    if (!*path || (slash && !slash[1])) {
        cli_error("%s: '%s' is not a file name", flag, path);
        return 2;
    }
    if (!ext_is(path, ".png") && !ext_is(path, ".exr") && !ext_is(path, ".pfm")) {
        cli_error("%s: '%s': unknown image format (use .exr, .png or .pfm)", flag, path);
        return 1; /* as the library's refusal of the format */
    }
    if (need_exr && !ext_is(path, ".exr")) {
        cli_error("%s: '%s': --aov layers need an .exr output", flag, path);
        return 2;
    }
    return 0;
}

int cli_prepare_folder(const char *flag, const char *path, bool make)
{
    char dir[4096];
    const char *slash = strrchr(path, '/');
    if (!slash)
        snprintf(dir, sizeof dir, ".");
    else if (slash == path)
        snprintf(dir, sizeof dir, "/");
    else if ((size_t)(slash - path) >= sizeof dir) {
        cli_error("%s: '%s': path too long", flag, path);
        return 1;
    } else
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    /* make the missing folders, parents first */
    for (char *p = dir + 1;; p++) {
        if (*p != '/' && *p != '\0')
            continue;
        char keep = *p;
        *p = '\0';
        struct stat st;
        if (stat(dir, &st) != 0 && !make) {
            /* the first missing folder: its parent must let it be made */
            char *up = strrchr(dir, '/');
            char parent[4096];
            snprintf(parent, sizeof parent, "%.*s", up ? (int)(up == dir ? 1 : up - dir) : 1, up ? dir : ".");
            if (access(parent, W_OK | X_OK) != 0) {
                cli_error("%s: '%s': cannot make the folder '%s': %s", flag, path, dir, strerror(errno));
                return 1;
            }
            return 0;
        } else if (stat(dir, &st) != 0) {
            if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
                cli_error("%s: '%s': cannot make the folder '%s': %s", flag, path, dir, strerror(errno));
                return 1;
            }
        } else if (!S_ISDIR(st.st_mode)) {
            cli_error("%s: '%s': '%s' is not a folder", flag, path, dir);
            return 1;
        }
        *p = keep;
        if (!keep)
            break;
    }
    /* a file can be made there (write permission, a writable file system); a signal that
     * ends brume waits until the probe is gone, which it would otherwise leave behind */
    char probe[4200];
    snprintf(probe, sizeof probe, "%s/.brume-probe-XXXXXX", dir);
    sigset_t block, old;
    sigemptyset(&block);
    sigaddset(&block, SIGINT);
    sigaddset(&block, SIGTERM);
    sigaddset(&block, SIGHUP);
    pthread_sigmask(SIG_BLOCK, &block, &old);
    int fd = mkstemp(probe), err = errno;
    if (fd >= 0) {
        close(fd);
        unlink(probe);
    }
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (fd < 0) {
        cli_error("%s: '%s': cannot write in the folder '%s': %s", flag, path, dir, strerror(err));
        return 1;
    }
    return 0;
}

/* ---- running a job -------------------------------------------------------------------------- */

/* What the progress callback needs; one job runs at a time in brume render. */
typedef struct job_state {
    const brume_render_job *job;
    const char *checkpoint;
    uint64_t scene_key;
    double every, t_last;
    brume_context *ctx; /* the callback's own: it runs on a worker thread */
    bool warned;
} job_state;

static job_state g_job;

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static bool on_progress(void *user, uint64_t done, uint64_t total)
{
    (void)done;
    (void)total;
    job_state *st = user;
    if (g_signal)
        return false;
    cli_progress_tick(st->job);
    if (st->checkpoint && st->job && now_seconds() - st->t_last >= st->every) {
        if (brume_render_job_save(st->ctx, st->job, st->scene_key, st->checkpoint) != BRUME_OK && !st->warned) {
            cli_error("warning: %s", brume_context_last_error(st->ctx));
            st->warned = true;
        }
        st->t_last = now_seconds();
    }
    return true;
}

void cli_job_callback(brume_progress_fn *fn, void **user)
{
    *fn = on_progress;
    *user = &g_job;
}

int cli_check_output(const char *flag, const char *path, brume_file_kind kind, const char *scene_path,
                     const brume_scene *scene, const char *const *others, int nothers)
{
    const char *files[80];
    int n = 0;
    files[n++] = scene_path;
    for (int i = 0; i < nothers && n < (int)(sizeof files / sizeof files[0]); i++)
        files[n++] = others[i];
    brume_context *ctx = brume_context_new();
    if (!ctx) {
        cli_error("out of memory");
        return 1;
    }
    int rc = 0;
    if (scene_path && brume_output_check(ctx, flag, path, BRUME_FILE_ANY, NULL, &scene_path, 1) != BRUME_OK &&
        strstr(brume_context_last_error(ctx), "another file of this command")) {
        cli_error("%s: %s: is the scene file: brume does not write over its inputs", flag, path);
        rc = 1;
    } else if (brume_output_check(ctx, flag, path, kind, scene, files, n) != BRUME_OK) {
        cli_error("%s", brume_context_last_error(ctx));
        rc = 1;
    }
    brume_context_release(ctx);
    return rc;
}

uint64_t cli_scene_key(const char *scene_path, const brume_scene *scene, int nsets, const char *const *sets,
                       long frame)
{
    uint64_t h = 0xcbf29ce484222325ULL;
#define FOLD(p, n)                                                                                              \
    for (size_t k_ = 0; k_ < (n); k_++) {                                                                      \
        h ^= ((const unsigned char *)(p))[k_];                                                                 \
        h *= 0x100000001b3ULL;                                                                                 \
    }
    if (scene_path) {
        FILE *fp = fopen(scene_path, "rb");
        unsigned char buf[65536];
        size_t n;
        while (fp && (n = fread(buf, 1, sizeof buf, fp)) > 0)
            FOLD(buf, n)
        if (fp)
            fclose(fp);
    } else {
        FOLD("<default scene>", 15) /* compiled in: the brume version in the checkpoint covers it */
    }
    /* a resumed render may take another time budget or thread count (neither changes a
     * sample): --time (render.time) and --set render.threads are left out */
    for (int i = 0; i < nsets; i++)
        if (strncmp(sets[i], "render.time=", 12) != 0 && strncmp(sets[i], "render.threads=", 15) != 0)
            FOLD(sets[i], strlen(sets[i]) + 1)
    FOLD(&frame, sizeof frame)
#undef FOLD
    return brume_scene_inputs_key(scene, h);
}

/* Releases a job that failed: the live view stops showing it first (its server thread reads
 * the job until then). */
static brume_status job_failed(const cli_job_opts *o, brume_render_job *job, brume_status st)
{
    cli_signals_keep(false);
    if (o->serve)
        cli_serve_show(o->serve, NULL, NULL);
    brume_render_job_release(job);
    return st;
}

brume_status cli_run_job(brume_context *ctx, const brume_scene *scene, const cli_job_opts *o, brume_render_job **job_out,
                         brume_image **out, cli_job_result *res)
{
    memset(res, 0, sizeof *res);
    *out = NULL;
    *job_out = NULL;
    brume_render_job *job = NULL;
    double t0 = now_seconds();
    cli_progress_begin(o->progress, o->progress_every);
    brume_status st = o->resume ? brume_render_job_resume(ctx, scene, o->scene_key, o->resume, &job)
                                : brume_render_begin(ctx, scene, &job);
    if (st != BRUME_OK) {
        cli_progress_end(NULL);
        return st;
    }
    g_job = (job_state){job, o->checkpoint, o->scene_key, o->checkpoint_every, now_seconds(), NULL, false};
    if (o->checkpoint && !(g_job.ctx = brume_context_new())) {
        brume_render_job_release(job);
        return BRUME_ERROR_OUT_OF_MEMORY;
    }
    if (o->serve)
        cli_serve_show(o->serve, job, o->label);
    cli_signals_keep(true);
    st = g_signal ? BRUME_ERROR_CANCELLED : brume_render_job_run(ctx, job);
    res->seconds = now_seconds() - t0;
    cli_progress_end(job);
    /* a signal from here on keeps the finished image too: the caller writes it, then lets go */
    g_job.job = NULL;
    brume_context_release(g_job.ctx);
    g_job.ctx = NULL;
    if (st == BRUME_ERROR_CANCELLED && g_signal) {
        res->interrupted = true;
        res->signal = g_signal;
    } else if (st != BRUME_OK) {
        return job_failed(o, job, st);
    }
    brume_render_job_progress(job, &res->progress);
    if (o->checkpoint) {
        /* a render its time budget ended before its samples or its noise target keeps its
         * state too: `--resume FILE --time T` adds samples (docs/render-jobs.md) */
        brume_render_settings rs;
        brume_scene_settings(scene, &rs);
        const brume_render_progress *p = &res->progress;
        res->budget_spent = !res->interrupted && o->time_budget > 0.0 && p->converged < 1.0 && p->spp_min < rs.spp;
        if (res->interrupted || res->budget_spent) {
            if ((st = brume_render_job_save(ctx, job, o->scene_key, o->checkpoint)) != BRUME_OK)
                return job_failed(o, job, st);
            res->checkpoint_written = true;
        } else {
            /* finished: the image is the result. Removed only when the file there is this
             * render's checkpoint (its header says so): never a file brume did not write */
            bool removed;
            (void)brume_render_job_remove_checkpoint(ctx, job, o->scene_key, o->checkpoint, &removed);
        }
    }
    if ((st = brume_render_job_image(ctx, job, out)) != BRUME_OK)
        return job_failed(o, job, st);
    /* the figures of a budgeted render (a fixed count is the command's own --spp) */
    if (o->noise_target > 0.0 || o->time_budget > 0.0) {
        char v[64];
        const brume_render_progress *p = &res->progress;
        snprintf(v, sizeof v, "%d", p->spp_min);
        brume_image_set_attribute(ctx, *out, "brume.spp_min", v);
        snprintf(v, sizeof v, "%d", p->spp_max);
        brume_image_set_attribute(ctx, *out, "brume.spp_max", v);
        snprintf(v, sizeof v, "%.3f", p->spp_mean);
        brume_image_set_attribute(ctx, *out, "brume.spp_mean", v);
        if (o->noise_target > 0.0) {
            snprintf(v, sizeof v, "%.5g", p->noise);
            brume_image_set_attribute(ctx, *out, "brume.noise", v);
        }
    }
    if (res->interrupted)
        brume_image_set_attribute(ctx, *out, "brume.partial", "yes");
    *job_out = job;
    return BRUME_OK;
}
