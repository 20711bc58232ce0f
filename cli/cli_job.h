/* cli_job.h - how `brume render` runs a render job: signals, checkpoints, resume, output
 * checks (cli/cli_job.c). */
#ifndef BRUME_CLI_JOB_H
#define BRUME_CLI_JOB_H

#include <stdbool.h>
#include <stdint.h>

#include "brume.h"
#include "cli_serve.h"

/* SIGINT, SIGTERM, SIGHUP: the first stops the render within a tile (the work is kept; a
 * finished image is still written, the denoiser cancelled), a second ends the process at
 * once after removing temporary files (exit 128 + signal). */
void cli_signals_install(void);
/* Whether a signal now stops a phase whose work is kept (true: a render job runs, or the live
 * view serves the final image) or ends the process at once (false, the default). */
void cli_signals_keep(bool keep);
/* The context whose brume_denoise (or scene load) a kept signal cancels, NULL for none. */
void cli_signals_cancel(brume_context *ctx);
/* Sends sig to this process unless a signal came already: a stop asked twice (the live
 * view's POST /stop) stops once and never counts as the second signal that ends at once. */
void cli_signals_raise(int sig);
/* The first signal received, 0 if none. */
int cli_signal(void);
const char *cli_signal_name(int sig);

/* Before any work: the name of an image output: 0, or with a message 1 for an unknown
 * format, 2 (a bad command line) for layers asked without .exr. */
int cli_check_image_name(const char *flag, const char *path, bool need_exr);
/* Checks that path's folder exists or can be made, and (make) makes the missing folders and
 * checks a file can be made there; without make nothing is created, so a check before the
 * scene is read leaves nothing behind. 0, or 1 with a message. */
int cli_prepare_folder(const char *flag, const char *path, bool make);

/* The progress callback to put in the render settings: it stops the job on a signal and
 * writes checkpoints. */
void cli_job_callback(brume_progress_fn *fn, void **user);
/* What a checkpoint is tied to: the scene file's bytes (or the default scene), the bytes of
 * every file the loaded scene read (grids, meshes, tables, images), the scene overrides
 * (--set KEY=VALUE) but the time budget and the thread count, and the frame. */
uint64_t cli_scene_key(const char *scene_path, const brume_scene *scene, int nsets, const char *const *sets,
                       long frame);
/* Before any work: brume writes path (named by flag) as a file of kind only when
 * brume_output_check allows it: absent, or a regular file holding nothing or that kind, which
 * is not scene_path (may be NULL), not one of the scene's inputs (scene may be NULL) and not
 * one of others[0..nothers-1] (the command's other inputs and outputs, NULL entries skipped).
 * 0, or 1 with a message. */
int cli_check_output(const char *flag, const char *path, brume_file_kind kind, const char *scene_path,
                     const brume_scene *scene, const char *const *others, int nothers);

typedef struct cli_job_opts {
    const char *checkpoint;  /* --checkpoint FILE, or NULL */
    double checkpoint_every; /* seconds between checkpoints */
    const char *resume;      /* --resume FILE, or NULL */
    uint64_t scene_key;
    double noise_target;     /* the render's budgets: the figures written with the image */
    double time_budget;
    cli_serve *serve;        /* the live view, or NULL */
    const char *label;       /* what the live view calls this render */
    bool progress;           /* show the render's progress on stderr (cli_progress.h) */
    double progress_every;   /* seconds between two log lines; 0: the default */
} cli_job_opts;

typedef struct cli_job_result {
    bool interrupted;        /* a signal stopped it: the image is partial */
    int signal;
    bool checkpoint_written;
    bool budget_spent;       /* the time budget ended it with samples left to take (its
                                checkpoint, if any, is kept to resume from) */
    brume_render_progress progress;
    double seconds;          /* this run's rendering: begin (or resume, with the integrator's
                                preparation) and the passes; progress.elapsed counts the runs
                                before a resume too, not part of this run's time budget */
} cli_job_result;

/* Begins (or resumes) a job on the committed scene and runs it to its end or to a signal,
 * signals kept from its start (cli_signals_keep(true)) and still kept on success: the
 * caller writes the image, then calls cli_signals_keep(false);
 * *out is the image (partial when res->interrupted) with its figures as attributes, *job
 * the job (the caller releases it, after the live view lets go of it). On failure returns
 * the status (the context has the message) and nothing is allocated. */
brume_status cli_run_job(brume_context *ctx, const brume_scene *scene, const cli_job_opts *o, brume_render_job **job,
                         brume_image **out, cli_job_result *res);

#endif
