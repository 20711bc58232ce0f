/* cli_render_output.c - what `brume render` writes and says: the frames' file names, the
 * image (denoised with --denoise), the video, the statistics, the line each frame gets. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "cli_progress.h"
#include "cli_render.h"
#include "commands.h"

double render_now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A printf pattern with exactly one %d conversion (flags 0 and a width allowed) and %%
 * for a literal percent: 1; no conversion: 0; anything else: -1. */
int render_pattern_kind(const char *p)
{
    int convs = 0;
    for (; *p; p++) {
        if (*p != '%')
            continue;
        if (p[1] == '%') {
            p++;
            continue;
        }
        p++;
        int digits = 0;
        while (*p >= '0' && *p <= '9') {
            p++;
            digits++;
        }
        if (*p != 'd' || digits > 2) /* a width up to 99: frame_path's sum cannot overflow */
            return -1;
        convs++;
    }
    return convs == 0 ? 0 : (convs == 1 ? 1 : -1);
}

/* The file name of frame f from a pattern that render_pattern_kind accepted: the %d conversion
 * (with its zero flag and width) becomes f, %% a percent sign. */
void render_frame_path(const char *p, long f, char *out, size_t n)
{
    size_t k = 0;
    for (; *p && k + 1 < n; p++) {
        if (*p != '%') {
            out[k++] = *p;
            continue;
        }
        if (p[1] == '%') {
            out[k++] = '%';
            p++;
            continue;
        }
        p++;
        bool zero = *p == '0';
        int width = 0;
        while (*p >= '0' && *p <= '9')
            width = 10 * width + (*p++ - '0');
        char num[32];
        int len = snprintf(num, sizeof num, "%ld", f);
        for (int pad = len; pad < width && k + 1 < n; pad++)
            out[k++] = zero ? '0' : ' ';
        for (int i = 0; i < len && k + 1 < n; i++)
            out[k++] = num[i];
    }
    out[k] = '\0';
}

/* The full path of `name` found in PATH, or false. */
static bool find_in_path(const char *name, char *out, size_t n)
{
    const char *path = getenv("PATH");
    while (path && *path) {
        const char *colon = strchr(path, ':');
        size_t len = colon ? (size_t)(colon - path) : strlen(path);
        if (len > 0) {
            snprintf(out, n, "%.*s/%s", (int)len, path, name);
            if (access(out, X_OK) == 0)
                return true;
        }
        path = colon ? colon + 1 : NULL;
    }
    return false;
}

/* Before any work: --video names a file brume may write (not an option ffmpeg would read,
 * not the scene, not a device) in a folder that can be made, and ffmpeg is there. 0 or 1/2
 * with a message. */
int render_check_video(const char *video, const char *scene_path)
{
    if (video[0] == '-') {
        cli_error("--video: '%s' is not a file name (it would reach ffmpeg as an option)", video);
        return 2;
    }
    char ffmpeg[4096];
    if (!find_in_path("ffmpeg", ffmpeg, sizeof ffmpeg)) {
        cli_error("--video: ffmpeg not found in PATH (install Debian's ffmpeg: apt-get install ffmpeg)");
        return 1;
    }
    return cli_check_output("--video", video, BRUME_FILE_ANY, scene_path, NULL, NULL, 0) ||
                   cli_prepare_folder("--video", video, false)
               ? 1
               : 0;
}

/* ffmpeg -framerate FPS -start_number FIRST -i PATTERN ... VIDEO (H.264, yuv420p). ffmpeg's
 * stderr goes to a temporary file; on failure its last line is quoted in brume's one line. */
int render_make_video(const char *pattern, long first, double fps, const char *video)
{
    char ffmpeg[4096];
    if (!find_in_path("ffmpeg", ffmpeg, sizeof ffmpeg)) {
        cli_error("--video: ffmpeg not found in PATH; the frames are written, the video is not "
                  "(install Debian's ffmpeg: apt-get install ffmpeg)");
        return 1;
    }
    char rate[64], start[32];
    snprintf(rate, sizeof rate, "%.9g", fps);
    snprintf(start, sizeof start, "%ld", first);
    char *args[] = {ffmpeg, "-nostdin", "-y", "-loglevel", "error", "-framerate", rate, "-start_number", start, "-i",
                    (char *)pattern, "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt",
                    "yuv420p", "-movflags", "+faststart", (char *)video, NULL};
    FILE *log = tmpfile();
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0) {
        if (log)
            fclose(log);
        cli_error("--video: cannot start ffmpeg: %s", strerror(errno));
        return 1;
    }
    if (pid == 0) {
        if (log)
            dup2(fileno(log), 2);
        execv(ffmpeg, args);
        _exit(127);
    }
    int status = 0;
    bool ok = waitpid(pid, &status, 0) >= 0 && WIFEXITED(status) && WEXITSTATUS(status) == 0;
    char last[512] = "", line[512];
    while (log && !ok && (rewind(log), true)) { /* the last non-empty line ffmpeg wrote */
        while (fgets(line, sizeof line, log))
            if (line[strspn(line, " \t\r\n")])
                snprintf(last, sizeof last, "%s", line);
        break;
    }
    last[strcspn(last, "\r\n")] = '\0';
    if (log)
        fclose(log);
    if (!ok) {
        cli_error("--video: ffmpeg failed making %s (exit status %d)%s%s", video,
                  WIFEXITED(status) ? WEXITSTATUS(status) : -1, last[0] ? ": " : "", last);
        return 1;
    }
    return 0;
}

bool render_raw_companion(const char *path, char *raw, size_t cap)
{
    const char *dot = strrchr(path, '.');
    if (!dot || strcmp(dot, ".exr") == 0)
        return false;
    snprintf(raw, cap, "%.*s-raw%s", (int)(dot - path), path, dot);
    return true;
}

void render_plan_files(const render_opts *o, output_plan *p)
{
    static char raw[4200];
    p->nfiles = 0;
    p->files[p->nfiles++] = o->resume; /* NULL entries are skipped */
    p->files[p->nfiles++] = o->checkpoint;
    p->files[p->nfiles++] = o->video;
    for (int k = 0; k < o->nlight && p->nfiles < (int)(sizeof p->files / sizeof p->files[0]) - 2; k++)
        p->files[p->nfiles++] = o->light_value[k];
    p->nbase = p->nfiles;
    if (o->kind != 1) {
        p->files[p->nfiles++] = o->out_path;
        if (o->denoise && render_raw_companion(o->out_path, raw, sizeof raw))
            p->files[p->nfiles++] = raw;
    }
}

/* Writes the render's image to path; with --denoise the denoised image (brume_denoise),
 * the image before denoising kept: in the EXR's layer "raw", else beside it as NAME-raw.EXT,
 * written first. A kept signal (cli_signals_keep) cancels the denoiser, and an image whose
 * render a signal stopped is not denoised: then only the image before denoising is written,
 * as NAME-raw.EXT, or as the EXR marked brume.denoise "no" (never a file named as the
 * denoised image holding anything else), its name in `written`, and *skipped is true. */
static brume_status write_image(brume_context *ctx, brume_image *image, const char *path,
                                const brume_write_options *wopts, bool denoise, int threads, bool quiet,
                                char *written, size_t cap, bool *skipped)
{
    *skipped = false;
    snprintf(written, cap, "%s", path);
    if (!denoise)
        return brume_image_write(ctx, image, path, wopts);
    char raw[4200];
    bool beside = render_raw_companion(path, raw, sizeof raw);
    brume_status st;
    if (beside && (st = brume_image_write(ctx, image, raw, wopts)) != BRUME_OK)
        return st;
    if (beside && !quiet && !cli_signal())
        fprintf(stderr, "brume: the image before denoising: %s\n", raw);
    brume_image *den = NULL;
    st = BRUME_ERROR_CANCELLED;
    if (!cli_signal()) {
        cli_signals_cancel(ctx);
        st = brume_denoise(ctx, image, threads, &den);
        cli_signals_cancel(NULL);
    }
    if (st == BRUME_ERROR_CANCELLED && cli_signal()) {
        *skipped = true;
        if (beside) {
            snprintf(written, cap, "%s", raw);
            return BRUME_OK;
        }
        if ((st = brume_image_set_attribute(ctx, image, "brume.denoise", "no: interrupted")) != BRUME_OK)
            return st;
        return brume_image_write(ctx, image, path, wopts);
    }
    if (st != BRUME_OK)
        return st;
    st = brume_image_write(ctx, den, path, wopts);
    brume_image_release(den);
    return st;
}

int render_check_denoise_memory(const brume_scene *scene)
{
    brume_render_settings rs;
    brume_scene_settings(scene, &rs);
    /* the image's layers: depth and samples 1 channel each, the others 3 */
    static const struct { unsigned aov; int channels; } layers[] = {
        {BRUME_AOV_DEPTH, 1}, {BRUME_AOV_ALBEDO, 3}, {BRUME_AOV_NORMAL, 3}, {BRUME_AOV_VARIANCE, 3}, {BRUME_AOV_SAMPLES, 1}};
    int channels = 0;
    for (size_t i = 0; i < sizeof layers / sizeof layers[0]; i++)
        channels += (rs.aovs & layers[i].aov) ? layers[i].channels : 0;
    /* the image it reads is held with them (the film is let go first: render_write_frame) */
    size_t limit = 0, used = brume_scene_memory(scene, &limit), left = limit > used ? limit - used : 0;
    double need = (double)brume_denoise_memory(rs.width, rs.height, channels) +
                  (4.0 + channels) * sizeof(float) * rs.width * rs.height;
    if (need <= (double)left)
        return 0;
    const double mib = 1.0 / 1048576.0;
    cli_error("--denoise: render.max_memory_mb: denoising a %d x %d image needs %.1f MiB, over the %.1f MiB left "
              "of the limit of %.0f MiB (the scene took %.1f MiB)", rs.width, rs.height, need * mib,
              (double)left * mib, (double)limit * mib, (double)used * mib);
    return 1;
}

/* Checks every output of the plan (make false: nothing is created) or makes their missing
 * folders (make true), each folder once. 0, or 1 with a message. */
int render_prepare_outputs(output_plan *p, bool make)
{
    char prev[4096] = "", path[4096];
    for (long k = 0; k < p->nframes; k++) {
        long f = p->sequence ? p->first + k : -1;
        if (p->nshards > 1 && f % p->nshards != p->shard)
            continue;
        if (p->kind == 1)
            render_frame_path(p->out_path, f, path, sizeof path);
        else
            snprintf(path, sizeof path, "%s", p->out_path);
        char raw[4200];
        if (!make && (cli_check_output("-o", path, BRUME_FILE_IMAGE, p->scene_path, NULL, p->files, p->nbase) != 0 ||
                      (p->denoise && render_raw_companion(path, raw, sizeof raw) &&
                       cli_check_output("--denoise", raw, BRUME_FILE_IMAGE, p->scene_path, NULL, p->files, p->nbase))))
            return 1;
        const char *slash = strrchr(path, '/');
        size_t dl = slash ? (size_t)(slash - path) : 0;
        if (k > 0 && strlen(prev) == dl && strncmp(prev, path, dl) == 0)
            continue;
        snprintf(prev, sizeof prev, "%.*s", (int)dl, path);
        if (cli_prepare_folder("-o", path, make) != 0)
            return 1;
    }
    if (make && p->checkpoint && cli_prepare_folder("--checkpoint", p->checkpoint, true) != 0)
        return 1;
    if (make && p->video && cli_prepare_folder("--video", p->video, true) != 0)
        return 1;
    p->made = make;
    return 0;
}

/* --stats: the run's statistics (brume_stats, docs/stats.md), one line per quantity. */
static void print_stats(brume_context *ctx, const brume_scene *scene, const char *path)
{
    (void)ctx;
    brume_stats st;
    brume_scene_stats(scene, &st);
    if (!st.rendered)
        return;
    const char *method = brume_method_name(st.method);
    FILE *e = stderr;
    fprintf(e, "stats: %s: method %s, %.3f s, %llu camera rays, %.3f CPU s in the estimator\n", path, method,
            st.seconds, (unsigned long long)st.camera_rays, st.li_cpu_seconds);
    if (st.method == BRUME_METHOD_BLASI) {
        fprintf(e, "stats: blasi light pass %.3f s: %llu rays, %llu interceptions, %llu deposits\n",
                st.blasi.light_seconds, (unsigned long long)st.blasi.light_rays,
                (unsigned long long)st.blasi.interceptions, (unsigned long long)st.blasi.deposits);
        fprintf(e, "stats: blasi power stored %.6g of %.6g emitted (%.1f %%)\n", st.blasi.power_stored,
                st.blasi.power_emitted,
                st.blasi.power_emitted > 0.0 ? 100.0 * st.blasi.power_stored / st.blasi.power_emitted : 0.0);
        fprintf(e, "stats: blasi view pass %.3f s\n", st.blasi.view_seconds);
    } else if (st.method == BRUME_METHOD_STAM) {
        fprintf(e, "stats: stam %.2f blobs per camera ray; %.2f hierarchy queries per camera ray, %.2f cells "
                   "(BVH nodes) and %.2f blobs per query\n",
                st.stam.blobs_per_ray, st.stam.queries_per_ray, st.stam.nodes_per_query, st.stam.blobs_per_query);
    } else {
        fprintf(e, "stats: %s %.3f vertices per path, %.3f collisions and %.3f null collisions per camera path\n",
                method, st.path.vertices, st.path.collisions, st.path.null_collisions);
        fprintf(e, "stats: %s %.3f majorant cells walked and %.3f density lookups per camera path\n", method,
                st.path.majorant_cells, st.path.density_lookups);
        fprintf(e, "stats: %s CPU s: tracking %.3f, next-event estimation %.3f, shading %.3f\n", method,
                st.path.tracking_cpu_seconds, st.path.nee_cpu_seconds, st.path.shading_cpu_seconds);
    }
    fprintf(e, "stats: %llu samples reached the bound of %llu tentative collisions a sample\n",
            (unsigned long long)st.samples_cut, (unsigned long long)st.collision_bound);
    fprintf(e, "stats: %llu samples gave NaN or infinity and were added as 0\n",
            (unsigned long long)st.samples_nonfinite);
}

/* --print-scene: the scene description the loader reads, on stdout. */
int render_print_scene(const render_opts *o)
{
    if (o->nsets > 0) { /* brume_scene_text shows the file before the overrides: never a --set dropped silently */
        cli_error("--print-scene prints the scene as the file gives it, before --set: leave --set out");
        return 2;
    }
    brume_context *ctx = brume_context_new();
    if (!ctx) {
        cli_error("out of memory");
        return 1;
    }
    brume_load_options lo = {0.0, 0, NULL, 0, &o->studio, 0, o->lenient};
    char *text = NULL;
    int rc = 0;
    if (brume_scene_text(ctx, &(brume_source){.path = o->scene_path}, &lo, &text) != BRUME_OK) {
        cli_error("%s", brume_context_last_error(ctx));
        rc = 1;
    } else if (fputs(text, stdout) == EOF || putchar('\n') == EOF || fflush(stdout) != 0) {
        cli_error("--print-scene: cannot write to stdout");
        rc = 1;
    }
    free(text);
    brume_context_release(ctx);
    return rc;
}

/* The line a written frame gets on stderr (not with --quiet): size, samples, method, time,
 * and the noise and time budgets when the render had them, with what stopped it (the
 * library's brume_render_progress.stopped). */
static void report_frame(const render_run *r, const char *path, int owner, const brume_render_settings *rs,
                         double secs)
{
    if (owner != r->d.rank)
        fprintf(stderr, "brume: %s: %d x %d, %d spp, method %s, rendered by rank %d\n", path, rs->width, rs->height,
                rs->spp, brume_method_name(rs->method), owner);
    else if (!r->split_tiles && (rs->time_budget > 0.0 || rs->noise_target > 0.0)) {
        const brume_render_progress *p = &r->jr.progress;
        char noise[64] = "";
        if (rs->noise_target > 0.0 && p->spp_max < 2)
            snprintf(noise, sizeof noise, ", noise not known (under 2 samples; target %.3g%%)",
                     100.0 * rs->noise_target);
        else if (rs->noise_target > 0.0)
            snprintf(noise, sizeof noise, ", noise %.3g%% (target %.3g%%)", 100.0 * p->noise,
                     100.0 * rs->noise_target);
        char budget[64] = "";
        if (rs->time_budget > 0.0)
            snprintf(budget, sizeof budget, " (rendering %.2f s of a %.3g s budget)", r->jr.seconds, rs->time_budget);
        char why[192];
        cli_progress_stop_reason(p, rs, why, sizeof why);
        fprintf(stderr, "brume: %s: %d x %d, %d to %d spp (%.1f on average)%s, method %s, %.2f s%s%s%s\n", path,
                rs->width, rs->height, p->spp_min, p->spp_max, p->spp_mean, noise, brume_method_name(rs->method), secs,
                budget, why[0] ? "; stopped: " : "", why);
    } else
        fprintf(stderr, "brume: %s: %d x %d, %d spp, method %s, %.2f s (%.2f M samples/s)\n", path, rs->width,
                rs->height, rs->spp, brume_method_name(rs->method), secs, (double)rs->width * rs->height * rs->spp / secs * 1e-6);
    int ignored = brume_scene_ignored_count(r->scene);
    if (ignored > 0)
        fprintf(stderr, "brume: %d pbrt construct%s ignored (--lenient)\n", ignored, ignored == 1 ? "" : "s");
}

/* A failure the context explains: its message, exit status 1. */
static int render_write_failed(const render_run *r)
{
    cli_error("%.1000s", brume_context_last_error(r->ctx));
    return 1;
}

/* After a frame: its statistics; on rank 0 its image written (denoised with --denoise), or
 * the partial image of an interrupted render under a name that says so. 0, or the exit
 * status with a message. path (a buffer of size n) may be renamed. */
int render_write_frame(render_run *r, char *path, size_t n, int owner, const brume_render_settings *rs,
                       double t0)
{
    const render_opts *o = r->o;
    if (o->stats && owner == r->d.rank)
        print_stats(r->ctx, r->scene, path);
    if (o->stats && owner == r->d.rank && r->ahead)
        fprintf(stderr, "stats: frame %ld grids read ahead: %s\n", r->ahead_frame, r->ahead);
    if (r->root && r->jr.interrupted && r->jr.progress.spp_max == 0) {
        fprintf(stderr, "brume: interrupted by %s before any sample of %s: nothing written\n",
                cli_signal_name(r->jr.signal), path);
        return 128 + r->jr.signal;
    }
    if (r->root && o->denoise && !r->serve) { /* the film is let go before the denoiser's buffers are
                                                 made (render_check_denoise_memory counts on it) */
        brume_render_job_release(r->job);
        r->job = NULL;
    }
    if (r->root && r->jr.interrupted) {
        /* a frame of a sequence is named for what it is: "f_0003.partial.png", never the
         * name a finished frame has (a video or a later run would take it for whole) */
        if (o->sequence) {
            char whole[4096];
            snprintf(whole, sizeof whole, "%s", path);
            const char *slash = strrchr(whole, '/'), *dot = strrchr(whole, '.');
            size_t stem = dot && (!slash || dot > slash) ? (size_t)(dot - whole) : strlen(whole);
            snprintf(path, n, "%.*s.partial%s", (int)stem, whole, whole + stem);
        }
        char written[4200];
        bool skipped;
        if (write_image(r->ctx, r->image, path, &o->wopts, o->denoise, rs->threads, o->quiet, written,
                        sizeof written, &skipped) != BRUME_OK)
            return render_write_failed(r);
        const brume_render_progress *p = &r->jr.progress;
        char spp[128] = "the ranks' tiles as far as each came"; /* MPI: the counts stay on the ranks */
        if (p->spp_max >= 0)
            snprintf(spp, sizeof spp, "%d to %d samples per pixel, %.1f on average", p->spp_min, p->spp_max,
                     p->spp_mean);
        fprintf(stderr, "brume: interrupted by %s: wrote the partial image %s%s (%s)%s%s\n",
                cli_signal_name(r->jr.signal), written, skipped ? ", not denoised" : "", spp,
                r->jr.checkpoint_written ? "; checkpoint " : "", r->jr.checkpoint_written ? o->checkpoint : "");
        return 128 + r->jr.signal;
    }
    if (r->root) {
        char written[4200];
        bool skipped;
        if (write_image(r->ctx, r->image, path, &o->wopts, o->denoise, rs->threads, o->quiet, written,
                        sizeof written, &skipped) != BRUME_OK)
            return render_write_failed(r);
        if (skipped) { /* the render was whole: only its denoising was stopped */
            fprintf(stderr, "brume: interrupted by %s while denoising: wrote the image before denoising %s, not "
                            "denoised\n", cli_signal_name(cli_signal()), written);
            return 128 + cli_signal();
        }
        if (!o->quiet)
            report_frame(r, path, owner, rs, render_now_seconds() - t0);
        brume_stats bs;
        brume_scene_stats(r->scene, &bs);
        if (!o->quiet && bs.samples_cut > 0 && owner == r->d.rank) /* a bias: said even without --stats */
            fprintf(stderr, "brume: %s: %llu samples reached the bound of %llu tentative collisions a sample and were "
                            "ended there (docs/stats.md)\n",
                    path, (unsigned long long)bs.samples_cut, (unsigned long long)bs.collision_bound);
        if (!o->quiet && bs.samples_nonfinite > 0 && owner == r->d.rank) /* a bias too */
            fprintf(stderr, "brume: %s: %llu samples gave NaN or infinity and were added as 0 (docs/stats.md)\n", path,
                    (unsigned long long)bs.samples_nonfinite);
        if (!o->quiet && r->jr.budget_spent && r->jr.checkpoint_written)
            fprintf(stderr, "brume: the time budget ended the render before its samples: its state is kept in %s "
                            "(--resume %s with another --time adds samples)\n", o->checkpoint, o->checkpoint);
    }
    brume_image_release(r->image);
    r->image = NULL;
    return 0;
}
