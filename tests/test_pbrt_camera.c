/* test_pbrt_camera.c - the camera's medium, in scene JSON and from pbrt-v4 files
 * (docs/pbrt.md): what pbrt-v4 gives the camera is read or refused by name, never dropped.
 * A camera inside an absorbing fog sees a sky, or a wall its point light lights, through the
 * analytic transmittance exp(-sigma_t d). */
#include "test.h"

#include <math.h>

#include "brume.h"
#include "core/error.h"
#include "io/json.h"
#include "scene/scene_pbrt.h"

/* A pbrt file of these lines, loaded: the status, and the one-line message on failure. */
static brume_status load_pbrt(const char *text, char *msg, size_t cap)
{
    const char *path = test_tmp_path("cam.pbrt");
    test_write_file(path, text);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    brume_status st = brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s);
    snprintf(msg, cap, "%s", st == BRUME_OK ? "" : brume_context_last_error(ctx));
    brume_scene_release(s);
    brume_context_release(ctx);
    return st;
}

/* text refused with one line "FILE:LINE: " naming frag. */
static void expect_refusal(const char *text, int line, const char *frag)
{
    char msg[2048], want[1200];
    ASSERT_TRUE(load_pbrt(text, msg, sizeof msg) != BRUME_OK);
    snprintf(want, sizeof want, "%s:%d: ", test_tmp_path("cam.pbrt"), line);
    ASSERT_CONTAINS(msg, want);
    ASSERT_CONTAINS(msg, frag);
    ASSERT_TRUE(strchr(msg, '\n') == NULL);
}

#define FOG "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [0.5 0.5 0.5]\n"
#define VIEW "LookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\" \"float fov\" [1]\n"

/* A film brume does not write is refused by name. */
TEST(film_types_refused_by_name)
{
    expect_refusal("Film \"spectral\"\n" VIEW "WorldBegin\n", 1, "Film \"spectral\"");
}

/* A camera at the origin looking along +z through a 1-degree view, inside an absorbing fog
 * (sigma_a = 0.2, 0.5, 1 per channel, sigma_s 0) that fills [-1, 1] x [-1, 1] x [-2, 2],
 * against a sky of radiance 1: every pixel is exp(-sigma_a 2), the fog's far face being 2
 * away. Paths at the image's corners are longer by 1 / cos(0.71 deg) - 1 = 8e-5 at most.
 * Tolerance: 4 standard errors of the image's mean plus that spread. */
TEST(json_camera_in_fog_sees_transmittance)
{
    brume_image *img = test_render_json(
        "{\"camera\": {\"position\": [0, 0, 0], \"look_at\": [0, 0, 1], \"fov\": 1, \"medium\": \"fog\"},"
        " \"background\": [1, 1, 1], \"lights\": [],"
        " \"media\": [{\"name\": \"fog\", \"sigma_a\": [0.2, 0.5, 1], \"sigma_s\": [0, 0, 0],"
        "   \"density\": {\"type\": \"constant\", \"value\": 1, \"bounds\": [[-1, -1, -2], [1, 1, 2]]}}],"
        " \"render\": {\"width\": 16, \"height\": 16, \"spp\": 64, \"method\": \"path\"}}",
        11);
    int n = brume_image_width(img) * brume_image_height(img);
    const double sigma[3] = {0.2, 0.5, 1.0};
    for (int c = 0; c < 3; c++) {
        double mean, se, want = exp(-2.0 * sigma[c]);
        test_channel_mean(brume_image_pixels(img), n, c, &mean, &se);
        if (!(fabs(mean - want) <= 4.0 * se + 2.0 * sigma[c] * 8e-5 * want + 1e-6))
            TEST_FAIL("channel %d: mean %.6f, want exp(-%g) = %.6f (se %g)", c, mean, 2.0 * sigma[c], want, se);
    }
    brume_image_release(img);
}

/* The scene JSON of a camera at position p naming the medium m, a fog in [-1, 1]^3. */
static brume_status load_json_camera(const char *p, const char *m, char *msg, size_t cap)
{
    char json[1024];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": %s, \"look_at\": [0, 0, 9], \"medium\": \"%s\"}, \"lights\": [],"
             " \"media\": [{\"name\": \"fog\", \"sigma_a\": 1, \"sigma_s\": 0,"
             " \"density\": {\"type\": \"constant\", \"value\": 1}}]}", p, m);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    brume_status st = brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = json}, NULL, &s);
    if (st == BRUME_OK)
        st = brume_scene_commit(ctx, s);
    snprintf(msg, cap, "%s", st == BRUME_OK ? "" : brume_context_last_error(ctx));
    brume_scene_release(s);
    brume_context_release(ctx);
    return st;
}

/* camera.medium is checked at commit: a medium of that name whose field holds the camera. */
TEST(json_camera_medium_checked)
{
    char msg[2048];
    if (load_json_camera("[0, 0, 0.5]", "fog", msg, sizeof msg) != BRUME_OK)
        TEST_FAIL("%s", msg);
    ASSERT_TRUE(load_json_camera("[0, 0, 0.5]", "smoke", msg, sizeof msg) != BRUME_OK);
    ASSERT_CONTAINS(msg, "camera.medium: no medium named \"smoke\"");
    ASSERT_TRUE(load_json_camera("[0, 0, -3]", "fog", msg, sizeof msg) != BRUME_OK);
    ASSERT_CONTAINS(msg, "camera.medium: the camera at (0, 0, -3)");
    ASSERT_CONTAINS(msg, "is not inside \"fog\"");
}

/* A pbrt camera in a grey-to-red absorbing fog (sigma_a = 0.25, 0.5, 1), named by the
 * MediumInterface in effect at Camera, with a point light of intensity 10 where the camera is
 * and a diffuse wall (reflectance 0.5) facing it 2 ahead: the wall's radiance is
 * 0.5 / pi x 10 / 2^2 x exp(-sigma_a 2) on the way in and exp(-sigma_a 2) on the way back.
 * Across the 1-degree view the wall is farther by a factor 1 / cos(0.71 deg) (8e-5): a
 * relative spread of at most (3 + 4 sigma_a) 8e-5. The translation bounds pbrt-v4's
 * unbounded fog by the cube of half-side 64 / 0.25 around the camera. */
#define LIT_WALL                                                                                 \
    "Film \"rgb\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"                   \
    "Sampler \"halton\" \"integer pixelsamples\" [64]\n"                                         \
    "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [0.25 0.5 1]\n"     \
    "  \"rgb sigma_s\" [0 0 0]\n"                                                                \
    "MediumInterface \"\" \"fog\"\n"                                                             \
    "Scale -1 1 1\nLookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\" \"float fov\" [1]\n"       \
    "WorldBegin\n"                                                                               \
    "LightSource \"point\" \"rgb I\" [10 10 10]\n"                                               \
    "Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n"                                   \
    "Shape \"bilinearmesh\" \"point3 P\" [-5 -5 2  5 -5 2  -5 5 2  5 5 2]\n"

TEST(pbrt_camera_in_fog_sees_lit_wall)
{
    const char *path = test_tmp_path("wall.pbrt");
    test_write_file(path, LIT_WALL);
    char *json = NULL;
    if (scene_pbrt_json(path, &json) != BRUME_OK)
        TEST_FAIL("%s", err_message());
    cJSON *root = cJSON_Parse(json);
    free(json);
    const cJSON *cam = cJSON_GetObjectItemCaseSensitive(root, "camera");
    ASSERT_EQ_STR(cJSON_GetObjectItemCaseSensitive(cam, "medium")->valuestring, "fog");
    const cJSON *d = cJSON_GetObjectItemCaseSensitive(
        cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "media"), 0), "density");
    const cJSON *lo = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(d, "bounds"), 0);
    ASSERT_NEAR(cJSON_GetArrayItem(lo, 2)->valuedouble, -256.0, 1e-9);
    cJSON_Delete(root);

    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    brume_image *img = test_render_scene(s, -1, 13);
    int n = brume_image_width(img) * brume_image_height(img);
    const double sigma[3] = {0.25, 0.5, 1.0};
    for (int c = 0; c < 3; c++) {
        double mean, se, want = 0.5 / PI * 10.0 / 4.0 * exp(-4.0 * sigma[c]);
        test_channel_mean(brume_image_pixels(img), n, c, &mean, &se);
        if (!(fabs(mean - want) <= 4.0 * se + (3.0 + 4.0 * sigma[c]) * 8e-5 * want + 1e-7))
            TEST_FAIL("channel %d: mean %.6g, want %.6g (se %g)", c, mean, want, se);
    }
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
    remove(path);
}

/* A grid medium at the camera is its own field, bounded as pbrt-v4 bounds it: added as it is,
 * with no camera.medium (the camera may be outside its box, as in pbrt-v4). */
TEST(pbrt_camera_in_grid_adds_the_grid)
{
    const char *path = test_tmp_path("grid.pbrt");
    test_write_file(path, "MakeNamedMedium \"g\" \"string type\" \"uniformgrid\" \"float density\" [1]\n"
                          "MediumInterface \"g\"\n" VIEW "WorldBegin\n");
    char *json = NULL;
    if (scene_pbrt_json(path, &json) != BRUME_OK)
        TEST_FAIL("%s", err_message());
    cJSON *root = cJSON_Parse(json);
    free(json);
    ASSERT_EQ_INT(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "media")), 1);
    ASSERT_TRUE(!cJSON_HasObjectItem(cJSON_GetObjectItemCaseSensitive(root, "camera"), "medium"));
    cJSON_Delete(root);
    remove(path);
}

/* What a camera medium brings that brume cannot follow, each refused by name and line. */
TEST(camera_medium_refusals_name_file_and_line)
{
    /* pbrt-v4 attenuates a distant or infinite light over twice the scene's radius of fog */
    expect_refusal(FOG "MediumInterface \"\" \"fog\"\n" VIEW "WorldBegin\nLightSource \"distant\"\n", 6,
                   "LightSource \"distant\" with the camera in the homogeneous medium \"fog\"");
    expect_refusal(FOG "MediumInterface \"\" \"fog\"\n" VIEW "WorldBegin\nLightSource \"infinite\"\n", 6,
                   "LightSource \"infinite\"");
    expect_refusal("MediumInterface \"\" \"mist\"\n" VIEW "WorldBegin\n", 3, "no medium \"mist\"");
    /* an interface shape naming a medium no MakeNamedMedium gives */
    expect_refusal(FOG "MediumInterface \"\" \"fog\"\n" VIEW "WorldBegin\nMaterial \"interface\"\n"
                   "MediumInterface \"g\" \"fog\"\nShape \"sphere\"\n",
                   8, "MediumInterface: no medium named \"g\"");
    /* the same medium both sides of an interface shape is no transition in pbrt-v4 */
    expect_refusal(FOG VIEW "WorldBegin\nMaterial \"interface\"\nMediumInterface \"fog\"\nShape \"sphere\"\n", 7,
                   "no transition");
}

TEST_MAIN(film_types_refused_by_name, json_camera_in_fog_sees_transmittance, json_camera_medium_checked,
          pbrt_camera_in_fog_sees_lit_wall, pbrt_camera_in_grid_adds_the_grid, camera_medium_refusals_name_file_and_line)
