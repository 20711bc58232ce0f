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

#include "brume.h"

/* ---- Messages (tool.c) ---------------------------------------------------------------- */

/* printf-style formatting into out[n] as the library formats its messages: control
 * characters in string arguments escaped, a plain %s cut after 200 bytes, a "%.1000s" cut
 * at its precision (core/error.h's err_vformat). One line. */
void tool_vformat(char *out, size_t n, const char *fmt, va_list ap);
/* The message of the calling thread's last failure in a tool_* call ("" when none), and
 * clearing it. */
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

#endif
