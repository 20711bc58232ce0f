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

/* Linear value to 8-bit sRGB after exposure and tone curve (shared by PNG and plots). */
unsigned char image_encode_srgb8(double linear, const brume_write_options *opts);

#endif
