/* image_formats.h - brume_image's file formats, one file each: OpenEXR (image_exr.c, C core API),
 * PNG (image_png.c, libpng), PFM (image_pfm.c); image_file.c chooses among them. */
#ifndef BRUME_IO_IMAGE_FORMATS_H
#define BRUME_IO_IMAGE_FORMATS_H

#include "image/image.h"

/* Each writer is atomic (io/atomic.h) and sets err_set() naming the path on failure. */
brume_status image_write_exr(const char *path, const brume_image *img);
brume_status image_write_png(const char *path, const brume_image *img, const brume_write_options *opts);
brume_status image_write_pfm(const char *path, const brume_image *img);
/* PNG bytes in memory (malloc'd, *size bytes), as image_write_png would write them. */
brume_status image_encode_png(const brume_image *img, const brume_write_options *opts, unsigned char **data,
                              size_t *size);
brume_status image_read_exr(const char *path, brume_image **out);
/* The channel index (0..3 for R, G, B, A; -1 for another channel) of each of the first
 * `cap` channels of part 0 in the file's order, OpenEXR's (sorted by name: A, B, G, R);
 * *count is how many the file has. pbrt-v4 reads a sky's channels in this order. */
brume_status image_exr_channel_order(const char *path, int *index, int cap, int *count);
brume_status image_read_png(const char *path, brume_image **out);
brume_status image_read_pfm(const char *path, brume_image **out);

#endif
