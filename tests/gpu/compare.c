/* compare.c - are two renders of one scene the same estimator? (tests/gpu/run.sh)
 *
 *   compare A.exr B.exr
 *
 * Both images carry the `variance` layer (--aov variance: per pixel and channel, the
 * variance of the pixel's mean). For each channel, over the whole image and over each
 * 32 x 32 block, the difference of the two means is divided by its standard error,
 * sqrt(sum of both images' variances) / pixels: z is standard normal when both estimate
 * the same image. The test passes when |z| < 4 for the whole image and every block is
 * within the Bonferroni bound for the number of blocks tested (|z| < 4.5 for up to 200
 * tests, a false alarm under 0.2 % each run); the mean of z^2 over blocks (about 1 when
 * the variances are right) is printed too. Exit status 0: the same; 1: not; 2: usage. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "brume.h"

static const float *layer(const brume_image *img, const char *name)
{
    for (int i = 0; i < brume_image_layer_count(img); i++)
        if (strcmp(brume_image_layer_name(img, i), name) == 0)
            return brume_image_layer_pixels(img, i);
    return NULL;
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: compare A.exr B.exr\n");
        return 2;
    }
    brume_context *ctx = brume_context_new();
    brume_image *im[2];
    for (int k = 0; k < 2; k++)
        if (brume_image_read(ctx, argv[1 + k], &im[k]) != BRUME_OK) {
            fprintf(stderr, "compare: %s\n", brume_context_last_error(ctx));
            return 2;
        }
    int w = brume_image_width(im[0]), h = brume_image_height(im[0]);
    const float *px[2] = {brume_image_pixels(im[0]), brume_image_pixels(im[1])};
    const float *var[2] = {layer(im[0], "variance"), layer(im[1], "variance")};
    if (w != brume_image_width(im[1]) || h != brume_image_height(im[1]) || !var[0] || !var[1]) {
        fprintf(stderr, "compare: the images differ in size or lack the variance layer\n");
        return 2;
    }
    const int B = 32;
    double zmax = 0.0, z2 = 0.0, zall[3];
    int nblocks = 0;
    for (int c = 0; c < 3; c++) {
        double d = 0.0, v = 0.0, m[2] = {0.0, 0.0};
        for (int i = 0; i < w * h; i++) {
            m[0] += px[0][4 * i + c];
            m[1] += px[1][4 * i + c];
            v += var[0][3 * i + c] + var[1][3 * i + c];
        }
        d = m[0] - m[1];
        zall[c] = v > 0.0 ? d / sqrt(v) : (d == 0.0 ? 0.0 : INFINITY);
        printf("channel %d: mean %.6g vs %.6g (ratio %.5f), z %.2f\n", c, m[0] / (w * h), m[1] / (w * h),
               m[1] > 0.0 ? m[0] / m[1] : 1.0, zall[c]);
        for (int by = 0; by < h; by += B)
            for (int bx = 0; bx < w; bx += B) {
                double bd = 0.0, bv = 0.0;
                for (int y = by; y < by + B && y < h; y++)
                    for (int x = bx; x < bx + B && x < w; x++) {
                        int i = y * w + x;
                        bd += px[0][4 * i + c] - px[1][4 * i + c];
                        bv += var[0][3 * i + c] + var[1][3 * i + c];
                    }
                if (!(bv > 0.0)) {
                    if (bd != 0.0)
                        zmax = INFINITY;
                    continue;
                }
                double z = bd / sqrt(bv);
                zmax = fmax(zmax, fabs(z));
                z2 += z * z;
                nblocks++;
            }
    }
    double bound = nblocks <= 200 ? 4.5 : 5.0;
    bool ok = fabs(zall[0]) < 4.0 && fabs(zall[1]) < 4.0 && fabs(zall[2]) < 4.0 && zmax < bound;
    printf("%d blocks of %d^2 x channel: max |z| %.2f (bound %.1f), mean z^2 %.2f: %s\n", nblocks, B, zmax, bound,
           nblocks ? z2 / nblocks : 0.0, ok ? "the same" : "DIFFERENT");
    return ok ? 0 : 1;
}
