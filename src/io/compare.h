/* compare.h - how far an image is from a reference: the figures every comparison in
 * brume's docs reports (a method against the path tracer, brume against another renderer).
 * Only R, G, B are compared. */
#ifndef BRUME_IO_COMPARE_H
#define BRUME_IO_COMPARE_H

#include "brume.h"

typedef struct image_diff_stats {
    double rmse;          /* sqrt(mean over pixels and channels of (a - ref)^2) */
    double rel_rmse;      /* rmse / mean(ref) */
    double mean_ref, mean_img;
    double mean_rel;      /* mean over pixels with ref luminance > floor of |a - ref| / ref (luminance) */
    double max_rel;       /* the largest such relative difference */
    double floor;         /* luminance floor: 1 % of the mean reference luminance */
    long pixels;
} image_diff_stats;

/* Same size required (BRUME_ERROR_INVALID_ARGUMENT otherwise, err_set names both sizes). */
brume_status image_compare(const brume_image *img, const brume_image *ref, image_diff_stats *out);
/* A false-colour picture of the signed relative difference (luminance): blue where img is
 * darker than ref, red where brighter, white at +-scale or beyond; *out is new. */
brume_status image_diff_picture(const brume_image *img, const brume_image *ref, double scale, brume_image **out);

#endif
