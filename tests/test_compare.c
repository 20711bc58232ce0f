/* test_compare.c - the error figures of brume_image_compare and its kin (brume.h, "comparing
 * images") on images with known differences, through the public API. */
#include "test.h"

#include "brume.h"
#include "core/rng.h"

static brume_image *ramp(int w, int h, double scale)
{
    brume_image *img = NULL;
    ASSERT_EQ_INT(brume_image_new(NULL, w, h, &img), BRUME_OK);
    float *p = brume_image_pixels(img);
    for (int i = 0; i < w * h; i++)
        for (int c = 0; c < 3; c++)
            p[4 * i + c] = (float)(scale * (1.0 + i % 7 + c));
    return img;
}

TEST(identical_images_have_zero_error)
{
    brume_image *a = ramp(9, 5, 1.0), *b = ramp(9, 5, 1.0);
    brume_image_diff st;
    ASSERT_EQ_INT(brume_image_compare(NULL, a, b, &st), BRUME_OK);
    ASSERT_NEAR(st.rmse, 0.0, 0.0);
    ASSERT_NEAR(st.max_rel, 0.0, 0.0);
    brume_image_release(a);
    brume_image_release(b);
}

/* An image 10 % brighter everywhere: every relative difference is 0.1, and the rmse is
 * 0.1 times the root mean square of the reference. */
TEST(scaled_image_figures)
{
    brume_image *a = ramp(9, 5, 1.1), *b = ramp(9, 5, 1.0);
    brume_image_diff st;
    ASSERT_EQ_INT(brume_image_compare(NULL, a, b, &st), BRUME_OK);
    ASSERT_NEAR(st.mean_rel, 0.1, 1e-6);
    ASSERT_NEAR(st.max_rel, 0.1, 1e-6);
    double ss = 0.0, s = 0.0;
    const float *p = brume_image_pixels(b);
    for (int i = 0; i < 45; i++)
        for (int c = 0; c < 3; c++) {
            ss += p[4 * i + c] * p[4 * i + c];
            s += p[4 * i + c];
        }
    ASSERT_NEAR(st.rmse, 0.1 * sqrt(ss / 135.0), 1e-5);
    ASSERT_NEAR(st.rel_rmse, st.rmse / (s / 135.0), 1e-9);
    brume_image_release(a);
    brume_image_release(b);
}

TEST(size_mismatch_is_an_error)
{
    brume_image *a = ramp(9, 5, 1.0), *b = ramp(5, 9, 1.0);
    brume_image_diff st;
    ASSERT_EQ_INT(brume_image_compare(NULL, a, b, &st), BRUME_ERROR_INVALID_ARGUMENT);
    brume_image_release(a);
    brume_image_release(b);
}

/* A constant ratio of 1.1 over a region: ratio 1.1, signed_rel 0.1, and every bootstrap
 * draw gives the same figures, so the interval is the point. */
TEST(region_figures_of_a_scaled_image)
{
    brume_image *a = ramp(20, 12, 1.1), *b = ramp(20, 12, 1.0);
    brume_region_stats st;
    ASSERT_EQ_INT(brume_image_compare_region(NULL, a, b, NULL, 200, 7, &st), BRUME_OK);
    ASSERT_EQ_INT((int)st.pixels, 240);
    ASSERT_EQ_INT((int)st.tiles, 6);
    ASSERT_NEAR(st.fig[BRUME_FIG_RATIO], 1.1, 1e-6);
    ASSERT_NEAR(st.fig[BRUME_FIG_SIGNED_REL], 0.1, 1e-6);
    ASSERT_NEAR(st.lo[BRUME_FIG_RATIO], 1.1, 1e-6);
    ASSERT_NEAR(st.hi[BRUME_FIG_SIGNED_REL], 0.1, 1e-6);
    brume_image_release(a);
    brume_image_release(b);
}

/* The region is the reference's alpha above the threshold: an image that differs from the
 * reference only outside it scores 0 over the region and not over the frame. */
TEST(alpha_mask_selects_the_cloud)
{
    brume_image *a = ramp(16, 16, 1.0), *b = ramp(16, 16, 1.0);
    float *pa = brume_image_pixels(a), *pb = brume_image_pixels(b);
    long in = 0;
    for (int i = 0; i < 256; i++) {
        int x = i % 16, y = i / 16;
        bool cloud = (x - 8) * (x - 8) + (y - 8) * (y - 8) < 25;
        pb[4 * i + 3] = cloud ? 0.9f : 0.01f;
        in += cloud;
        if (!cloud)
            for (int c = 0; c < 3; c++)
                pa[4 * i + c] *= 2.0f;
    }
    unsigned char *mask = NULL;
    long count = 0;
    ASSERT_EQ_INT(brume_image_mask_alpha(NULL, b, 0.05, &mask, &count), BRUME_OK);
    ASSERT_EQ_INT((int)count, (int)in);
    brume_region_stats fr, rg;
    ASSERT_EQ_INT(brume_image_compare_region(NULL, a, b, mask, 100, 1, &rg), BRUME_OK);
    ASSERT_EQ_INT(brume_image_compare_region(NULL, a, b, NULL, 100, 1, &fr), BRUME_OK);
    ASSERT_EQ_INT((int)rg.pixels, (int)in);
    ASSERT_NEAR(rg.fig[BRUME_FIG_RATIO], 1.0, 1e-9);
    ASSERT_NEAR(rg.fig[BRUME_FIG_REL_RMSE], 0.0, 1e-9);
    ASSERT_TRUE(fr.fig[BRUME_FIG_RATIO] > 1.5);
    free(mask);
    ASSERT_EQ_INT(brume_image_mask_alpha(NULL, b, 0.95, &mask, &count), BRUME_OK);
    ASSERT_EQ_INT((int)count, 0);
    ASSERT_EQ_INT(brume_image_compare_region(NULL, a, b, mask, 100, 1, &rg), BRUME_ERROR_INVALID_ARGUMENT);
    free(mask);
    brume_image *small = ramp(4, 4, 1.0);
    ASSERT_EQ_INT(brume_image_mask_picture(NULL, small, 16, 16, &mask, &count), BRUME_ERROR_INVALID_ARGUMENT);
    ASSERT_TRUE(mask == NULL);
    brume_image_release(small);
    brume_image_release(a);
    brume_image_release(b);
}

/* Independent noise of standard deviation s on each pixel's relative difference: the mean
 * signed_rel over N pixels has standard error s / sqrt(N), so the 95 % interval is about
 * 2 * 1.96 s / sqrt(N) wide. With 64 tiles the bootstrap's standard error is itself known
 * to about 1 / sqrt(2 * 64) = 9 %; the tolerance is 3 of those. */
TEST(bootstrap_interval_has_the_width_of_the_noise)
{
    const int w = 64, h = 64, n = w * h;
    const double s = 0.1;
    brume_image *a = NULL, *b = NULL;
    ASSERT_EQ_INT(brume_image_new(NULL, w, h, &a), BRUME_OK);
    ASSERT_EQ_INT(brume_image_new(NULL, w, h, &b), BRUME_OK);
    float *pa = brume_image_pixels(a), *pb = brume_image_pixels(b);
    for (int i = 0; i < n; i++) {
        rng r = rng_make(99, (uint64_t)i, 0);
        double u1 = rng_next(&r), u2 = rng_next(&r);
        double g = sqrt(-2.0 * log(1.0 - u1)) * cos(6.283185307179586 * u2);
        for (int c = 0; c < 3; c++) {
            pb[4 * i + c] = 1.0f;
            pa[4 * i + c] = (float)(1.0 + s * g);
        }
    }
    brume_region_stats st;
    ASSERT_EQ_INT(brume_image_compare_region(NULL, a, b, NULL, 2000, 3, &st), BRUME_OK);
    double width = st.hi[BRUME_FIG_SIGNED_REL] - st.lo[BRUME_FIG_SIGNED_REL];
    double expect = 2.0 * 1.96 * s / sqrt((double)n);
    printf("signed_rel %.5f [%.5f, %.5f], width %.5f, expected %.5f\n", st.fig[BRUME_FIG_SIGNED_REL],
           st.lo[BRUME_FIG_SIGNED_REL], st.hi[BRUME_FIG_SIGNED_REL], width, expect);
    ASSERT_NEAR(width / expect, 1.0, 3.0 / sqrt(128.0));
    ASSERT_NEAR(st.fig[BRUME_FIG_SIGNED_REL], 0.0, 5.0 * s / sqrt((double)n));
    ASSERT_TRUE(st.lo[BRUME_FIG_SIGNED_REL] < st.fig[BRUME_FIG_SIGNED_REL]);
    ASSERT_TRUE(st.hi[BRUME_FIG_SIGNED_REL] > st.fig[BRUME_FIG_SIGNED_REL]);
    brume_image_release(a);
    brume_image_release(b);
}

/* The colour map keeps the sign: white at 0, blue (darker) below, red (brighter) above,
 * saturated, and distinct, at +-scale. */
TEST(difference_colours_keep_the_sign)
{
    float z[3], lo[3], hi[3], lo2[3], hi2[3], half[3];
    brume_diff_color(0.0, 0.5, z);
    brume_diff_color(-0.5, 0.5, lo);
    brume_diff_color(0.5, 0.5, hi);
    brume_diff_color(-3.0, 0.5, lo2);
    brume_diff_color(3.0, 0.5, hi2);
    brume_diff_color(0.25, 0.5, half);
    for (int c = 0; c < 3; c++) {
        ASSERT_NEAR(z[c], 1.0, 1e-6);
        ASSERT_NEAR(lo2[c], lo[c], 1e-6);
        ASSERT_NEAR(hi2[c], hi[c], 1e-6);
    }
    ASSERT_TRUE(lo[2] > lo[0] + 0.2);
    ASSERT_TRUE(hi[0] > hi[2] + 0.2);
    ASSERT_TRUE(half[0] > half[2] && half[1] < 0.9f);
    /* the picture itself: darker pixels blue, brighter red */
    brume_image *a = ramp(2, 1, 1.0), *b = ramp(2, 1, 1.0), *d = NULL;
    float *pa = brume_image_pixels(a);
    for (int c = 0; c < 3; c++) {
        pa[c] *= 0.5f;
        pa[4 + c] *= 1.5f;
    }
    ASSERT_EQ_INT(brume_image_diff_picture(NULL, a, b, 0.5, &d), BRUME_OK);
    const float *pd = brume_image_pixels(d);
    ASSERT_TRUE(pd[2] > pd[0]);
    ASSERT_TRUE(pd[4] > pd[6]);
    const char *png = test_tmp_path("diff.png");
    ASSERT_EQ_INT(brume_image_diff_png(NULL, a, b, NULL, 0.5, png), BRUME_OK);
    brume_image *back = NULL;
    brume_context *ctx = brume_context_new();
    ASSERT_EQ_INT(brume_image_read(ctx, png, &back), BRUME_OK);
    ASSERT_TRUE(brume_image_height(back) > 1 && brume_image_width(back) >= 2);
    remove(png);
    brume_image_release(back);
    brume_context_release(ctx);
    brume_image_release(d);
    brume_image_release(a);
    brume_image_release(b);
}

/* `brume compare --scene S --seeds K REF` renders S at seeds S0 .. S0+K-1: against a
 * reference rendered at S0 with the same settings, the first render's figures are exact
 * (ratio 1, rel_rmse 0) and the second's are not; --alpha makes a region; bad flags are
 * usage errors (exit 2). */
TEST(compare_cli_seeds_and_region)
{
    const char *ref = test_tmp_path("ref.exr"), *out = test_tmp_path("seeds.txt");
    char cmd[2048];
    const char *scene = BRUME_SOURCE_DIR "/scenes/stam-compare.json";
    snprintf(cmd, sizeof cmd, "%s render %s -q --width 24 --height 18 --spp 2 --seed 5 -o %s", BRUME_EXE, scene, ref);
    ASSERT_EQ_INT(test_system(cmd), 0);
    snprintf(cmd, sizeof cmd,
             "%s compare --scene %s --seeds 2 --seed 5 --width 24 --height 18 --spp 2 --alpha 0.05 %s > %s", BRUME_EXE,
             scene, ref, out);
    ASSERT_EQ_INT(test_system(cmd), 0);
    size_t n;
    char *txt = test_slurp(out, &n);
    ASSERT_CONTAINS(txt, "seed 5 frame ratio 1 rel_rmse 0 signed_rel 0\n");
    ASSERT_CONTAINS(txt, "seed 5 region ratio 1 rel_rmse 0 signed_rel 0\n");
    ASSERT_CONTAINS(txt, "seed 6 frame ratio");
    ASSERT_TRUE(strstr(txt, "seed 6 frame ratio 1 rel_rmse 0 ") == NULL);
    ASSERT_CONTAINS(txt, "region rel_rmse ");
    ASSERT_CONTAINS(txt, " +- ");
    free(txt);
    snprintf(cmd, sizeof cmd, "%s compare %s %s --alpha 0.05 --mask %s 2>/dev/null", BRUME_EXE, ref, ref, ref);
    ASSERT_EQ_INT(test_system(cmd), 2);
    snprintf(cmd, sizeof cmd, "%s compare %s %s --seeds 3 2>/dev/null", BRUME_EXE, ref, ref);
    ASSERT_EQ_INT(test_system(cmd), 2);
    const char *small = test_tmp_path("small.pfm");
    snprintf(cmd, sizeof cmd, "%s render %s -q --width 4 --height 3 --spp 1 -o %s", BRUME_EXE, scene, small);
    ASSERT_EQ_INT(test_system(cmd), 0);
    snprintf(cmd, sizeof cmd, "%s compare %s %s --mask %s 2>/dev/null", BRUME_EXE, ref, ref, small);
    ASSERT_EQ_INT(test_system(cmd), 1);
    remove(small);
    remove(ref);
    remove(out);
}

TEST_MAIN(identical_images_have_zero_error, scaled_image_figures, size_mismatch_is_an_error,
          region_figures_of_a_scaled_image, alpha_mask_selects_the_cloud, bootstrap_interval_has_the_width_of_the_noise,
          difference_colours_keep_the_sign, compare_cli_seeds_and_region)
