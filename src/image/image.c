/* image.c - brume_image (RGBA float32, rows top first): the object, its layers and
 * attributes, and the linear -> 8-bit sRGB encoding shared by the PNG writer and plots.
 * The files it is read from and written to are io/image_file.c's. */
#include "image/image.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/bigmem.h"
#include "core/budget.h"
#include "core/context.h"
#include "core/error.h"

/* ---- the image object ------------------------------------------------------------------- */

brume_image *image_new(int width, int height)
{
    if (width < 1 || width > IMAGE_MAX_SIDE || height < 1 || height > IMAGE_MAX_SIDE)
        return NULL;
    /* Both sides are at most 2^16, so the count is at most 2^34 floats: check against
     * SIZE_MAX anyway so that a 32-bit size_t cannot wrap. */
    size_t n = (size_t)width * (size_t)height;
    if (n > SIZE_MAX / (4 * sizeof(float)))
        return NULL;
    brume_image *img = calloc(1, sizeof *img);
    if (!img)
        return NULL;
    img->rgba = bigmem_calloc(n * 4, sizeof(float)); /* huge pages when large: core/bigmem.h */
    if (!img->rgba) {
        free(img);
        return NULL;
    }
    img->width = width;
    img->height = height;
    return img;
}

brume_status brume_image_new(brume_context *ctx, int width, int height, brume_image **out)
{
    err_clear();
    if (!out)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_image_new: out: NULL"));
    *out = NULL;
    if (width < 1 || width > IMAGE_MAX_SIDE || height < 1 || height > IMAGE_MAX_SIDE)
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "brume_image_new: size %d x %d: each side must be in [1, %d]",
                                       width, height, IMAGE_MAX_SIDE));
    if (!(*out = image_new(width, height)))
        return ctx_report(ctx, err_set(BRUME_ERROR_OUT_OF_MEMORY, "brume_image_new: out of memory for a %d x %d image",
                                       width, height));
    return ctx_report(ctx, BRUME_OK);
}

int brume_image_width(const brume_image *image) { return image ? image->width : 0; }
int brume_image_height(const brume_image *image) { return image ? image->height : 0; }
float *brume_image_pixels(const brume_image *image) { return image ? image->rgba : NULL; }

void brume_image_release(brume_image *image)
{
    if (!image)
        return;
    for (int i = 0; i < image->nlayers; i++)
        free(image->layers[i].px);
    free(image->rgba);
    free(image);
}

float *image_add_layer(brume_image *img, const char *name, int channels, const char *const *chan)
{
    if (img->nlayers >= IMAGE_MAX_LAYERS || channels < 1 || channels > 3)
        return NULL;
    image_layer *l = &img->layers[img->nlayers];
    memset(l, 0, sizeof *l);
    l->px = bigmem_calloc((size_t)img->width * (size_t)img->height * (size_t)channels, sizeof(float));
    if (!l->px)
        return NULL;
    snprintf(l->name, sizeof l->name, "%s", name);
    l->channels = channels;
    for (int c = 0; c < channels; c++)
        snprintf(l->chan[c], sizeof l->chan[c], "%s", chan[c]);
    img->nlayers++;
    return l->px;
}

void image_set_meta(brume_image *img, const char *key, const char *value)
{
    int i = 0;
    while (i < img->nmeta && strcmp(img->meta[i].key, key) != 0)
        i++;
    if (i == IMAGE_MAX_META)
        return;
    snprintf(img->meta[i].key, sizeof img->meta[i].key, "%s", key);
    snprintf(img->meta[i].value, sizeof img->meta[i].value, "%s", value);
    if (i == img->nmeta)
        img->nmeta++;
}

brume_status brume_image_set_attribute(brume_context *ctx, brume_image *image, const char *key, const char *value)
{
    err_clear();
    if (!image || !key || !value)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_image_set_attribute: %s: NULL",
                                       !image ? "image" : !key ? "key" : "value"));
    if (!*key) /* an EXR attribute needs a name */
        return ctx_report(ctx,
                          err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_image_set_attribute: key: empty (a name is needed)"));
    int i = 0;
    while (i < image->nmeta && strcmp(image->meta[i].key, key) != 0)
        i++;
    if (i == IMAGE_MAX_META)
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "brume_image_set_attribute: %s: more than %d attributes", key,
                                       IMAGE_MAX_META));
    image_set_meta(image, key, value);
    return ctx_report(ctx, BRUME_OK);
}

const char *brume_image_attribute(const brume_image *image, const char *key)
{
    if (!image || !key)
        return NULL;
    for (int i = 0; i < image->nmeta; i++)
        if (strcmp(image->meta[i].key, key) == 0)
            return image->meta[i].value;
    return NULL;
}

static const image_layer *layer_at(const brume_image *image, int i)
{
    return image && i >= 0 && i < image->nlayers ? &image->layers[i] : NULL;
}

int brume_image_layer_count(const brume_image *image) { return image ? image->nlayers : 0; }
const char *brume_image_layer_name(const brume_image *image, int i)
{
    const image_layer *l = layer_at(image, i);
    return l ? l->name : NULL;
}
int brume_image_layer_channels(const brume_image *image, int i)
{
    const image_layer *l = layer_at(image, i);
    return l ? l->channels : 0;
}
const float *brume_image_layer_pixels(const brume_image *image, int i)
{
    const image_layer *l = layer_at(image, i);
    return l ? l->px : NULL;
}

brume_status image_create(const char *path, int64_t width, int64_t height, brume_image **out)
{
    *out = NULL;
    if (width < 1 || width > IMAGE_MAX_SIDE || height < 1 || height > IMAGE_MAX_SIDE)
        return err_set(BRUME_ERROR_PARSE,
                       "%s: image size %lld x %lld: each side must be in [1, %d]", path,
                       (long long)width, (long long)height, IMAGE_MAX_SIDE);
    if (width * height > IMAGE_MAX_PIXELS)
        return err_set(BRUME_ERROR_PARSE, "%s: image size %lld x %lld: more than %lld pixels", path,
                       (long long)width, (long long)height, (long long)IMAGE_MAX_PIXELS);
    /* a read image counts against the scene's memory budget (an environment map) */
    brume_status st = budget_take((size_t)width * (size_t)height * 4 * sizeof(float), path);
    if (st != BRUME_OK)
        return st;
    brume_image *img = image_new((int)width, (int)height);
    if (!img)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for a %lld x %lld image", path,
                       (long long)width, (long long)height);
    size_t n = (size_t)img->width * (size_t)img->height;
    for (size_t i = 0; i < n; i++)
        img->rgba[4 * i + 3] = 1.0f;
    *out = img;
    return BRUME_OK;
}

/* ---- sRGB -------------------------------------------------------------------------------- */

/* IEC 61966-2-1:1999, section 5.2 (encoding) and 5.3 (decoding): a linear segment of slope
 * 12.92 below 0.0031308 (0.04045 encoded), a 2.4 power curve above. */
double image_srgb_encode(double linear)
{
    if (linear <= 0.0031308)
        return 12.92 * linear;
    return 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
}

double image_srgb_decode(double encoded)
{
    if (encoded <= 0.04045)
        return encoded / 12.92;
    return pow((encoded + 0.055) / 1.055, 2.4);
}

/* ACES filmic tone curve fitted by K. Narkowicz, "ACES Filmic Tone Mapping Curve" (2015,
 * knarkowicz.wordpress.com/2016/01/06): f(x) = x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14).
 * f(0) = 0, increasing for x >= 0, tends to 2.51 / 2.43 > 1 (clamped afterwards). */
static double aces_filmic(double x)
{
    if (x <= 0.0)
        return 0.0;
    if (x > 1e12) /* avoids inf / inf; f is 1.03 there, clamped to 1 */
        return 1.0;
    return (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14);
}

unsigned char image_encode_srgb8(double linear, const brume_write_options *opts)
{
    double exposure = opts ? opts->exposure : 0.0;
    brume_tonemap tonemap = opts ? opts->tonemap : BRUME_TONEMAP_CLAMP;
    double x = linear * exp2(exposure);
    if (isnan(x))
        return 0;
    if (tonemap == BRUME_TONEMAP_FILMIC)
        x = aces_filmic(x);
    if (x <= 0.0)
        return 0;
    if (x >= 1.0)
        return 255;
    return (unsigned char)floor(255.0 * image_srgb_encode(x) + 0.5);
}

static float float_of_bits(uint32_t b)
{
    float f;
    memcpy(&f, &b, sizeof f);
    return f;
}

/* Each bound by bisection over the bit patterns of the positive floats, 1 (the smallest
 * subnormal) to 0x7f800000 (+inf), which are ordered as the floats: 255 x 31 evaluations of
 * image_encode_srgb8, under a millisecond. The code is a rising step function of the float:
 * x = linear 2^exposure, the tone curve and the sRGB curve all rise, and between two floats
 * (2^29 doubles apart) the rising parts outweigh any rounding of exp2 or pow, so each code
 * is taken by one run of floats and bisection finds where it starts
 * (tests/test_image.c checks the table against image_encode_srgb8 float by float around
 * every bound). */
void image_srgb8_table_init(image_srgb8_table *t, const brume_write_options *opts)
{
    t->first[0] = 0;
    uint32_t lo = 1;
    for (int k = 1; k < 256; k++) {
        const uint32_t top = 0x7f800000u; /* +inf */
        if (image_encode_srgb8((double)float_of_bits(top), opts) < k) {
            for (; k < 256; k++)
                t->first[k] = UINT32_MAX; /* no float reaches code k (a tone curve below 1) */
            return;
        }
        uint32_t hi = top; /* code(hi) >= k; code(b) < k for every b < lo */
        while (lo < hi) {
            uint32_t mid = lo + (hi - lo) / 2;
            if (image_encode_srgb8((double)float_of_bits(mid), opts) >= k)
                hi = mid;
            else
                lo = mid + 1;
        }
        t->first[k] = lo;
    }
}


/* The first value of px[npix * ch] that is not finite, or negative when !is_signed: its index, or
 * -1 when none. */
static long bad_value(const float *px, size_t npix, int ch, int stride, bool is_signed)
{
    for (size_t i = 0; i < npix; i++)
        for (int c = 0; c < ch; c++) {
            float v = px[i * (size_t)stride + (size_t)c];
            if (!isfinite(v) || (!is_signed && v < 0.0f))
                return (long)(i * (size_t)stride + (size_t)c);
        }
    return -1;
}

static brume_status bad_report(const brume_image *img, const char *what, const char *layer, const float *px, long k,
                               int stride, const char *chan, bool is_signed)
{
    size_t i = (size_t)k / (size_t)stride;
    float v = px[k];
    return err_set(BRUME_ERROR_RANGE, "%s: %s%spixel (%zu, %zu) %s is %g: %s", what, layer ? "layer " : "",
                   layer ? layer : "", i % (size_t)img->width, i / (size_t)img->width, chan, (double)v,
                   is_signed ? "values must be finite" : "values must be finite and >= 0");
}

brume_status image_check_values(const brume_image *img, const char *what, bool layers)
{
    return image_check_values_signed(img, what, layers, false);
}

brume_status image_check_values_signed(const brume_image *img, const char *what, bool layers, bool rgb_signed)
{
    size_t npix = (size_t)img->width * (size_t)img->height;
    static const char *const rgba[4] = {"R", "G", "B", "A"};
    long k = bad_value(img->rgba, npix, 3, 4, rgb_signed);
    if (k >= 0)
        return bad_report(img, what, NULL, img->rgba, k, 4, rgba[k % 4], rgb_signed);
    k = bad_value(img->rgba + 3, npix, 1, 4, false); /* alpha */
    if (k >= 0)
        return bad_report(img, what, NULL, img->rgba + 3, k, 4, "A", false);
    for (int l = 0; layers && l < img->nlayers; l++) {
        const image_layer *L = &img->layers[l];
        bool is_signed = strcmp(L->name, "normal") == 0;
        k = bad_value(L->px, npix, L->channels, L->channels, is_signed);
        if (k >= 0) {
            char layer[48];
            snprintf(layer, sizeof layer, "%s, ", L->name);
            return bad_report(img, what, layer, L->px, k, L->channels, L->chan[k % L->channels], is_signed);
        }
    }
    return BRUME_OK;
}

brume_status brume_image_check_values(brume_context *ctx, const brume_image *image, const char *name, bool layers)
{
    err_clear();
    if (!image)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_image_check_values: image: NULL"));
    return ctx_report(ctx, image_check_values(image, name ? name : "image", layers));
}
