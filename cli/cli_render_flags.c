/* cli_render_flags.c - the flags of `brume render` in one table (cli_flags.h), from which
 * the command line is read and `brume help render` printed, and the checks of the request
 * they make before any work. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "args.h"
#include "cli_flags.h"
#include "cli_render.h"
#include "commands.h"

/* Scene overrides name files relative to the scene file's folder; on the command line a
 * relative name means the working directory, so the files a scene reads ("file" keys) are
 * made absolute here, and blasi's light files go to set_option (render_opts). */
static bool set_override(render_opts *o, const char *key, size_t keylen, const char *value)
{
    if (o->nsets == MAX_SETS || o->nlight == MAX_SETS) {
        cli_error("render: more than %d --set options", MAX_SETS);
        return false;
    }
    if ((keylen == 16 && strncmp(key, "blasi.save_light", 16) == 0) ||
        (keylen == 16 && strncmp(key, "blasi.load_light", 16) == 0)) {
        o->light_key[o->nlight] = key[6] == 's' ? "blasi.save_light" : "blasi.load_light";
        o->light_value[o->nlight++] = value;
        return true;
    }
    const char *leaf = key + keylen;
    while (leaf > key && leaf[-1] != '.' && leaf[-1] != ']')
        leaf--;
    size_t leaflen = (size_t)(key + keylen - leaf);
    bool is_file = leaflen == 4 && strncmp(leaf, "file", 4) == 0; /* files read by the scene */
    char cwd[2048] = "";
    if (is_file && value[0] && value[0] != '/' && value[0] != '"' && !getcwd(cwd, sizeof cwd)) {
        cli_error("--set %.*s: cannot read the working directory: %s", (int)keylen, key, strerror(errno));
        return false;
    }
    int n = snprintf(o->set_buf[o->nsets], sizeof o->set_buf[0], "%.*s=%s%s%s", (int)keylen, key, cwd,
                     cwd[0] ? "/" : "", value);
    if (n < 0 || (size_t)n >= sizeof o->set_buf[0]) {
        cli_error("--set %.*s: value too long", (int)keylen, key);
        return false;
    }
    o->sets[o->nsets] = o->set_buf[o->nsets];
    o->nsets++;
    return true;
}

/* "A-B" or "A" with 0 <= A <= B. */
static bool parse_range(const char *flag, const char *text, long *a, long *b)
{
    char *end;
    errno = 0;
    *a = strtol(text, &end, 10);
    *b = *a;
    if (*end == '-' && end != text) {
        const char *s = end + 1;
        *b = strtol(s, &end, 10);
        if (end == s)
            *b = -1;
    }
    if (errno || *end || *a < 0 || *b < *a || *b > 100000000L) {
        cli_error("%s: expected A-B with 0 <= A <= B, got '%s'", flag, text);
        return false;
    }
    return true;
}

/* "I/N" with 0 <= I < N. */
static bool parse_shard(const char *text, int *i, int *n)
{
    char *end;
    long a = strtol(text, &end, 10), b = -1;
    if (*end == '/' && end != text) {
        const char *s = end + 1;
        b = strtol(s, &end, 10);
        if (end == s)
            b = -1;
    }
    if (*end || b < 1 || b > 1000000 || a < 0 || a >= b) {
        cli_error("--shard: expected I/N with 0 <= I < N, got '%s'", text);
        return false;
    }
    *i = (int)a;
    *n = (int)b;
    return true;
}

/* "depth,albedo,..." -> bits of brume_aov. */
static bool parse_aovs(const char *text, unsigned *out)
{
    static const char *const names[5] = {"depth", "albedo", "normal", "variance", "samples"};
    *out = 0;
    for (const char *p = text;;) {
        size_t n = strcspn(p, ",");
        int k = 0;
        while (k < 5 && !(strlen(names[k]) == n && strncmp(p, names[k], n) == 0))
            k++;
        if (k == 5) {
            cli_error("--aov: unknown layer '%.*s' (known: depth, albedo, normal, variance, samples)", (int)n, p);
            return false;
        }
        *out |= 1u << k;
        if (!p[n])
            return true;
        p += n + 1;
    }
}

/* The flags that take more than a number or a name: each reads its value into the options
 * (cli_flag.call). */
static bool flag_frames(void *opts, const cli_flag *f, const char *v)
{
    const char *a = f->name;
    render_opts *o = opts;
    if (!parse_range(a, v, &o->first, &o->last))
        return false;
    if (a[7] == '\0' && o->first != o->last) {
        cli_error("--frame: one frame number expected, got '%s' (use --frames A-B)", v);
        return false;
    }
    return true;
}

static bool flag_shard(void *opts, const cli_flag *f, const char *v)
{
    (void)f;
    render_opts *o = opts;
    return parse_shard(v, &o->shard, &o->nshards);
}

static bool flag_seed(void *opts, const cli_flag *f, const char *v)
{
    const char *a = f->name;
    render_opts *o = opts;
    return (o->have_seed = arg_u64(a, v, &o->seed));
}

static bool flag_device(void *opts, const cli_flag *f, const char *v)
{
    (void)f;
    render_opts *o = opts;
    if (brume_device_from_name(NULL, v, &o->device) != BRUME_OK) {
        cli_error("--device: unknown device '%s' (known: cpu, cuda, cuda:N)", v);
        return false;
    }
    return true;
}

static bool flag_filmic(void *opts, const cli_flag *f, const char *v)
{
    (void)f, (void)v;
    ((render_opts *)opts)->wopts.tonemap = BRUME_TONEMAP_FILMIC;
    return true;
}

static bool flag_set(void *opts, const cli_flag *f, const char *v)
{
    (void)f;
    const char *eq = strchr(v, '=');
    if (!eq || eq == v) {
        cli_error("--set: expected KEY=VALUE, got '%s'", v);
        return false;
    }
    return set_override(opts, v, (size_t)(eq - v), eq + 1);
}

static bool flag_light(void *opts, const cli_flag *f, const char *v)
{
    const char *a = f->name;
    const char *key = a[2] == 's' ? "blasi.save_light" : "blasi.load_light"; /* --save-light, --load-light */
    return set_override(opts, key, strlen(key), v);
}

/* --time and --noise go in as render.time and render.noise: spp, from --spp, the scene or
 * its default, is the maximum under them all alike */
static bool flag_budget(void *opts, const cli_flag *f, const char *v)
{
    const char *a = f->name;
    render_opts *o = opts;
    bool t = a[2] == 't';
    double *x = t ? &o->time_budget : &o->noise;
    if (!arg_double(a, v, t ? 1e-3 : 1e-6, t ? 1e9 : 1.0, x))
        return false;
    char json[64];
    snprintf(json, sizeof json, "%.17g", *x);
    return set_override(o, t ? "render.time" : "render.noise", t ? 11 : 12, json);
}

static bool flag_aov(void *opts, const cli_flag *f, const char *v)
{
    (void)f;
    return parse_aovs(v, &((render_opts *)opts)->aovs);
}

static bool flag_up(void *opts, const cli_flag *f, const char *v)
{
    (void)f;
    if (strcmp(v, "y") != 0 && strcmp(v, "z") != 0) {
        cli_error("--up: '%s': y or z", v);
        return false;
    }
    ((render_opts *)opts)->studio.up = v[0] == 'z' ? BRUME_AXIS_Z : BRUME_AXIS_Y;
    return true;
}

#define OFF(field) offsetof(render_opts, field)
#define CALL(fn) CLI_FLAG_CALL, 0, 0, 0, fn

static const cli_flag render_flags[] = {
    {"--output", "-o", "FILE", "output image: .png (8-bit sRGB), .exr (float RGBA), .pfm (float RGB)\n"
     "(default brume.png); for several frames a printf pattern such as\n"
     "out/frame_%04d.exr, the frame number in place of %d", NULL, CLI_FLAG_STRING, OFF(out_path), 0, 0, NULL},
    {"--frames", NULL, "A-B", "render frames A to B (frame f at time f / render.fps)", NULL, CALL(flag_frames)},
    {"--frame", NULL, "F", "render frame F only", NULL, CALL(flag_frames)},
    {"--video", NULL, "FILE.mp4", "after the frames, assemble them with ffmpeg (PNG frames)", NULL, CLI_FLAG_STRING,
     OFF(video), 0, 0, NULL},
    {"--shard", NULL, "I/N", "render only the frames f with f % N == I (render farms)", NULL, CALL(flag_shard)},
    {"--no-read-ahead", NULL, NULL, "a sequence's next frame is read while this one renders, where\n"
     "render.max_memory_mb holds both: read it after instead", NULL, CLI_FLAG_TRUE, OFF(no_read_ahead), 0, 0, NULL},
    {"--spp", NULL, "N", "samples per pixel", "render.spp", CLI_FLAG_INT, OFF(spp), 1, 1 << 24, NULL},
    {"--width", NULL, "W", "image width in pixels", "render.width", CLI_FLAG_INT, OFF(width), 1, 65536, NULL},
    {"--height", NULL, "H", "image height in pixels", "render.height", CLI_FLAG_INT, OFF(height), 1, 65536, NULL},
    {"--seed", NULL, "S", "random seed: the image depends on seed and spp, not on threads\n"
     "nor on the number of MPI processes", "render.seed", CALL(flag_seed)},
    {"--threads", NULL, "N", "worker threads per process (default: one per core)", "render.threads", CLI_FLAG_INT,
     OFF(threads), 0, 1024, NULL},
    {"--device", NULL, "D", "cpu (default), cuda or cuda:N: path and single on an NVIDIA GPU (brume devices)",
     "settings.device", CALL(flag_device)},
    {"--method", NULL, "NAME", "integrator: path (unbiased reference), single (single scattering),\n"
     "blasi (Blasi et al. 1993 two-pass method, docs/blasi.md),\n"
     "stam (Stam 1994, blob fields only, docs/stam.md)", "render.method", CLI_FLAG_STRING, OFF(method), 0, 0, NULL},
    {"--max-depth", NULL, "N", "maximum scattering events per path", "render.max_depth", CLI_FLAG_INT, OFF(max_depth),
     1, 100000, NULL},
    {"--exposure", NULL, "STOPS", "PNG only: scale by 2^STOPS before tone mapping", NULL, CLI_FLAG_DOUBLE,
     OFF(wopts.exposure), -64.0, 64.0, NULL},
    {"--filmic", NULL, NULL, "PNG only: ACES filmic tone curve instead of clamping", NULL, CALL(flag_filmic)},
    {"--set", NULL, "KEY=VALUE", "any scene key, set in the scene file before it is read: a dotted path with\n"
     "array indices and a JSON value, e.g. --set camera.fov=30,\n"
     "--set media.0.sigma_s=[5,5,5], --set stam.eps=0.1, --set blasi.variant=physical\n"
     "(docs/scene-format.md); repeatable, later ones win", NULL, CALL(flag_set)},
    {"--stats", NULL, NULL, "per-run statistics of the method on stderr (docs/stats.md)", "settings.stats",
     CLI_FLAG_TRUE, OFF(stats), 0, 0, NULL},
    {"--save-light", NULL, "PATH", "blasi: write the first pass's radiance grid", "blasi.save_light",
     CALL(flag_light)},
    {"--load-light", NULL, "PATH", "blasi: reuse a saved first pass instead of running it", "blasi.load_light",
     CALL(flag_light)},
    {"--time", NULL, "SECONDS", "time budget: the render (a light pass included) ends within it, passes\n"
     "sized from the measured cost of a sample; --spp or render.spp is a maximum", "render.time", CALL(flag_budget)},
    {"--noise", NULL, "TARGET", "noise target in (0, 1]: adaptive sampling until every pixel that carries\n"
     "signal has a relative standard error <= TARGET (--spp is then a maximum)", "render.noise", CALL(flag_budget)},
    {"--min-spp", NULL, "N", "samples every pixel gets before adaptive sampling may stop it (16)", "render.min_spp",
     CLI_FLAG_INT, OFF(min_spp), 1, 1 << 24, NULL},
    {"--aov", NULL, "LIST", "extra layers in the EXR: depth,albedo,normal,variance,samples", "settings.aovs",
     CALL(flag_aov)},
    {"--denoise", NULL, NULL, "write the image denoised (docs/denoise.md); the raw one is kept: the EXR's\n"
     "layer \"raw\", or NAME-raw.png beside a PNG. Biased: not for validation", NULL, CLI_FLAG_TRUE, OFF(denoise), 0,
     0, NULL},
    {"--checkpoint", NULL, "FILE", "save the render's state to FILE every few seconds and when interrupted", NULL,
     CLI_FLAG_STRING, OFF(checkpoint), 0, 0, NULL},
    {"--resume", NULL, "FILE", "continue from a checkpoint: the image is the one an uninterrupted render\n"
     "gives (same scene, options and settings)", NULL, CLI_FLAG_STRING, OFF(resume), 0, 0, NULL},
    {"--serve", NULL, "[HOST:]PORT", "live view in a browser (default host 127.0.0.1; port 0: any free port);\n"
     "after the render it serves the final image until Ctrl-C", NULL, CLI_FLAG_STRING, OFF(serve_spec), 0, 0, NULL},
    {"--serve-exit", NULL, NULL, "with --serve: exit when the render is written", NULL, CLI_FLAG_TRUE,
     OFF(serve_exit), 0, 0, NULL},
    {"--progress-every", NULL, "S", "with stderr not a terminal: a progress line every S seconds (default 10)",
     NULL, CLI_FLAG_DOUBLE, OFF(progress_every), 0.01, 1e9, NULL},
    {"--quiet", "-q", NULL, "no progress bar, progress lines or summary", NULL, CLI_FLAG_TRUE, OFF(quiet), 0, 0,
     NULL},
    {"--lenient", NULL, NULL, "a .pbrt scene: skip what brume cannot honour, with a warning each, instead of\n"
     "refusing the file (malformed input is still refused)", NULL, CLI_FLAG_TRUE, OFF(lenient), 0, 0, NULL},
    {"--print-scene", NULL, NULL, "write the scene as brume JSON to stdout and exit (the studio scene of a\n"
     "grid file, to start editing from)", NULL, CLI_FLAG_TRUE, OFF(print_scene), 0, 0, NULL},
    {"--up", NULL, "y|z", "a grid file's studio scene: the up axis (default y)", "studio.up", CALL(flag_up)},
    {"--grid", NULL, "NAME", "a grid file's studio scene: the density grid", "studio.grid", CLI_FLAG_STRING,
     OFF(studio.grid), 0, 0, NULL},
    {"--no-ground", NULL, NULL, "a grid file's studio scene: no ground plane", "studio.no_ground", CLI_FLAG_TRUE,
     OFF(studio.no_ground), 0, 0, NULL},
};

static void render_epilogue(FILE *out)
{
    fprintf(out, "This build: %s.\n\n"
                 "The methods' options, for --set METHOD.KEY=VALUE (`brume options`: their values, defaults\n"
                 "and meanings):\n", dist_build_info());
    cli_options_keys(out);
}

const cli_command cli_render_command = {
    "render", "render a scene (or the built-in default scene) to an image, or a sequence of frames",
    "[SCENE] [options]",
    "Renders SCENE (or the built-in default scene) and writes an image, or a sequence of frames.\n"
    "SCENE is a brume scene (.json), or a grid file (.vdb, .nvdb) rendered in a studio scene\n"
    "(docs/production.md); a grid file without --spp, --time or --noise renders as `make render`\n"
    "does: a 15 s time budget, then the denoiser (--spp N: N samples per pixel, deterministic).\n",
    render_flags, CLI_NFLAGS(render_flags),
    "SIGINT (Ctrl-C), SIGTERM or SIGHUP stop the render within about a second: the image so far\n"
    "is written to -o (a partial image; stderr says how many samples it holds), a checkpoint too\n"
    "with --checkpoint, and brume exits 130, 143 or 129. While a finished image is written the\n"
    "write ends whole; --denoise's denoiser stops within a row of pixels and only the image\n"
    "before denoising is written (NAME-raw.EXT, or the EXR marked brume.denoise). A second\n"
    "Ctrl-C ends at once, and so does the first while loading or in Blasi's light pass.\n"
    "Under `mpirun -np N brume render ...` the processes split the frames of a sequence, or\n"
    "the tiles of each frame, and rank 0 writes every file: the same bytes as one process.\n",
    render_epilogue};

int render_parse_options(render_opts *o, int argc, char **argv)
{
    o->threads = -1;
    o->device = -2;
    o->out_path = "brume.png";
    o->first = o->last = -1;
    o->nshards = 1;
    o->wopts = (brume_write_options){0.0, BRUME_TONEMAP_CLAMP};
    const char *scenes[2];
    int n = 0, rc = cli_flags_parse(&cli_render_command, o, argc, argv, scenes, 2, &n);
    if (rc < 0 && n > 1) {
        cli_error("render: more than one scene given ('%s' and '%s')", scenes[0], scenes[1]);
        rc = 2;
    }
    if (rc < 0 && n == 1)
        o->scene_path = scenes[0];
    return rc;
}

int render_check_request(render_opts *o)
{
    o->sequence = o->first >= 0;
    o->nframes = o->sequence ? o->last - o->first + 1 : 1;
    o->kind = render_pattern_kind(o->out_path);
    if (o->kind < 0) {
        cli_error("-o: '%s': use one %%d conversion (such as %%04d, width at most 99) for the frame number, and %%%% for a percent "
                  "sign", o->out_path);
        return 2;
    }
    if (o->nframes > 1 && o->kind == 0) {
        cli_error("-o: '%s' has no %%d for the frame number, and %ld frames would overwrite one file "
                  "(e.g. -o out/frame_%%04d.png)", o->out_path, o->nframes);
        return 2;
    }
    if (!o->sequence && o->kind == 1) {
        cli_error("-o: '%s' is a frame pattern: give --frames A-B or --frame F", o->out_path);
        return 2;
    }
    if (o->nshards > 1 && o->nframes < 2) {
        cli_error("--shard: splits the frames of a sequence (--frames A-B); to split one frame over processes, "
                  "run it under mpirun");
        return 2;
    }
    if (o->video && o->nshards > 1) {
        cli_error("--video: needs every frame, and --shard renders only some: assemble the video once every shard "
                  "is done (docs/animation.md gives the ffmpeg command)");
        return 2;
    }
    if (o->video) {
        const char *dot = strrchr(o->out_path, '.');
        if (!dot || strcmp(dot, ".png") != 0 || o->kind != 1) {
            cli_error("--video: the frames must be PNG files named by a pattern (-o out/frame_%%04d.png)");
            return 2;
        }
        int vbad = render_check_video(o->video, o->scene_path);
        if (vbad)
            return vbad;
    }
    int bad = cli_check_image_name("-o", o->out_path, o->aovs != 0);
    if (bad)
        return bad;
    if ((o->checkpoint || o->resume) && o->sequence) {
        cli_error("%s: one frame at a time (a checkpoint holds one image's state)",
                  o->checkpoint ? "--checkpoint" : "--resume");
        return 2;
    }
    if (o->serve_exit && !o->serve_spec) {
        cli_error("--serve-exit: only with --serve");
        return 2;
    }
    return 0;
}

/* A bare grid file's defaults, as `make render` renders the default scene: a time budget
 * and the denoiser, unless the command line or the overrides give a sample budget. */
#define GRID_SECONDS "15"
#define GRID_SPP_CAP "1024"

bool render_grid_defaults(render_opts *o)
{
    const char *dot = o->scene_path ? strrchr(o->scene_path, '.') : NULL;
    if (!dot || (strcmp(dot, ".vdb") != 0 && strcmp(dot, ".nvdb") != 0) || o->sequence || o->resume || o->spp ||
        o->time_budget > 0.0 || o->noise > 0.0)
        return false;
    for (int k = 0; k < o->nsets; k++)
        if (strncmp(o->sets[k], "render.spp=", 11) == 0 || strncmp(o->sets[k], "render.time=", 12) == 0 ||
            strncmp(o->sets[k], "render.noise=", 13) == 0)
            return false;
    if (!set_override(o, "render.spp", 10, GRID_SPP_CAP) || !set_override(o, "render.time", 11, GRID_SECONDS))
        return false;
    o->time_budget = atof(GRID_SECONDS);
    o->denoise = true;
    o->grid_defaults = true;
    return true;
}
