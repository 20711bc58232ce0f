/* cmd_render.c - `brume render`: load a scene (or the default), render one image or a
 * sequence of frames, optionally over MPI ranks or as one shard of a render farm, and
 * assemble a video with ffmpeg (docs/animation.md). Its flags are cli_render_flags.c's
 * table; what it writes and prints is cli_render_output.c. */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli_render.h"
#include "commands.h"

/* Loads frame `f` (or the plain scene when f < 0), applies the command-line settings and
 * commits, counting `held` bytes of another scene against the memory limit (the frame that
 * renders while this one is read ahead). On failure returns NULL; the context has the
 * message. */
static brume_scene *load_scene(brume_context *ctx, const render_opts *o, long f, size_t held)
{
    brume_scene *scene = NULL;
    brume_status st;
    /* the built-in scene is static: it is loaded at time 0 and its camera moved below */
    brume_load_options lo = {0.0, o->scene_path && f > 0 ? f : 0, o->sets, o->nsets, &o->studio, held, o->lenient};
    st = brume_scene_load(ctx, &(brume_source){.path = o->scene_path}, &lo, &scene);
    if (st != BRUME_OK)
        return NULL;
    for (int i = 0; (f < 0 || f == o->first) && i < brume_scene_ignored_count(scene); i++)
        fprintf(stderr, "brume: warning: %s (ignored: --lenient)\n", brume_scene_ignored(scene, i));
    for (int k = 0; k < o->nlight; k++)
        if (brume_scene_set_option(ctx, scene, o->light_key[k], o->light_value[k]) != BRUME_OK) {
            brume_scene_release(scene);
            return NULL;
        }
    brume_render_settings rs;
    brume_scene_settings(scene, &rs);
    if (o->spp) rs.spp = o->spp;
    if (o->width) rs.width = o->width;
    if (o->height) rs.height = o->height;
    if (o->threads >= 0) rs.threads = o->threads;
    if (o->device >= -1) rs.device = o->device;
    if (o->max_depth) rs.max_depth = o->max_depth;
    if (o->have_seed) rs.seed = o->seed;
    if (o->method && brume_method_from_name(ctx, o->method, &rs.method) != BRUME_OK) {
        brume_scene_release(scene);
        return NULL;
    }
    /* --time and --noise went in as render.time and render.noise (set_override): spp, from
     * --spp, the scene or its default, is the maximum under them all alike */
    if (o->min_spp) rs.min_spp = o->min_spp;
    rs.aovs |= o->aovs;
    if (o->denoise) /* what the denoiser reads (docs/denoise.md) */
        rs.aovs |= BRUME_AOV_VARIANCE | BRUME_AOV_ALBEDO | BRUME_AOV_NORMAL | BRUME_AOV_DEPTH;
    cli_job_callback(&rs.progress_fn, &rs.progress_user);
    rs.stats = o->stats;
    if (brume_scene_set_settings(ctx, scene, &rs) != BRUME_OK || brume_scene_commit(ctx, scene) != BRUME_OK) {
        brume_scene_release(scene);
        return NULL;
    }
    /* the built-in scene has no file to load at a frame: it is static, so move its camera */
    if (!o->scene_path && f >= 0 && brume_scene_set_camera_time(ctx, scene, (double)f / rs.fps) != BRUME_OK) {
        brume_scene_release(scene);
        return NULL;
    }
    return scene;
}

/* After dist_begin: checks the processes against the options and, on rank 0, every file
 * the run will write or read. 0, or the exit status with a message. */
static int check_processes(render_run *r)
{
    const render_opts *o = r->o;
    if (r->d.size > 1 && o->nshards > 1) {
        cli_error("--shard: not under mpirun (mpirun already splits the work)");
        return 2;
    }
    /* Several ranks split the frames when each gets a fair share, else the tiles of each
     * frame. Either way rank 0 writes every file. */
    r->split_frames = r->d.size > 1 && (o->nframes % r->d.size == 0 || o->nframes >= 4L * r->d.size);
    r->split_tiles = r->d.size > 1 && !r->split_frames;
    r->root = r->d.rank == 0;
    r->load_progress = !o->quiet && r->root && !r->split_frames;
    r->ahead_why = "no (the first frame)";
    if (r->d.size > 1 && (o->checkpoint || o->resume || o->serve_spec || o->time_budget > 0.0 || o->noise > 0.0)) {
        cli_error("%s: not under mpirun", o->checkpoint ? "--checkpoint" : o->resume ? "--resume" : o->serve_spec ? "--serve"
                                            : o->time_budget > 0.0 ? "--time" : "--noise");
        return 2;
    }
    /* outputs: checked before any work (every frame's, once per folder); the missing folders
     * are made once the first scene has been read and checked (prepare_outputs), so that a bad
     * scene leaves none behind */
    r->plan = (output_plan){o->out_path, o->kind, o->sequence, o->first, o->nframes, o->nshards, o->shard,
                            o->checkpoint, o->video, o->scene_path, false, o->denoise, {NULL}, 0, 0};
    if (!r->root)
        return 0;
    render_plan_files(o, &r->plan);
    if (render_prepare_outputs(&r->plan, false) != 0)
        return 1;
    output_plan *p = &r->plan;
    for (int k = 0; k < o->nlight; k++)
        /* what the file holds is blasi_prepare's to check, after the scene's inputs */
        if (o->light_key[k][6] == 's' && cli_check_output("--save-light", o->light_value[k], BRUME_FILE_ANY,
                                                          o->scene_path, NULL, p->files, p->nfiles) != 0)
            return 1;
    /* the checkpoint may be the file the render resumes from: the files but that one */
    if (o->checkpoint && (cli_check_output("--checkpoint", o->checkpoint, BRUME_FILE_CHECKPOINT, o->scene_path, NULL,
                                           p->files + 1, p->nfiles - 1) != 0 ||
                          cli_prepare_folder("--checkpoint", o->checkpoint, false) != 0))
        return 1;
    if (o->resume && access(o->resume, R_OK) != 0) {
        cli_error("--resume: %s: %s", o->resume, strerror(errno));
        return 1;
    }
    return 0;
}

/* Everything before the first frame, after dist_begin: processes, outputs, signals, the
 * live view, the context, a grid sequence's files. 0, or the exit status with a message and
 * nothing left open. */
static int begin_run(render_run *r)
{
    const render_opts *o = r->o;
    int rc = check_processes(r);
    if (rc != 0) {
        dist_end(&r->d);
        return rc;
    }
    cli_signals_install();
    if (o->serve_spec) {
        if (!(r->serve = cli_serve_start(o->serve_spec))) {
            dist_end(&r->d);
            return 1;
        }
        fprintf(stderr, "brume: live view at %s\n", cli_serve_url(r->serve));
    }
    if (!(r->ctx = brume_context_new())) {
        cli_error("out of memory");
        cli_serve_stop(r->serve);
        dist_end(&r->d);
        return 1;
    }
    if (o->sequence && o->scene_path) { /* grid sequences: every frame's file, before the first frame */
        brume_load_options lo = {0.0, 0, o->sets, o->nsets, &o->studio, 0, o->lenient};
        if (brume_scene_check_frames(r->ctx, &(brume_source){.path = o->scene_path}, &lo, o->first, o->last) != BRUME_OK) {
            cli_error("%.1000s", brume_context_last_error(r->ctx));
            brume_context_release(r->ctx);
            cli_serve_stop(r->serve);
            dist_end(&r->d);
            return 1;
        }
    }
    return 0;
}

/* A failure the context explains: its message, exit status 1. */
static int render_failed(const render_run *r)
{
    cli_error("%.1000s", brume_context_last_error(r->ctx));
    return 1;
}

/* Rank 0 receives frame f (index k) that rank `owner` rendered; the scene gives its size.
 * 0, or the exit status with a message. */
static int receive_frame(render_run *r, long k, long f, int owner, brume_render_settings *rs)
{
    if (!r->scene && !(r->scene = load_scene(r->ctx, r->o, f, 0)))
        return render_failed(r);
    if (!r->plan.made && render_prepare_outputs(&r->plan, true) != 0)
        return 1;
    brume_scene_settings(r->scene, rs);
    if (brume_image_new(r->ctx, rs->width, rs->height, &r->image) != BRUME_OK || !dist_recv_at_root(&r->d, brume_image_pixels(r->image), (size_t)rs->width * (size_t)rs->height * 4,
                                        owner, (int)k)) {
        cli_error("frame %ld: could not receive it from rank %d", f, owner);
        return 1;
    }
    return 0;
}

/* The rank that renders frame index k, or -1 when this shard skips it. */
static int frame_owner(const render_run *r, long k)
{
    const render_opts *o = r->o;
    long f = o->sequence ? o->first + k : -1;
    if (o->nshards > 1 && f % o->nshards != o->shard)
        return -1;
    return r->split_frames ? (int)(k % r->d.size) : r->d.rank;
}

/* The read-ahead thread's load (cli_read_ahead.h): what render_frame would load. */
static brume_scene *load_ahead(brume_context *ctx, const void *user, long f, size_t held)
{
    const render_run *r = user;
    return load_scene(ctx, r->o, f, held);
}

/* Before frame index k renders: the next frame this process renders is read on a thread
 * when the world moves (each frame a scene of its own) and the memory limit holds both. */
static void read_next(render_run *r, long k)
{
    const render_opts *o = r->o;
    if (!o->sequence || !o->scene_path || brume_scene_world_is_static(r->scene))
        return;
    long j = k + 1;
    while (j < o->nframes && frame_owner(r, j) != r->d.rank)
        j++;
    if (j == o->nframes)
        return;
    if (o->no_read_ahead) {
        r->ahead_why = "no (--no-read-ahead)";
        return;
    }
    if (!r->ra.load)
        r->ra = (cli_read_ahead){.load = load_ahead, .user = r};
    r->ahead_why = "no (its read beside the frame before failed: read again after it)"; /* if it fails */
    cli_read_ahead_start(&r->ra, r->scene, o->first + j, &r->ahead_why);
}

/* On rank 0, once frame path's scene is loaded: its inputs are known now, and none of them may
 * be written over (the image, its raw companion, the checkpoint); the scene is good, so the
 * output folders are made. 0, or 1 with a message. */
static int check_frame_outputs(render_run *r, const char *path)
{
    const render_opts *o = r->o;
    const output_plan *p = &r->plan;
    char raw[4200];
    if (cli_check_output("-o", path, BRUME_FILE_IMAGE, o->scene_path, r->scene, p->files, p->nbase) != 0 ||
        (o->denoise && render_raw_companion(path, raw, sizeof raw) &&
         cli_check_output("--denoise", raw, BRUME_FILE_IMAGE, o->scene_path, r->scene, p->files, p->nbase) != 0) ||
        (o->checkpoint && cli_check_output("--checkpoint", o->checkpoint, BRUME_FILE_CHECKPOINT, o->scene_path,
                                           r->scene, p->files + 1, p->nfiles - 1) != 0) ||
        (o->denoise && render_check_denoise_memory(r->scene) != 0))
        return 1;
    return !r->plan.made && render_prepare_outputs(&r->plan, true) != 0 ? 1 : 0;
}

/* This rank's tiles of the frame (MPI). A signal stops the part, its samples kept
 * (cli_job.h), on every rank mpirun passes it to; the ranks then sum which of them were
 * stopped, so that rank 0 writes the sum of their tiles as a partial image when any was.
 * 0, or the exit status with a message. */
static int render_part(render_run *r)
{
    memset(&r->jr, 0, sizeof r->jr);
    cli_signals_keep(true);
    brume_status st = brume_render_part(r->ctx, r->scene, r->d.rank, r->d.size, &r->image);
    if (st != BRUME_OK && !(st == BRUME_ERROR_CANCELLED && cli_signal() && r->image)) {
        cli_signals_keep(false);
        return render_failed(r);
    }
    float stopped = cli_signal() ? (float)cli_signal() : 0.0f; /* kept on: the write keeps it too */
    if (!dist_reduce_to_root(&r->d, &stopped, 1)) {
        cli_signals_keep(false);
        cli_error("gathering the ranks' interruptions on rank 0 failed");
        return 1;
    }
    if (r->root && stopped > 0.0f) {
        r->jr.interrupted = true;
        r->jr.signal = cli_signal() ? cli_signal() : SIGTERM; /* another rank's: mpirun's SIGTERM */
        r->jr.progress.spp_max = -1; /* the ranks' sample counts are not gathered */
        brume_image_set_attribute(r->ctx, r->image, "brume.partial", "yes");
    }
    return 0;
}

/* Loads frame f (or moves the camera of the scene it shares with the frame before), then
 * renders it here: the whole image, or this rank's tiles gathered on rank 0. 0; -1 when
 * the frame went to rank 0 (nothing more to do here); or the exit status with a message. */
static int render_frame(render_run *r, long k, long f, const char *path, brume_render_settings *rs)
{
    const render_opts *o = r->o;
    r->ahead = NULL;
    r->ahead_frame = f;
    /* frames that differ only by the camera share one scene (and its integrator state:
     * Blasi's first pass is done once) */
    if (r->scene && brume_scene_world_is_static(r->scene) && f >= 0) {
        brume_scene_settings(r->scene, rs);
        if (brume_scene_set_camera_time(r->ctx, r->scene, (double)f / rs->fps) != BRUME_OK)
            return render_failed(r);
    } else {
        brume_scene_release(r->scene);
        r->scene = cli_read_ahead_take(&r->ra, f); /* read while the frame before rendered */
        r->ahead = r->scene ? "yes" : r->ahead_why;
        if (!r->scene && !(r->scene = load_scene(r->ctx, o, f, 0)))
            return render_failed(r);
        if (!o->sequence || !o->scene_path || brume_scene_world_is_static(r->scene))
            r->ahead = NULL; /* no grids of its own per frame: nothing to say */
        if (r->root && check_frame_outputs(r, path) != 0)
            return 1;
    }
    read_next(r, k);
    brume_scene_settings(r->scene, rs);
    if (r->split_tiles) {
        int rc = render_part(r);
        if (rc != 0)
            return rc;
    } else {
        if (r->serve)
            cli_serve_show(r->serve, NULL, NULL);
        brume_render_job_release(r->job);
        r->job = NULL;
        cli_job_opts jo = {o->checkpoint, 5.0, o->resume, 0, rs->noise_target, rs->time_budget, r->serve, path,
                           r->load_progress, o->progress_every};
        if (o->checkpoint || o->resume)
            jo.scene_key = cli_scene_key(o->scene_path, r->scene, o->nsets, o->sets, f);
        if (cli_run_job(r->ctx, r->scene, &jo, &r->job, &r->image, &r->jr) != BRUME_OK)
            return render_failed(r);
    }
    size_t n = (size_t)rs->width * (size_t)rs->height * 4;
    if (r->split_tiles && !dist_reduce_to_root(&r->d, brume_image_pixels(r->image), n)) {
        cli_error("frame %ld: gathering the tiles on rank 0 failed", f);
        return 1;
    }
    if (r->split_frames && !r->root && r->jr.interrupted) {
        /* rank 0 would take the partial frame for a whole one: it keeps the frames it has */
        fprintf(stderr, "brume: rank %d: interrupted by %s: frame %ld not sent (partial)\n", r->d.rank,
                cli_signal_name(r->jr.signal), f);
        return 128 + r->jr.signal;
    }
    if (r->split_frames && !r->root) {
        if (!dist_send_to_root(&r->d, brume_image_pixels(r->image), n, (int)k)) {
            cli_error("frame %ld: could not send it to rank 0", f);
            return 1;
        }
        brume_image_release(r->image);
        r->image = NULL;
        return -1;
    }
    return 0;
}

/* Every frame of the run this process has a part in (a shard's, a rank's share), stopping
 * between frames on a signal. 0, or the exit status with a message. */
static int render_frames(render_run *r)
{
    const render_opts *o = r->o;
    for (long k = 0; k < o->nframes; k++) {
        long f = o->sequence ? o->first + k : -1;
        int owner = frame_owner(r, k);
        if (owner < 0)
            continue;
        if (cli_signal()) { /* between frames: the finished ones stay */
            fprintf(stderr, "brume: interrupted by %s after %ld frame%s\n", cli_signal_name(cli_signal()), r->done,
                    r->done == 1 ? "" : "s");
            return 128 + cli_signal();
        }
        if (owner != r->d.rank && !r->root)
            continue;
        char path[4096];
        if (o->kind == 1)
            render_frame_path(o->out_path, f, path, sizeof path);
        else
            snprintf(path, sizeof path, "%s", o->out_path);
        brume_render_settings rs;
        double t0 = render_now_seconds();
        int st = owner != r->d.rank ? receive_frame(r, k, f, owner, &rs) : render_frame(r, k, f, path, &rs);
        if (st == 0) { /* from the render's end to the write: a signal keeps the image (cli_job.h) */
            cli_signals_keep(true);
            st = render_write_frame(r, path, sizeof path, owner, &rs, t0);
        }
        cli_signals_keep(false);
        if (st < 0)
            continue;
        if (st > 0)
            return st;
        r->done++;
    }
    return 0;
}

/* After the frames: the summary line, the live view's final image until Ctrl-C, the video.
 * 0, or the exit status with a message. */
static int finish_run(render_run *r, double t_all)
{
    const render_opts *o = r->o;
    if (r->root && !o->quiet && (o->nframes > 1 || r->d.size > 1))
        fprintf(stderr, "brume: %ld frame%s in %.2f s (%d process%s)\n", r->done, r->done == 1 ? "" : "s",
                render_now_seconds() - t_all, r->d.size, r->d.size == 1 ? "" : "es");
    if (r->serve && !o->serve_exit && r->root && !cli_signal()) {
        if (!o->quiet)
            fprintf(stderr, "brume: serving the final image at %s until Ctrl-C\n", cli_serve_url(r->serve));
        cli_signals_keep(true); /* Ctrl-C ends the serving, not the command */
        while (!cli_signal()) {
            struct timespec ts = {0, 50000000};
            nanosleep(&ts, NULL);
        }
        cli_signals_keep(false);
    }
    if (r->root && o->video && r->scene) {
        brume_render_settings rs;
        brume_scene_settings(r->scene, &rs);
        return render_make_video(o->out_path, o->first, rs.fps, o->video);
    }
    return 0;
}

/* Releases what the run holds; a failure on one rank stops the others. */
static void end_run(render_run *r, int rc)
{
    if (rc != 0 && r->d.size > 1)
        dist_abort(&r->d, rc);
    cli_read_ahead_end(&r->ra); /* a read under way is cancelled (a signal, a failure) */
    cli_serve_stop(r->serve);
    brume_render_job_release(r->job);
    brume_image_release(r->image);
    brume_scene_release(r->scene);
    brume_context_release(r->ctx);
    dist_end(&r->d);
}

int cmd_render(int argc, char **argv)
{
    render_opts o = {0};
    int rc = render_parse_options(&o, argc, argv);
    if (rc >= 0)
        return rc;
    if (o.print_scene)
        return render_print_scene(&o);
    if ((rc = render_check_request(&o)) != 0)
        return rc;
    render_run r = {.o = &o};
    if (!dist_begin(&r.d))
        return 1;
    /* one process: under mpirun a time budget is refused, so a bare grid keeps its spp */
    if (r.d.size == 1 && render_grid_defaults(&o) && !o.quiet)
        fprintf(stderr, "brume: %s: a grid file without --spp, --time or --noise: %g s of rendering, then the "
                        "denoiser (--spp N: N samples per pixel, deterministic)\n", o.scene_path, o.time_budget);
    if ((rc = begin_run(&r)) != 0)
        return rc;
    double t_all = render_now_seconds();
    rc = render_frames(&r);
    if (rc == 0)
        rc = finish_run(&r, t_all);
    end_run(&r, rc);
    return rc;
}
