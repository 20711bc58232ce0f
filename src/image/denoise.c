/* denoise.c - a feature-guided edge-avoiding a-trous filter of a rendered image (Dammertz
 * et al. 2010, "Edge-Avoiding A-Trous Wavelet Transform for fast Global Illumination
 * Filtering"), its colour weight normalised by the per-pixel variance the render measured
 * (Rousselle et al. 2012, "Adaptive Rendering with Non-Local Means Filtering", Eq. 3: the
 * squared difference of two pixels less its expected value under noise, over the sum of
 * their variances) and taken over 3 x 3 patches as in their non-local means, the variance
 * carried through the levels (Schied et al. 2017, SVGF).
 *
 * Inputs: the beauty (RGBA), the "variance" layer (the variance of each pixel's mean, what
 * `--aov variance` writes), and when present the "albedo", "normal" and "depth" layers as
 * edge-stopping features. Level i filters with the 5 x 5 B3-spline kernel dilated by 2^i:
 *
 *     c'_p = sum_q h(q - p) w(p, q) c_q / sum_q h(q - p) w(p, q)
 *     v'_p = sum_q (h w)^2 v_q / (sum_q h w)^2
 *     w    = w_colour w_albedo w_normal w_depth
 *     w_colour = exp(-max(0, mean_o mean_c ((c_p+o - c_q+o)^2 - (v_p+o + v_q+o))
 *                                          / (k^2 (v_p+o + v_q+o) + eps)))
 *                (o over the 3 x 3 patch's offsets, spaced 2^i as the level's taps)
 *     w_feature = exp(-|f_p - f_q|^2 / sigma_f^2)   (depth: relative to the larger depth)
 *
 * Every output pixel is a fixed sum over the level's input, in one order, written to a
 * separate buffer: the result is the same bits whatever the number of threads.
 * docs/denoise.md gives the measured error and bias. */
#include <math.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/budget.h"
#include "core/context.h"
#include "core/error.h"
#include "core/pool.h"
#include "image/image.h"

#define DENOISE_LEVELS 5 /* kernel footprint 1 + 4 (2^5 - 1) = 125 pixels */
#define DENOISE_K 2.0    /* colour weight: a mean difference of k standard deviations over the
                            patch costs e^-1 (the default scene at 17 spp, sigma_albedo 0.3: k = 2
                            left 1.63 % error per pixel, k = 3 1.69 %, k = 1.5 1.72 %;
                            docs/denoise.md) */
#define DENOISE_PATCH 1  /* the colour distance's patch: (2 r + 1)^2 pixels, r = 1 */
#define DENOISE_SIGMA_ALBEDO 0.6 /* loose: a medium's albedo layer is a noisy mean (hit or miss); 0.3
                                    left 1.63 % per pixel on the default scene at 17 spp, 0.6
                                    1.49 % (docs/denoise.md) */
#define DENOISE_SIGMA_NORMAL 0.3 /* |n_p - n_q|: 0.3 is about 17 degrees */
#define DENOISE_SIGMA_DEPTH 0.3  /* relative depth difference; loose, as a medium's first collision is random */
#define DENOISE_E_MAX 30.0       /* a neighbour of weight below e^-30 (1e-13 of the centre's) is skipped */

typedef struct denoise_job {
    int w, h, step;
    const double *c, *v;   /* level input: RGB colour, RGB variance, 3 per pixel */
    double *c_out, *v_out; /* level output */
    const float *albedo, *normal, *depth; /* features, or NULL */
    double k2, ia, in, iz; /* k^2 and 1 / sigma^2 of the features */
    const atomic_uint *cancels; /* the context's brume_context_cancel_loads count, or NULL */
    unsigned cancels_start;     /* its value when the denoiser began */
    atomic_bool stop;           /* a cancel was seen: the rows left are skipped */
} denoise_job;

static const double B3[5] = {1.0 / 16.0, 1.0 / 4.0, 3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0};

static double sq(double x) { return x * x; }

/* Whether brume_context_cancel_loads was called since the denoiser began; once seen, every
 * later call says so (rows are short: a cancel is seen within a row of work). */
static bool cancelled(denoise_job *j)
{
    if (atomic_load_explicit(&j->stop, memory_order_relaxed))
        return true;
    if (!j->cancels || atomic_load_explicit(j->cancels, memory_order_relaxed) == j->cancels_start)
        return false;
    atomic_store(&j->stop, true);
    return true;
}

/* The colour weight's exponent of the pair p = (x, y), q = (xq, yq): the per-pixel distance
 * of Rousselle et al. 2012, Eq. 3, averaged over the patch offsets o (spaced as the level's
 * taps) for which p + o and q + o are both in the image. With v_p + v_q (the expected squared
 * difference under noise) where they subtract v_p + min(v_p, v_q): the weight is then
 * symmetric, w(p, q) = w(q, p). Theirs is not, and a bright outlier with a large variance took
 * its neighbours in while they shut it out, so its energy was lost: -5.3 % of wdas-dense's
 * mean at 3 spp, -3.2 % so (docs/denoise.md, "Bias"). The patch's mean varies less under
 * noise than one pixel's distance, so the weight tells structure from noise at a smaller k. */
static double colour_exponent(const denoise_job *j, int x, int y, int xq, int yq)
{
    const int w = j->w, h = j->h, s = j->step;
    double d = 0.0, n = 0.0;
    for (int oy = -DENOISE_PATCH; oy <= DENOISE_PATCH; oy++) {
        const int ya = y + oy * s, yb = yq + oy * s;
        if (ya < 0 || ya >= h || yb < 0 || yb >= h)
            continue;
        for (int ox = -DENOISE_PATCH; ox <= DENOISE_PATCH; ox++) {
            const int xa = x + ox * s, xb = xq + ox * s;
            if (xa < 0 || xa >= w || xb < 0 || xb >= w)
                continue;
            const size_t a = 3 * ((size_t)ya * (size_t)w + (size_t)xa), b = 3 * ((size_t)yb * (size_t)w + (size_t)xb);
            for (size_t c = 0; c < 3; c++) {
                double vs = j->v[a + c] + j->v[b + c];
                d += (sq(j->c[a + c] - j->c[b + c]) - vs) / (1e-10 + j->k2 * vs);
            }
            n += 1.0;
        }
    }
    /* n >= 1: the offset 0 pairs p and q themselves. The channels' mean: the sum would count a
     * grey medium's one noise three times */
    return fmax(0.0, d / (3.0 * n));
}

/* One row of one level. */
static void denoise_row(size_t task, int thread, void *user)
{
    (void)thread;
    denoise_job *j = user;
    if (cancelled(j))
        return;
    const int y = (int)task, w = j->w, h = j->h, step = j->step;
    for (int x = 0; x < w; x++) {
        const size_t p = (size_t)y * (size_t)w + (size_t)x;
        double sw = 0.0, acc[3] = {0.0, 0.0, 0.0}, accv[3] = {0.0, 0.0, 0.0};
        for (int dy = -2; dy <= 2; dy++) {
            int yq = y + dy * step;
            if (yq < 0 || yq >= h)
                continue;
            for (int dx = -2; dx <= 2; dx++) {
                int xq = x + dx * step;
                if (xq < 0 || xq >= w)
                    continue;
                const size_t q = (size_t)yq * (size_t)w + (size_t)xq;
                double e = 0.0; /* the features first: they are cheaper than the patch */
                if (j->albedo) {
                    const float *a = j->albedo + 3 * p, *b = j->albedo + 3 * q;
                    e += (sq(a[0] - b[0]) + sq(a[1] - b[1]) + sq(a[2] - b[2])) * j->ia;
                }
                if (j->normal) {
                    const float *a = j->normal + 3 * p, *b = j->normal + 3 * q;
                    e += (sq(a[0] - b[0]) + sq(a[1] - b[1]) + sq(a[2] - b[2])) * j->in;
                }
                if (j->depth) {
                    double zp = j->depth[p], zq = j->depth[q];
                    e += sq(zp - zq) / sq(fmax(fmax(zp, zq), 1e-6)) * j->iz;
                }
                if (e > DENOISE_E_MAX)
                    continue;
                e += colour_exponent(j, x, y, xq, yq);
                if (e > DENOISE_E_MAX)
                    continue;
                double wq = B3[dx + 2] * B3[dy + 2] * exp(-e);
                const double *cq = j->c + 3 * q, *vq = j->v + 3 * q;
                sw += wq;
                for (size_t c = 0; c < 3; c++) {
                    acc[c] += wq * cq[c];
                    accv[c] += wq * wq * vq[c];
                }
            }
        }
        /* sw > 0: the centre's own weight is B3[2]^2 exp(-e) with e from the features only,
         * which are equal to themselves */
        for (size_t c = 0; c < 3; c++) {
            j->c_out[3 * p + c] = acc[c] / sw;
            j->v_out[3 * p + c] = accv[c] / (sw * sw);
        }
    }
}

static const float *layer_of(const brume_image *img, const char *name, int channels)
{
    for (int i = 0; i < img->nlayers; i++)
        if (strcmp(img->layers[i].name, name) == 0 && img->layers[i].channels == channels)
            return img->layers[i].px;
    return NULL;
}

/* A copy of in (pixels, layers, attributes); NULL when out of memory. */
static brume_image *image_copy(const brume_image *in)
{
    brume_image *img = image_new(in->width, in->height);
    if (!img)
        return NULL;
    size_t npix = (size_t)in->width * (size_t)in->height;
    memcpy(img->rgba, in->rgba, npix * 4 * sizeof(float));
    for (int i = 0; i < in->nlayers; i++) {
        const image_layer *l = &in->layers[i];
        const char *chan[3] = {l->chan[0], l->chan[1], l->chan[2]};
        float *px = image_add_layer(img, l->name, l->channels, chan);
        if (!px) {
            brume_image_release(img);
            return NULL;
        }
        memcpy(px, l->px, npix * (size_t)l->channels * sizeof(float));
    }
    for (int i = 0; i < in->nmeta; i++)
        image_set_meta(img, in->meta[i].key, in->meta[i].value);
    return img;
}

/* The per-pixel variance v0 (w x h, 3 channels) made fit to weigh the first level: where it
 * is missing, the spatial variance of the colour c0 around the pixel, then a 3 x 3 blur of
 * it all; v1 is scratch. Stops early (v0 then meaningless) when j is cancelled. */
static void steady_variance(denoise_job *j, int w, int h, const double *c0, double *v0, double *v1)
{
    const size_t npix = (size_t)w * (size_t)h;
    /* a pixel of fewer than 2 samples has no variance estimate (the layer holds 0): it takes
     * the spatial variance of its 3 x 3 neighbourhood, what SVGF does before the temporal
     * history has samples; a flat region (the sky) gives 0 there as it should */
    for (int y = 0; y < h && !cancelled(j); y++)
        for (int x = 0; x < w; x++)
            for (size_t c = 0; c < 3; c++) {
                const size_t p = (size_t)y * (size_t)w + (size_t)x;
                if (v0[3 * p + c] > 0.0)
                    continue;
                double s1 = 0.0, s2 = 0.0, n = 0.0;
                for (int dy = -1; dy <= 1; dy++)
                    for (int dx = -1; dx <= 1; dx++) {
                        int xq = x + dx, yq = y + dy;
                        if (xq < 0 || xq >= w || yq < 0 || yq >= h)
                            continue;
                        double cq = c0[3 * ((size_t)yq * (size_t)w + (size_t)xq) + c];
                        s1 += cq;
                        s2 += cq * cq;
                        n += 1.0;
                    }
                v1[3 * p + c] = n > 1.0 ? fmax(0.0, (s2 - s1 * s1 / n) / (n - 1.0)) : 0.0;
            }
    for (size_t p = 0; p < 3 * npix; p++) /* v1 holds the fallbacks only where v0 is 0 */
        if (!(v0[p] > 0.0))
            v0[p] = v1[p];
    /* the variance estimate of a few samples is itself noisy: a 3 x 3 binomial blur of it
     * steadies the first level's weights (Schied et al. 2017 do the same) */
    for (int y = 0; y < h && !cancelled(j); y++)
        for (int x = 0; x < w; x++)
            for (size_t c = 0; c < 3; c++) {
                double s = 0.0, sw = 0.0;
                for (int dy = -1; dy <= 1; dy++)
                    for (int dx = -1; dx <= 1; dx++) {
                        int xq = x + dx, yq = y + dy;
                        if (xq < 0 || xq >= w || yq < 0 || yq >= h)
                            continue;
                        double k = (dx ? 1.0 : 2.0) * (dy ? 1.0 : 2.0);
                        s += k * v0[3 * ((size_t)yq * (size_t)w + (size_t)xq) + c];
                        sw += k;
                    }
                v1[3 * ((size_t)y * (size_t)w + (size_t)x) + c] = s / sw;
            }
    memcpy(v0, v1, npix * 3 * sizeof *v0);
}

size_t brume_denoise_memory(int width, int height, int layer_channels)
{
    if (width <= 0 || height <= 0 || layer_channels < 0)
        return 0;
    /* the output: RGBA, the layers and the "raw" layer in float; the levels' colour and
     * variance, input and output, in double */
    double per_pixel = (4.0 + layer_channels + 3.0) * sizeof(float) + 12.0 * sizeof(double);
    double bytes = per_pixel * (double)width * (double)height;
    return bytes < (double)SIZE_MAX ? (size_t)bytes : SIZE_MAX;
}

/* The levels over j's buffers (c0, v0 into c1, v1 and back), then the result into img. */
static void denoise_levels(denoise_job *j, int threads, brume_image *img)
{
    for (int level = 0; level < DENOISE_LEVELS && !cancelled(j); level++) {
        j->step = 1 << level;
        pool_run(threads, (size_t)j->h, denoise_row, j);
        double *tc = (double *)j->c, *tv = (double *)j->v; /* the output is the next level's input */
        j->c = j->c_out;
        j->v = j->v_out;
        j->c_out = tc;
        j->v_out = tv;
    }
    const size_t npix = (size_t)j->w * (size_t)j->h;
    for (size_t p = 0; p < npix; p++)
        for (size_t c = 0; c < 3; c++)
            img->rgba[4 * p + c] = (float)j->c[3 * p + c];
}

/* What brume_denoise refuses before any work: NULL arguments, no variance layer, an image
 * denoised already, values outside its range, more memory than the limit. */
static brume_status denoise_check(const brume_image *in, brume_image **out)
{
    if (!in || !out)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_denoise: %s: NULL", !in ? "image" : "out");
    if (!layer_of(in, "variance", 3))
        return err_set(BRUME_ERROR_INVALID_ARGUMENT,
                       "brume_denoise: the image has no \"variance\" layer (render with --aov variance, "
                       "or --denoise, which asks for it)");
    if (layer_of(in, "raw", 3) || brume_image_attribute(in, "brume.denoised"))
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_denoise: the image is denoised already (it has a \"raw\" layer)");
    /* NaN, infinities, negative features: refused; R, G, B may be signed (the filter is linear) */
    brume_status st = image_check_values_signed(in, "brume_denoise: image", true, true);
    if (st != BRUME_OK)
        return st;
    int channels = 0;
    for (int i = 0; i < in->nlayers; i++)
        channels += in->layers[i].channels;
    char who[96];
    snprintf(who, sizeof who, "brume_denoise: a %d x %d image", in->width, in->height);
    return budget_take(brume_denoise_memory(in->width, in->height, channels), who);
}

brume_status brume_denoise(brume_context *ctx, const brume_image *in, int threads, brume_image **out)
{
    err_clear();
    if (out)
        *out = NULL;
    if (denoise_check(in, out) != BRUME_OK)
        return ctx_report(ctx, err_status());
    denoise_job j = {in->width, in->height, 1, NULL, NULL, NULL, NULL, layer_of(in, "albedo", 3),
                     layer_of(in, "normal", 3), layer_of(in, "depth", 1), DENOISE_K * DENOISE_K,
                     1.0 / sq(DENOISE_SIGMA_ALBEDO), 1.0 / sq(DENOISE_SIGMA_NORMAL), 1.0 / sq(DENOISE_SIGMA_DEPTH),
                     ctx ? &ctx->load_cancels : NULL, ctx ? atomic_load(&ctx->load_cancels) : 0u, false};
    const int w = in->width, h = in->height;
    const size_t npix = (size_t)w * (size_t)h;
    const float *var = layer_of(in, "variance", 3);
    brume_image *img = image_copy(in);
    double *buf = malloc(npix * 12 * sizeof *buf);
    static const char *const rgb[3] = {"R", "G", "B"};
    float *raw = img ? image_add_layer(img, "raw", 3, rgb) : NULL;
    if (!img || !buf || !raw) {
        brume_image_release(img);
        free(buf);
        return ctx_report(ctx, err_set(BRUME_ERROR_OUT_OF_MEMORY, "brume_denoise: out of memory for a %d x %d image", w, h));
    }
    double *c0 = buf, *v0 = buf + 3 * npix, *c1 = buf + 6 * npix, *v1 = buf + 9 * npix;
    for (size_t p = 0; p < npix; p++)
        for (size_t c = 0; c < 3; c++) {
            float x = in->rgba[4 * p + c], v = var[3 * p + c];
            raw[3 * p + c] = x;
            c0[3 * p + c] = isfinite(x) ? (double)x : 0.0;
            v0[3 * p + c] = isfinite(v) && v > 0.0f ? (double)v : 0.0;
        }
    j.c = c0, j.v = v0, j.c_out = c1, j.v_out = v1;
    steady_variance(&j, w, h, c0, v0, v1);
    denoise_levels(&j, threads, img);
    free(buf);
    if (cancelled(&j)) {
        brume_image_release(img);
        return ctx_report(ctx, err_set(BRUME_ERROR_CANCELLED, "brume_denoise: cancelled (brume_context_cancel_loads)"));
    }
    image_set_meta(img, "brume.denoised", "a-trous, variance-guided, 3 x 3 patches, 5 levels (docs/denoise.md); raw image: layer raw");
    *out = img;
    return ctx_report(ctx, BRUME_OK);
}
