/* test_pbrt_rehearsal.c - hand-written pbrt-v4 scenes (tests/pbrt_rehearsal/) that combine
 * the constructs of pbrt-v4-scenes' media scenes, each rendered as it is at 16 x 16 and
 * checked against a value worked out by hand from its geometry: a camera in fog, a
 * homogeneous medium in a sphere, a nanovdb slab under a blackbody distant light, Include,
 * named materials, disks. bench/pbrt_scenes.sh compares the same files with pbrt-v4
 * (docs/pbrt-scenes.md): against 5f7a6068 the slab agrees within the noise; the fog and the
 * ink differ per channel, by up to 7 %, through pbrt-v4's spectral transmittance of their
 * chromatic coefficients, and their grey twins agree. */
#include "test.h"

#include <math.h>

#include "brume.h"

#define PI 3.14159265358979323846

/* The rehearsal folder copied to a fresh temporary folder (the nanovdb slab is written
 * there); returns the path of `file` in it. */
static const char *rehearsal_copy(const char *file)
{
    const char *dir = test_fresh_dir("rehearsal");
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "cp %s/tests/pbrt_rehearsal/*.pbrt %s/", BRUME_SOURCE_DIR, dir);
    ASSERT_EQ_INT(test_system(cmd), 0);
    static char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, file);
    return path;
}

/* Loads a .pbrt; NULL with the reader's message in msg when it refuses the file. */
static brume_scene *load_pbrt(brume_context *ctx, const char *path, char *msg, size_t n)
{
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK) {
        snprintf(msg, n, "%s", brume_context_last_error(ctx));
        return NULL;
    }
    return s;
}

/* fog_camera.pbrt: the camera in an absorbing fog (sigma_a 0.1, 0.2, 0.3), a point light of
 * intensity 4 at the camera, the named material "matte" (reflectance 0.5, from an Include)
 * on a disk 3 ahead: radiance 0.5 / pi x 4 / 9 x exp(-6 sigma_a). Across the 2-degree view
 * the disk is farther by at most 1 / cos(1.42 deg) (3.1e-4): a relative spread of at most
 * (2 + 6 sigma_a) 3.1e-4 below that value. */
TEST(camera_in_fog_lights_included_named_disk)
{
    const char *path = rehearsal_copy("fog_camera.pbrt");
    brume_context *ctx = brume_context_new();
    char msg[1024];
    brume_scene *s = load_pbrt(ctx, path, msg, sizeof msg);
    if (!s)
        TEST_FAIL("%s", msg);
    brume_image *img = test_render_scene(s, -1, 5);
    int n = brume_image_width(img) * brume_image_height(img);
    ASSERT_EQ_INT(n, 256);
    const double sigma[3] = {0.1, 0.2, 0.3};
    for (int c = 0; c < 3; c++) {
        double mean, se, want = 0.5 / PI * 4.0 / 9.0 * exp(-6.0 * sigma[c]);
        test_channel_mean(brume_image_pixels(img), n, c, &mean, &se);
        if (!(fabs(mean - want) <= 4.0 * se + (2.0 + 6.0 * sigma[c]) * 3.1e-4 * want))
            TEST_FAIL("channel %d: mean %.6g, want %.6g (se %g)", c, mean, want, se);
    }
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* blackbody_slab.pbrt: a nanovdb grid of density 1, 8 x 4 x 8 voxels on the box
 * [-2, 2] x [1, 1.5] x [-2, 2], sigma_a 0.4, between a distant light overhead
 * ("blackbody L" 3000 K, scale 2) and the disk "matte" 10 below the camera. pbrt-v4 gives a
 * blackbody light the luminance of its scale. Its NanoVDB lookup puts the voxels' samples at
 * their centres (brume convert's placement) and cuts the medium to NanoVDB's world box,
 * index [min, max + 1]: along y the field is 1 from the first centre (1.0625) to the last
 * (1.4375), then falls to 0 at 1.5625, so a column's optical depth is sigma_a x 3.5 voxels x
 * 0.125 = 0.4 x 0.4375, and the disk's luminance Y is 0.5 / pi x 2 x exp(-2 x 0.4 x 0.4375),
 * on the way down and up (a grid held to its voxel box, 0.5 thick, renders 3.5 % darker). */
TEST(nanovdb_slab_under_blackbody_distant_light)
{
    const char *path = rehearsal_copy("blackbody_slab.pbrt");
    const char *dir = test_tmp_path("rehearsal");
    char raw[4096], cmd[8192];
    snprintf(raw, sizeof raw, "%s/slab.raw", dir);
    float ones[8 * 4 * 8];
    for (int i = 0; i < 8 * 4 * 8; i++)
        ones[i] = 1.0f;
    test_write_bytes(raw, ones, sizeof ones);
    snprintf(cmd, sizeof cmd, "%s convert %s %s/slab.nvdb --dims 8x4x8 --bounds -2,1,-2,2,1.5,2 > /dev/null",
             BRUME_EXE, raw, dir);
    ASSERT_EQ_INT(test_system(cmd), 0);

    brume_context *ctx = brume_context_new();
    char msg[1024];
    brume_scene *s = load_pbrt(ctx, path, msg, sizeof msg);
    if (!s)
        TEST_FAIL("%s", msg);
    brume_image *img = test_render_scene(s, -1, 9);
    int n = brume_image_width(img) * brume_image_height(img);
    const float *px = brume_image_pixels(img);
    float *lum = malloc(sizeof(float) * 4 * (size_t)n);
    ASSERT_TRUE(lum != NULL);
    for (int i = 0; i < n; i++) /* Rec. 709 luminance in channel 0 */
        lum[4 * i] = 0.2126f * px[4 * i] + 0.7152f * px[4 * i + 1] + 0.0722f * px[4 * i + 2];
    double mean, se, want = 0.5 / PI * 2.0 * exp(-2.0 * 0.4 * 0.4375);
    test_channel_mean(lum, n, 0, &mean, &se);
    if (!(fabs(mean - want) <= 4.0 * se + 1e-4 * want))
        TEST_FAIL("luminance: mean %.6g, want %.6g (se %g)", mean, want, se);
    /* a 3000 K source is reddish: red above green above blue, as for any Planck spectrum
     * below about 5000 K */
    double r, g, b, unused;
    test_channel_mean(px, n, 0, &r, &unused);
    test_channel_mean(px, n, 1, &g, &unused);
    test_channel_mean(px, n, 2, &b, &unused);
    ASSERT_TRUE(r > g && g > b && b > 0.0);
    free(lum);
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* ink_ball.pbrt: an absorbing ink (sigma_a 0.25, 0.5, 1) inside a sphere of radius 1 at
 * distance 4, a white sky behind: a pixel whose centre's ray makes the angle theta with the
 * axis sees exp(-sigma_a 2 sqrt(1 - 16 sin^2 theta)). The image's mean is that over the
 * pixel centres (the image varies by 1 % over the view and smoothly: a filter moves its
 * mean by far less than the 1e-3 allowed). Where brume cannot bound a homogeneous medium by
 * a sphere it must say so at the Shape's line, never render something else. */
TEST(homogeneous_ink_in_a_sphere_or_refused_by_line)
{
    const char *path = rehearsal_copy("ink_ball.pbrt");
    brume_context *ctx = brume_context_new();
    char msg[1024];
    brume_scene *s = load_pbrt(ctx, path, msg, sizeof msg);
    if (!s) {
        ASSERT_CONTAINS(msg, "ink_ball.pbrt:18:");
        ASSERT_CONTAINS(msg, "Shape \"sphere\"");
        brume_context_release(ctx);
        return;
    }
    brume_image *img = test_render_scene(s, -1, 3);
    int w = brume_image_width(img), h = brume_image_height(img), n = w * h;
    ASSERT_EQ_INT(n, 256);
    const double sigma[3] = {0.25, 0.5, 1.0}, t = tan(1.0 * PI / 180.0);
    for (int c = 0; c < 3; c++) {
        double want = 0.0;
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                double u = ((x + 0.5) / w * 2.0 - 1.0) * t, v = ((y + 0.5) / h * 2.0 - 1.0) * t;
                double sin2 = (u * u + v * v) / (1.0 + u * u + v * v);
                want += exp(-sigma[c] * 2.0 * sqrt(1.0 - 16.0 * sin2)) / n;
            }
        double mean, se;
        test_channel_mean(brume_image_pixels(img), n, c, &mean, &se);
        if (!(fabs(mean - want) <= 4.0 * se + 1e-3 * want))
            TEST_FAIL("channel %d: mean %.6g, want %.6g (se %g)", c, mean, want, se);
    }
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
}

TEST_MAIN(camera_in_fog_lights_included_named_disk, nanovdb_slab_under_blackbody_distant_light,
          homogeneous_ink_in_a_sphere_or_refused_by_line)
