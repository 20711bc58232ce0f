/* image.h - brume_image: the image type of the library, its layers (AOVs) and attributes.
 * Pixels are RGBA float32, linear Rec. 709, rows top first, 4 floats per pixel. */
#ifndef BRUME_IMAGE_IMAGE_H
#define BRUME_IMAGE_IMAGE_H

#include <stdint.h>
#include <string.h>

#include "brume.h"

#define IMAGE_MAX_LAYERS 8
#define IMAGE_MAX_META 8

/* An extra layer (AOV): `channels` floats per pixel, channel names for EXR ("R", "G", "B";
 * "X", "Y", "Z"; or one name). */
typedef struct image_layer {
    char name[32];
    int channels;      /* 1 or 3 */
    char chan[3][8];   /* EXR channel suffixes */
    float *px;         /* width * height * channels, owned */
} image_layer;

/* A string attribute written into EXR headers ("brume.spp_mean" = "24.5"). */
typedef struct image_meta {
    char key[48];
    char value[80];
} image_meta;

struct brume_image {
    int width, height; /* pixels, >= 1 */
    float *rgba;       /* width * height * 4, owned */
    int nlayers;
    image_layer layers[IMAGE_MAX_LAYERS];
    int nmeta;
    image_meta meta[IMAGE_MAX_META];
};

/* Adds a zeroed layer with channel suffixes chan[0..channels-1]; returns its pixels, or NULL
 * (out of memory, too many layers). */
float *image_add_layer(brume_image *img, const char *name, int channels, const char *const *chan);
/* Sets (or replaces) a string attribute; silently ignored past IMAGE_MAX_META. */
void image_set_meta(brume_image *img, const char *key, const char *value);

/* Largest image a reader accepts: 65536 per side and 2^28 pixels (4 GiB of RGBA float). */
#define IMAGE_MAX_SIDE 65536
#define IMAGE_MAX_PIXELS ((int64_t)1 << 28)

/* A black, transparent image (brume_image_new without a context); NULL on a side outside
 * [1, IMAGE_MAX_SIDE] or out of memory. */
brume_image *image_new(int width, int height);

/* For readers: checks a size taken from the file at path (1..IMAGE_MAX_SIDE per side, at
 * most IMAGE_MAX_PIXELS) and allocates the image, A = 1, RGB = 0. On failure *out is NULL
 * and err_set() names path and the reason (BRUME_ERROR_PARSE for a bad size). */
brume_status image_create(const char *path, int64_t width, int64_t height, brume_image **out);

/* Before an image's values are used as light (compare, denoise): every R, G, B and alpha and
 * every layer's value finite and >= 0, but the "normal" layer's, which is a signed unit vector
 * (finite only). Otherwise BRUME_ERROR_RANGE (err_set) naming `what`, the layer, the pixel and
 * the channel. The layers are looked at only when `layers`. */
brume_status image_check_values(const brume_image *img, const char *what, bool layers);
/* The same with R, G, B allowed below 0 when rgb_signed (finite still): the denoiser's input,
 * which the filter treats linearly (a synthetic noisy image goes below 0). */
brume_status image_check_values_signed(const brume_image *img, const char *what, bool layers, bool rgb_signed);

/* The sRGB transfer functions of IEC 61966-2-1: linear in [0, 1] to encoded and back. */
double image_srgb_encode(double linear);
double image_srgb_decode(double encoded);

/* Linear value to 8-bit sRGB after exposure and tone curve (shared by PNG and plots). */
unsigned char image_encode_srgb8(double linear, const brume_write_options *opts);

/* image_encode_srgb8 of float pixels under one opts, by table: the same byte for every float
 * at a binary search over 255 bounds instead of an exp2 and a pow per value (a 400 x 400
 * PNG: 480,000 values). first[k] is the bit pattern of the smallest positive float whose code
 * is at least k (UINT32_MAX: none); the code rises with the value (exposure, tone curve and
 * transfer function all do), 0 for NaN, zero and negative values. */
typedef struct image_srgb8_table {
    uint32_t first[256];
} image_srgb8_table;

void image_srgb8_table_init(image_srgb8_table *t, const brume_write_options *opts);

/* The code of one value; near is a guess (the neighbouring pixel's code), tried first. */
static inline unsigned char image_srgb8_lookup(const image_srgb8_table *t, float linear, unsigned char near)
{
    if (!(linear > 0.0f)) /* NaN, zero, negative */
        return 0;
    uint32_t b;
    memcpy(&b, &linear, sizeof b);
    if (t->first[near] <= b && (near == 255 || b < t->first[near + 1]))
        return near;
    unsigned k = 0; /* the largest k with first[k] <= b */
    for (unsigned step = 128; step > 0; step /= 2)
        k += t->first[k + step] <= b ? step : 0;
    return (unsigned char)k;
}

#endif
