/* image.h - brume_image and its file formats: OpenEXR (C core API), PNG (libpng), PFM.
 * Pixels are RGBA float32, linear Rec. 709, rows top first, 4 floats per pixel. */
#ifndef BRUME_IO_IMAGE_H
#define BRUME_IO_IMAGE_H

#include "brume.h"

struct brume_image {
    int width, height; /* pixels, >= 1 */
    float *rgba;       /* width * height * 4, owned */
};

/* Each writer is atomic (io/atomic.h) and sets err_set() naming the path on failure. */
brume_status image_write_exr(const char *path, const brume_image *img);
brume_status image_write_png(const char *path, const brume_image *img, const brume_write_options *opts);
brume_status image_write_pfm(const char *path, const brume_image *img);
brume_status image_read_exr(const char *path, brume_image **out);
brume_status image_read_png(const char *path, brume_image **out);
brume_status image_read_pfm(const char *path, brume_image **out);

/* Largest image a reader accepts: 65536 per side and 2^28 pixels (4 GiB of RGBA float). */
#define IMAGE_MAX_SIDE 65536
#define IMAGE_MAX_PIXELS ((int64_t)1 << 28)

/* For readers: checks a size taken from the file at path (1..IMAGE_MAX_SIDE per side, at
 * most IMAGE_MAX_PIXELS) and allocates the image, A = 1, RGB = 0. On failure *out is NULL
 * and err_set() names path and the reason (BRUME_ERROR_PARSE for a bad size). */
brume_status image_create(const char *path, int64_t width, int64_t height, brume_image **out);

/* The sRGB transfer functions of IEC 61966-2-1: linear in [0, 1] to encoded and back. */
double image_srgb_encode(double linear);
double image_srgb_decode(double encoded);

/* Linear value to 8-bit sRGB after exposure and tone curve (shared by PNG and plots). */
unsigned char image_encode_srgb8(double linear, const brume_write_options *opts);

#endif
