/* cli_render.h - the parts of `brume render`: its flags and the request they make
 * (cli_render_flags.c), the run over frames, processes and the live view (cmd_render.c),
 * and what it writes and prints (cli_render_output.c). */
#ifndef BRUME_CLI_CLI_RENDER_H
#define BRUME_CLI_CLI_RENDER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "brume.h"
#include "cli_dist.h"
#include "cli_job.h"
#include "cli_read_ahead.h"
#include "cli_serve.h"

enum { MAX_SETS = 64 };

/* The command line of `brume render`, as cli_render_flags.c reads it. */
typedef struct render_opts {
    const char *scene_path;
    int spp, width, height, threads, max_depth;
    int device; /* -2: as the scene says */
    uint64_t seed;
    bool have_seed, quiet, denoise;
    const char *method;
    bool stats;
    double time_budget, noise; /* --time, --noise; 0 = the scene's */
    double progress_every;     /* --progress-every; 0 = the default */
    int min_spp;               /* --min-spp; 0 = the scene's */
    unsigned aovs;             /* --aov */
    int nsets; /* scene overrides "KEY=VALUE" (--set) */
    const char *sets[MAX_SETS];
    char set_buf[MAX_SETS][4200];
    /* files the command line names for blasi's light pass (--save-light, --load-light and
     * --set blasi.save_light / load_light): set as method options after loading, relative to
     * the working directory, since a scene file (and so an override of it) may write only
     * inside its own folder */
    int nlight;
    const char *light_key[MAX_SETS], *light_value[MAX_SETS];
    brume_studio_options studio; /* a grid file's studio scene (--up, --grid, --no-ground) */
    bool print_scene;            /* --print-scene */
    bool lenient;                /* --lenient */
    bool no_read_ahead;          /* --no-read-ahead */
    /* what the command writes, and how */
    const char *out_path;        /* -o: one file, or a frame pattern (kind 1) */
    const char *video;           /* --video, or NULL */
    long first, last;            /* --frames A-B or --frame F; -1: one image, no sequence */
    int shard, nshards;          /* --shard I/N */
    brume_write_options wopts;   /* --exposure, --filmic */
    const char *checkpoint, *resume, *serve_spec; /* or NULL */
    bool serve_exit;
    /* derived by check_request */
    bool sequence;               /* --frames or --frame given */
    long nframes;
    int kind;                    /* pattern_kind of out_path */
    bool grid_defaults;          /* a bare grid file without a sample budget: --time and --denoise */
} render_opts;

/* The files a render writes: every frame's output (a pattern or one path) and the checkpoint. */
typedef struct output_plan {
    const char *out_path;
    int kind; /* pattern_kind of out_path: 1 a frame pattern */
    bool sequence;
    long first, nframes;
    int nshards, shard;
    const char *checkpoint, *video; /* or NULL */
    const char *scene_path;
    bool made; /* the folders exist */
    bool denoise; /* a PNG or PFM output has its raw companion (render_raw_companion) */
    const char *files[72]; /* the run's other inputs and outputs, none of which an output may be */
    int nfiles, nbase;     /* files[nbase..] are -o (one image) and its raw companion */
} output_plan;

/* One run of the command: the processes, the files, and what is alive between frames. */
typedef struct render_run {
    const render_opts *o;
    dist d;
    bool split_frames, split_tiles; /* several ranks split the frames, or each frame's tiles */
    bool root;                      /* rank 0: it writes every file */
    output_plan plan;
    cli_serve *serve;               /* the live view, or NULL */
    brume_context *ctx;
    brume_scene *scene;             /* the last frame's, kept while the world is static */
    bool load_progress;             /* the render's progress is shown (cli_progress.h) */
    cli_read_ahead ra;              /* the next frame, read while this one renders */
    const char *ahead_why;          /* why the next frame was not read ahead, or NULL */
    const char *ahead;              /* --stats: the rendered frame's "yes" or why not; NULL: no line */
    long ahead_frame;
    brume_image *image;
    brume_render_job *job;
    cli_job_result jr;
    long done;                      /* frames written */
} render_run;

/* cli_render_flags.c: the command line into *o (zeroed by the caller). -1: go on; otherwise
 * the exit status (0 after --help, 2 for a bad command line, with its message). */
int render_parse_options(render_opts *o, int argc, char **argv);
/* What to render, checked before any work: the output name against the frames, the shards,
 * the video, the checkpoint. Sets sequence, nframes and kind. 0, or the exit status with a
 * message. */
int render_check_request(render_opts *o);

/* A grid file (.vdb, .nvdb) without --spp, --time, --noise (nor their render.* overrides)
 * renders as `make render` renders the default scene: a time budget (render.spp a cap), then
 * the denoiser. True when these defaults were set. */
bool render_grid_defaults(render_opts *o);

/* cli_render_output.c */
double render_now_seconds(void);
/* A printf pattern with exactly one %d conversion (flags 0 and a width allowed) and %%
 * for a literal percent: 1; no conversion: 0; anything else: -1. */
int render_pattern_kind(const char *p);
/* The file name of frame f from a pattern that render_pattern_kind accepted. */
void render_frame_path(const char *p, long f, char *out, size_t n);
/* Before any work: --video names a file brume may write, and ffmpeg is there. 0 or 1/2. */
int render_check_video(const char *video, const char *scene_path);
/* The name of --denoise's raw image beside a PNG or PFM path (NAME-raw.EXT); false for an EXR,
 * which keeps it as a layer. */
bool render_raw_companion(const char *path, char *raw, size_t cap);
/* With --denoise, on rank 0 before rendering: the denoiser's buffers (brume_denoise_memory)
 * and the image it reads fit in what render.max_memory_mb leaves after the scene, as the
 * film must (the film is released before denoising, but while the live view shows it).
 * 0, or 1 with a message naming the limit. */
int render_check_denoise_memory(const brume_scene *scene);
/* The files the run names, none of which an output may be: --resume first (the one file
 * --checkpoint may be), --checkpoint, --video, the light files, then -o (one image) and its
 * raw companion. Each output is compared with all of them but itself (the images' frames with
 * files[0..nbase)). */
void render_plan_files(const render_opts *o, output_plan *p);
/* ffmpeg assembles the PNG frames of pattern into video. 0, or 1 with a message. */
int render_make_video(const char *pattern, long first, double fps, const char *video);
/* Checks every output of the plan (make false: nothing is created) or makes their missing
 * folders (make true), each folder once. 0, or 1 with a message. */
int render_prepare_outputs(output_plan *p, bool make);
/* --print-scene: the scene description the loader reads, on stdout. The exit status. */
int render_print_scene(const render_opts *o);
/* After a frame: its statistics; on rank 0 its image written (denoised with --denoise), or
 * the partial image of an interrupted render under a name that says so. 0, or the exit
 * status with a message. path (a buffer of size n) may be renamed. */
int render_write_frame(render_run *r, char *path, size_t n, int owner, const brume_render_settings *rs, double t0);

#endif
