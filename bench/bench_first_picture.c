/* bench_first_picture.c - the error of a picture of the default scene against a converged
 * reference, as bench/first_picture.sh measures `make render`'s 15-second picture.
 *
 *   bench_first_picture [--mean] REFERENCE.exr IMAGE.exr...
 *
 * REFERENCE is a long render with the "variance" and "depth" layers (first_picture.sh makes
 * it); each IMAGE an EXR of brume render, denoised or not (a denoised one is measured twice:
 * its pixels, and its "raw" layer). The region is the pixels that are not sky: those where
 * the reference's depth layer is finite and above 0 (a camera ray that met the cloud or the
 * ground). Figures, of the luminance L = 0.2126 R + 0.7152 G + 0.0722 B over the region:
 *
 *   pixel  sqrt(mean over pixels of (L - L_ref)^2 - V_ref) / mean L_ref
 *   block  the same over the 8 x 8-pixel blocks' means (blocks with at least half of their
 *          pixels in the region, the mean over those), V_ref the block mean's variance
 *   mean   mean L / mean L_ref - 1
 *
 * V_ref is the reference's own variance of L (from its variance layer, the channels taken as
 * fully correlated: an upper bound), subtracted so that a finite reference does not inflate
 * the figures; each figure is then the error against the converged picture.
 *
 * --mean: the IMAGEs are renders of the same samples per pixel with different seeds; the
 * figures of their mean follow, and the split of the block error that they give: the noise
 * is independent between the seeds and the bias is not, so with N images of block errors e_i
 * and their mean's e_m, noise^2 = (mean e_i^2 - e_m^2) N / (N - 1) and bias^2 = e_m^2 -
 * noise^2 / N. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brume.h"

#define BLOCK 8

static const float *layer(const brume_image *img, const char *name, int channels)
{
    for (int i = 0; i < brume_image_layer_count(img); i++)
        if (strcmp(brume_image_layer_name(img, i), name) == 0 && brume_image_layer_channels(img, i) == channels)
            return brume_image_layer_pixels(img, i);
    return NULL;
}

static double lum(const float *c) { return 0.2126 * (double)c[0] + 0.7152 * (double)c[1] + 0.0722 * (double)c[2]; }

/* the standard deviation of L from the channels' variances, taken as fully correlated */
static double sd_lum(const float *v)
{
    return 0.2126 * sqrt((double)v[0]) + 0.7152 * sqrt((double)v[1]) + 0.0722 * sqrt((double)v[2]);
}

typedef struct figures {
    double pixel, block, mean;
} figures;

/* px: RGB of each pixel at px + step * p (step 4 for RGBA, 3 for a layer) */
static figures measure(const brume_image *ref, const float *var, const unsigned char *mask, const float *px,
                       size_t step)
{
    const int w = brume_image_width(ref), h = brume_image_height(ref);
    const float *rp = brume_image_pixels(ref);
    double se = 0.0, sum = 0.0, sum_ref = 0.0, n = 0.0;
    for (size_t p = 0; p < (size_t)w * (size_t)h; p++) {
        if (!mask[p])
            continue;
        double l = lum(px + step * p), lr = lum(rp + 4 * p);
        double sd = sd_lum(var + 3 * p);
        se += (l - lr) * (l - lr) - sd * sd;
        sum += l;
        sum_ref += lr;
        n += 1.0;
    }
    figures f = {0.0, 0.0, 0.0};
    if (n == 0.0 || sum_ref <= 0.0)
        return f;
    const double mean_ref = sum_ref / n;
    f.pixel = sqrt(fmax(0.0, se / n)) / mean_ref;
    f.mean = sum / sum_ref - 1.0;
    double bse = 0.0, nb = 0.0;
    for (int by = 0; by + BLOCK <= h; by += BLOCK)
        for (int bx = 0; bx + BLOCK <= w; bx += BLOCK) {
            double s = 0.0, sr = 0.0, v = 0.0, k = 0.0;
            for (int y = by; y < by + BLOCK; y++)
                for (int x = bx; x < bx + BLOCK; x++) {
                    const size_t p = (size_t)y * (size_t)w + (size_t)x;
                    if (!mask[p])
                        continue;
                    s += lum(px + step * p);
                    sr += lum(rp + 4 * p);
                    double sd = sd_lum(var + 3 * p);
                    v += sd * sd;
                    k += 1.0;
                }
            if (k < BLOCK * BLOCK / 2)
                continue;
            bse += (s / k - sr / k) * (s / k - sr / k) - v / (k * k);
            nb += 1.0;
        }
    f.block = nb > 0.0 ? sqrt(fmax(0.0, bse / nb)) / mean_ref : 0.0;
    return f;
}

static void print(const char *name, const char *what, figures f)
{
    printf("%-40s %-8s pixel %6.2f %%  block %6.3f %%  mean %+6.2f %%\n", name, what, 100.0 * f.pixel, 100.0 * f.block,
           100.0 * f.mean);
}

/* The images measured so far, for --mean: their pixels' sums (denoised or plain RGBA, and
 * their raw layers) and the sums of their squared block errors. */
typedef struct tally {
    const brume_image *ref;
    const float *var;
    const unsigned char *mask;
    float *sum, *sum_raw;
    double block2, block2_raw;
    int n;
    bool raws; /* every image so far had a raw layer */
} tally;

/* Measures and prints the image at path, and adds it to t; 0, or 1 when it cannot be read. */
static int measure_file(brume_context *ctx, const char *path, tally *t)
{
    const int w = brume_image_width(t->ref), h = brume_image_height(t->ref);
    brume_image *img = NULL;
    if (brume_image_read(ctx, path, &img) != BRUME_OK || brume_image_width(img) != w || brume_image_height(img) != h) {
        fprintf(stderr, "bench_first_picture: %s: %s\n", path, img ? "not the reference's size" : brume_context_last_error(ctx));
        brume_image_release(img);
        return 1;
    }
    const float *raw = layer(img, "raw", 3), *px = brume_image_pixels(img);
    figures f = measure(t->ref, t->var, t->mask, px, 4);
    print(path, raw ? "denoised" : "image", f);
    t->block2 += f.block * f.block;
    if (raw) {
        figures fr = measure(t->ref, t->var, t->mask, raw, 3);
        print(path, "raw", fr);
        t->block2_raw += fr.block * fr.block;
    }
    t->raws = t->raws && raw;
    for (size_t p = 0; p < (size_t)w * (size_t)h; p++)
        for (size_t c = 0; c < 3; c++) {
            t->sum[4 * p + c] += px[4 * p + c];
            t->sum_raw[3 * p + c] += raw ? raw[3 * p + c] : 0.0f;
        }
    t->n++;
    brume_image_release(img);
    return 0;
}

/* The mean's figures and the block error's split into noise and bias (--mean). */
static void print_split(const tally *t, const char *what, const float *mean, size_t step, double sum_block2)
{
    figures f = measure(t->ref, t->var, t->mask, mean, step);
    print("the mean of the images", what, f);
    const int n = t->n;
    double e2 = sum_block2 / n, m2 = f.block * f.block;
    double noise2 = fmax(0.0, (e2 - m2) * n / (n - 1.0)), bias2 = fmax(0.0, m2 - noise2 / n);
    printf("%-40s %-8s block error of one image: noise %6.3f %%, bias %6.3f %%\n", "", what, 100.0 * sqrt(noise2),
           100.0 * sqrt(bias2));
}

int main(int argc, char **argv)
{
    const bool mean = argc > 1 && strcmp(argv[1], "--mean") == 0;
    if (mean) {
        argv++;
        argc--;
    }
    if (argc < 3) {
        fprintf(stderr, "usage: bench_first_picture [--mean] REFERENCE.exr IMAGE.exr...\n");
        return 2;
    }
    brume_context *ctx = brume_context_new();
    brume_image *ref = NULL;
    if (!ctx || brume_image_read(ctx, argv[1], &ref) != BRUME_OK) {
        fprintf(stderr, "bench_first_picture: %s: %s\n", argv[1], ctx ? brume_context_last_error(ctx) : "no memory");
        return 1;
    }
    const float *var = layer(ref, "variance", 3), *depth = layer(ref, "depth", 1);
    if (!var || !depth) {
        fprintf(stderr, "bench_first_picture: %s: no \"variance\" or \"depth\" layer (render it with --aov "
                        "variance,depth)\n", argv[1]);
        return 1;
    }
    const int w = brume_image_width(ref), h = brume_image_height(ref);
    const size_t npix = (size_t)w * (size_t)h;
    unsigned char *mask = malloc(npix);
    tally t = {ref, var, mask, calloc(npix * 4, sizeof(float)), calloc(npix * 3, sizeof(float)), 0.0, 0.0, 0, true};
    if (!mask || !t.sum || !t.sum_raw)
        return 1;
    size_t region = 0;
    for (size_t p = 0; p < npix; p++) {
        mask[p] = isfinite(depth[p]) && depth[p] > 0.0f;
        region += mask[p];
    }
    printf("reference %s: %d x %d, %zu pixels not sky (%.1f %%)\n", argv[1], w, h, region,
           100.0 * (double)region / ((double)w * h));
    int rc = 0;
    for (int i = 2; i < argc; i++)
        rc |= measure_file(ctx, argv[i], &t);
    if (mean && t.n > 1) {
        for (size_t p = 0; p < npix; p++)
            for (size_t c = 0; c < 3; c++) {
                t.sum[4 * p + c] /= (float)t.n;
                t.sum_raw[3 * p + c] /= (float)t.n;
            }
        print_split(&t, t.raws ? "denoised" : "image", t.sum, 4, t.block2);
        if (t.raws)
            print_split(&t, "raw", t.sum_raw, 3, t.block2_raw);
    }
    free(t.sum);
    free(t.sum_raw);
    free(mask);
    brume_image_release(ref);
    brume_context_release(ctx);
    return rc;
}
