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
 * At the last level v in w_colour is the true variance of the level's input: the carried one
 * times the ratio measured on synthetic noise that went through the same weights (a function
 * of the pixel index alone; denoise_levels).
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

#define DENOISE_LEVELS 6 /* kernel footprint 1 + 4 (2^6 - 1) = 253 pixels */
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
#define DENOISE_NOISE 2 /* realisations of synthetic luminance noise carried through the levels (4 gave
                            the same figures on the default scene) */
#define DENOISE_RATIO_WINDOW 2 /* the true variance is the noise's mean square over 5 x 5 taps */
#define DENOISE_E_MAX 30.0       /* a neighbour of weight below e^-30 (1e-13 of the centre's) is skipped */

typedef struct denoise_job {
    int w, h, step;
    const double *c, *v;   /* level input: RGB colour, RGB variance, 3 per pixel */
    double *c_out, *v_out; /* level output */
    const float *n;        /* level input: DENOISE_NOISE realisations of luminance noise a pixel */
    float *n_out;          /* level output */
    const float *ratio;    /* the level input's true luminance variance over the carried one, a
                              pixel (>= 1), or NULL: 1 */
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
                double vs = j->ratio ? j->v[a + c] * (double)j->ratio[a / 3] + j->v[b + c] * (double)j->ratio[b / 3]
                                     : j->v[a + c] + j->v[b + c];
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
        double sw = 0.0, acc[3] = {0.0, 0.0, 0.0}, accv[3] = {0.0, 0.0, 0.0}, accn[DENOISE_NOISE] = {0.0};
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
                for (size_t r = 0; r < DENOISE_NOISE; r++)
                    accn[r] += wq * (double)j->n[DENOISE_NOISE * q + r];
            }
        }
        for (size_t r = 0; r < DENOISE_NOISE; r++)
            j->n_out[DENOISE_NOISE * p + r] = (float)(accn[r] / sw);
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

/* The variance of a pixel's luminance from its channels' (taken as independent). */
static double lum_var(const double *v)
{
    return 0.2126 * 0.2126 * v[0] + 0.7152 * 0.7152 * v[1] + 0.0722 * 0.0722 * v[2];
}

/* A standard normal number that is a function of (p, r) alone (splitmix64, Box-Muller). */
static double noise_gauss(size_t p, size_t r)
{
    uint64_t z = (uint64_t)p * 0x9e3779b97f4a7c15ULL + (uint64_t)r * 0xd1b54a32d192ed03ULL + 0x632be59bd9b4e019ULL;
    double u[2];
    for (int i = 0; i < 2; i++) {
        z += 0x9e3779b97f4a7c15ULL;
        uint64_t x = z;
        x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
        x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
        x ^= x >> 31;
        u[i] = ((double)(x >> 11) + 0.5) / 9007199254740992.0;
    }
    return sqrt(-2.0 * log(u[0])) * cos(6.283185307179586 * u[1]);
}

typedef struct ratio_job {
    const denoise_job *j; /* its level output: n and v */
    float *ratio;
    int step; /* the window's tap spacing: the level's */
} ratio_job;

/* One row of the ratio of the level output's true luminance variance to the carried one: the
 * mean square of the noise carried through the level's weights over the carried variance,
 * both summed over (2 DENOISE_RATIO_WINDOW + 1)^2 taps spaced as the level's. The carried
 * variance treats the level's input pixels as independent, which they are not after the
 * first level (their kernels overlap); the noise went through the same weights, so it holds
 * the covariances the carried variance leaves out. */
static void ratio_row(size_t task, int thread, void *user)
{
    (void)thread;
    const ratio_job *rj = user;
    const denoise_job *j = rj->j;
    const int y = (int)task, w = j->w, h = j->h, m = DENOISE_RATIO_WINDOW;
    for (int x = 0; x < w; x++) {
        double num = 0.0, den = 0.0;
        for (int dy = -m; dy <= m; dy++) {
            int yq = y + dy * rj->step;
            if (yq < 0 || yq >= h)
                continue;
            for (int dx = -m; dx <= m; dx++) {
                int xq = x + dx * rj->step;
                if (xq < 0 || xq >= w)
                    continue;
                const size_t q = (size_t)yq * (size_t)w + (size_t)xq;
                for (size_t r = 0; r < DENOISE_NOISE; r++)
                    num += sq((double)j->n[DENOISE_NOISE * q + r]);
                den += DENOISE_NOISE * lum_var(j->v + 3 * q);
            }
        }
        /* the weights are positive, so the covariances the carried variance leaves out are
         * too: a ratio below 1 is the estimate's own noise */
        rj->ratio[(size_t)y * (size_t)w + (size_t)x] = den > 0.0 ? (float)fmax(1.0, num / den) : 1.0f;
    }
}

size_t brume_denoise_memory(int width, int height, int layer_channels)
{
    if (width <= 0 || height <= 0 || layer_channels < 0)
        return 0;
    /* the output: RGBA, the layers and the "raw" layer in float; the levels' colour and
     * variance, input and output, in double; the noise, input and output, and the variance
     * ratio in float */
    double per_pixel = (4.0 + layer_channels + 3.0 + 2.0 * DENOISE_NOISE + 1.0) * sizeof(float) + 12.0 * sizeof(double);
    double bytes = per_pixel * (double)width * (double)height;
    return bytes < (double)SIZE_MAX ? (size_t)bytes : SIZE_MAX;
}

/* The levels over j's buffers (c0, v0, n0 into c1, v1, n1 and back), then the result into img.
 * The noise starts as DENOISE_NOISE realisations of white gaussian noise of each pixel's
 * luminance variance, a function of the pixel's index alone; it goes through every level's
 * weights as the colour does. The last level, the coarsest (taps 32 pixels apart), weighs its
 * colour distance with the true variance of its input (the carried one times the ratio
 * ratio_row measures): with the carried one alone, 29 to 96 times too small there, it took its
 * input's low-frequency noise for structure and kept it. At the finer levels the carried
 * variance is kept: there the true one averaged across the cloud's structure
 * (docs/denoise.md, "Low-frequency noise"). */
static void denoise_levels(denoise_job *j, int threads, brume_image *img, float *ratio)
{
    const size_t npix = (size_t)j->w * (size_t)j->h;
    for (size_t p = 0; p < npix; p++)
        for (size_t r = 0; r < DENOISE_NOISE; r++)
            ((float *)j->n)[DENOISE_NOISE * p + r] = (float)(sqrt(lum_var(j->v + 3 * p)) * noise_gauss(p, r));
    for (int level = 0; level < DENOISE_LEVELS && !cancelled(j); level++) {
        j->step = 1 << level;
        if (level == DENOISE_LEVELS - 1) {
            ratio_job rj = {j, ratio, 1 << (level - 1)};
            pool_run(threads, (size_t)j->h, ratio_row, &rj);
            j->ratio = ratio;
        }
        pool_run(threads, (size_t)j->h, denoise_row, j);
        double *tc = (double *)j->c, *tv = (double *)j->v; /* the output is the next level's input */
        float *tn = (float *)j->n;
        j->c = j->c_out;
        j->v = j->v_out;
        j->n = j->n_out;
        j->c_out = tc;
        j->v_out = tv;
        j->n_out = tn;
    }
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
    denoise_job j = {in->width, in->height, 1, NULL, NULL, NULL, NULL, NULL, NULL, NULL, layer_of(in, "albedo", 3),
                     layer_of(in, "normal", 3), layer_of(in, "depth", 1), DENOISE_K * DENOISE_K,
                     1.0 / sq(DENOISE_SIGMA_ALBEDO), 1.0 / sq(DENOISE_SIGMA_NORMAL), 1.0 / sq(DENOISE_SIGMA_DEPTH),
                     ctx ? &ctx->load_cancels : NULL, ctx ? atomic_load(&ctx->load_cancels) : 0u, false};
    const int w = in->width, h = in->height;
    const size_t npix = (size_t)w * (size_t)h;
    const float *var = layer_of(in, "variance", 3);
    brume_image *img = image_copy(in);
    double *buf = malloc(npix * 12 * sizeof *buf);
    float *fbuf = malloc(npix * (2 * DENOISE_NOISE + 1) * sizeof *fbuf); /* the noise, in and out; the ratio */
    static const char *const rgb[3] = {"R", "G", "B"};
    float *raw = img ? image_add_layer(img, "raw", 3, rgb) : NULL;
    if (!img || !buf || !fbuf || !raw) {
        brume_image_release(img);
        free(buf);
        free(fbuf);
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
    j.n = fbuf, j.n_out = fbuf + DENOISE_NOISE * npix;
    steady_variance(&j, w, h, c0, v0, v1);
    denoise_levels(&j, threads, img, fbuf + 2 * DENOISE_NOISE * npix);
    free(buf);
    free(fbuf);
    if (cancelled(&j)) {
        brume_image_release(img);
        return ctx_report(ctx, err_set(BRUME_ERROR_CANCELLED, "brume_denoise: cancelled (brume_context_cancel_loads)"));
    }
    image_set_meta(img, "brume.denoised", "a-trous, variance-guided, 3 x 3 patches, 6 levels, the last weighed by the true variance (docs/denoise.md); raw image: layer raw");
    *out = img;
    return ctx_report(ctx, BRUME_OK);
}
