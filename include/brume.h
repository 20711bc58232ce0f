/* brume.h - the public API of libbrume, a renderer for participating media.
 *
 * brume renders clouds, fog, haze, smoke and fire described as density fields (voxel
 * grids, procedural fields) with an unbiased volumetric path tracer and with the methods
 * of Blasi, Le Saec and Schlick (1993) and Stam (1994). This header is the whole public
 * interface; everything under src/ is private.
 *
 * BUILD
 *   cmake -B build && cmake --build build && cmake --install build   (scripts/setup.sh
 *   installs the dependencies; --prefix DIR to install elsewhere than /usr/local), then
 *     cc app.c $(pkg-config --cflags --libs brume)
 *   which links the shared libbrume.so.1 (with an rpath to it: the program runs from any
 *   prefix); `pkg-config --cflags --libs brume-static` links the static libbrume.a.
 *   CMake projects: find_package(brume CONFIG) and link brume::brume or
 *   brume::brume_static. Python: import brume (docs/python.md). docs/install.md has more.
 *
 * OBJECTS AND THEIR LIFECYCLE
 *   Every object is an opaque handle with one lifecycle: new (or load), set, commit,
 *   release. A scene may be changed only before brume_scene_commit and rendered only after.
 *   Release functions accept NULL.
 *
 *   brume_context  owns the last error message and the error callback. One per thread
 *                  that calls the API (a context is not thread-safe; the renderer itself
 *                  uses its own worker threads).
 *   brume_scene    camera, lights, media, surfaces, background, render settings: built in
 *                  memory (brume_scene_new and the builders below) or loaded
 *                  (brume_scene_load, the one loader: a scene file, a grid or pbrt-v4 file,
 *                  scene JSON text, or the built-in default scene; its reader uses the
 *                  same builders).
 *   brume_image    a rendered or loaded picture: width x height pixels, RGBA float32,
 *                  linear Rec. 709, rows top first, 4 floats per pixel; A = 1 - the
 *                  transmittance of the media along the pixel (1 = opaque cloud).
 *
 * NAMES
 *   brume_OBJECT_VERB for what changes or makes something (brume_scene_load,
 *   brume_scene_add_medium, brume_render_job_save); brume_OBJECT_set_NOUN for a setter,
 *   which takes a context and returns a status; brume_OBJECT_NOUN for a getter
 *   (brume_image_width, brume_scene_settings, brume_scene_stats): it takes the object
 *   first and no context, cannot fail, and gives 0, NULL or zeros for a NULL object.
 *   Every object is made from a context (brume_scene_load, brume_image_new, ...), and no
 *   call acts on the whole process: what a signal handler may do (cancel loads, remove
 *   temporary files) it does for one context. A closed set of choices is an enum, with
 *   brume_X_name and brume_X_from_name where a user types the names (brume_method).
 *
 * ERRORS
 *   Functions that can fail return a brume_status. On failure nothing is allocated or
 *   changed for the caller (out pointers are set to NULL; the one exception is a render that
 *   the progress callback cancelled: BRUME_ERROR_CANCELLED with the partial image in *out),
 *   and the context holds a one-line
 *   message naming the file and the field at fault, e.g.
 *     "scenes/bad.json: camera.fov: 400 outside [0.001, 179]"
 *   which brume_context_last_error() returns and the error callback (if set) receives;
 *   a builder's message names the function and the argument instead, e.g.
 *     "brume_density_new_array: nx: 0 outside [1, 65536]"
 *   A NULL pointer where the header does not allow one is BRUME_ERROR_INVALID_ARGUMENT
 *   ("brume_scene_commit: scene: NULL"), never a crash; functions without a status return
 *   0, NULL or nothing for a NULL object. ctx itself may be NULL: the call then reports
 *   only through its status.
 *
 * DETERMINISM
 *   An image depends on the scene, the seed and the sample count, never on the number of
 *   threads: renders with 1 and with 2 threads are bit-identical.
 *
 * MINIMAL EXAMPLE (compiled and run as a test; see CMakeLists.txt)
 * BEGIN EXAMPLE
#include <brume.h>
#include <stdio.h>

int main(void)
{
    brume_context *ctx = brume_context_new();
    brume_scene *scene = NULL;
    brume_image *image = NULL;
    if (brume_scene_load(ctx, NULL, NULL, &scene) != BRUME_OK) // NULL source: the default scene
        goto fail;
    brume_render_settings rs;
    brume_scene_settings(scene, &rs);
    rs.width = 64;
    rs.height = 48;
    rs.spp = 4;
    if (brume_scene_set_settings(ctx, scene, &rs) != BRUME_OK ||
        brume_scene_commit(ctx, scene) != BRUME_OK ||
        brume_render(ctx, scene, &image) != BRUME_OK ||
        brume_image_write(ctx, image, "example.exr", NULL) != BRUME_OK)
        goto fail;
    printf("rendered %d x %d\n", brume_image_width(image), brume_image_height(image));
    brume_image_release(image);
    brume_scene_release(scene);
    brume_context_release(ctx);
    return 0;
fail:
    fprintf(stderr, "brume: %s\n", brume_context_last_error(ctx));
    brume_image_release(image);
    brume_scene_release(scene);
    brume_context_release(ctx);
    return 1;
}
 * END EXAMPLE
 */
#ifndef BRUME_H
#define BRUME_H

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---- status and errors ---------------------------------------------------------------- */

typedef enum brume_status {
    BRUME_OK = 0,
    BRUME_ERROR_INVALID_ARGUMENT, /* a parameter is outside its domain (NULL, negative size) */
    BRUME_ERROR_IO,               /* a file could not be opened, read or written */
    BRUME_ERROR_PARSE,            /* a file is malformed: syntax, unknown key, wrong type */
    BRUME_ERROR_OUT_OF_MEMORY,    /* allocation failed, or a size exceeds the memory limit */
    BRUME_ERROR_UNSUPPORTED,      /* valid request this build or method cannot do */
    BRUME_ERROR_RANGE,            /* a value is NaN, infinite, negative or out of range */
    BRUME_ERROR_STATE,            /* an object used before commit, or changed after */
    BRUME_ERROR_CANCELLED         /* the progress callback asked to stop: a render's out-image
                                     then holds the samples finished so far (the one exception to
                                     "out is NULL on failure") */
} brume_status;

/* A short English phrase for a status ("malformed input"). Never NULL. */
const char *brume_status_string(brume_status status);

/* The version of this header; CMakeLists.txt's project VERSION must equal it (the build
 * checks). The major number is the shared library's (libbrume.so.MAJOR): it changes when a
 * call or a struct changes incompatibly (docs/api-migration.md lists what changed). */
#define BRUME_VERSION_MAJOR 1
#define BRUME_VERSION_MINOR 0
#define BRUME_VERSION_PATCH 0
/* The library's "MAJOR.MINOR.PATCH" (the one it was built as: compare with the macros). */
const char *brume_version(void);

/* ---- context ---------------------------------------------------------------------------- */

typedef struct brume_context brume_context;

/* Called with every error recorded in the context, from the thread that made the call. */
typedef void (*brume_error_fn)(void *user, brume_status status, const char *message);

/* A new context, or NULL when out of memory. The caller owns it. */
brume_context *brume_context_new(void);
void brume_context_release(brume_context *ctx);
void brume_context_set_error_callback(brume_context *ctx, brume_error_fn fn, void *user);
/* The message of the last failed call ("" if none). Valid until the next call with ctx. */
const char *brume_context_last_error(const brume_context *ctx);
brume_status brume_context_last_status(const brume_context *ctx);
/* Ends every scene load and every brume_denoise in progress with ctx, on any thread: its
 * generators (procedural clouds, fractal grids) stop within about a second, the denoiser
 * within a row of pixels, and brume_scene_load or brume_denoise returns
 * BRUME_ERROR_CANCELLED. Calls with other contexts, and calls that start afterwards, are not
 * affected. Async-signal-safe: for a SIGINT handler (a render is cancelled by its progress
 * callback instead). */
void brume_context_cancel_loads(brume_context *ctx);
/* Removes the temporary files of the writes in progress made with ctx (brume_image_write,
 * brume_render_job_save, a render's blasi.save_light); a write that then fails or finishes
 * leaves no file behind it. Async-signal-safe: for a signal handler that then calls _exit. */
void brume_context_remove_temporaries(brume_context *ctx);
/* The same for every context, and for the temporary files of brume_file_write without one: for
 * a program's fatal-signal handler, which then calls _exit. Async-signal-safe. */
void brume_remove_all_temporaries(void);
/* printf-style formatting into out[n] (NUL-terminated, one line) as brume formats its own
 * messages: control characters in string arguments escaped, a plain %s cut after 200 bytes,
 * a "%.1000s" cut at its precision. For a program that reports its errors as brume does. */
void brume_vformat_message(char *out, size_t n, const char *fmt, va_list ap);

/* ---- scene -------------------------------------------------------------------------------- */

typedef struct brume_scene brume_scene;
typedef struct brume_image brume_image; /* below: rendering and images */

typedef enum brume_filter {
    BRUME_FILTER_BOX = 0,     /* uniform over the pixel square */
    BRUME_FILTER_GAUSSIAN = 1 /* truncated gaussian, standard deviation filter_width / 4 px */
} brume_filter;

/* Where a camera sample's random numbers come from (docs/sampling.md). Either way every
 * number is uniform and the image unbiased; the image depends on the choice. */
typedef enum brume_sampler {
    BRUME_SAMPLER_INDEPENDENT = 0, /* "independent": a hash of (seed, pixel, sample, dimension) */
    BRUME_SAMPLER_SOBOL = 1        /* "sobol": the first dimensions of each sample are the pixel's
                                      Owen-scrambled Sobol points, the rest the same hash */
} brume_sampler;

/* The rendering methods, a closed set (render.method in a scene file, docs/scene-format.md). */
typedef enum brume_method {
    BRUME_METHOD_PATH = 0,   /* "path": the unbiased volumetric path tracer (docs/path-tracer.md) */
    BRUME_METHOD_SINGLE = 1, /* "single": the same estimator with single scattering only */
    BRUME_METHOD_BLASI = 2,  /* "blasi": Blasi, Le Saec and Schlick 1993's two passes (docs/blasi.md) */
    BRUME_METHOD_STAM = 3    /* "stam": Stam 1994's renderer of blob fields (docs/stam.md) */
} brume_method;
/* The method's name as a scene file writes it ("path"); NULL for a value outside the enum. */
const char *brume_method_name(brume_method method);
/* Parses a method name ("path", "single", "blasi", "stam") into *method. BRUME_OK, or
 * BRUME_ERROR_INVALID_ARGUMENT with the context's message naming the text and the names. */
brume_status brume_method_from_name(brume_context *ctx, const char *name, brume_method *method);

/* Progress of a render: `done` and `total` count pixel samples (total is exact for a fixed
 * sample count, an estimate that may change between calls under a time budget or a noise
 * target; never below done). Called after each finished tile, from the calling thread or a
 * worker, never two at once. Return true to go on, false to cancel: every worker then stops
 * after the tile it is rendering. A phase before the first tile (Blasi's light pass, Stam's
 * random field) calls it with done = 0 and total = 1 about every 0.1 s, so that it may
 * cancel there too (brume_render_begin then returns BRUME_ERROR_CANCELLED).
 * done / total is a count, not the fraction to show: a display asks the job for its figures
 * (brume_render_job_progress, which the callback may call), whose fraction never goes back.
 * The library prints nothing: a progress bar is the caller's to draw. */
typedef bool (*brume_progress_fn)(void *user, uint64_t done, uint64_t total);

/* Extra image layers (AOVs), a bit mask for brume_render_settings.aovs. Each layer is the
 * mean over the pixel's samples unless said otherwise. */
typedef enum brume_aov {
    BRUME_AOV_DEPTH = 1u << 0,    /* "depth": distance (world units) from the camera to the first
                                     scattering event (media: the first real collision of a
                                     delta-tracked flight) or surface hit, mean over the samples
                                     that hit something; 0 = nothing hit */
    BRUME_AOV_ALBEDO = 1u << 1,   /* "albedo": RGB, the first vertex's single-scattering albedo
                                     sigma_s / sigma_t (media) or diffuse albedo (surfaces); 0 for
                                     samples that hit nothing */
    BRUME_AOV_NORMAL = 1u << 2,   /* "normal": RGB = xyz unit world normal at the first surface hit,
                                     facing the camera; 0 for samples that hit no surface first */
    BRUME_AOV_VARIANCE = 1u << 3, /* "variance": RGB per-pixel variance of the pixel mean, the
                                     unbiased sample variance / n (0 when n < 2) */
    BRUME_AOV_SAMPLES = 1u << 4   /* "samples": one channel, samples the pixel received */
} brume_aov;

/* Render settings. The scene file provides them; a caller may override before commit. */
typedef struct brume_render_settings {
    int width, height;  /* image size in pixels, each in [1, 65536] */
    int spp;            /* samples per pixel, >= 1 */
    uint64_t seed;      /* the image is a function of (scene, seed, spp) */
    int threads;        /* worker threads; 0 = one per core */
    brume_method method; /* the rendering method; default BRUME_METHOD_PATH (stam: blob fields only) */
    int max_depth;      /* maximum number of scattering events on a path (path), >= 1 */
    brume_filter filter;
    double filter_width; /* filter support in pixels (box: side; gaussian: diameter), > 0 */
    double fps;          /* frames per second of a sequence: frame f is at time f / fps, > 0 */
    brume_progress_fn progress_fn; /* NULL: none. See brume_progress_fn */
    void *progress_user;           /* passed to progress_fn */
    unsigned aovs;       /* bit mask of brume_aov: extra layers of the rendered image */
    double time_budget;  /* seconds, 0 = none: passes until spent (spp is then a maximum), in [0, 1e9];
                            a job resumed from a checkpoint spends a budget of its own */
    double noise_target; /* relative standard error, 0 = none: adaptive sampling until every pixel
                            that carries signal meets it (spp is then a maximum), in [0, 1]
                            (docs/render-jobs.md gives the estimator) */
    int min_spp;         /* samples every pixel gets before adaptive sampling may stop it, >= 1 */
    bool stats;          /* count per-run statistics (brume_scene_stats); off: no cost */
    brume_sampler sampler; /* camera-sample numbers (render.sampler); default BRUME_SAMPLER_SOBOL */
    int device;          /* where path and single run: -1 the CPU (default), N >= 0 the CUDA GPU N
                            (render.device "cpu", "cuda" or "cuda:N"; docs/gpu.md) */
    double max_component; /* 0 = none; else each camera sample's radiance is scaled so that the
                             largest of its sensor values (CIE X, Y, Z with the cie1931 sensor,
                             a camera's raw r, g, b with a named one) is at most this (pbrt-v4's
                             Film "maxcomponentvalue"): a clamp, biased low, in [0, 1e30]
                             (render.max_component) */
    double white_balance; /* 0 = none; else kelvin in [1000, 100000]: each sample's colour is
                             mapped from the daylight white of that temperature to D65's, as
                             pbrt-v4's Film "whitebalance" does (render.white_balance); with a
                             camera sensor 0 stands for 6500 K, as in pbrt-v4 */
    int sensor;           /* the film's sensor, pbrt-v4's Film "sensor" (render.sensor): 0 its
                             "cie1931", the CIE observer, whose values are brume's linear Rec. 709
                             (default); 1 .. 17 the cameras pbrt-v4 names, in the order of
                             brume_sensor_name, whose measured responses map each sample's colour
                             (docs/pbrt.md, Film) */
} brume_render_settings;

/* The name of render.sensor's number sensor ("cie1931", "canon_eos_100d", ...), NULL for a
 * number without one: brume_sensor_name(0), (1), ... until NULL lists them. */
const char *brume_sensor_name(int sensor);

/* Parses a device name, "cpu" (-1), "cuda" (0) or "cuda:N" (N, 0 <= N < 64), into *device.
 * BRUME_OK, or BRUME_ERROR_INVALID_ARGUMENT with the context's message naming the text. */
brume_status brume_device_from_name(brume_context *ctx, const char *name, int *device);

/* A GPU brume can render on (docs/gpu.md). */
typedef struct brume_device_info {
    char name[128];
    size_t memory;          /* bytes */
    int cc_major, cc_minor; /* CUDA compute capability */
    int multiprocessors;
} brume_device_info;
/* The CUDA GPUs the NVIDIA driver sees: fills up to max entries of out and sets *count to how
 * many there are. BRUME_OK, or BRUME_ERROR_UNSUPPORTED with a message that says why there
 * are none (a build without GPU kernels, no driver, no device); *count is then 0. */
brume_status brume_devices(brume_context *ctx, brume_device_info *out, int max, int *count);

/* LOADING: the one way from a scene description to a scene.
 *
 * A source is a file or a text. A file is read by its name: a scene file (JSON,
 * docs/scene-format.md), a grid file (.vdb, .nvdb: its studio scene, below) or a pbrt-v4
 * scene (.pbrt: its translation, docs/production.md). A text is scene-file JSON in memory;
 * `path` then names it in messages, and relative file names in it resolve against path's
 * folder (path NULL: "<json>" and the current folder). A NULL source, or one with path and
 * text both NULL, is the built-in default scene (scenes/default.json: a cumulus of five
 * fractal clouds over a ground plane, lit by the sun and a blue sky, rendered to a 3 %
 * noise target). Every source becomes scene-file JSON (brume_scene_text shows it) and goes
 * through the one reader, which builds with the public builders below. */
typedef struct brume_source {
    const char *path; /* the file to read; with text, the text's name and base folder */
    const char *text; /* scene-file JSON, NUL-terminated, borrowed for the call; NULL: read path */
} brume_source;

/* STUDIO SCENES (docs/production.md). A grid file given where a scene is expected (.vdb,
 * .nvdb) becomes a studio scene: the camera framed on the grid's non-zero voxels
 * (brume_scene_frame_camera) from a three-quarter view, a sun and a sky, a ground plane
 * under the box or none, and optical coefficients from the grids found: "density" (or the
 * only float grid) as fog, a "temperature" grid as blackbody fire. */
typedef enum brume_axis {
    BRUME_AXIS_Y = 0, /* OpenVDB's and Houdini's up */
    BRUME_AXIS_Z = 1
} brume_axis;
typedef struct brume_studio_options {
    const char *grid;     /* the density grid's name; NULL or "" = the default (docs/grids.md) */
    brume_axis up;        /* the world's up axis; default BRUME_AXIS_Y */
    bool no_ground;       /* true: no ground plane */
    double optical_depth; /* > 0: the extinction is scaled so that a ray along the box's
                             shortest side through density max(rho) has this optical depth;
                             0 = 10 */
} brume_studio_options;

/* How to load. opts NULL, or all fields 0, is time 0, no overrides, the studio defaults.
 *
 * ANIMATION (docs/animation.md). A scene file may give keyframes (camera, lights, surfaces,
 * media) and time-varying densities; loading it at a time evaluates what is fixed per frame
 * (lights, generated densities) at that time, and keeps what moves within the shutter
 * (camera, surface and medium transforms) for each ray's own time. frame > 0 gives the time
 * as frame / render.fps of the scene; else `time` (seconds) is used.
 *
 * OVERRIDES (the mechanism behind `brume render --set KEY=VALUE`). Each "KEY=VALUE" of
 * overrides[0..noverrides) is set in the source's JSON document, in order, before it is
 * read: KEY is a dotted path of object keys and array indices ("camera.fov",
 * "media.0.sigma_s", "media[0].density.seed", "stam.eps", "render.spp"), VALUE is JSON (30,
 * [0, 1, 2], true, "text") or, when it does not parse as JSON, a string
 * (stam.variant=paper). Missing objects on the path are created. The edited document then
 * goes through the scene reader, so every override is validated as the file's own keys
 * are; an unknown key fails with the keys known at that place, an index outside an array
 * with the indices there. Relative file names in VALUE are relative to the source's folder,
 * and a file an override writes (blasi.save_light) must lie inside it, as for the file's
 * own keys: a caller's own output path goes to brume_scene_set_option instead. The strings
 * are borrowed for the call. */
typedef struct brume_load_options {
    double time;                   /* scene time, seconds (used when frame is 0) */
    long frame;                    /* > 0: time = frame / render.fps of the scene; >= 0 */
    const char *const *overrides;  /* "KEY=VALUE" strings, or NULL when noverrides is 0 */
    int noverrides;
    const brume_studio_options *studio; /* for a grid file; NULL = the defaults (all 0) */
    /* Bytes of render.max_memory_mb that another scene holds while this one is read and
     * committed (0: none): a sequence's frame being rendered while the next frame is read
     * ahead (brume_scene_memory gives them). Reading and committing fail with
     * BRUME_ERROR_OUT_OF_MEMORY where this scene's bytes and these would pass the limit;
     * otherwise the scene is the one a load without them makes (the same choices, the same
     * image). Rendering it counts only its own bytes. */
    size_t memory_held;
    /* A pbrt-v4 scene (docs/pbrt.md): true skips each directive or parameter brume cannot
     * honour instead of refusing the file, and lists its refusal (brume_scene_ignored);
     * malformed input is refused either way. `brume render --lenient`. */
    bool lenient;
} brume_load_options;

/* Loads a scene from src (NULL: the default scene) with opts (NULL: the defaults). On
 * success *out is a new uncommitted scene owned by the caller; on failure *out is NULL and
 * the context names the file (or the text's name) and the key at fault. A load can be
 * ended from another thread or a signal handler: brume_context_cancel_loads. */
brume_status brume_scene_load(brume_context *ctx, const brume_source *src, const brume_load_options *opts,
                              brume_scene **out);
/* The scene-file JSON that brume_scene_load reads for src, before the overrides: a JSON
 * file's own text, the studio scene of a grid file, the translation of a pbrt-v4 scene, a
 * copy of src->text, or the default scene's text (opts may be NULL; only opts->studio is
 * used). It makes no scene: it shows what the loader reads, so that a translated or
 * generated scene can be saved, read and edited (`brume render --print-scene`), and a
 * sequence's frames be checked; the scene itself comes only from brume_scene_load. *json
 * is a new NUL-terminated string the caller frees with free(); file names in it are
 * absolute or relative to the source's folder, as the loader reads them. */
brume_status brume_scene_text(brume_context *ctx, const brume_source *src, const brume_load_options *opts,
                              char **json);
/* SEQUENCES (docs/grids.md, "Sequences"). A grid's file name may hold a frame pattern
 * (smoke_%04d.vdb, smoke_####.vdb, smoke_$F4.vdb): each frame reads its own file, file
 * number frame_offset + frame_step x frame. Checks, before any frame is loaded, that every
 * frame in [first, last] (frame numbers as brume_load_options.frame) has its file; fails
 * with one line naming the first frame that has none. opts may be NULL. */
brume_status brume_scene_check_frames(brume_context *ctx, const brume_source *src, const brume_load_options *opts,
                                      long first, long last);
/* What the scene's source asked for and the scene leaves out: the scene file's "ignored"
 * list (docs/scene-format.md), which a pbrt-v4 translation read with
 * brume_load_options.lenient fills, one "FILE:LINE: what was refused" per construct. The
 * count (0 for NULL), and entry `index` (NULL outside [0, count)), owned by the scene. */
int brume_scene_ignored_count(const brume_scene *scene);
const char *brume_scene_ignored(const brume_scene *scene, int index);
/* The scene's frame time in seconds. */
double brume_scene_time(const brume_scene *scene);
/* Bytes of render.max_memory_mb that reading and committing the scene took (its grids, the
 * majorants and blobs commit builds; 0 for NULL); *limit (when not NULL) gets the limit in
 * bytes. A render's film counts against the same limit when the render begins. */
size_t brume_scene_memory(const brume_scene *scene, size_t *limit);
/* True when nothing but the camera depends on time (no keyframed light, surface or medium,
 * no evolving density): then frames differ only by the camera, and one committed scene can
 * be moved from frame to frame with brume_scene_set_camera_time, keeping the work an
 * integrator did once (Blasi's first pass). */
bool brume_scene_world_is_static(const brume_scene *scene);
/* Moves a committed scene whose world is static to frame time `time`: the camera takes its
 * keyframed pose there. Fails with BRUME_ERROR_STATE when the world is not static. */
brume_status brume_scene_set_camera_time(brume_context *ctx, brume_scene *scene, double time);
/* Copies the scene's render settings into *rs (zeros for a NULL scene). */
void brume_scene_settings(const brume_scene *scene, brume_render_settings *rs);
/* Validates and replaces the render settings; only before commit. */
brume_status brume_scene_set_settings(brume_context *ctx, brume_scene *scene, const brume_render_settings *rs);
/* Sets a named option of a rendering method from its text form, as the scene file would
 * give it; only before commit. This is the one option mechanism: each method owns its keys
 * "METHOD.KEY" (the scene file's "METHOD" object is read through it), one table per method
 * in the library. Paths are used as given (a scene file's are relative to its folder). An
 * unknown key or a bad value fails with a message naming the key; nothing is changed then.
 * The keys and their values (brume_option_get lists them with defaults and meanings, as do
 * `brume options` and docs/scene-format.md, "Method options"; ctest options.header_lists_every_key
 * fails when this list differs from the tables):
 * BEGIN OPTION KEYS
 *   path.sun_lobe              a number in [0, 100]
 *   path.sun_roulette          a number in [0, 1]
 *   path.split                 a whole number in [1, 8]
 *   blasi.light_rays           an integer in [1, 1e12]
 *   blasi.r                    a number in [0, 1]
 *   blasi.kprime               a number in (-1, 1)
 *   blasi.step                 a length >= 0 (0 = voxel by voxel)
 *   blasi.threshold            a number in [0, 1)
 *   blasi.sources              an integer in [1, 65536]
 *   blasi.exit_deposit         one of paper, none
 *   blasi.view_attenuation     one of absorption, extinction
 *   blasi.gather               one of path_length, printed
 *   blasi.interpolate          one of trilinear, voxel
 *   blasi.variant              one of paper, physical
 *   blasi.voxels               0 or an integer in [2, 2048]
 *   blasi.save_light           a file name
 *   blasi.load_light           a file name
 *   stam.eps                   a number >= 0
 *   stam.eta                   a number > 0
 *   stam.alpha                 a length > 0
 *   stam.lattice               0 (automatic) or an integer in [2, 512]
 *   stam.cell                  a length >= 0 (0 = alpha / 3)
 *   stam.seed                  an integer in [0, 2^53]
 *   stam.time                  a finite time in seconds
 *   stam.rate                  a rate >= 0
 *   stam.ambient               a radiance >= 0 (v or r,g,b)
 *   stam.steps                 an integer in [1, 256]
 *   stam.light_grid            an integer in [0, 512]
 *   stam.bvh                   true or false
 *   stam.variant               one of corrected, paper
 *   stam.kernel                one of gaussian, table
 *   stam.kernel_file           a file name
 *   stam.overlap               one of independent, joint
 *   stam.voxelize.resolution   an integer in [2, 2048] (0 = off)
 *   stam.voxelize.realization  true or false
 * END OPTION KEYS */
brume_status brume_scene_set_option(brume_context *ctx, brume_scene *scene, const char *key, const char *value);
/* The methods' options, from the same tables that parse them: brume_option_count() of them,
 * in a fixed order (by method, then as docs/scene-format.md lists them). */
typedef enum brume_option_kind {
    BRUME_OPTION_NUMBER = 0, /* "number": a finite number in a range */
    BRUME_OPTION_INTEGER,    /* "integer": a whole number in a range */
    BRUME_OPTION_ENUM,       /* "enum": one of the names `values` lists */
    BRUME_OPTION_BOOL,       /* "bool": true, false, 1 or 0 */
    BRUME_OPTION_COLOR,      /* "color": "v" (gray) or "r,g,b" */
    BRUME_OPTION_PATH        /* "path": a file name */
} brume_option_kind;
/* The kind's name as above ("enum"); NULL for a value outside the enum. */
const char *brume_option_kind_name(brume_option_kind kind);
typedef struct brume_option {
    const char *key;           /* "METHOD.KEY", as brume_scene_set_option takes it: "blasi.r" */
    brume_option_kind kind;    /* what a value's text is */
    const char *values;        /* what a value is: "a number in [0, 1]", "one of paper, none" */
    const char *default_value; /* the default as text ("2", "paper"), words when the method
                                  computes it ("from the phase function"), "" when none */
    const char *doc;           /* meaning and units, one line */
} brume_option;
int brume_option_count(void);
/* Fills *out with option `index`, 0 <= index < brume_option_count() (BRUME_ERROR_RANGE
 * otherwise); its strings are the library's, valid as long as it is loaded. */
brume_status brume_option_get(brume_context *ctx, int index, brume_option *out);
/* Freezes the scene and builds what rendering needs (majorants, light tables). */
brume_status brume_scene_commit(brume_context *ctx, brume_scene *scene);
void brume_scene_release(brume_scene *scene);

/* ---- building a scene in memory ------------------------------------------------------------ */
/* The one way to make a scene: every field a scene file can give has a builder here, and
 * the scene file reader (brume_scene_load) is a client of these
 * builders. Builders work on an uncommitted scene; each validates its arguments (NaN,
 * infinities, negative or absurd sizes) and on failure changes nothing and names the
 * function and the argument, e.g. "brume_scene_set_camera: fov: 400 outside [0.001, 179]".
 * Units: world units of length, seconds, degrees for angles, linear Rec. 709 RGB. Every
 * `const double x[3]` is an (x, y, z) point or vector, or an (R, G, B) triple. */

/* A new empty scene: default render settings (640 x 480, 16 spp, path), the default camera
 * (brume_camera_default), no lights, no media, no surfaces, a black background. `name`
 * names the scene in messages; NULL gives "<scene>". */
brume_status brume_scene_new(brume_context *ctx, const char *name, brume_scene **out);
/* The scene's frame time in seconds (brume_scene_time), before commit: the camera's shutter
 * and keyframes are relative to it; what a builder evaluates at a time (a fractal's time, a
 * light's keyframes) the caller evaluates. */
brume_status brume_scene_set_time(brume_context *ctx, brume_scene *scene, double time);
/* Declares that the caller evaluated something besides the camera at the scene's time (a
 * keyframed light): brume_scene_world_is_static is then false. Moving media and surfaces
 * (motion keys, drifting blobs, evolving fractals) are known to the scene already. */
brume_status brume_scene_set_animated(brume_context *ctx, brume_scene *scene);

/* A look-at perspective camera with a thin lens. */
typedef struct brume_camera {
    double position[3];     /* world units */
    double look_at[3];      /* the world point at the image centre, != position */
    double up[3];           /* approximate up direction, not zero (default +y) */
    double fov;             /* vertical field of view, degrees, in [0.001, 179] */
    double aperture_radius; /* lens radius, world units, >= 0; 0 = pinhole */
    double focus_distance;  /* distance to the plane in focus, world units; 0 = |look_at - position| */
    double shutter_open, shutter_close; /* seconds relative to the frame time, open <= close */
} brume_camera;
/* At (0, 0, 5) looking at the origin, up +y, fov 40, pinhole, shutter [0, 0]. */
void brume_camera_default(brume_camera *camera);
brume_status brume_scene_set_camera(brume_context *ctx, brume_scene *scene, const brume_camera *camera);
/* A keyframed camera: n in [1, 64] complete poses at strictly increasing times (seconds);
 * between keys every field is interpolated linearly, beyond them the end keys hold. The pose
 * at the frame time is used for the image, each ray's own time within the shutter. */
typedef struct brume_camera_key {
    double time;
    double position[3], look_at[3], up[3];
    double fov, aperture_radius, focus_distance; /* as brume_camera; focus_distance > 0 */
} brume_camera_key;
brume_status brume_scene_set_camera_keys(brume_context *ctx, brume_scene *scene, const brume_camera_key *keys,
                                         int n);
/* Auto-framing: at commit, the camera keeps its view direction (position - look_at), up and
 * fov and is moved to look at the centre of the box holding every non-zero density of the
 * media named (`media` NULL, "" or "media": all of them; else the medium of that name),
 * from the distance at which the whole box is in view with `margin` (a fraction in
 * [0, 0.9] of the half-frame) left on the tighter side, for the final image size. The media
 * are taken at rest (keyframed motion is not followed); a keyframed camera is refused at
 * commit. The camera's focus distance keeps its ratio to the look-at distance. */
brume_status brume_scene_frame_camera(brume_context *ctx, brume_scene *scene, const char *media, double margin);
/* The same framing on a given world box (x0, y0, z0, x1, y1, z1; lo <= hi, finite) instead of
 * the media's: a sequence's studio scene frames the box over all its files, so that the
 * camera is the same for every frame (docs/production.md). */
brume_status brume_scene_frame_camera_box(brume_context *ctx, brume_scene *scene, const double box[6], double margin);
/* The camera's medium (scene JSON camera.medium; pbrt-v4's MediumInterface at Camera): the
 * camera sits inside the medium `name`. brume's media are fields, so camera rays start in
 * every medium whose field's box holds the camera, named or not; commit checks that the
 * named medium exists, is at rest (no keyframes) and that its field's box holds every point
 * a camera ray starts from (the position, each key's, and the lens around them), and refuses
 * the scene otherwise. NULL or "" clears it. */
brume_status brume_scene_set_camera_medium(brume_context *ctx, brume_scene *scene, const char *name);

/* Lights (at most 4096). Colors are linear RGB, each component finite and >= 0. */
/* Sunlight-like: irradiance (W m^-2) on a surface facing the light, travelling along
 * `direction`; angular_radius (degrees, [0, 90]) > 0 makes it a disk of uniform radiance. */
brume_status brume_scene_add_distant_light(brume_context *ctx, brume_scene *scene, const double direction[3],
                                           const double irradiance[3], double angular_radius);
/* Intensity in W sr^-1. */
brume_status brume_scene_add_point_light(brume_context *ctx, brume_scene *scene, const double position[3],
                                         const double intensity[3]);
/* A spot along `direction`: full intensity (W sr^-1) inside falloff_start degrees of its
 * axis, falling smoothly to 0 at cone_angle degrees; 0 < cone_angle <= 180,
 * 0 <= falloff_start <= cone_angle. */
brume_status brume_scene_add_spot_light(brume_context *ctx, brume_scene *scene, const double position[3],
                                        const double direction[3], const double intensity[3], double cone_angle,
                                        double falloff_start);
/* A spot with a goniometric profile: intensity times factor[i] at angle[i] degrees from the
 * axis, linear between; n in [2, 256] pairs, angles increasing within [0, 180], factors >= 0. */
brume_status brume_scene_add_spot_light_profile(brume_context *ctx, brume_scene *scene, const double position[3],
                                                const double direction[3], const double intensity[3],
                                                const double *angle, const double *factor, int n);
/* Uniform radiance (W m^-2 sr^-1) leaving a sphere of radius > 0 (world units). */
brume_status brume_scene_add_sphere_light(brume_context *ctx, brume_scene *scene, const double position[3],
                                          double radius, const double radiance[3]);
/* Uniform radiance leaving one side (along `normal`) of a disk of radius > 0. */
brume_status brume_scene_add_disk_light(brume_context *ctx, brume_scene *scene, const double position[3],
                                        const double normal[3], double radius, const double radiance[3]);

/* The background: radiance (W m^-2 sr^-1) arriving from infinity. */
brume_status brume_scene_set_background_color(brume_context *ctx, brume_scene *scene, const double radiance[3]);
/* An environment in latitude-longitude layout, copied: the top row looks along `up` (NULL:
 * +y), column u at azimuth 2 pi u - pi; radiance = pixel value * scale (finite, >= 0). */
brume_status brume_scene_set_background_image(brume_context *ctx, brume_scene *scene, const brume_image *image,
                                              double scale, const double up[3]);
/* An environment in pbrt-v4's equal-area octahedral layout, copied: a square image whose
 * point (u, v) (u to the right, v down from the top row, both in [0, 1]) looks along pbrt-v4's
 * EqualAreaSquareToSphere(u, v) in the map's frame; world_from_map (row-major 3 x 3, NULL: the
 * identity) turns the map's frame into the world: a rotation, possibly with a mirror, times a
 * uniform scale (which is divided out). Every texel covers 4 pi / texels steradians;
 * radiance = pixel value * scale (finite, >= 0). */
brume_status brume_scene_set_background_equal_area(brume_context *ctx, brume_scene *scene, const brume_image *image,
                                                   double scale, const double world_from_map[9]);

/* Density fields rho(x) >= 0 (unitless), made here and given to a medium. */
typedef struct brume_density brume_density;
typedef enum brume_grid_filter {
    BRUME_GRID_NEAREST = 0,  /* constant over each voxel (Blasi) */
    BRUME_GRID_TRILINEAR = 1 /* trilinear between cell-centred samples */
} brume_grid_filter;
/* Called once when brume no longer needs borrowed memory. */
typedef void (*brume_release_fn)(void *user);
/* A dense grid of nx x ny x nz float32 values, x fastest (value (i, j, k) at
 * data[i + nx (j + ny k)], i.e. a C array [nz][ny][nx]), covering the world box
 * bounds = {xmin, ymin, zmin, xmax, ymax, zmax} (min < max); sample (i, j, k) sits at its
 * cell's centre. Each dimension in [1, 65536], values finite and >= 0. With release NULL
 * the values are copied; else they are borrowed: data must stay valid and unchanged until
 * brume calls release(user), once, when the density (or the scene it was given to) is
 * released. On failure nothing is kept and release is not called. */
brume_status brume_density_new_array(brume_context *ctx, const float *data, int nx, int ny, int nz,
                                     const double bounds[6], brume_grid_filter filter, brume_release_fn release,
                                     void *user, brume_density **out);
/* A constant density `value` (>= 0) filling the box bounds. */
brume_status brume_density_new_constant(brume_context *ctx, double value, const double bounds[6],
                                        brume_density **out);
/* The default scene's cloud: fBm value noise carved by an ellipsoid, resolution^3 voxels
 * (resolution in [2, 512]) over bounds, max rho 1. */
brume_status brume_density_new_procedural_cloud(brume_context *ctx, int resolution, uint64_t seed,
                                                const double bounds[6], brume_density **out);
/* pbrt-v4's procedural cloud (its "cloud" medium's density): Perlin noise of `frequency`
 * (pbrt's default 5) perturbed by `wispiness` (1), scaled by `density` (1) and falling off
 * with height, in [0, 1], evaluated where it is looked up over the box bounds (pbrt's p0, p1:
 * the cloud's own space, y its height); each value in [0, 1e30]. docs/pbrt.md gives the
 * formula. */
brume_status brume_density_new_pbrt_cloud(brume_context *ctx, double density, double wispiness, double frequency,
                                          const double bounds[6], brume_density **out);
/* A NanoVDB buffer holding a float grid (copied; size in bytes), placed by its own map;
 * values multiplied by scale (> 0). */
brume_status brume_density_new_nanovdb(brume_context *ctx, const void *buffer, size_t size,
                                       brume_grid_filter filter, double scale, brume_density **out);
/* The formats of grid files (docs/grids.md), a scene file's density "format". */
typedef enum brume_grid_format {
    BRUME_GRID_FORMAT_AUTO = 0, /* "auto": by the extension, else the magic number */
    BRUME_GRID_FORMAT_RAW,      /* "raw": float32 values (docs/grids.md gives the sidecar) */
    BRUME_GRID_FORMAT_DF3,      /* "df3": POV-Ray density file */
    BRUME_GRID_FORMAT_VOL,      /* "vol": Mitsuba's grid volume */
    BRUME_GRID_FORMAT_NVDB,     /* "nvdb": NanoVDB */
    BRUME_GRID_FORMAT_VDB       /* "vdb": OpenVDB */
} brume_grid_format;
/* A grid file (docs/grids.md: raw, df3, vol, nvdb, vdb), as a scene file's density of type
 * "grid". opts may be NULL (defaults). */
typedef struct brume_grid_file_options {
    brume_grid_format format; /* default BRUME_GRID_FORMAT_AUTO */
    int dims[3];            /* raw without a sidecar: nx, ny, nz; all 0 = from the file */
    bool has_bounds;        /* place the voxel box on bounds (world units), replacing the file's */
    double bounds[6];       /* xmin, ymin, zmin, xmax, ymax, zmax */
    bool has_transform;     /* then world = transform(placement(voxel)) */
    double transform[12];   /* 3 x 4 row-major affine map [R | t], invertible */
    brume_grid_filter filter; /* default trilinear */
    double scale;           /* multiplies every density, > 0 (default 1) */
    double max_memory_mb;   /* MiB the voxels may take; 0 = 4096 */
    char grid[128];         /* .vdb/.nvdb: the grid by name; "" = the one named "density", else the
                               only float grid (several and none named density is an error) */
    bool edge_zero;         /* .vdb/.nvdb, trilinear, own placement: pbrt-v4's NanoVDB lookup (voxels
                               beyond the grid read 0; the field cut to index [min, max + 1]) */
} brume_grid_file_options;
void brume_grid_file_options_default(brume_grid_file_options *opts);
brume_status brume_density_load(brume_context *ctx, const char *path, const brume_grid_file_options *opts,
                                brume_density **out);
/* The three components (out[0..2], an array of 3) of a vec3 grid of a .vdb/.nvdb (a float grid gives the same field
 * three times), e.g. Houdini's Cd, sharing one sparse buffer: out[0..2] (each released or
 * given away on its own). opts.grid names the grid. */
brume_status brume_density_load_rgb(brume_context *ctx, const char *path, const brume_grid_file_options *opts,
                                    brume_density **out);
/* The three components (out[0..2], an array of 3) of a velocity grid of a .vdb/.nvdb: opts.grid
 * names a vec3 grid ("" = "vel"), or, when the file has no grid of that name, the three float
 * grids NAME.x, NAME.y, NAME.z. Values may be negative, must be finite; opts.scale multiplies
 * them (world units per second: brume_scene_set_medium_velocity). A grid of another type is
 * refused, naming it. */
brume_status brume_density_load_velocity(brume_context *ctx, const char *path, const brume_grid_file_options *opts,
                                         brume_density **out);
/* A fractal cloud grid (Blasi et al. 1993, 4.1; docs/grids.md), generated now. */
typedef enum brume_fractal_method { BRUME_FRACTAL_MIDPOINT, BRUME_FRACTAL_SPECTRAL, BRUME_FRACTAL_PERLIN } brume_fractal_method;
typedef enum brume_fractal_shape { BRUME_FRACTAL_SHAPE_NONE, BRUME_FRACTAL_SHAPE_ELLIPSOID, BRUME_FRACTAL_SHAPE_SLAB } brume_fractal_shape;
typedef struct brume_fractal {
    int dims[3];              /* voxels per axis, each in [1, 1024] */
    uint64_t seed;
    brume_fractal_method method;
    double hurst;             /* Hurst exponent H in [0.001, 0.999] */
    int octaves;              /* perlin base and turbulence, [1, 16] */
    double frequency;         /* perlin base: cycles across the largest axis, [0.001, 1000] */
    brume_fractal_shape shape;
    double falloff;           /* fraction of the half-extent, [0.001, 1] */
    double threshold;         /* theta at time 0, [0, 0.99] */
    double threshold_rate;    /* d theta / dt per second, [-1000, 1000] */
    double turbulence;        /* amplitude, [0, 1000] */
    double turbulence_frequency; /* cycles across the largest axis, [0.001, 1000] */
    double wind[3];           /* turbulence drift, normalized units per second */
    double time;              /* seconds: the time the field is evaluated at */
    double density;           /* the largest rho, [1e-9, 1e9] */
    double bounds[6];         /* world box; default unit voxels centred on the origin */
    brume_grid_filter filter; /* default nearest */
} brume_fractal;
/* Defaults of docs/grids.md (midpoint, slab, 65 x 65 x 10 voxels, ...). */
void brume_fractal_default(brume_fractal *fractal);
brume_status brume_density_new_fractal(brume_context *ctx, const brume_fractal *fractal, brume_density **out);
/* Stam's gaussian blobs (docs/stam.md): explicit blobs and generated ones. */
typedef enum brume_blob_generator_type { BRUME_BLOBS_CLOUD, BRUME_BLOBS_CLUSTER, BRUME_BLOBS_FIRE } brume_blob_generator_type;
typedef struct brume_blob_generator {
    brume_blob_generator_type type;
    double center[3], radii[3];   /* cloud: ellipsoid centre and semi-axes (> 0) */
    double bounds_min[3], bounds_max[3], radii_min[3], radii_max[3]; /* cluster: box of centres, semi-axes */
    int clouds;                   /* cluster: number of clouds, [1, 100000] */
    int count;                    /* blobs (per cloud), [1, 2^22] */
    double h[2];                  /* cloud, cluster: blob radius range [min, max], > 0 */
    double density;               /* peak mean density, >= 0 */
    double falloff;               /* cloud, cluster: [0, 100] */
    double base[3], up[3];        /* fire: base point and axis (up not zero) */
    double height, radius;        /* fire: > 0 and >= 0, world units */
    double fire_h;                /* fire: blob radius at the base, > 0 */
    double band[2];               /* fire: relative heights [lo, hi] within [0, 1] */
    uint64_t seed;
} brume_blob_generator;
/* The defaults of a generator type (docs/scene-format.md). */
void brume_blob_generator_default(brume_blob_generator *gen, brume_blob_generator_type type);
/* blobs: n rows of 5 doubles (x, y, z, mass >= 0, radius h > 0); then ngens generators; at
 * least one blob in all. cutoff in [1, 10] (blob radii; 0 = the default 3); velocity NULL
 * or the drift in world units per second (stam.time moves the blobs). */
brume_status brume_density_new_blobs(brume_context *ctx, const double *blobs, int n,
                                     const brume_blob_generator *gens, int ngens, double cutoff,
                                     const double velocity[3], brume_density **out);
void brume_density_release(brume_density *density);

/* ---- Grid files: what `brume info`, `convert` and `gen` do (docs/grids.md) ------------------ */

/* Whether this build reads and writes .vdb and writes .nvdb (OpenVDB, an optional part). */
bool brume_grid_have_openvdb(void);
/* The format a name says: "raw", "df3", "vol", "nvdb" or "vdb" (and "auto"); false, and *out
 * unchanged, for any other name or NULL. */
bool brume_grid_format_from_name(const char *name, brume_grid_format *out);
/* The name of a format: "auto", "raw", "df3", "vol", "nvdb", "vdb"; NULL for another value. */
const char *brume_grid_format_name(brume_grid_format format);
/* The format of the grid file at path: by its extension, else (a regular file only, read
 * without blocking) by its magic number; BRUME_GRID_FORMAT_AUTO when neither says. */
brume_grid_format brume_grid_format_of(const char *path);

/* One grid of a .vdb or .nvdb file, as it is stored. */
typedef struct brume_grid_entry {
    char name[128];
    char type[32];                    /* value type: "float", "vec3s", "double", "int32", ... */
    char grid_class[32];              /* "fog volume", "level set", "staggered", "unknown" */
    int index_min[3], index_max[3];   /* active voxels' index box (voxels), inclusive; min > max: none */
    unsigned long long active_voxels; /* active voxel count */
    double value_min, value_max;      /* range of the active values (vec3: of their components) */
    unsigned long long nanovdb_bytes; /* size as NanoVDB (float and vec3 grids; else 0), bytes */
} brume_grid_entry;
/* The grids of a .vdb or .nvdb file: fills up to max entries of out (out may be NULL when max
 * is 0) and sets *count to how many the file has. opts may be NULL; its max_memory_mb bounds
 * what is read. */
brume_status brume_grid_file_list(brume_context *ctx, const char *path, const brume_grid_file_options *opts,
                                  brume_grid_entry *out, int max, int *count);
/* Grids by the names fire and smoke tools write (docs/grids.md, "Fire files: grids by
 * name"): the role ("density", "temperature", "emission", "albedo", "velocity") takes the
 * first grid of its list of names, in the list's order, that the file has with a fitting
 * value type (density and temperature: float; emission: float or vec3; albedo and velocity:
 * vec3). brume_grid_pick: the index of the role's grid in grids, or -1 (none, or an unknown
 * role). brume_grid_role: the role of grid `index` ("" when none; NULL when grids is NULL).
 * brume_grid_role_names: the role's names in order, comma-separated ("" for an unknown role,
 * NULL for a NULL one). */
int brume_grid_pick(const brume_grid_entry *grids, int count, const char *role);
const char *brume_grid_role(const brume_grid_entry *grids, int count, int index);
const char *brume_grid_role_names(const char *role);

/* What a density holds, as `brume info` prints it. */
typedef struct brume_density_info {
    bool sparse;                      /* a NanoVDB tree, else a dense grid (or an analytic field) */
    int dims[3];                      /* voxels per axis (a tree's index box) */
    double bounds[6];                 /* world box: xmin, ymin, zmin, xmax, ymax, zmax */
    double voxel_to_world[12];        /* 3 x 4 row-major affine map; voxel (i, j, k) spans [i, i + 1) x ... */
    double rho_min, rho_max;          /* values (unitless) */
    size_t memory_bytes;              /* voxels and majorants, bytes */
    unsigned long long active_voxels; /* voxels with rho > 0 (a tree: its active count) */
    bool majorant_tree;               /* majorants from the tree's nested walk, else a cell grid: */
    int majorant_dims[3];             /* majorant cells per axis (a tree: majorant_dims[0] blocks of 128^3) */
    int majorant_cell;                /* voxels per majorant cell edge */
} brume_density_info;
brume_status brume_density_get_info(brume_context *ctx, const brume_density *density, brume_density_info *out);
/* Writes density to path as a grid file of format (AUTO: by path's extension; raw, df3, vol,
 * and with OpenVDB nvdb and vdb), through a temporary file renamed into place; a file already
 * at path is replaced only when it is a grid file (brume_output_check). */
brume_status brume_density_write(brume_context *ctx, const brume_density *density, const char *path,
                                 brume_grid_format format);
/* A .vdb straight to .nvdb (OpenVDB), keeping the sparse trees: every grid, or only the one
 * named grid (NULL or "": all); written as brume_density_write writes. */
brume_status brume_grid_convert_vdb_to_nvdb(brume_context *ctx, const char *in, const char *out, const char *grid);
/* The world box (bounds: xmin, ymin, zmin, xmax, ymax, zmax) and the largest value over the
 * files first..last of a frame pattern (brume_sequence_range), each loaded in turn with opts
 * (one in memory at a time). */
brume_status brume_grid_sequence_extent(brume_context *ctx, const char *pattern, long first, long last,
                                        const brume_grid_file_options *opts, double bounds[6], double *rho_max);

/* Sparse grids generated and written through OpenVDB to a .vdb or .nvdb file (docs/grids.md).
 * What was written: */
typedef struct brume_grid_gen_result {
    unsigned long long active_voxels; /* active voxels of the density grid */
    long box[3];                      /* index box, voxels per axis */
    double voxel;                     /* voxel size, world units */
} brume_grid_gen_result;
/* A procedural flame (`brume gen fire`): grids "density" and "temperature" (kelvin). */
typedef struct brume_fire {
    int resolution;   /* voxels up its height, [8, 1024]; n / 2 across */
    uint64_t seed;
    double height;    /* world units, (0, 1e6] */
    double velocity;  /* > 0: also a vec3 grid "vel", the updraft (velocity (0.5 + h) up at height
                         fraction h, world units per second); 0: none. [0, 1e6] */
    double time;      /* seconds: the turbulence has risen by time times the updraft's speed at
                         mid-height (velocity, or 1 world unit per second without one) */
    double max_memory_mb; /* MiB the generated trees may take; 0 = 4096 */
} brume_fire;
void brume_fire_default(brume_fire *fire); /* 128 voxels, seed 1, height 2, no velocity, time 0 */
/* How far the flame's turbulence has risen at fire->time, in flame heights (the generator
 * refuses more than 1e6: its noise's lattice index is an int). */
double brume_fire_rise(const brume_fire *fire);
brume_status brume_grid_gen_fire(brume_context *ctx, const brume_fire *fire, const char *out,
                                 brume_grid_gen_result *result);
/* `brume gen upres`: in's density grid (read with opts) upsampled factor in [1, 16] times per
 * axis (trilinear) with fractal detail of amplitude detail in [0, 1], kept sparse, within
 * opts->max_memory_mb. */
brume_status brume_grid_gen_upres(brume_context *ctx, const char *in, const brume_grid_file_options *opts, int factor,
                                  uint64_t seed, double detail, const char *out, brume_grid_gen_result *result);

/* Phase functions, made here and given to a medium. */
typedef struct brume_phase brume_phase;
/* The phase functions without parameters (a scene file's "type" names them). */
typedef enum brume_phase_preset {
    BRUME_PHASE_ISOTROPIC = 0, /* "isotropic": 1 / (4 pi) */
    BRUME_PHASE_RAYLEIGH = 1,  /* "rayleigh": 3 / (16 pi) (1 + cos^2) */
    BRUME_PHASE_HAZY = 2,      /* "hazy": Mie, hazy atmosphere (Nishita et al.) */
    BRUME_PHASE_MURKY = 3      /* "murky": Mie, murky atmosphere (Nishita et al.) */
} brume_phase_preset;
brume_status brume_phase_new_preset(brume_context *ctx, brume_phase_preset preset, brume_phase **out);
/* Henyey-Greenstein with mean cosine g in [-0.999999, 0.999999]. */
brume_status brume_phase_new_hg(brume_context *ctx, double g, brume_phase **out);
/* Schlick with k in [-0.999999, 0.999999]. */
brume_status brume_phase_new_schlick(brume_context *ctx, double k, brume_phase **out);
/* Blasi Eq. 22: r schlick(k) + (1 - r) schlick(kprime), r in [0, 1]. */
brume_status brume_phase_new_schlick_mix(brume_context *ctx, double r, double k, double kprime, brume_phase **out);
/* A table of n values at increasing angles (degrees), normalized by brume. */
brume_status brume_phase_new_tabulated(brume_context *ctx, const double *angle, const double *value, int n,
                                       brume_phase **out);
/* The same from a file (docs/phase-functions.md). */
brume_status brume_phase_load(brume_context *ctx, const char *path, brume_phase **out);
/* Blasi Eq. 20: the normalized sum of n in [1, 16] lobes with weights >= 0. On success the
 * mixture takes over the lobes (do not release them); on failure the caller keeps them. */
brume_status brume_phase_new_mixture(brume_context *ctx, const double *weights, brume_phase *const *lobes, int n,
                                     brume_phase **out);
void brume_phase_release(brume_phase *phase);
/* By name, as `brume phase` and `brume slab --phase` take it: "isotropic", "rayleigh",
 * "hazy", "murky", "hg:G", "schlick:K", or else the path of a tabulated file (brume_phase_load). */
brume_status brume_phase_new_named(brume_context *ctx, const char *name, brume_phase **out);
/* Schlick's k for Henyey-Greenstein's g (Blasi et al. 1993): k = 1.55 g - 0.55 g^3, clamped to
 * |k| <= 0.999999; 0 for a NaN. */
double brume_schlick_k_from_g(double g);

/* Fitting Blasi's two-lobe Schlick mixture (Eq. 22) to any phase function: phi(t) =
 * r phi_k(t) + (1 - r) phi_k'(t), r in [0, 1], |k|, |k'| < 1, reported with k <= k' (k the
 * backward or less forward lobe, r its weight, as in the paper's Figure 7). The error norms
 * (docs/phase-functions.md) compare phi = 4 pi p of the model and of the target; each is
 * relative (no unit): 0.01 is a 1 % root-mean-square difference. */
typedef enum brume_phase_fit_norm {
    BRUME_PHASE_FIT_COS,   /* "cos": sqrt(int (phi_fit - phi)^2 dt / int phi^2 dt), t = cos in [-1, 1] */
    BRUME_PHASE_FIT_ANGLE, /* "angle": the same over theta in [0, pi] (weights back and side
                              scattering more); the default */
    BRUME_PHASE_FIT_LOG    /* "log": sqrt(int (ln phi_fit - ln phi)^2 dt / 2); a target without zeros */
} brume_phase_fit_norm;
typedef struct brume_phase_fit {
    double r, k, kprime; /* Blasi Eq. 22, k <= kprime */
    double error;        /* the norm at (r, k, kprime) */
} brume_phase_fit;
/* "cos", "angle", "log" (BRUME_ERROR_INVALID_ARGUMENT for any other name). */
brume_status brume_phase_fit_norm_from_name(brume_context *ctx, const char *name, brume_phase_fit_norm *out);
const char *brume_phase_fit_norm_name(brume_phase_fit_norm norm); /* "?" for a value not in the enum */
/* The error of the mixture (r, k, kprime) against target in norm, by composite Gauss-Legendre
 * quadrature over the angle; NAN for parameters outside Eq. 22's domain or a NULL target. */
double brume_phase_fit_error(const brume_phase *target, brume_phase_fit_norm norm, double r, double k, double kprime);
/* The mixture that minimizes brume_phase_fit_error: a grid search over the domain, then
 * Nelder-Mead from the best points. Deterministic. The log norm refuses a target that is 0
 * somewhere. */
brume_status brume_phase_fit_schlick_mix(brume_context *ctx, const brume_phase *target, brume_phase_fit_norm norm,
                                         brume_phase_fit *out);

/* Polar and cartesian plots of phase functions (Blasi's Figures 2 to 6), one row per function:
 * the polar plot of phi(theta) on the left (light arrives from the left), phi against the angle
 * in degrees on the right; the function solid, an approximation dashed; or an overlay of
 * ncurves > 0 functions on the same axes, each in its colour, named in a legend. Every pointer
 * is borrowed. */
typedef struct brume_phase_plot_row {
    const char *title;                 /* printed above the row */
    const brume_phase *truth;          /* drawn solid */
    const brume_phase *approx;         /* drawn dashed, or NULL */
    int ncurves;                       /* an overlay instead, when > 0 (at most 16) */
    const brume_phase *const *curves;
    const char *const *labels;         /* NULL entries: no legend line */
    const bool *dashed;                /* may be NULL */
} brume_phase_plot_row;
/* An 8-bit RGB PNG of n in [1, 64] rows at path (a BRUME_FILE_IMAGE, brume_output_check). The
 * polar panel is linear, phi / max phi; log_scale plots log10(phi) on the cartesian one. */
brume_status brume_phase_plot_png(brume_context *ctx, const char *path, int n, const brume_phase_plot_row *rows,
                                  bool log_scale);

/* Total diffuse reflectance and transmittance of a homogeneous plane-parallel slab (index 1
 * both sides) lit by a collimated beam at normal incidence, estimated by the renderer's own
 * walk (`brume slab`, docs/validation.md); deterministic for a seed and a sample count,
 * whatever the thread count. */
typedef struct brume_slab_params {
    double albedo;            /* in [0, 1] */
    double tau;               /* optical thickness (sigma_t = 1 per unit length), > 0; 0 = semi-infinite */
    const brume_phase *phase; /* borrowed */
    uint64_t samples;         /* photons, >= 1 */
    uint64_t seed;
    int threads;              /* 0 = one per core */
    int max_depth;            /* scattering events counted, >= 1 (1 = single scattering) */
} brume_slab_params;
typedef struct brume_slab_result {
    double Rd, Rd_stderr; /* total diffuse reflectance (fraction of the beam's power) and its standard error */
    double Tt, Tt_stderr; /* total transmittance, with the unscattered part exp(-tau) */
} brume_slab_result;
brume_status brume_slab_run(brume_context *ctx, const brume_slab_params *params, brume_slab_result *out);


/* How a medium's emission (its constant, blackbody and emission field alike) is emitted
 * (docs/scene-format.md, "Emission"). */
typedef enum brume_emission_units {
    /* pbrt-v4's: Le is a radiance (W m^-2 sr^-1) emitted at the rate sigma_a rho(x) Le per
     * unit length, so it follows the density */
    BRUME_EMISSION_RADIANCE = 0,
    /* Cycles' Principled Volume: Le is a radiance per unit length (W m^-2 sr^-1 per world
     * unit) emitted wherever rho(x) > 0, whatever the density */
    BRUME_EMISSION_PER_LENGTH = 1
} brume_emission_units;

/* A participating medium: sigma_t(x) = (sigma_a + sigma_s) rho(x) per world unit. At most 16. */
typedef struct brume_medium {
    char name[64];      /* "" or a name for messages */
    double sigma_a[3];  /* absorption per world unit per unit density, each in [0, 1e12] */
    double sigma_s[3];  /* scattering per world unit per unit density, each in [0, 1e12] */
    double emission[3]; /* constant emission Le, >= 0, in emission_units */
    int emission_units; /* a brume_emission_units; 0 (the default) = BRUME_EMISSION_RADIANCE */
} brume_medium;
/* On success the scene takes over density and phase (phase NULL = isotropic): do not use or
 * release them again. On failure the caller keeps both. */
brume_status brume_scene_add_medium(brume_context *ctx, brume_scene *scene, const brume_medium *medium,
                                    brume_density *density, brume_phase *phase);
int brume_scene_medium_count(const brume_scene *scene);
/* Replaces the density of medium `medium` (counting from 0 in the order added: a scene
 * file's "media" order), e.g. a scene file's placeholder by a simulation's array. On success
 * the scene takes over density and releases the old one; on failure the caller keeps it. */
brume_status brume_scene_set_medium_density(brume_context *ctx, brume_scene *scene, int medium,
                                            brume_density *density);

/* Fields of a medium besides its density, each with its own placement (docs/grids.md,
 * "Media with several fields"); rendered by the path and single methods. On success the
 * scene takes over the densities given; on failure the caller keeps them.
 * Albedo A(x) per channel (albedo: an array of 3): sigma_s(x) = sigma_s rho(x) A(x) (values >= 0). */
brume_status brume_scene_set_medium_albedo(brume_context *ctx, brume_scene *scene, int medium,
                                           brume_density *const *albedo);
/* Blackbody emission from a temperature grid: where T' = (T(x) - temperature_offset)
 * temperature_scale exceeds cutoff, the medium emits, in its emission_units,
 * - BRUME_BLACKBODY_PBRT (pbrt-v4's): Le(x) = scale * B(T'), B the peak-normalized Planck
 *   spectrum in linear Rec. 709;
 * - BRUME_BLACKBODY_BLENDER (Cycles' Principled Volume): Le(x) = tint * (5.670373e-14 / pi)
 *   * ((1 - intensity) + intensity T'^4) * C(T'), C the Planck colour of luminance 1 with
 *   T' held within [800, 12000] K (Cycles' Blackbody node, unclamped). */
typedef enum brume_blackbody_model { BRUME_BLACKBODY_PBRT = 0, BRUME_BLACKBODY_BLENDER = 1 } brume_blackbody_model;
typedef struct brume_blackbody {
    double scale;              /* PBRT: radiance scale (W m^-2 sr^-1), > 0; default 1 */
    double temperature_scale;  /* > 0; default 1 (Blender's Temperature input) */
    double temperature_offset; /* kelvin; default 0 */
    double cutoff;             /* kelvin, >= 0; default 100 */
    int model;                 /* a brume_blackbody_model; default BRUME_BLACKBODY_PBRT */
    double intensity;          /* BLENDER: Blackbody Intensity, in [0, 1]; default 1 */
    double tint[3];            /* BLENDER: Blackbody Tint, >= 0; default 1 */
} brume_blackbody;
void brume_blackbody_default(brume_blackbody *bb);
/* bb NULL = the defaults. */
brume_status brume_scene_set_medium_temperature(brume_context *ctx, brume_scene *scene, int medium,
                                                brume_density *temperature, const brume_blackbody *bb);
/* An emission field E(x): n = 1 (a float grid) or 3 (per channel, e.g. from
 * brume_density_load_rgb); the medium emits color * E(x) (>= 0) in its emission_units,
 * besides its constant emission. */
brume_status brume_scene_set_medium_emission_field(brume_context *ctx, brume_scene *scene, int medium,
                                                   brume_density *const *fields, int n, const double color[3]);
/* Velocity motion blur (docs/animation.md, "Velocity motion blur"): a velocity field v(x) =
 * M u(x), u the sampled vectors (velocity: an array of 3, their x, y and z components, e.g.
 * from brume_density_load_velocity) and M the 3 x 3 row-major matrix `map` (NULL = identity:
 * the linear part of the grid's placement transform turns and scales the vectors with it),
 * in world units per second, in the medium's own frame (before its keyframed motion). A ray
 * at time t sees the density advected back from the frame time t_f (brume_scene_time):
 * rho(x, t) = rho(x - v(x) (t - t_f)), and so its other fields; t - t_f lies within the
 * camera's shutter. The majorants are widened at commit by max |v| times the shutter's
 * reach from t_f, so the estimators stay unbiased. Rendered by path and single (and on the
 * GPU); blasi and stam refuse such a medium. */
brume_status brume_scene_set_medium_velocity(brume_context *ctx, brume_scene *scene, int medium,
                                             brume_density *const *velocity, const double map[9]);

/* Keyframed motion of a medium or a surface: n in [1, 64] keys at strictly increasing times;
 * the object at time t is placed by translate(rotate(scale(p))) of the interpolated key
 * (slerp for the rotation) after its own placement. */
typedef struct brume_transform_key {
    double time;         /* seconds */
    double translate[3]; /* world units */
    double axis[3];      /* rotation axis, not zero */
    double angle;        /* degrees, counter-clockwise seen from the axis' tip */
    double scale[3];     /* factors > 0 */
} brume_transform_key;
brume_status brume_scene_set_medium_motion(brume_context *ctx, brume_scene *scene, int medium,
                                           const brume_transform_key *keys, int n);

/* TEXTURES (docs/surfaces.md, "Textures"): a value that varies over a surface with its
 * texture coordinates (u, v) (brume_scene_set_mesh_uv; a sphere's are pbrt's longitude and
 * latitude). A texture is a tree of nodes in an array, node 0 its root; a node's inputs
 * (tex1, tex2, amount) are indices of later nodes (so no loop), or -1 for the node's
 * default value. Every node maps (u, v) to (s, t) = (uscale u + udelta, vscale v + vdelta)
 * for what it reads itself; its inputs map the surface's (u, v) again, as in pbrt-v4.
 *   CONSTANT      value
 *   IMAGEMAP      the file (PNG, EXR, PFM, through brume_image_read and its limits) read
 *                 bilinearly at (s, 1 - t) (t = 0 is the image's bottom row, pbrt-v4's
 *                 convention), pixel centres at (i + 0.5) / width; `wrap` outside [0, 1];
 *                 8-bit (PNG) values decoded by `encoding` (sRGB, linear or gamma), float
 *                 files linear; times `scale`, then 1 - x when `invert`
 *   SCALE         tex1 x amount (each defaults to 1)
 *   MIX           (1 - amount) tex1 + amount tex2 (defaults 0, 1 and amount 0.5)
 *   CHECKERBOARD  tex1 where floor(s) + floor(t) is even, else tex2 (defaults 1 and 0),
 *                 point-sampled (pbrt-v4 filters it over a pixel's footprint)
 * A float texture (is_float) gives one number to all channels: an image's first channel. */
typedef enum brume_texture_type {
    BRUME_TEXTURE_CONSTANT,
    BRUME_TEXTURE_IMAGEMAP,
    BRUME_TEXTURE_SCALE,
    BRUME_TEXTURE_MIX,
    BRUME_TEXTURE_CHECKERBOARD
} brume_texture_type;
typedef enum brume_texture_wrap { BRUME_WRAP_REPEAT, BRUME_WRAP_BLACK, BRUME_WRAP_CLAMP } brume_texture_wrap;
typedef struct brume_texture_node {
    brume_texture_type type;
    bool is_float;
    double value[3];             /* CONSTANT: each finite */
    int tex1, tex2, amount;      /* inputs: a later node's index, or -1 for the default */
    double uscale, vscale, udelta, vdelta; /* finite; 0 scales are read as 1 */
    const char *filename;        /* IMAGEMAP (borrowed for the call) */
    double gamma;                /* IMAGEMAP, 8-bit files: 0 = sRGB, 1 = linear, else x^gamma */
    double scale;                /* IMAGEMAP: 0 is read as 1 */
    bool invert;                 /* IMAGEMAP */
    brume_texture_wrap wrap;     /* IMAGEMAP */
} brume_texture_node;
#define BRUME_TEXTURE_MAX_NODES 64
typedef struct brume_texture {
    const brume_texture_node *nodes; /* n nodes, borrowed for the call */
    int n;                           /* 1 to BRUME_TEXTURE_MAX_NODES */
} brume_texture;

/* Surfaces: a material of one type (docs/surfaces.md, "Materials") and emission. The
 * default type, diffuse, is a Lambertian lobe plus a normalized Phong lobe; the others are
 * pbrt-v4's dielectric, conductor and coateddiffuse. Each type reads its own fields. */
typedef enum brume_material_type {
    BRUME_MATERIAL_DIFFUSE = 0,   /* albedo, specular, exponent */
    BRUME_MATERIAL_DIELECTRIC,    /* eta, roughness */
    BRUME_MATERIAL_CONDUCTOR,     /* conductor_eta, conductor_k, roughness */
    BRUME_MATERIAL_COATEDDIFFUSE, /* albedo (the base's reflectance), eta, roughness, thickness,
                                     layer_albedo, g, max_depth, nsamples */
    BRUME_MATERIAL_MIX,           /* materials, amount (pbrt-v4's MixMaterial) */
} brume_material_type;
typedef struct brume_material {
    double albedo[3];   /* diffuse reflectance, each in [0, 1] */
    double specular[3]; /* Phong reflectance, each in [0, 1], albedo + specular <= 1 */
    double exponent;    /* Phong exponent, [0, 1e6] */
    double emission[3]; /* emitted radiance W m^-2 sr^-1 from the front side, >= 0 */
    bool two_sided;     /* emit from both sides */
    /* NULL, or the reflectance as a texture (copied; its images read once per shape), in
     * place of albedo (diffuse: clamped to [0, 1 - specular] per channel; coateddiffuse: the
     * base's, clamped to [0, 1]) or of conductor_eta and conductor_k (conductor: pbrt-v4's
     * "reflectance", eta 1 and the k of that normal reflectance). Rendered on the CPU (the
     * GPU refuses textures by name). */
    const brume_texture *albedo_texture;
    brume_material_type type;
    double eta;         /* index of refraction behind the front side over in front, (0, 100]; 1.5 */
    double conductor_eta[3], conductor_k[3]; /* complex index per channel, [0, 100]; copper's */
    double roughness;   /* Trowbridge-Reitz alpha in [0, 100] (pbrt-v4's after its remap); 0 smooth */
    double thickness;   /* coateddiffuse: the layer's optical thickness, (0, 1e6]; 0.01 */
    double layer_albedo[3]; /* coateddiffuse: scattering albedo in the layer, [0, 1]; 0 */
    double g;           /* coateddiffuse: the layer's Henyey-Greenstein g, (-1, 1); 0 */
    int max_depth;      /* coateddiffuse: most events of a walk between the layers, [1, 1000]; 10 */
    int nsamples;       /* coateddiffuse: walks per evaluation, [1, 1000]; 1 */
    /* NULL, or a float texture in place of roughness (dielectric, conductor, coateddiffuse):
     * pbrt-v4's roughness r at the hit, alpha = sqrt(r) when remap_roughness, else r */
    const brume_texture *roughness_texture;
    bool remap_roughness;
    /* mix: materials[1] with probability amount (amount_texture's value at the hit when not
     * NULL), else materials[0], chosen per shading point by a hash of the point and the
     * direction as pbrt-v4's MixMaterial does, so that the image is the amount-weighted mix.
     * The two are copied (mixes nest, BRUME_MATERIAL_MAX_MIX deep); their emission is not
     * read (the mix's own is). Rendered on the CPU. */
    const struct brume_material *materials[2];
    double amount;      /* [0, 1]; 0.5 */
    const brume_texture *amount_texture;
    /* NULL, or pbrt-v4's displacement d(u, v), a float texture in world units along the front
     * normal (any type but mix): bump mapping as pbrt-v4's BumpMap, the shading normal of
     * dp/du + dd/du n and dp/dv + dd/dv n by finite differences over 0.0005 in u and v (pbrt-v4's
     * offsets where it has no ray differentials, which brume has not). Rendered on the CPU. */
    const brume_texture *displacement_texture;
    /* NULL, or textures in place of these, as pbrt-v4 textures them (CPU only): conductor's
     * conductor_eta and conductor_k (spectrum textures, clamped to [0, 100]), coateddiffuse's
     * thickness (float, at least 0), g (float, clamped to [-0.999, 0.999]) and layer_albedo
     * (spectrum, clamped to [0, 1]) */
    const brume_texture *conductor_eta_texture, *conductor_k_texture;
    const brume_texture *thickness_texture, *g_texture, *layer_albedo_texture;
} brume_material;
#define BRUME_MATERIAL_MAX_MIX 8
/* albedo 0.8, no specular (exponent 50), no emission; the other types' pbrt-v4 defaults
 * (eta 1.5, copper, thickness 0.01, max_depth 10, nsamples 1, amount 0.5, remap_roughness). */
void brume_material_default(brume_material *material);
/* Every shape takes an optional transform (NULL = identity): 12 doubles, a 3 x 4 row-major
 * affine map [R | t] applied to the shape's points; material NULL = brume_material_default;
 * name NULL = "surfaces[INDEX]". Shapes are added in order; their index counts from 0. */
brume_status brume_scene_add_sphere(brume_context *ctx, brume_scene *scene, const double center[3], double radius,
                                    const double *transform, const brume_material *material, const char *name);
/* An axis-aligned box min < max (before the transform); faces outward. */
brume_status brume_scene_add_box(brume_context *ctx, brume_scene *scene, const double min[3], const double max[3],
                                 const double *transform, const brume_material *material, const char *name);
/* A parallelogram: corner, edges u and v (not parallel); the front side is along u x v. */
brume_status brume_scene_add_quad(brume_context *ctx, brume_scene *scene, const double corner[3],
                                  const double edge_u[3], const double edge_v[3], const double *transform,
                                  const brume_material *material, const char *name);
/* A square of side size (> 0) centred on point, front side along normal (not zero). */
brume_status brume_scene_add_plane(brume_context *ctx, brume_scene *scene, const double point[3],
                                   const double normal[3], double size, const double *transform,
                                   const brume_material *material, const char *name);
/* A triangle mesh: nv vertices (x, y, z triples), ntri triangles (index triples into the
 * vertices, counter-clockwise seen from the front). Copied. */
brume_status brume_scene_add_mesh(brume_context *ctx, brume_scene *scene, const double *positions, int nv,
                                  const int *indices, int ntri, const double *transform,
                                  const brume_material *material, const char *name);
/* Texture coordinates for surface `index`, a mesh of nv vertices (before commit): uv holds
 * (u, v) per vertex, finite, copied. A mesh without them gives each triangle (0, 0),
 * (1, 0), (1, 1) at its corners, as pbrt-v4 does. */
brume_status brume_scene_set_mesh_uv(brume_context *ctx, brume_scene *scene, int index, const double *uv, int nv);
/* A mesh file (OBJ, PLY, ... through assimp), with its texture coordinates when every mesh
 * of the file has them (else pbrt-v4's per triangle, as for an inline mesh without uv). */
brume_status brume_scene_add_mesh_file(brume_context *ctx, brume_scene *scene, const char *path,
                                       const double *transform, const brume_material *material, const char *name);
int brume_scene_surface_count(const brume_scene *scene);
brume_status brume_scene_set_surface_motion(brume_context *ctx, brume_scene *scene, int surface,
                                            const brume_transform_key *keys, int n);
/* Bounded media (docs/surfaces.md, "How surfaces meet media"): surface `surface` (its index)
 * bounds the medium named `inside` (behind its front side: a sphere's or a closed mesh's
 * interior; NULL or "": none) and the one named `outside` (before it). A medium named by a
 * surface is bounded: present only where the crossings put a path (the camera starts in
 * the ones its line from infinity enters, and in camera.medium); every other medium is a
 * free field, present everywhere. With `interface` the surface has no material: paths and
 * shadow rays cross it. The shape must be closed. Names are resolved at commit. */
brume_status brume_scene_set_surface_media(brume_context *ctx, brume_scene *scene, int surface, const char *inside,
                                           const char *outside, bool interface);

/* STATISTICS of the last render of a scene (docs/stats.md). Counts are exact sums over the
 * whole run and do not depend on the thread count; times are seconds (wall time, or CPU
 * time summed over threads where named so). Counted only when render settings' `stats` is
 * true (then a few percent slower), except the blasi light pass, which always counts. What
 * every method has is in brume_stats itself; each method's own figures are in its struct,
 * which is zero unless that method rendered. */
typedef struct brume_path_stats {     /* path and single (the reference) */
    double vertices;             /* mean scattering vertices (media and surfaces) per camera path */
    double collisions;           /* mean real collisions (medium scattering events) per camera path */
    double null_collisions;      /* mean null (rejected tentative) collisions per camera path */
    double tracking_cpu_seconds; /* CPU seconds in delta tracking of the path flights */
    double nee_cpu_seconds;      /* CPU seconds in next-event estimation (shadow rays included) */
    double shading_cpu_seconds;  /* the rest of the estimator: intersection, emission, phase and
                                    BSDF sampling */
    double majorant_cells;       /* majorant cells walked per camera path, by all its walks (flights
                                    and shadow rays; both levels of a two-level walk) */
    double density_lookups;      /* lookups of the media at a point per camera path, all walks */
} brume_path_stats;
typedef struct brume_blasi_stats {    /* Blasi et al. 1993: the light pass that made the radiance grid in use */
    double light_seconds;        /* wall time of the light (first) pass, or of loading it */
    double view_seconds;         /* wall time of the view (second) pass of the last render */
    uint64_t light_rays;         /* rays sent from the lights (0 when the pass was loaded) */
    uint64_t interceptions;      /* scattering events of the light pass (Eq. 9-11) */
    uint64_t deposits;           /* voxel deposits: interceptions plus exit deposits (erratum 5) */
    double power_emitted;        /* power sent by the light rays, mean over RGB, W (scene units) */
    double power_stored;         /* power stored in the voxels, mean over RGB, same unit */
} brume_blasi_stats;
typedef struct brume_stam_stats {     /* Stam 1994 */
    double blobs_per_ray;        /* blobs met by a camera ray's transparency walk, mean */
    double queries_per_ray;      /* ray queries of the blob hierarchy (camera, shadow and cache rays
                                    of the render) per camera ray */
    double nodes_per_query;      /* hierarchy cells (BVH nodes) visited per query, mean */
    double blobs_per_query;      /* blobs met per query, mean */
} brume_stam_stats;
typedef struct brume_stats {
    bool rendered;               /* false before a render of the scene finished (all fields 0 then) */
    brume_method method;         /* the method of the last render */
    double seconds;              /* wall time of the last brume_render, integrator set-up included */
    uint64_t camera_rays;        /* camera samples traced (width x height x spp) */
    double li_cpu_seconds;       /* CPU seconds in the method's per-ray estimator, all threads */
    brume_path_stats path;       /* method path or single */
    brume_blasi_stats blasi;     /* method blasi */
    brume_stam_stats stam;       /* method stam */
    /* Every method's camera samples: the bound on one sample's tentative collisions, derived
     * from the scene (docs/stats.md), and the samples that reached it and were ended there
     * (a bias: 0 for every valid scene brume was tested with). Counted with or without
     * render.stats. */
    uint64_t collision_bound;
    uint64_t samples_cut;
    /* Camera samples whose estimate was NaN or infinite, on the CPU or the GPU: each added 0
     * to its pixel, as a black sample (0 for every valid scene brume was tested with).
     * Counted with or without render.stats. */
    uint64_t samples_nonfinite;
} brume_stats;
/* Copies the statistics of the last render of scene into *out (zeros before any render). */
void brume_scene_stats(const brume_scene *scene, brume_stats *out);

/* ---- rendering and images ----------------------------------------------------------------- */


/* Renders a committed scene with its settings. *out is a new image owned by the caller.
 * Work an integrator does once per scene (a light pass) is kept with the scene and reused
 * by later renders of it; call brume_render on one scene from one thread at a time.
 * It is one render job (below) run to its end: begin, run, image, release. When the
 * progress callback cancels, it returns BRUME_ERROR_CANCELLED and *out is the image of the
 * samples finished so far (the "samples" layer tells how many each pixel has). */
brume_status brume_render(brume_context *ctx, const brume_scene *scene, brume_image **out);
/* Renders part `part` of `nparts` (0 <= part < nparts): the image tiles t with
 * t % nparts == part, the other pixels left +0. Every pixel is computed exactly as by
 * brume_render, so the sum of all parts is the whole image bit for bit (each pixel has one
 * nonzero contributor): what distributed rendering (`mpirun brume render`) relies on. */
brume_status brume_render_part(brume_context *ctx, const brume_scene *scene, int part, int nparts,
                               brume_image **out);

/* ---- render jobs: progressive rendering, budgets, checkpoints ------------------------------
 *
 * A job holds, per pixel, the sums and sums of squares of its samples and their count.
 * Sample i of pixel p always draws the random numbers of (seed, p, i), so N passes of k
 * samples are bit-identical to one render of N x k, and a job resumed from a checkpoint
 * ends with the bytes of one that never stopped. With a noise target, a pixel stops
 * receiving samples at a pass boundary once its own statistics meet the target (after
 * min_spp samples): the decisions never depend on the thread count or on timing. */
typedef struct brume_render_job brume_render_job;

/* Starts a job on a committed scene (runs the integrator's once-per-scene work). *out is
 * owned by the caller; the scene must outlive it. */
brume_status brume_render_begin(brume_context *ctx, const brume_scene *scene, brume_render_job **out);
/* Adds spp >= 1 samples to every pixel that is still sampled (a pass). May return
 * BRUME_ERROR_CANCELLED (the progress callback): the pixels then hold what finished; a
 * later call continues, and a pass that was cut is completed first. */
brume_status brume_render_job_add(brume_context *ctx, brume_render_job *job, int spp);
/* Runs passes until the settings say stop: spp samples per pixel, the time budget spent, or
 * every pixel at the noise target. May return BRUME_ERROR_CANCELLED; call again to go on. */
brume_status brume_render_job_run(brume_context *ctx, brume_render_job *job);
/* The image so far (RGBA, plus the layers the settings ask for), a new image owned by the
 * caller. Safe to call from another thread while a pass runs (use another context): it sees
 * every finished tile. */
brume_status brume_render_job_image(brume_context *ctx, const brume_render_job *job, brume_image **out);
/* Samples per pixel so far (the maximum over pixels). */
int brume_render_job_samples(const brume_render_job *job);

/* What ended a render job's passes (brume_render_progress.stopped). */
typedef enum brume_stop_reason {
    BRUME_STOP_NONE = 0,  /* passes are left under the settings (or one runs) */
    BRUME_STOP_SPP,       /* the pixels still sampled reached spp, the sample maximum */
    BRUME_STOP_NOISE,     /* every pixel met the noise target */
    BRUME_STOP_TIME,      /* the time budget ran out */
    BRUME_STOP_CANCELLED  /* the progress callback cancelled the last pass (an interrupt) */
} brume_stop_reason;

/* Figures of a job, for a progress display; safe from any thread at any time, the progress
 * callback included. Every display of a job (brume's bar and log lines, its live view,
 * Python's) shows these, so they agree; the library computes them and prints nothing. */
typedef struct brume_render_progress {
    uint64_t done, total;  /* pixel samples, as the progress callback gets them */
    int spp_min, spp_max;  /* samples per pixel over the pixels */
    double spp_mean;
    double noise;          /* largest estimated relative standard error over the pixels that
                              carry signal, at the last pass boundary (0 before the first) */
    double converged;      /* fraction of pixels that adaptive sampling has stopped, [0, 1] */
    double elapsed;        /* seconds spent rendering (across resumes), the integrator's
                              preparation (a light pass) included */
    double eta;            /* seconds left, an estimate (0 when finished); negative: not known
                              yet (a noise target before the first error estimate). Under a
                              noise target it is the samples the pixels' own error trend says
                              they still need (n (e / target)^2 each), each at its tile's cost
                              per sample; under a time budget at most the time left. Smoothed
                              over the calls: a new estimate shows over a quarter of the time
                              spent (or left) rather than at once (docs/render-jobs.md) */
    bool finished;         /* nothing left to do under the settings */
    double fraction;       /* of the work done, elapsed / (elapsed + eta), [0, 1), 1 only when
                              finished; never below what an earlier call gave, however the
                              estimate of the total moves; negative while the ETA is not known */
    brume_stop_reason stopped; /* why the passes ended; BRUME_STOP_NONE while work is left */
} brume_render_progress;
void brume_render_job_progress(const brume_render_job *job, brume_render_progress *out);

/* Checkpoints (docs/render-jobs.md gives the format). brume_render_job_save writes the
 * job's whole state atomically to path: sums, counts, the settings that shape the image,
 * brume's version and scene_key, a number the caller derives from what the scene was made
 * of (brume render hashes the scene file and its options). Safe to call while a pass runs
 * (from another thread, with another context): it saves every finished tile.
 * brume_render_job_resume starts a job on a committed scene from such a file; a file from
 * another brume version, another scene_key or other settings, or one truncated or
 * corrupt, is refused with a one-line message naming the file and what differs. */
brume_status brume_render_job_save(brume_context *ctx, const brume_render_job *job, uint64_t scene_key,
                                   const char *path);
brume_status brume_render_job_resume(brume_context *ctx, const brume_scene *scene, uint64_t scene_key,
                                     const char *path, brume_render_job **out);
void brume_render_job_release(brume_render_job *job);

/* A new black, transparent image of width x height pixels (each in [1, 65536]). On success
 * *out is owned by the caller. */
brume_status brume_image_new(brume_context *ctx, int width, int height, brume_image **out);
int brume_image_width(const brume_image *image);
int brume_image_height(const brume_image *image);
/* width * height * 4 floats, RGBA, rows top first. Owned by the image; the caller may
 * write them where it may change the image (one it owns: a const image only reads them). */
float *brume_image_pixels(const brume_image *image);
void brume_image_release(brume_image *image);

/* Image layers: besides RGBA an image carries named extra layers (AOVs, in the order of
 * brume_aov's bits). A layer has 1 or 3 channels of float32, rows top first. */
int brume_image_layer_count(const brume_image *image);               /* extra layers, >= 0 */
const char *brume_image_layer_name(const brume_image *image, int i);  /* "depth", "albedo", ...; NULL if no layer i */
int brume_image_layer_channels(const brume_image *image, int i);      /* 1 or 3; 0 if no layer i */
const float *brume_image_layer_pixels(const brume_image *image, int i); /* w * h * channels; NULL if no layer i */

/* String attributes of an image, written into EXR headers (brume render stores the sample
 * counts and the noise estimate as "brume.spp_min", "brume.spp_mean", ...). key and value are
 * copied (at most 47 and 79 bytes kept); at most 8 attributes. */
brume_status brume_image_set_attribute(brume_context *ctx, brume_image *image, const char *key, const char *value);
/* The value of an attribute, or NULL. Owned by the image. */
const char *brume_image_attribute(const brume_image *image, const char *key);

/* Whether an image holds light: every R, G, B and alpha value, and with `layers` every layer's,
 * finite and >= 0, but the "normal" layer's, a signed unit vector, finite only. Otherwise
 * BRUME_ERROR_RANGE, one line naming `name` (a file, say; NULL: "image"), the layer, the pixel
 * and the channel. brume_image_compare and its kin check their images this way, and
 * brume_scene_set_background_image its environment map; brume_denoise checks every layer so,
 * but takes signed R, G, B (finite: its filter is linear in them). */
brume_status brume_image_check_values(brume_context *ctx, const brume_image *image, const char *name, bool layers);

/* DENOISING (docs/denoise.md). Filters a rendered image with an edge-avoiding a-trous
 * filter (Dammertz et al. 2010) whose colour weights are normalised by the per-pixel
 * variance (Rousselle et al. 2012), guided by the "albedo", "normal" and "depth" layers
 * when the image has them. The image must have the "variance" layer (BRUME_AOV_VARIANCE).
 * *out is a new image owned by the caller: RGB denoised, alpha and every layer as in `in`,
 * the unfiltered RGB in a layer "raw", and the attribute "brume.denoised" set; an image
 * that has them already is refused. threads: 0 = one per core; the result does not depend
 * on it. A NaN or an infinity anywhere, or a negative value in a layer but "normal", is
 * BRUME_ERROR_RANGE naming the layer and the pixel. A denoised image is biased
 * (docs/denoise.md measures by how much): never a validation result. */
brume_status brume_denoise(brume_context *ctx, const brume_image *in, int threads, brume_image **out);
/* Bytes brume_denoise allocates for a width x height image whose layers hold layer_channels
 * channels in all (depth and samples 1 each, variance, albedo and normal 3 each): its output
 * and its working buffers, (12 + layer_channels) floats and 12 doubles a pixel; 0 for a side
 * <= 0. brume_denoise refuses (BRUME_ERROR_OUT_OF_MEMORY, one line) an image whose figure is
 * over the default memory limit (render.max_memory_mb's 4096 MiB) before allocating;
 * `brume render --denoise` checks it against the scene's render.max_memory_mb before
 * rendering. brume_context_cancel_loads(ctx) stops it (BRUME_ERROR_CANCELLED, no image). */
size_t brume_denoise_memory(int width, int height, int layer_channels);

typedef enum brume_tonemap {
    BRUME_TONEMAP_CLAMP = 0, /* sRGB of the exposed linear value, clamped to [0, 1] */
    BRUME_TONEMAP_FILMIC = 1 /* ACES filmic curve (Narkowicz 2015) before the sRGB transfer */
} brume_tonemap;

/* How linear values become 8-bit PNG. Ignored by EXR and PFM, which store linear floats. */
typedef struct brume_write_options {
    double exposure; /* stops: values are scaled by 2^exposure before tone mapping */
    brume_tonemap tonemap;
} brume_write_options;

/* Writes by extension: .exr (OpenEXR, RGBA float32, ZIP, plus every layer as channels
 * "NAME.R/G/B" or "NAME.Y", and the image's attributes as strings), .png (8-bit sRGB RGB:
 * alpha is dropped), .pfm (RGB float32); PNG and PFM hold no layers. opts may be NULL
 * (exposure 0, clamp). The write is atomic: data go to a
 * temporary file in the same folder that is renamed over path only when complete, so a
 * failed write never leaves a file that looks whole. */
brume_status brume_image_write(brume_context *ctx, const brume_image *image, const char *path,
                               const brume_write_options *opts);
/* Reads .exr (R, G, B and optional A channels; "NAME.C" channels become layers), .pfm or .png
 * into a new linear image. */
brume_status brume_image_read(brume_context *ctx, const char *path, brume_image **out);
/* The image as PNG bytes (as brume_image_write would write them; opts may be NULL) in a new
 * buffer of *size bytes that the caller frees with free(). */
brume_status brume_image_encode_png(brume_context *ctx, const brume_image *image, const brume_write_options *opts,
                                    unsigned char **data, size_t *size);

/* ---- frame sequences of grid files (docs/grids.md, "Sequences") ---------------------------- */

/* A file name with a frame pattern (smoke_%04d.vdb, smoke_####.vdb, smoke_$F4.vdb) names one
 * file per frame. *is_pattern: whether the name's last component holds one pattern; a
 * malformed one, or more than one, is BRUME_ERROR_INVALID_ARGUMENT. */
brume_status brume_sequence_pattern(brume_context *ctx, const char *name, bool *is_pattern);
/* The file of number n: the pattern's name with n in its place, zero-padded to its width, in
 * out[cap] (BRUME_ERROR_INVALID_ARGUMENT when it does not fit or name holds no pattern). */
brume_status brume_sequence_name(brume_context *ctx, const char *pattern, long n, char *out, size_t cap);
/* The smallest and largest number of the files present; a gap, or no file, is an error naming
 * the first missing number and its file. */
brume_status brume_sequence_range(brume_context *ctx, const char *pattern, long *first, long *last);

/* Stam (1994)'s plots that are not renderings, as PNG at path (a BRUME_FILE_IMAGE): figure 1,
 * a random blob along a line through its centre (mean, mean +- sigma, a realization, with and
 * without clamping); figure 4, Var T_i against the distance d_i of a ray from the blob's
 * centre for several eta, closed form (lines) against the sample variance over explicit
 * realizations (points; 120 when quick, else 1200), *max_z (may be NULL) receiving the largest
 * |sample - closed form| in standard errors of the sample variance. docs/stam.md explains
 * both. One figure at a time: a second call waits for the first. */
brume_status brume_stam_figure_png(brume_context *ctx, int figure, const char *path, bool quick, double *max_z);

/* ---- outputs: written whole, never over what they must not replace ---------------------- */

/* What a file brume writes holds. A file of one kind replaces only a file of the same kind, or
 * an empty one: an image replaces an image, a checkpoint a brume checkpoint, a light file a
 * brume light file (each known by its first bytes). */
typedef enum brume_file_kind {
    BRUME_FILE_ANY,        /* no check of what the target holds */
    BRUME_FILE_IMAGE,      /* EXR, PNG, PFM */
    BRUME_FILE_CHECKPOINT, /* brume_render_job_save's */
    BRUME_FILE_LIGHT,      /* Blasi's light pass (blasi.save_light) */
    BRUME_FILE_GRID,       /* .vol, NanoVDB, OpenVDB; .raw and .df3 (no magic number) by name */
    BRUME_FILE_TEXT        /* Markdown, HTML, JSON: no NUL byte in its first 512 bytes */
} brume_file_kind;

/* Before any work: whether brume may write path as a file of kind (`what` names it in the
 * message: "-o", "--checkpoint"). It may when path is absent, or a regular file that is not the
 * scene's file nor one the scene read (scene may be NULL), not one of
 * others[0..nothers-1] (the caller's other inputs and outputs; NULL entries skipped; compared
 * as files: the same device and inode, or for names not yet written the same name in the same
 * folder), and that holds nothing or content of kind. Else BRUME_ERROR_INVALID_ARGUMENT, one
 * line naming path and what it is.
 * Every writer of the library (brume_image_write, brume_render_job_save, a render's
 * blasi.save_light, brume_file_write and the writers below) checks the kind again when it
 * opens the file, and writes a temporary file beside path that it renames over path once
 * whole: a full disk, a quota or a read-only folder end in one line (BRUME_ERROR_IO) with path
 * as it was and no temporary file left. */
brume_status brume_output_check(brume_context *ctx, const char *what, const char *path, brume_file_kind kind,
                                const brume_scene *scene, const char *const *others, int nothers);
/* Writes size bytes of data to path that way, as a file of kind. */
brume_status brume_file_write(brume_context *ctx, const char *path, brume_file_kind kind, const void *data,
                              size_t size);

/* A key for brume_render_job_save and _resume that changes when any file scene was read from
 * changes: h with the bytes of each folded in (FNV-1a 64), in the order they were read. */
uint64_t brume_scene_inputs_key(const brume_scene *scene, uint64_t h);
/* Removes path when, and only when, it is a regular file whose header says it is a checkpoint
 * of this job (this build of brume, scene_key, the job's settings): *removed says whether it
 * did. A file brume did not write is never removed. */
brume_status brume_render_job_remove_checkpoint(brume_context *ctx, const brume_render_job *job, uint64_t scene_key,
                                                const char *path, bool *removed);

/* ---- comparing images (docs/validation.md, "Comparing images"; `brume compare`) -------- */

/* How far an image is from a reference over the whole frame: the figures brume's docs report.
 * Only R, G, B are compared; both images must be the same size and hold finite values >= 0 in
 * R, G, B and alpha (BRUME_ERROR_RANGE naming the image, pixel and channel otherwise). Values
 * are the images' linear radiance; the relative figures have no unit. */
typedef struct brume_image_diff {
    double rmse;      /* sqrt(mean over pixels and channels of (image - ref)^2) */
    double rel_rmse;  /* rmse / mean(ref) */
    double mean_ref, mean_img;
    double mean_rel;  /* mean over pixels with ref luminance > floor of |image - ref| / ref (luminance) */
    double max_rel;   /* the largest such relative difference */
    double floor;     /* luminance floor: 1 % of the mean reference luminance */
    long pixels;
} brume_image_diff;
brume_status brume_image_compare(brume_context *ctx, const brume_image *image, const brume_image *ref,
                                 brume_image_diff *out);

/* The figures over a region R of pixels; means are over R's pixels and the channels R, G, B.
 *   ratio      = mean(image) / mean(ref)                 (1: unbiased on average)
 *   rel_rmse   = sqrt(mean (image - ref)^2) / mean(ref)  (bias and noise of both images)
 *   signed_rel = mean over R's pixels whose reference luminance exceeds `floor` of
 *                (lum image - lum ref) / lum ref         (< 0: darker than the reference)
 * floor is 1 % of the mean reference luminance over R. Each figure comes with a 95 % interval
 * [lo, hi] from a block bootstrap: R is cut into 8 x 8-pixel tiles, drawn with replacement
 * `boot` times from `seed` (the interval is a function of the images and the seed), and lo,
 * hi are the 2.5 and 97.5 percentiles of the figure over the draws. */
enum { BRUME_FIG_RATIO, BRUME_FIG_REL_RMSE, BRUME_FIG_SIGNED_REL, BRUME_NFIGS };
typedef struct brume_region_stats {
    long pixels;               /* pixels in R */
    long tiles;                /* 8 x 8 tiles holding at least one pixel of R */
    double mean_img, mean_ref; /* over R, channels R, G, B */
    double floor;              /* luminance floor of signed_rel */
    double fig[BRUME_NFIGS];   /* ratio, rel_rmse, signed_rel */
    double lo[BRUME_NFIGS], hi[BRUME_NFIGS]; /* the 95 % bootstrap interval of each; = fig when boot is 0 */
} brume_region_stats;
/* mask: width * height bytes, non-zero for pixels in R (rows top first), or NULL for the whole
 * frame. boot: bootstrap draws in [0, 100000]. An empty region, a reference whose mean over R
 * is 0 or a size mismatch is BRUME_ERROR_INVALID_ARGUMENT. */
brume_status brume_image_compare_region(brume_context *ctx, const brume_image *image, const brume_image *ref,
                                        const unsigned char *mask, int boot, uint64_t seed, brume_region_stats *out);
/* A mask (width * height bytes, the caller frees it with free()) of the pixels where ref's alpha
 * exceeds threshold; *count: the pixels in it. */
brume_status brume_image_mask_alpha(brume_context *ctx, const brume_image *ref, double threshold,
                                    unsigned char **mask, long *count);
/* A mask from a picture: the pixels whose luminance exceeds 0.5 (white in a black-and-white
 * PNG); its size must be width x height. */
brume_status brume_image_mask_picture(brume_context *ctx, const brume_image *picture, int width, int height,
                                      unsigned char **mask, long *count);
/* The signed colour map of difference pictures, sRGB in [0, 1]: relative difference r against
 * scale s > 0. White at 0, through light to dark blue at r <= -s (darker than the reference),
 * through light to dark red at r >= s (brighter). */
void brume_diff_color(double r, double s, float rgb[3]);
/* A picture of the signed relative difference of luminance (against max(lum ref, floor of
 * brume_image_compare)) in brume_diff_color's map, as linear colours; *out is new. */
brume_status brume_image_diff_picture(brume_context *ctx, const brume_image *image, const brume_image *ref,
                                      double scale, brume_image **out);
/* The same picture written as a PNG at path with a scale bar under it (-scale to scale in
 * percent) and, when mask is not NULL, the pixels outside the region dimmed to grey; written as
 * a BRUME_FILE_IMAGE (brume_output_check). */
brume_status brume_image_diff_png(brume_context *ctx, const brume_image *image, const brume_image *ref,
                                  const unsigned char *mask, double scale, const char *path);

/* A contact sheet written as a PNG at path (a BRUME_FILE_IMAGE): cells[r * ncols + c] drawn at
 * column c, row r (ncols, nrows in [1, 256]), tone mapped as a PNG of it would be (opts may be
 * NULL); a NULL cell is left blank. Each column is as wide as its widest cell, each row as
 * tall as its tallest, at most 16384 pixels a side. col_labels[ncols] above the columns,
 * row_labels[nrows] left of the rows, captions[ncols * nrows] under the cells (each array,
 * and each entry, may be NULL), title (may be NULL) on top. */
brume_status brume_image_sheet_png(brume_context *ctx, const char *path, const char *title, int ncols, int nrows,
                                   const brume_image *const *cells, const char *const *col_labels,
                                   const char *const *row_labels, const char *const *captions,
                                   const brume_write_options *opts);

#ifdef __cplusplus
}
#endif

#endif
