/* bench_stam_terms.c - Stam's two variants on equal terms with the explicit realization
 * (docs/stam.md, "On one realization"): the pixel transparency T = 1 - alpha of
 * scenes/stam-compare.json over K realizations of Q (stam.seed = 1 .. K), rendered by
 *   - stam, variant corrected and variant paper (Stam's per-blob transparencies), and the
 *     corrected variant with stam.overlap = joint, and
 *   - `single` on stam.voxelize's explicit realization mean + sum_i sigma_i Q of the SAME Q
 *     (the truth: the transparency of the realized density, estimated by ratio tracking),
 * and reports over the cloud's pixels (the mean field's alpha > 0.05):
 *   - pixel by pixel on the same realization: RMS of T_variant - T_explicit;
 *   - over realizations: each pixel's variance of T over the K seeds, averaged over the
 *     cloud, against the explicit realization's (its own ratio-tracking noise measured by a
 *     second render seed and removed);
 *   - the histogram of T over the cloud's pixels and all seeds (10 bins), and its L1
 *     distance to the explicit realization's.
 *   build/bench/bench_stam_terms [K [WIDTH [HEIGHT [SPP]]]]    (defaults 16 80 60 16) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_common.h"
#include "brume.h"

#define NB 10
enum { V_CORRECTED, V_PAPER, V_JOINT, V_EXPLICIT, V_EXPLICIT2, NV };
static const char *const vname[NV] = {"corrected", "paper", "corrected, overlap joint", "explicit",
                                      "explicit, 2nd render seed"};

static brume_image *render(brume_context *ctx, int v, int seed, int w, int h, int spp, double eps)
{
    char sseed[64], seps[64];
    snprintf(sseed, sizeof sseed, "stam.seed=%d", seed);
    snprintf(seps, sizeof seps, "stam.eps=%g", eps);
    const char *ov[6] = {sseed, seps};
    int n = 2;
    if (v == V_PAPER)
        ov[n++] = "stam.variant=paper";
    if (v == V_JOINT)
        ov[n++] = "stam.overlap=joint";
    if (v >= V_EXPLICIT) {
        ov[n++] = "stam.voxelize.resolution=192";
        ov[n++] = "stam.voxelize.realization=true";
    }
    brume_load_options lo = {.overrides = ov, .noverrides = n};
    brume_scene *s = NULL;
    brume_image *img = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = BRUME_SOURCE_DIR "/scenes/stam-compare.json"}, &lo, &s) != BRUME_OK)
        goto fail;
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    rs.width = w;
    rs.height = h;
    rs.spp = spp;
    rs.seed = v == V_EXPLICIT2 ? 77 : 1;
    if (v >= V_EXPLICIT)
        rs.method = BRUME_METHOD_SINGLE;
    if (brume_scene_set_settings(ctx, s, &rs) != BRUME_OK || brume_scene_commit(ctx, s) != BRUME_OK ||
        brume_render(ctx, s, &img) != BRUME_OK)
        goto fail;
    brume_scene_release(s);
    return img;
fail:
    fprintf(stderr, "bench_stam_terms: %s\n", brume_context_last_error(ctx));
    exit(1);
}

int main(int argc, char **argv)
{
    int K = argc > 1 ? atoi(argv[1]) : 16, w = argc > 2 ? atoi(argv[2]) : 80, h = argc > 3 ? atoi(argv[3]) : 60,
        spp = argc > 4 ? atoi(argv[4]) : 16;
    double eps = argc > 5 ? atof(argv[5]) : 0.4;
    if (K < 2 || w < 1 || h < 1 || spp < 1) {
        fprintf(stderr, "usage: bench_stam_terms [K>=2 [WIDTH [HEIGHT [SPP [EPS]]]]]\n");
        return 2;
    }
    bench_machine();
    printf("scenes/stam-compare.json, eps %g, %d x %d, %d spp, %d realizations of Q (stam.seed 1..%d)\n", eps, w, h,
           spp, K, K);
    brume_context *ctx = brume_context_new();
    long n = (long)w * h;
    /* the cloud: the mean field's alpha (eps = 0) above 0.05 */
    brume_image *mean = render(ctx, V_CORRECTED, 1, w, h, spp, 0.0);
    unsigned char *cloud = malloc((size_t)n);
    long nc = 0; /* cloud pixels */
    for (long i = 0; i < n; i++)
        nc += cloud[i] = brume_image_pixels(mean)[4 * i + 3] > 0.05f;
    brume_image_release(mean);
    double *s1 = calloc((size_t)(NV * n), sizeof *s1), *s2 = calloc((size_t)(NV * n), sizeof *s2);
    double hist[NV][NB] = {{0}}, sq[NV] = {0}, noise = 0.0;
    for (int k = 1; k <= K; k++) {
        const float *px[NV];
        brume_image *img[NV];
        for (int v = 0; v < NV; v++) {
            img[v] = render(ctx, v, k, w, h, spp, eps);
            px[v] = brume_image_pixels(img[v]);
        }
        for (long i = 0; i < n; i++) {
            if (!cloud[i])
                continue;
            double te = 1.0 - (double)px[V_EXPLICIT][4 * i + 3];
            for (int v = 0; v < NV; v++) {
                double t = 1.0 - (double)px[v][4 * i + 3];
                s1[v * n + i] += t;
                s2[v * n + i] += t * t;
                int b = (int)(t * NB);
                hist[v][b < 0 ? 0 : b >= NB ? NB - 1 : b] += 1.0;
                sq[v] += (t - te) * (t - te);
            }
            double d = (double)px[V_EXPLICIT2][4 * i + 3] - (double)px[V_EXPLICIT][4 * i + 3];
            noise += 0.5 * d * d; /* each explicit render's own estimator variance */
        }
        for (int v = 0; v < NV; v++)
            brume_image_release(img[v]);
    }
    double var[NV] = {0}, mT[NV] = {0};
    for (int v = 0; v < NV; v++)
        for (long i = 0; i < n; i++)
            if (cloud[i]) {
                double m = s1[v * n + i] / K;
                var[v] += (s2[v * n + i] - K * m * m) / (K - 1);
                mT[v] += m;
            }
    double N = (double)nc * K;
    noise /= N;
    printf("cloud: %ld pixels; explicit render's own variance of T (ratio tracking, %d spp): %.5f\n", nc, spp, noise);
    double C = (double)nc, truth = var[V_EXPLICIT] / C - noise;
    printf("| T over the cloud | mean T | variance over realizations (per pixel, averaged) | / explicit's | RMS of T - "
           "T_explicit, same realization | histogram L1 to explicit |\n| --- | --- | --- | --- | --- | --- |\n");
    for (int v = 0; v < NV; v++) {
        double l1 = 0.0;
        for (int b = 0; b < NB; b++)
            l1 += fabs(hist[v][b] - hist[V_EXPLICIT][b]) / N;
        double vv = var[v] / C - (v >= V_EXPLICIT ? noise : 0.0);
        printf("| %s | %.4f | %.5f | %.2f | %.4f | %.3f |\n", vname[v], mT[v] / C, vv, vv / truth,
               sqrt(sq[v] / N), l1);
    }
    printf("histogram of T (bins of 0.1, fraction of cloud pixels x realizations):\n");
    for (int v = 0; v < NV; v++) {
        printf("%-26s", vname[v]);
        for (int b = 0; b < NB; b++)
            printf(" %.3f", hist[v][b] / N);
        printf("\n");
    }
    free(s1);
    free(s2);
    free(cloud);
    brume_context_release(ctx);
    return 0;
}
