/* tool.h - what the brume tool (cli/) uses from the library beyond include/brume.h.
 *
 * The one internal header cli/ includes (docs/architecture.md, checked by
 * tests/arch_includes.py): the services the command-line tool needs that are not public API,
 * each declared here with brume.h's types or its own, so that cli/ sees no internal struct.
 * Not a stable interface: a service a library user would also want belongs in brume.h.
 * Implemented in src/tool/ (the top layer: it may call any other). */
#ifndef BRUME_TOOL_TOOL_H
#define BRUME_TOOL_TOOL_H

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "brume.h"

/* ---- Messages (tool.c) ---------------------------------------------------------------- */

/* printf-style formatting into out[n] as the library formats its messages: control
 * characters in string arguments escaped, a plain %s cut after 200 bytes, a "%.1000s" cut
 * at its precision (core/error.h's err_vformat). One line. */
void tool_vformat(char *out, size_t n, const char *fmt, va_list ap);
/* The message of the calling thread's last failure in a call declared here ("" when none;
 * brume_* calls report to their context instead), and clearing it. */
const char *tool_last_error(void);
void tool_clear_error(void);

/* ---- Outputs and checkpoints (tool.c) ------------------------------------------------- */

/* Before any work: whether brume may write path (named by `what`: "-o", "--checkpoint",
 * "--video"...): absent or a regular file, not scene_file (may be NULL) nor, when scene is not
 * NULL, one of the files the scene was read from. Else a one-line error (tool_last_error). */
brume_status tool_output_check(const char *what, const char *path, const char *scene_file, const brume_scene *scene);
/* Before any work: a checkpoint path is absent or holds a brume checkpoint (its magic), so
 * that the saves every few seconds never replace a file brume did not write. */
brume_status tool_checkpoint_target_check(const char *path);
/* h with the contents of every file scene was read from folded in (FNV-1a): a checkpoint
 * key that changes when any of them does. */
uint64_t tool_checkpoint_inputs_key(const brume_scene *scene, uint64_t h);
/* Removes path when, and only when, it is a regular file whose header says it is a
 * checkpoint of this job (this build, scene_key, the job's settings); true when removed. */
bool tool_checkpoint_remove_own(const brume_render_job *job, uint64_t scene_key, const char *path);

/* ---- Files written whole or not at all (tool.c over io/atomic.h) --------------------- */

/* A temporary file beside path, open for writing: tool_file_commit renames it over path
 * (flushed and closed first), tool_file_abort removes it; each frees f, and a signal that
 * ends brume removes it too. NULL on failure (tool_last_error names path). */
typedef struct tool_file tool_file;
tool_file *tool_file_open(const char *path);
FILE *tool_file_stream(tool_file *f);
/* For a writer that opens the temporary file by name (OpenVDB): closes the stream, returns
 * the name. */
const char *tool_file_by_name(tool_file *f);
brume_status tool_file_commit(tool_file *f);
void tool_file_abort(tool_file *f);
/* Removes the temporary file of every write in progress in this process, the library's
 * (any context's) and the tool's own: for brume's fatal-signal handler, which then calls
 * _exit. Async-signal-safe. */
void tool_remove_temporaries(void);

/* ---- Frame sequences of grid files (tool.c over io/grid_sequence.h) ------------------ */

/* A file name with a frame pattern (smoke_%04d.vdb, smoke_####.vdb, smoke_$F4.vdb) names
 * one file per frame (docs/grids.md, "Sequences"). 1 when the name (after the last '/')
 * holds one pattern, 0 when none, -1 (tool_last_error) when it holds a malformed one or
 * more than one. */
int tool_seq_is_pattern(const char *name);
/* The name with n in place of the pattern (zero-padded to its width). */
void tool_seq_name(const char *pattern, long n, char *out, size_t cap);
/* The smallest and largest number of the files present; a gap, or no file, is an error
 * naming the first missing number and its file. */
brume_status tool_seq_range(const char *pattern, long *first, long *last);

/* ---- Comparing images (compare.c) ----------------------------------------------------- */

/* How far an image is from a reference: the figures every comparison in brume's docs
 * reports (a method against the path tracer, brume against another renderer), over the
 * whole frame or over a region (the cloud: the reference's alpha above a threshold), with a
 * confidence interval. Only R, G, B are compared. Errors: tool_last_error. */
typedef struct image_diff_stats {
    double rmse;          /* sqrt(mean over pixels and channels of (a - ref)^2) */
    double rel_rmse;      /* rmse / mean(ref) */
    double mean_ref, mean_img;
    double mean_rel;      /* mean over pixels with ref luminance > floor of |a - ref| / ref (luminance) */
    double max_rel;       /* the largest such relative difference */
    double floor;         /* luminance floor: 1 % of the mean reference luminance */
    long pixels;
} image_diff_stats;

/* Same size required (BRUME_ERROR_INVALID_ARGUMENT otherwise, the message names both sizes). */
brume_status image_compare(const brume_image *img, const brume_image *ref, image_diff_stats *out);

/* The figures a referee asks for, over a region R of pixels (docs/validation.md, "Comparing
 * images"). Means are over R's pixels and the channels R, G, B.
 *   ratio      = mean(img) / mean(ref)                  (1: unbiased on average)
 *   rel_rmse   = sqrt(mean (img - ref)^2) / mean(ref)   (bias and noise of both images)
 *   signed_rel = mean over R's pixels whose reference luminance exceeds `floor` of
 *                (lum img - lum ref) / lum ref          (< 0: darker than the reference)
 * floor is 1 % of the mean reference luminance over R. Each figure comes with a 95 %
 * interval [lo, hi] from a block bootstrap: R is cut into 8 x 8-pixel tiles, the tiles are
 * drawn with replacement `boot` times (seed fixed, so the interval is a function of the
 * images), and lo, hi are the 2.5 and 97.5 percentiles of the figure over the draws. Tiles,
 * not pixels, because the methods' errors are correlated over neighbouring pixels (Blasi's
 * light pass, Stam's Q). The interval says how much the figure depends on which parts of the
 * region were rendered; the noise of the renders themselves shows over seeds (`brume compare
 * --seeds`). */
enum { IMAGE_FIG_RATIO, IMAGE_FIG_REL_RMSE, IMAGE_FIG_SIGNED_REL, IMAGE_NFIGS };
typedef struct image_region_stats {
    long pixels;               /* pixels in R */
    long tiles;                /* 8 x 8 tiles holding at least one pixel of R */
    double mean_img, mean_ref; /* over R, channels R, G, B */
    double floor;              /* luminance floor of signed_rel */
    double fig[IMAGE_NFIGS];   /* ratio, rel_rmse, signed_rel */
    double lo[IMAGE_NFIGS], hi[IMAGE_NFIGS]; /* the 95 % bootstrap interval of each; = fig when boot is 0 */
} image_region_stats;
#define IMAGE_TILE 8

/* mask: width * height bytes, non-zero for pixels in R (rows top first), or NULL for the
 * whole frame. boot: bootstrap draws, 0 for none, at most 100000. An empty region or a
 * reference whose mean over R is 0 is BRUME_ERROR_INVALID_ARGUMENT (the message says which);
 * so is a size mismatch. */
brume_status image_compare_region(const brume_image *img, const brume_image *ref, const unsigned char *mask, int boot,
                                  uint64_t seed, image_region_stats *out);

/* A mask (malloc'd, width * height bytes, the caller frees it) of the pixels where ref's
 * alpha (1 - the media's transmittance along the pixel, docs/scene-format.md) exceeds
 * threshold. *count: the pixels in it. */
brume_status image_mask_alpha(const brume_image *ref, double threshold, unsigned char **mask, long *count);
/* A mask from a picture: the pixels whose luminance exceeds 0.5 (white in a black-and-white
 * PNG); its size must be width x height (else BRUME_ERROR_INVALID_ARGUMENT naming both). */
brume_status image_mask_picture(const brume_image *pic, int width, int height, unsigned char **mask, long *count);

/* The signed colour map of difference pictures: relative difference r against scale s.
 * White at 0, through light to dark blue at r <= -s (darker than the reference), through
 * light to dark red at r >= s (brighter). */
void image_diff_color(double r, double s, float rgb[3]);
/* A false-colour picture of the signed relative difference (luminance, against max(lum ref,
 * the 1 % floor of image_compare)) in image_diff_color's map; *out is new. */
brume_status image_diff_picture(const brume_image *img, const brume_image *ref, double scale, brume_image **out);
/* The same picture written as a PNG with a scale bar under it (the colours at -scale,
 * -scale/2, 0, scale/2, scale labelled in percent, "darker" left, "brighter" right), and,
 * when mask is not NULL, the pixels outside the region dimmed to grey. Written atomically;
 * errors name path. */
brume_status image_diff_png(const brume_image *img, const brume_image *ref, const unsigned char *mask, double scale,
                            const char *path);

/* ---- Contact sheets (sheet.c) --------------------------------------------------------- */

/* cells[r * ncols + c] is drawn at column c, row r, tone mapped as a PNG of it would be
 * (opts: exposure and curve; NULL = exposure 0, clamp); a NULL cell is left blank. Cells may
 * differ in size: each column is as wide as its widest cell, each row as tall as its tallest.
 * col_labels[ncols] go above the columns, row_labels[nrows] left of the rows (either array
 * NULL: none), captions (NULL, or one per cell, NULL entries allowed) under each cell; title
 * (may be NULL) on top. Written atomically; errors name path. */
brume_status sheet_png(const char *path, const char *title, int ncols, int nrows, const brume_image *const *cells,
                       const char *const *col_labels, const char *const *row_labels, const char *const *captions,
                       const brume_write_options *opts);

/* ---- Phase functions: making them, fitting Blasi's mixture, plotting (tool.c, phase_fit.c,
 * phase_plot.c) ---------------------------------------------------------------------------- */

typedef struct phase phase; /* a phase function (phase/phase.h), opaque to the tool */
/* Each NULL on failure (tool_last_error). By name: "isotropic", "rayleigh", "hazy",
 * "murky", "hg:G", "schlick:K", or else the path of a tabulated file. */
phase *tool_phase_named(const char *name);
phase *tool_phase_hg(double g);
phase *tool_phase_schlick(double k);
phase *tool_phase_schlick_mix(double r, double k, double kprime); /* Blasi Eq. 22 */
void tool_phase_release(phase *p); /* accepts NULL */
/* Schlick's k for Henyey-Greenstein's g: k = 1.55 g - 0.55 g^3, clamped to |k| < 1. */
double tool_schlick_k_from_g(double g);

/* Fitting Blasi's two-lobe Schlick mixture (Eq. 22) to any phase function.
 *
 * The model is phi(t) = r phi_k(t) + (1 - r) phi_k'(t) with Schlick lobes (Eq. 21),
 * r in [0, 1], |k|, |k'| < 1. The result is reported with k <= k', so that, as in the
 * paper's Figure 7, k is the backward (or less forward) lobe and r its weight.
 *
 * The error norms (docs/phase-functions.md) compare phi = 4 pi p of the model and of the
 * target; each is relative, so 0.01 means a 1 % root-mean-square difference. */
typedef enum phase_fit_norm {
    /* sqrt( int (phi_fit - phi)^2 dt / int phi^2 dt ), t = cos in [-1, 1]: the L2 norm
     * over the sphere (uniform in solid angle). */
    PHASE_FIT_NORM_COS,
    /* The same with d(theta) in [0, pi] in place of dt: the L2 norm of the cartesian plot
     * of phi against the angle, weighting back and side scattering more than the sphere.
     * The default: of the three norms, the paper's Figure 7 parameters come closest to
     * its minimum (docs/phase-functions.md). */
    PHASE_FIT_NORM_ANGLE,
    /* sqrt( int (ln phi_fit - ln phi)^2 dt / 2 ): root-mean-square relative (log) error
     * over the sphere; needs a target without zeros. */
    PHASE_FIT_NORM_LOG
} phase_fit_norm;

typedef struct phase_fit_result {
    double r, k, kprime; /* Blasi Eq. 22, k <= kprime */
    double error;        /* the norm at (r, k, kprime) */
} phase_fit_result;

/* "cos", "angle", "log" to a norm; returns false for any other name. */
bool phase_fit_norm_from_name(const char *name, phase_fit_norm *out);
const char *phase_fit_norm_name(phase_fit_norm norm);

/* The error of the mixture (r, k, kprime) against target in the given norm, computed by
 * composite Gauss-Legendre quadrature over the angle (fine near both poles, where the
 * peaks are). Returns NAN for parameters outside the domain of Eq. 22. */
double phase_fit_error(const phase *target, phase_fit_norm norm, double r, double k, double kprime);

/* Minimizes phase_fit_error over (r, k, kprime): a coarse grid search over the whole
 * domain, then Nelder-Mead from the best grid points in unconstrained coordinates
 * (r = sin^2 a, k = K sin b). Deterministic. Fails (tool_last_error) only when out of memory or
 * when the log norm meets a target that is 0 somewhere. */
brume_status phase_fit_schlick_mix(const phase *target, phase_fit_norm norm, phase_fit_result *out);

/* Polar and cartesian plots of phase functions (cairo), as Blasi's
 * Figures 2 to 6: one row per function, the polar plot of phi(theta) on the left (light
 * arrives from the left, forward scattering points right), phi against the angle in
 * degrees on the right; the true function solid, an optional approximation dashed. */
typedef struct phase_plot_row {
    const char *title; /* printed above the row, borrowed */
    const phase *truth; /* drawn solid, borrowed */
    const phase *approx; /* drawn dashed, or NULL; borrowed */
    /* An overlay instead (Blasi's Figures 5 and 6): ncurves > 0 functions on the same axes,
     * each in its own colour (solid; dashed where dashed[i]), named in a legend. */
    int ncurves;
    const phase *const *curves;  /* borrowed */
    const char *const *labels;   /* borrowed, NULL entries: no legend line */
    const bool *dashed;          /* may be NULL */
} phase_plot_row;

/* Writes an 8-bit RGB PNG of n >= 1 rows to path, atomically (a temporary file beside it,
 * renamed when complete). The polar panel is always linear, phi / max phi; log_scale plots
 * log10(phi) on the cartesian panel (the polar plot's log companion). Errors name path. */
brume_status phase_plot_png(const char *path, int n, const phase_plot_row *rows, bool log_scale);

/* ---- The papers' figures (stam_figures.c) --------------------------------------------- */


/* Figure 1: one random blob along a line through its centre, mean, mean +- sigma and one
 * realization, without clamping and with eta (Section 4). Errors name path. */
brume_status stam_figure1_png(const char *path, bool quick);

/* Figure 4: Var T_i against d_i for several eta, blob_T_var (lines) against the sample
 * variance over explicit realizations (points; 120 when quick, else 1200). *max_z (may be
 * NULL) receives the largest |sample - closed form| in standard errors of the sample
 * variance. Errors name path. */
brume_status stam_figure4_png(const char *path, bool quick, double *max_z);

/* ---- A plane-parallel slab (tool.c over render/slab.c; `brume slab`) ------------------ */

/* Total diffuse reflectance and transmittance of a homogeneous slab (render/slab.h: optical
 * thickness tau with sigma_t = 1, tau = 0 semi-infinite; lit by a collimated beam at normal
 * incidence), estimated by the renderer's own walk; deterministic for a seed and a sample
 * count, whatever the thread count. */
typedef struct tool_slab_params {
    double albedo;    /* in [0, 1] */
    double tau;       /* optical thickness, > 0; 0 = semi-infinite */
    const phase *ph;  /* borrowed */
    uint64_t samples; /* photons, >= 1 */
    uint64_t seed;
    int threads;      /* 0 = one per core */
    int max_depth;    /* scattering events counted, >= 1 (1 = single scattering) */
} tool_slab_params;
typedef struct tool_slab_result {
    double Rd, Rd_stderr; /* total diffuse reflectance and its standard error */
    double Tt, Tt_stderr; /* total transmittance (with the unscattered part exp(-tau)) */
} tool_slab_result;
brume_status tool_slab_run(const tool_slab_params *p, tool_slab_result *out);

/* ---- Grid files: `brume info`, `convert`, `gen` (grids.c, gen_sparse.c) ---------------- */

/* The options of reading a grid file are brume.h's brume_grid_file_options, taken as given
 * (the command line checked them): format from tool_grid_format_parse, max_memory_mb any
 * size > 0 (the command line's --max-memory counts bytes). */
typedef struct density density; /* a density field (density/density.h), opaque to the tool */
/* Whether name is a grid format: "raw", "df3", "vol", "nvdb", "vdb". */
bool tool_grid_format_known(const char *name);
/* The format a name says; BRUME_GRID_FORMAT_AUTO for NULL, "" or a name not known. */
brume_grid_format tool_grid_format_parse(const char *name);
/* The name of path's format: `format` when not AUTO, else by extension, else (when head has
 * n > 0 bytes) by its magic number; NULL when none of them says. */
const char *tool_grid_format_of(const char *path, brume_grid_format format, const unsigned char *head, size_t n);
/* Whether this build reads and writes .vdb and writes .nvdb (OpenVDB). */
bool tool_grid_have_openvdb(void);
/* A grid file; NULL on failure (tool_last_error: "PATH: reason"). */
density *tool_grid_load(const char *path, const brume_grid_file_options *o);
void tool_grid_release(density *d); /* accepts NULL */
/* Writes d to path in format (NULL or "": by extension), atomically; errors name path. */
brume_status tool_grid_write(const density *d, const char *path, const char *format);
/* A .vdb straight to .nvdb, keeping the sparse trees: every grid, or only `grid` ("": all). */
brume_status tool_grid_convert_vdb_to_nvdb(const char *in, const char *out, const char *grid);
/* `brume info`: the grids of a .vdb/.nvdb file, one line each, on out; *count of them. */
brume_status tool_grid_print_list(FILE *out, const char *path, const brume_grid_file_options *o, int *count);
/* `brume info`: d's format (as named), dimensions, bounds, placement, values, memory, active
 * voxels and majorants, one line each, on out. */
void tool_grid_print_info(FILE *out, const char *path, const char *format, const density *d);
/* The world box (xmin, ymin, zmin, xmax, ymax, zmax) and the largest value over the files
 * first..last of a frame pattern, each loaded in turn (one in memory at a time). */
brume_status tool_grid_sequence_extent(const char *pattern, long first, long last, const brume_grid_file_options *o,
                                       double bounds[6], double *rho_max);
/* `brume gen cloud`: the fractal cloud (brume.h's brume_fractal, its bounds and filter
 * used as given); NULL on failure (tool_last_error). */
density *tool_gen_cloud(const brume_fractal *f);

/* `brume gen fire` and `gen upres` (gen_sparse.c): sparse grids written through OpenVDB to
 * out (.vdb or .nvdb, atomically). What was written: */
typedef struct tool_gen_result {
    unsigned long long active; /* active voxels of the density grid */
    long box[3];               /* index box, voxels per axis */
    double voxel;              /* voxel size, world units */
} tool_gen_result;
/* A procedural flame: grids "density" and "temperature" (kelvin), n voxels up its height
 * (world units), n/2 across; with velocity > 0 also a vec3 grid "vel", its updraft
 * (velocity (0.5 + h) up at height fraction h, world units per second). At time t (seconds)
 * its turbulence has risen by t times the updraft's speed at mid-height (velocity, or 1 world
 * unit per second without one): frames at f / fps flicker and rise. */
brume_status tool_gen_fire(const char *out, int n, uint64_t seed, double height, double velocity, double time,
                           tool_gen_result *res);
/* How far tool_gen_fire's turbulence has risen at time t, in flame heights; it refuses
 * |rise| > 1e6 (the noise's lattice index is an int). */
double tool_gen_fire_rise(double height, double velocity, double time);
/* in's density grid upsampled factor times per axis (trilinear) with fractal detail of
 * amplitude detail in [0, 1], kept sparse. */
brume_status tool_gen_upres(const char *in, const brume_grid_file_options *o, int factor, uint64_t seed, double detail,
                            const char *out, tool_gen_result *res);

#endif
