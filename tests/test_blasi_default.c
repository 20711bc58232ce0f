/* test_blasi_default.c - Blasi's light pass on scenes of several overlapping media: the
 * built-in default scene, and two grids where the first medium's voxel is empty where the
 * second's is not. A light ray's energy lands only in voxels that hold density (the light
 * pass keeps sums for no other). */
#include "test.h"

#include "brume.h"

/* Renders the scene of src with the blasi method at w x h, 1 spp, `rays` light rays. */
static brume_image *render_blasi(const brume_source *src, int w, int h, const char *rays)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, src, NULL, &s) != BRUME_OK)
        TEST_FAIL("scene: %s", brume_context_last_error(ctx));
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    ASSERT_EQ_INT(brume_method_from_name(NULL, "blasi", &rs.method), BRUME_OK);
    rs.width = w;
    rs.height = h;
    rs.spp = 1;
    rs.noise_target = 0.0;
    rs.time_budget = 0.0;
    rs.min_spp = 1;
    rs.seed = 7;
    if (brume_scene_set_settings(ctx, s, &rs) != BRUME_OK)
        TEST_FAIL("settings: %s", brume_context_last_error(ctx));
    if (brume_scene_set_option(ctx, s, "blasi.light_rays", rays) != BRUME_OK)
        TEST_FAIL("option: %s", brume_context_last_error(ctx));
    brume_image *img = NULL;
    if (brume_scene_commit(ctx, s) != BRUME_OK || brume_render(ctx, s, &img) != BRUME_OK)
        TEST_FAIL("render: %s", brume_context_last_error(ctx));
    brume_scene_release(s);
    brume_context_release(ctx);
    return img;
}

/* Every pixel finite, and the mean of the green channel over the picture above lo. */
static void check_lit(const brume_image *img, double lo)
{
    const float *px = brume_image_pixels(img);
    int n = brume_image_width(img) * brume_image_height(img);
    double mean = 0.0, se = 0.0;
    for (int i = 0; i < 4 * n; i++)
        ASSERT_TRUE(isfinite(px[i]));
    test_channel_mean(px, n, 1, &mean, &se);
    ASSERT_TRUE(mean > lo);
}

/* The default scene: five fractal clouds whose boxes overlap, over a ground plane. */
TEST(default_scene)
{
    brume_image *img = render_blasi(NULL, 32, 18, "200000");
    check_lit(img, 0.0);
    brume_image_release(img);
}

/* Sun straight down through two media: where x < 0 the first grid's voxel is empty and the
 * second's is dense, so a light ray that leaves there crossed a non-empty piece whose first
 * voxel is empty: the paper's exit deposit goes to the voxel that holds density. */
#define OVERLAP_SCENE                                                                                               \
    "{\"camera\": {\"position\": [0, -4, 1], \"look_at\": [0, 0, 0], \"up\": [0, 0, 1], \"fov\": 40},"             \
    " \"lights\": [{\"type\": \"distant\", \"direction\": [0, 0, -1], \"irradiance\": [2, 2, 2]}],"                 \
    " \"media\": ["                                                                                                 \
    "  {\"sigma_a\": 0.1, \"sigma_s\": 0.5, \"density\": {\"type\": \"array\", \"dims\": [2, 1, 1],"                \
    "    \"data\": [0, 1], \"bounds\": [[-1, -1, -1], [1, 1, 1]], \"filter\": \"nearest\"}},"                       \
    "  {\"sigma_a\": 0.1, \"sigma_s\": 0.5, \"density\": {\"type\": \"array\", \"dims\": [1, 1, 1],"                \
    "    \"data\": [1], \"bounds\": [[-1, -1, -1], [0, 1, 1]], \"filter\": \"nearest\"}}],"                         \
    " \"render\": {\"width\": 16, \"height\": 16, \"spp\": 1, \"method\": \"blasi\"}}"

TEST(overlap_empty_first)
{
    brume_image *img = render_blasi(&(brume_source){.path = "<test>", .text = OVERLAP_SCENE}, 16, 16, "20000");
    check_lit(img, 0.0);
    brume_image_release(img);
}

TEST_MAIN(default_scene, overlap_empty_first)
