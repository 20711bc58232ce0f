/* test_compare.c - the error figures of image_compare on images with known differences. */
#include "test.h"

#include "brume.h"
#include "io/compare.h"

static brume_image *ramp(int w, int h, double scale)
{
    brume_image *img = brume_image_new(w, h);
    float *p = brume_image_pixels(img);
    for (int i = 0; i < w * h; i++)
        for (int c = 0; c < 3; c++)
            p[4 * i + c] = (float)(scale * (1.0 + i % 7 + c));
    return img;
}

TEST(identical_images_have_zero_error)
{
    brume_image *a = ramp(9, 5, 1.0), *b = ramp(9, 5, 1.0);
    image_diff_stats st;
    ASSERT_EQ_INT(image_compare(a, b, &st), BRUME_OK);
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
    image_diff_stats st;
    ASSERT_EQ_INT(image_compare(a, b, &st), BRUME_OK);
    ASSERT_NEAR(st.mean_rel, 0.1, 1e-6);
    ASSERT_NEAR(st.max_rel, 0.1, 1e-6);
    double ss = 0.0, s = 0.0;
    const float *p = brume_image_pixels_const(b);
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
    image_diff_stats st;
    ASSERT_EQ_INT(image_compare(a, b, &st), BRUME_ERROR_INVALID_ARGUMENT);
    brume_image_release(a);
    brume_image_release(b);
}

TEST_MAIN(identical_images_have_zero_error, scaled_image_figures, size_mismatch_is_an_error)
