/* cmd_render.c - `brume render`: load a scene (or the default), render one image or a
 * sequence of frames, optionally over MPI ranks or as one shard of a render farm, and
 * assemble a video with ffmpeg (docs/animation.md). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "args.h"
#include "brume.h"
#include "cli_dist.h"
#include "cli_job.h"
#include "cli_read_ahead.h"
#include "commands.h"

static void render_usage(FILE *out)
{
    fprintf(out,
            "usage: brume render [SCENE] [options]\n"
            "Renders SCENE (or the built-in default scene) and writes an image, or a sequence of frames.\n"
            "SCENE is a brume scene (.json), or a grid file (.vdb, .nvdb) rendered in a studio scene\n"
            "(docs/production.md).\n\n"
            "  -o, --output FILE   output image: .png (8-bit sRGB), .exr (float RGBA), .pfm (float RGB)\n"
            "                      (default brume.png); for several frames a printf pattern such as\n"
            "                      out/frame_%%04d.exr, the frame number in place of %%d\n"
            "  --frames A-B        render frames A to B (frame f at time f / render.fps)\n"
            "  --frame F           render frame F only\n"
            "  --video FILE.mp4    after the frames, assemble them with ffmpeg (PNG frames)\n"
            "  --shard I/N         render only the frames f with f %% N == I (render farms)\n"
            "  --no-read-ahead     a sequence's next frame is read while this one renders, where\n"
            "                      render.max_memory_mb holds both: read it after instead\n"
            "  --spp N             samples per pixel\n"
            "  --width W, --height H   image size in pixels\n"
            "  --seed S            random seed: the image depends on seed and spp, not on threads\n"
            "                      nor on the number of MPI processes\n"
            "  --threads N         worker threads per process (default: one per core)\n"
            "  --device D          cpu (default), cuda or cuda:N: path and single on an NVIDIA GPU (brume devices)\n"
            "  --method NAME       integrator: path (unbiased reference), single (single scattering),\n"
            "                      blasi (Blasi et al. 1993 two-pass method, docs/blasi.md),\n"
            "                      stam (Stam 1994, blob fields only, docs/stam.md)\n"
            "  --max-depth N       maximum scattering events per path\n"
            "  --exposure STOPS    PNG only: scale by 2^STOPS before tone mapping\n"
            "  --filmic            PNG only: ACES filmic tone curve instead of clamping\n"
            "  --set KEY=VALUE     any scene key, set in the scene file before it is read: a dotted path with\n"
            "                      array indices and a JSON value, e.g. --set camera.fov=30,\n"
            "                      --set media.0.sigma_s=[5,5,5], --set stam.eps=0.1, --set blasi.variant=physical\n"
            "                      (docs/scene-format.md); repeatable, later ones win\n"
            "  --stats             per-run statistics of the method on stderr (docs/stats.md)\n"
            "  --save-light PATH   blasi: write the first pass's radiance grid (= --set blasi.save_light=PATH)\n"
            "  --load-light PATH   blasi: reuse a saved first pass instead of running it\n"
            "  --time SECONDS      time budget: the render (a light pass included) ends within it, passes\n"
            "                      sized from the measured cost of a sample; --spp or render.spp is a maximum\n"
            "  --noise TARGET      noise target in (0, 1]: adaptive sampling until every pixel that carries\n"
            "                      signal has a relative standard error <= TARGET (--spp is then a maximum)\n"
            "  --min-spp N         samples every pixel gets before adaptive sampling may stop it (16)\n"
            "  --aov LIST          extra layers in the EXR: depth,albedo,normal,variance,samples\n"
            "  --denoise           write the image denoised (docs/denoise.md); the raw one is kept: the EXR's\n"
            "                      layer \"raw\", or NAME-raw.png beside a PNG. Biased: not for validation\n"
            "  --checkpoint FILE   save the render's state to FILE every few seconds and when interrupted\n"
            "  --resume FILE       continue from a checkpoint: the image is the one an uninterrupted render\n"
            "                      gives (same scene, options and settings)\n"
            "  --serve [HOST:]PORT live view in a browser (default host 127.0.0.1; port 0: any free port);\n"
            "                      after the render it serves the final image until Ctrl-C\n"
            "  --serve-exit        with --serve: exit when the render is written\n"
            "  --progress-every S  with stderr not a terminal: a progress line every S seconds (default 10)\n"
            "  --quiet             no progress bar, progress lines or summary\n"
            "  --print-scene       write the scene as brume JSON to stdout and exit (the studio scene of a\n"
            "                      grid file, to start editing from)\n"
            "  --up y|z, --grid NAME, --no-ground   a grid file's studio scene: the up axis (default y),\n"
            "                      the density grid, no ground plane\n\n"
            "SIGINT (Ctrl-C), SIGTERM or SIGHUP stop the render within about a second: the image so far\n"
            "is written to -o (a partial image; stderr says how many samples it holds), a checkpoint too\n"
            "with --checkpoint, and brume exits 130, 143 or 129. A second Ctrl-C ends at once, and so\n"
            "does the first outside rendering (loading, Blasi's light pass, writing): nothing is kept.\n"
            "Under `mpirun -np N brume render ...` the processes split the frames of a sequence, or\n"
            "the tiles of each frame, and rank 0 writes every file: the same bytes as one process.\n"
            "This build: %s.\n\n"
            "The methods' options, for --set METHOD.KEY=VALUE (`brume options`: their values, defaults\n"
            "and meanings):\n",
            dist_build_info());
    cli_options_keys(out);
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A printf pattern with exactly one %d conversion (flags 0 and a width allowed) and %%
 * for a literal percent: 1; no conversion: 0; anything else: -1. */
static int pattern_kind(const char *p)
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

/* The file name of frame f from a pattern that pattern_kind accepted: the %d conversion
 * (with its zero flag and width) becomes f, %% a percent sign. */
static void frame_path(const char *p, long f, char *out, size_t n)
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

/* Before any work: --video names a file brume may write (not an option ffmpeg would read,
 * not the scene, not a device) in a folder that can be made, and ffmpeg is there. 0 or 1/2
 * with a message. */
static int check_video(const char *video, const char *scene_path)
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
    return cli_check_output("--video", video, scene_path, NULL) || cli_prepare_folder("--video", video, false) ? 1 : 0;
}

/* ffmpeg -framerate FPS -start_number FIRST -i PATTERN ... VIDEO (H.264, yuv420p). ffmpeg's
 * stderr goes to a temporary file; on failure its last line is quoted in brume's one line. */
static int make_video(const char *pattern, long first, double fps, const char *video)
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

/* Writes the render's image to path; with --denoise the denoised image (brume_denoise),
 * the raw one kept: in the EXR's layer "raw", else beside it as NAME-raw.EXT. */
static brume_status write_image(brume_context *ctx, brume_image *image, const char *path,
                                const brume_write_options *wopts, bool denoise, int threads, bool quiet)
{
    if (!denoise)
        return brume_image_write(ctx, image, path, wopts);
    brume_image *den = NULL;
    brume_status st = brume_denoise(ctx, image, threads, &den);
    if (st != BRUME_OK)
        return st;
    const char *dot = strrchr(path, '.');
    bool exr = dot && strcmp(dot, ".exr") == 0;
    if (!exr) {
        char raw[4200];
        snprintf(raw, sizeof raw, "%.*s-raw%s", (int)(dot - path), path, dot);
        if ((st = brume_image_write(ctx, image, raw, wopts)) != BRUME_OK) {
            brume_image_release(den);
            return st;
        }
        if (!quiet)
            fprintf(stderr, "brume: the image before denoising: %s\n", raw);
    }
    st = brume_image_write(ctx, den, path, wopts);
    brume_image_release(den);
    return st;
}

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
} output_plan;

/* Checks every output of the plan (make false: nothing is created) or makes their missing
 * folders (make true), each folder once. 0, or 1 with a message. */
static int prepare_outputs(output_plan *p, bool make)
{
    char prev[4096] = "", path[4096];
    for (long k = 0; k < p->nframes; k++) {
        long f = p->sequence ? p->first + k : -1;
        if (p->nshards > 1 && f % p->nshards != p->shard)
            continue;
        if (p->kind == 1)
            frame_path(p->out_path, f, path, sizeof path);
        else
            snprintf(path, sizeof path, "%s", p->out_path);
        if (!make && cli_check_output("-o", path, p->scene_path, NULL) != 0)
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

enum { MAX_SETS = 64 };

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
} render_opts;

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

/* Loads frame `f` (or the plain scene when f < 0), applies the command-line settings and
 * commits, counting `held` bytes of another scene against the memory limit (the frame that
 * renders while this one is read ahead). On failure returns NULL; the context has the
 * message. */
static brume_scene *load_scene(brume_context *ctx, const render_opts *o, long f, bool progress, size_t held)
{
    brume_scene *scene = NULL;
    brume_status st;
    /* the built-in scene is static: it is loaded at time 0 and its camera moved below */
    brume_load_options lo = {0.0, o->scene_path && f > 0 ? f : 0, o->sets, o->nsets, &o->studio, held};
    st = brume_scene_load(ctx, &(brume_source){.path = o->scene_path}, &lo, &scene);
    if (st != BRUME_OK)
        return NULL;
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
    rs.progress_interval = o->progress_every;
    rs.aovs |= o->aovs;
    if (o->denoise) /* what the denoiser reads (docs/denoise.md) */
        rs.aovs |= BRUME_AOV_VARIANCE | BRUME_AOV_ALBEDO | BRUME_AOV_NORMAL | BRUME_AOV_DEPTH;
    cli_job_callback(&rs.progress_fn, &rs.progress_user);
    rs.progress = progress;
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
}

/* --print-scene: the scene description the loader reads, on stdout. */
static int print_scene(const render_opts *o)
{
    brume_context *ctx = brume_context_new();
    if (!ctx) {
        cli_error("out of memory");
        return 1;
    }
    brume_load_options lo = {0.0, 0, NULL, 0, &o->studio, 0};
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

/* The options that set the scene's settings or what is loaded. 1: argv[*i] taken (with its
 * value); 0: not one of these; -1: a bad value (the message printed). */
static int parse_scene_option(render_opts *o, int argc, char **argv, int *i)
{
    const char *a = argv[*i], *v;
    if (strcmp(a, "--spp") == 0) {
        if (!(v = arg_value(argc, argv, i)) || !arg_int(a, v, 1, 1 << 24, &o->spp)) return -1;
    } else if (strcmp(a, "--width") == 0) {
        if (!(v = arg_value(argc, argv, i)) || !arg_int(a, v, 1, 65536, &o->width)) return -1;
    } else if (strcmp(a, "--height") == 0) {
        if (!(v = arg_value(argc, argv, i)) || !arg_int(a, v, 1, 65536, &o->height)) return -1;
    } else if (strcmp(a, "--threads") == 0) {
        if (!(v = arg_value(argc, argv, i)) || !arg_int(a, v, 0, 1024, &o->threads)) return -1;
    } else if (strcmp(a, "--device") == 0) {
        if (!(v = arg_value(argc, argv, i))) return -1;
        if (brume_device_from_name(NULL, v, &o->device) != BRUME_OK) {
            cli_error("--device: unknown device '%s' (known: cpu, cuda, cuda:N)", v);
            return -1;
        }
    } else if (strcmp(a, "--max-depth") == 0) {
        if (!(v = arg_value(argc, argv, i)) || !arg_int(a, v, 1, 100000, &o->max_depth)) return -1;
    } else if (strcmp(a, "--seed") == 0) {
        if (!(v = arg_value(argc, argv, i)) || !arg_u64(a, v, &o->seed)) return -1;
        o->have_seed = true;
    } else if (strcmp(a, "--method") == 0) {
        if (!(o->method = arg_value(argc, argv, i))) return -1;
    } else if (strcmp(a, "--set") == 0 || strcmp(a, "--save-light") == 0 || strcmp(a, "--load-light") == 0) {
        if (!(v = arg_value(argc, argv, i))) return -1;
        if (strcmp(a, "--set") != 0) { /* --save-light, --load-light */
            const char *key = a[2] == 's' ? "blasi.save_light" : "blasi.load_light";
            return set_override(o, key, strlen(key), v) ? 1 : -1;
        }
        const char *eq = strchr(v, '=');
        if (!eq || eq == v) {
            cli_error("--set: expected KEY=VALUE, got '%s'", v);
            return -1;
        }
        if (!set_override(o, v, (size_t)(eq - v), eq + 1)) return -1;
    } else if (strcmp(a, "--stats") == 0) {
        o->stats = true;
    } else if (strcmp(a, "--time") == 0 || strcmp(a, "--noise") == 0) {
        bool t = a[2] == 't';
        double *x = t ? &o->time_budget : &o->noise;
        if (!(v = arg_value(argc, argv, i)) || !arg_double(a, v, t ? 1e-3 : 1e-6, t ? 1e9 : 1.0, x)) return -1;
        char json[64];
        snprintf(json, sizeof json, "%.17g", *x);
        if (!set_override(o, t ? "render.time" : "render.noise", t ? 11 : 12, json)) return -1;
    } else if (strcmp(a, "--denoise") == 0) {
        o->denoise = true;
    } else if (strcmp(a, "--progress-every") == 0) {
        if (!(v = arg_value(argc, argv, i)) || !arg_double(a, v, 0.01, 1e9, &o->progress_every)) return -1;
    } else if (strcmp(a, "--min-spp") == 0) {
        if (!(v = arg_value(argc, argv, i)) || !arg_int(a, v, 1, 1 << 24, &o->min_spp)) return -1;
    } else if (strcmp(a, "--aov") == 0) {
        if (!(v = arg_value(argc, argv, i)) || !parse_aovs(v, &o->aovs)) return -1;
    } else if (strcmp(a, "--no-ground") == 0) {
        o->studio.no_ground = true;
    } else if (strcmp(a, "--grid") == 0) {
        if (!(o->studio.grid = arg_value(argc, argv, i))) return -1;
    } else if (strcmp(a, "--up") == 0) {
        if (!(v = arg_value(argc, argv, i))) return -1;
        if ((strcmp(v, "y") != 0 && strcmp(v, "z") != 0)) {
            cli_error("--up: '%s': y or z", v);
            return -1;
        }
        o->studio.up = v[0] == 'z' ? BRUME_AXIS_Z : BRUME_AXIS_Y;
    } else
        return 0;
    return 1;
}

/* The options that say what the command writes and how it runs; returns as
 * parse_scene_option. */
static int parse_output_option(render_opts *o, int argc, char **argv, int *i)
{
    const char *a = argv[*i], *v;
    if (strcmp(a, "-o") == 0 || strcmp(a, "--output") == 0) {
        if (!(o->out_path = arg_value(argc, argv, i))) return -1;
    } else if (strcmp(a, "--frames") == 0 || strcmp(a, "--frame") == 0) {
        if (!(v = arg_value(argc, argv, i)) || !parse_range(a, v, &o->first, &o->last)) return -1;
        if (a[7] == '\0' && o->first != o->last) {
            cli_error("--frame: one frame number expected, got '%s' (use --frames A-B)", v);
            return -1;
        }
    } else if (strcmp(a, "--video") == 0) {
        if (!(o->video = arg_value(argc, argv, i))) return -1;
    } else if (strcmp(a, "--shard") == 0) {
        if (!(v = arg_value(argc, argv, i)) || !parse_shard(v, &o->shard, &o->nshards)) return -1;
    } else if (strcmp(a, "--exposure") == 0) {
        if (!(v = arg_value(argc, argv, i)) || !arg_double(a, v, -64.0, 64.0, &o->wopts.exposure)) return -1;
    } else if (strcmp(a, "--filmic") == 0) {
        o->wopts.tonemap = BRUME_TONEMAP_FILMIC;
    } else if (strcmp(a, "--checkpoint") == 0) {
        if (!(o->checkpoint = arg_value(argc, argv, i))) return -1;
    } else if (strcmp(a, "--resume") == 0) {
        if (!(o->resume = arg_value(argc, argv, i))) return -1;
    } else if (strcmp(a, "--serve") == 0) {
        if (!(o->serve_spec = arg_value(argc, argv, i))) return -1;
    } else if (strcmp(a, "--serve-exit") == 0) {
        o->serve_exit = true;
    } else if (strcmp(a, "--quiet") == 0 || strcmp(a, "-q") == 0) {
        o->quiet = true;
    } else if (strcmp(a, "--print-scene") == 0) {
        o->print_scene = true;
    } else if (strcmp(a, "--no-read-ahead") == 0) {
        o->no_read_ahead = true;
    } else
        return 0;
    return 1;
}

/* The command line into *o (zeroed by the caller). -1: go on; otherwise the exit status
 * (0 after --help, 2 for a bad command line, with its message). */
static int parse_options(render_opts *o, int argc, char **argv)
{
    o->threads = -1;
    o->device = -2;
    o->out_path = "brume.png";
    o->first = o->last = -1;
    o->nshards = 1;
    o->wopts = (brume_write_options){0.0, BRUME_TONEMAP_CLAMP};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            render_usage(stdout);
            return 0;
        }
        int taken = parse_scene_option(o, argc, argv, &i);
        if (taken == 0)
            taken = parse_output_option(o, argc, argv, &i);
        if (taken < 0)
            return 2;
        if (taken > 0)
            continue;
        if (a[0] == '-' && a[1] != '\0') {
            cli_error("render: unknown option '%s' (try `brume help render`)", a);
            return 2;
        } else if (!o->scene_path) {
            o->scene_path = a;
        } else {
            cli_error("render: more than one scene given ('%s' and '%s')", o->scene_path, a);
            return 2;
        }
    }
    return -1;
}

/* What to render, checked before any work: the output name against the frames, the shards,
 * the video, the checkpoint. Sets sequence, nframes and kind. 0, or the exit status with a
 * message. */
static int check_request(render_opts *o)
{
    o->sequence = o->first >= 0;
    o->nframes = o->sequence ? o->last - o->first + 1 : 1;
    o->kind = pattern_kind(o->out_path);
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
        int vbad = check_video(o->video, o->scene_path);
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
    bool load_progress;             /* the frames' scenes show the render's progress */
    cli_read_ahead ra;              /* the next frame, read while this one renders */
    const char *ahead_why;          /* why the next frame was not read ahead, or NULL */
    const char *ahead;              /* --stats: the rendered frame's "yes" or why not; NULL: no line */
    long ahead_frame;
    brume_image *image;
    brume_render_job *job;
    cli_job_result jr;
    long done;                      /* frames written */
} render_run;

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
                            o->checkpoint, o->video, o->scene_path, false};
    if (!r->root)
        return 0;
    if (prepare_outputs(&r->plan, false) != 0)
        return 1;
    for (int k = 0; k < o->nlight; k++)
        if (o->light_key[k][6] == 's' && cli_check_output("--save-light", o->light_value[k], o->scene_path, NULL) != 0)
            return 1;
    if (o->checkpoint && (cli_check_output("--checkpoint", o->checkpoint, o->scene_path, NULL) != 0 ||
                          cli_prepare_folder("--checkpoint", o->checkpoint, false) != 0))
        return 1;
    if (o->resume && access(o->resume, R_OK) != 0) {
        cli_error("--resume: %s: %s", o->resume, strerror(errno));
        return 1;
    }
    return 0;
}

/* Everything before the first frame: processes, outputs, signals, the live view, the
 * context, a grid sequence's files. 0, or the exit status with a message and nothing left
 * open. */
static int begin_run(render_run *r)
{
    const render_opts *o = r->o;
    if (!dist_begin(&r->d))
        return 1;
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
        brume_load_options lo = {0.0, 0, o->sets, o->nsets, &o->studio, 0};
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
    if (!r->scene && !(r->scene = load_scene(r->ctx, r->o, f, false, 0)))
        return render_failed(r);
    if (!r->plan.made && prepare_outputs(&r->plan, true) != 0)
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
    return load_scene(ctx, r->o, f, r->load_progress, held);
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
        if (!r->scene && !(r->scene = load_scene(r->ctx, o, f, r->load_progress, 0)))
            return render_failed(r);
        if (!o->sequence || !o->scene_path || brume_scene_world_is_static(r->scene))
            r->ahead = NULL; /* no grids of its own per frame: nothing to say */
        /* the scene's inputs are known now: none of them may be written over; the scene is
         * good, so the output folders are made */
        if (r->root && (cli_check_output("-o", path, o->scene_path, r->scene) != 0 ||
                        (o->checkpoint && cli_check_output("--checkpoint", o->checkpoint, o->scene_path, r->scene) != 0) ||
                        (!r->plan.made && prepare_outputs(&r->plan, true) != 0)))
            return 1;
    }
    read_next(r, k);
    brume_scene_settings(r->scene, rs);
    if (r->split_tiles) {
        if (brume_render_part(r->ctx, r->scene, r->d.rank, r->d.size, &r->image) != BRUME_OK)
            return render_failed(r);
    } else {
        if (r->serve)
            cli_serve_show(r->serve, NULL, NULL);
        brume_render_job_release(r->job);
        r->job = NULL;
        cli_job_opts jo = {o->checkpoint, 5.0, o->resume, 0, rs->noise_target, rs->time_budget, r->serve, path};
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

/* The line a written frame gets on stderr (not with --quiet): size, samples, method, time,
 * and the noise and time budgets when the render had them. */
static void report_frame(const render_run *r, const char *path, int owner, const brume_render_settings *rs,
                         double secs)
{
    if (owner != r->d.rank)
        fprintf(stderr, "brume: %s: %d x %d, %d spp, method %s, rendered by rank %d\n", path, rs->width, rs->height,
                rs->spp, brume_method_name(rs->method), owner);
    else if (r->job && (rs->time_budget > 0.0 || rs->noise_target > 0.0)) {
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
        fprintf(stderr, "brume: %s: %d x %d, %d to %d spp (%.1f on average)%s, method %s, %.2f s%s\n", path,
                rs->width, rs->height, p->spp_min, p->spp_max, p->spp_mean, noise, brume_method_name(rs->method), secs, budget);
    } else
        fprintf(stderr, "brume: %s: %d x %d, %d spp, method %s, %.2f s (%.2f M samples/s)\n", path, rs->width,
                rs->height, rs->spp, brume_method_name(rs->method), secs, (double)rs->width * rs->height * rs->spp / secs * 1e-6);
}

/* After a frame: its statistics; on rank 0 its image written (denoised with --denoise), or
 * the partial image of an interrupted render under a name that says so. 0, or the exit
 * status with a message. path (a buffer of size n) may be renamed. */
static int write_frame(render_run *r, char *path, size_t n, int owner, const brume_render_settings *rs,
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
        if (write_image(r->ctx, r->image, path, &o->wopts, o->denoise, rs->threads, o->quiet) != BRUME_OK)
            return render_failed(r);
        const brume_render_progress *p = &r->jr.progress;
        fprintf(stderr, "brume: interrupted by %s: wrote the partial image %s (%d to %d samples per pixel, %.1f on "
                        "average)%s%s\n", cli_signal_name(r->jr.signal), path, p->spp_min, p->spp_max, p->spp_mean,
                r->jr.checkpoint_written ? "; checkpoint " : "", r->jr.checkpoint_written ? o->checkpoint : "");
        return 128 + r->jr.signal;
    }
    if (r->root) {
        if (write_image(r->ctx, r->image, path, &o->wopts, o->denoise, rs->threads, o->quiet) != BRUME_OK)
            return render_failed(r);
        if (!o->quiet)
            report_frame(r, path, owner, rs, now_seconds() - t0);
        if (!o->quiet && r->jr.budget_spent && r->jr.checkpoint_written)
            fprintf(stderr, "brume: the time budget ended the render before its samples: its state is kept in %s "
                            "(--resume %s with another --time adds samples)\n", o->checkpoint, o->checkpoint);
    }
    brume_image_release(r->image);
    r->image = NULL;
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
            frame_path(o->out_path, f, path, sizeof path);
        else
            snprintf(path, sizeof path, "%s", o->out_path);
        brume_render_settings rs;
        double t0 = now_seconds();
        int st = owner != r->d.rank ? receive_frame(r, k, f, owner, &rs) : render_frame(r, k, f, path, &rs);
        if (st < 0)
            continue;
        if (st > 0 || (st = write_frame(r, path, sizeof path, owner, &rs, t0)) != 0)
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
                now_seconds() - t_all, r->d.size, r->d.size == 1 ? "" : "es");
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
        return make_video(o->out_path, o->first, rs.fps, o->video);
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
    int rc = parse_options(&o, argc, argv);
    if (rc >= 0)
        return rc;
    if (o.print_scene)
        return print_scene(&o);
    if ((rc = check_request(&o)) != 0)
        return rc;
    render_run r = {.o = &o};
    if ((rc = begin_run(&r)) != 0)
        return rc;
    double t_all = now_seconds();
    rc = render_frames(&r);
    if (rc == 0)
        rc = finish_run(&r, t_all);
    end_run(&r, rc);
    return rc;
}
