/* test_pbrt_sensor.c - pbrt-v4's film sensors (Film "sensor", render.sensor; docs/pbrt.md,
 * Film): the cie1931 sensor is the identity case; a camera's XYZFromSensorRGB and its film
 * response to a grey light against values computed from pbrt-v4's own source by a separate
 * program (scripts/pbrt_sensor_reference.py); brume's uplift of Rec. 709 to the camera's raw
 * values is the constrained least-squares fit over the 24 swatches (its optimality checked
 * from the data); renders of a grey sky through a camera, exposure and clamp included; and
 * names brume does not know refused. */
#include "test.h"
#include "pbrt_translate.h"

#include <math.h>
#include <string.h>

#include "brume.h"
#include "render/film.h"
#include "scene/film_sensor.h"

#include "../data/pbrt_sensors.inc"

#define VIEW "Scale -1 1 1\nLookAt 0 0 -5  0 0 0  0 1 0\n"

static const double xyz_from_rgb[9] = {0.4124564, 0.3575761, 0.1804375, 0.2126729, 0.7151522,
                                       0.0721750, 0.0193339, 0.1191920, 0.9503041};

static void row_sums(const double m[9], double out[3])
{
    for (int r = 0; r < 3; r++)
        out[r] = m[3 * r] + m[3 * r + 1] + m[3 * r + 2];
}

/* pbrt-v4's default sensor: its values are CIE XYZ and the film is the identity, or the
 * cie1931 white balance (film_white_balance, tested in test_pbrt_leftovers.c) with a kelvin. */
TEST(cie1931_is_the_identity_case)
{
    ASSERT_EQ_INT(film_sensor_find("cie1931"), 0);
    ASSERT_EQ_STR(brume_sensor_name(0), "cie1931");
    double A[9], N[9], wb[9];
    ASSERT_TRUE(!film_sensor_maps(0, 0.0, A, N));
    for (int i = 0; i < 9; i++) {
        ASSERT_NEAR(A[i], xyz_from_rgb[i], 0);
        ASSERT_NEAR(N[i], i % 4 == 0 ? 1.0 : 0.0, 0);
    }
    ASSERT_TRUE(film_sensor_maps(0, 4500.0, A, N));
    film_white_balance(4500.0, wb);
    for (int i = 0; i < 9; i++)
        ASSERT_NEAR(N[i], wb[i], 0);
}

/* The 17 cameras pbrt-v4 names, each found by its name and numbered 1 .. 17 in turn; each one's
 * film is made, and balanced to 6500 K (pbrt-v4's default for a camera: D(6500) is D65 within
 * its tabulation) it leaves white nearly white: pbrt-v4's fit of XYZ from the raw values is
 * not exact on white, about 2 % here, so within 0.03. */
TEST(every_pbrt_camera_is_named)
{
    static const char *const cams[] = {"canon_eos_100d", "canon_eos_1dx_mkii", "canon_eos_200d", "canon_eos_200d_mkii",
                                       "canon_eos_5d", "canon_eos_5d_mkii", "canon_eos_5d_mkiii", "canon_eos_5d_mkiv",
                                       "canon_eos_5ds", "canon_eos_m", "hasselblad_l1d_20c", "nikon_d810", "nikon_d850",
                                       "sony_ilce_6400", "sony_ilce_7m3", "sony_ilce_7rm3", "sony_ilce_9"};
    for (int i = 0; i < 17; i++) {
        ASSERT_EQ_INT(film_sensor_find(cams[i]), i + 1);
        ASSERT_EQ_STR(brume_sensor_name(i + 1), cams[i]);
        double A[9], N[9], w[3];
        ASSERT_TRUE(film_sensor_maps(i + 1, 0.0, A, N));
        row_sums(N, w);
        for (int c = 0; c < 3; c++)
            ASSERT_NEAR(w[c], 1.0, 0.03);
    }
    ASSERT_TRUE(brume_sensor_name(18) == NULL && brume_sensor_name(-1) == NULL);
    ASSERT_EQ_INT(film_sensor_find("nikon_d9000"), -1);
}

/* Reference values printed by `python3 scripts/pbrt_sensor_reference.py PBRT_V4 CAMERA KELVIN`
 * from pbrt-v4's source text (mmp/pbrt-v4 5f7a6068): XYZFromSensorRGB as PixelSensor fits it,
 * the camera's raw values of pbrt-v4's white light (rgb L [1 1 1]: D65 of luminance 1) and
 * what its RGB film writes for that light. */
typedef struct camera_ref {
    const char *name;
    double kelvin, xyz_from_raw[9], raw_white[3], film_white[3];
} camera_ref;

static const camera_ref refs[] = {
    {"nikon_d850", 5000, {1.4047567, 0.3019983, 0.2107121, 0.5715833, 1.1335590, -0.2753125, 0.2015021, -0.5391696, 2.5508813},
     {0.372791, 0.849690, 0.688020}, {0.797349, 1.011507, 1.300712}},
    {"canon_eos_100d", 0, {1.8044581, 0.0471274, 0.1992518, 0.6867286, 0.9810446, -0.3389998, 0.1400014, -0.4062369, 1.9657752},
     {0.417053, 0.967898, 0.721984}, {0.988344, 0.991496, 0.996697}},
    {"sony_ilce_9", 3000, {1.3052871, 0.3461882, 0.3647429, 0.3275346, 1.3727103, -0.4242800, 0.2326711, -0.8382682, 4.9991449},
     {0.355224, 0.944443, 0.727770}, {0.264841, 1.169257, 2.930325}},
};

static void mat3_mul(const double a[9], const double b[9], double out[9])
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            out[3 * r + c] = a[3 * r] * b[c] + a[3 * r + 1] * b[3 + c] + a[3 * r + 2] * b[6 + c];
}

/* A camera's film: the output of brume's white (1, 1, 1) is pbrt-v4's output of its white light,
 * the sensor's values of it are pbrt-v4's raw values, and XYZFromSensorRGB (recovered from the
 * two maps: XYZ_from_RGB film sensor_from_rgb^-1) is pbrt-v4's. The tolerance 2e-5 covers the
 * references' six decimals and pbrt-v4's sRGB matrix, made from D65's integrated white point,
 * against brume's standard one (differences ~1e-5). Swapping a camera's r and b moves the raw
 * white and M (the image itself is blind to a relabelling of the channels: M takes it back);
 * another camera's curves move all three. */
TEST(camera_film_is_pbrt_v4s)
{
    for (size_t k = 0; k < sizeof refs / sizeof refs[0]; k++) {
        const camera_ref *r = &refs[k];
        double A[9], N[9], w[3], raw[3];
        ASSERT_TRUE(film_sensor_maps(film_sensor_find(r->name), r->kelvin, A, N));
        row_sums(N, w);
        row_sums(A, raw);
        for (int c = 0; c < 3; c++) {
            ASSERT_NEAR(w[c], r->film_white[c], 2e-5);
            ASSERT_NEAR(raw[c], r->raw_white[c], 2e-6);
        }
        /* N = RGB_from_XYZ M A, so M = XYZ_from_RGB N A^-1: M A = XYZ_from_RGB N */
        double lhs[9], rhs[9];
        mat3_mul(r->xyz_from_raw, A, lhs);
        mat3_mul(xyz_from_rgb, N, rhs);
        for (int i = 0; i < 9; i++)
            ASSERT_NEAR(lhs[i], rhs[i], 3e-5);
    }
}

/* Spectra at whole nm 360 .. 830, the end values held (the test's own sampling of the data). */
static double at(const double *v, int n, int nm)
{
    if (nm <= v[0])
        return v[1];
    if (nm >= v[n - 2])
        return v[n - 1];
    int k = 0;
    while (v[2 * k + 2] < nm)
        k++;
    return v[2 * k + 1] + (nm - v[2 * k]) / (v[2 * k + 2] - v[2 * k]) * (v[2 * k + 3] - v[2 * k + 1]);
}

/* brume's uplift of a Rec. 709 colour to a camera's raw values, sensor_from_rgb, is the least-
 * squares fit over the 24 swatches under D65 with white held: the white's raw values are
 * exact, and the gradient of the squared residual, row by row, is normal to the constraint
 * (its three components equal): no matrix that keeps white fits the swatches better. The
 * residual itself is small against the swatches' raw values (RMS below 0.01). */
TEST(camera_uplift_is_constrained_least_squares)
{
    const int cam = film_sensor_find("nikon_d850");
    double A[9], N[9];
    ASSERT_TRUE(film_sensor_maps(cam, 0.0, A, N));
    const struct pbrt_camera_curves *cc = &pbrt_cameras[cam - 1];
    const int nd = (int)(sizeof pbrt_d65 / sizeof pbrt_d65[0]), ns = (int)(sizeof pbrt_swatches[0] / sizeof(double));
    double rgb_from_xyz[9] = {3.2404542, -1.5371385, -0.4985314, -0.9692660, 1.8760108, 0.0415560, 0.0556434, -0.2040259, 1.0572252};
    double yw = 0.0, white[3] = {0}, grad[3][3] = {{0}}, sq = 0.0;
    for (int nm = 360; nm <= 830; nm++)
        yw += pbrt_cie_y[nm - 360] * at(pbrt_d65, nd, nm);
    for (int c = 0; c < 3; c++)
        for (int nm = 360; nm <= 830; nm++)
            white[c] += at(cc->v[c], cc->n[c], nm) * at(pbrt_d65, nd, nm) / yw;
    for (int i = 0; i < 24; i++) {
        double xyz[3] = {0}, raw[3] = {0}, s[3];
        for (int nm = 360; nm <= 830; nm++) {
            double e = at(pbrt_swatches[i], ns, nm) * at(pbrt_d65, nd, nm) / yw;
            xyz[0] += pbrt_cie_x[nm - 360] * e;
            xyz[1] += pbrt_cie_y[nm - 360] * e;
            xyz[2] += pbrt_cie_z[nm - 360] * e;
            for (int c = 0; c < 3; c++)
                raw[c] += at(cc->v[c], cc->n[c], nm) * e;
        }
        for (int c = 0; c < 3; c++)
            s[c] = rgb_from_xyz[3 * c] * xyz[0] + rgb_from_xyz[3 * c + 1] * xyz[1] + rgb_from_xyz[3 * c + 2] * xyz[2];
        for (int k = 0; k < 3; k++) {
            double e = A[3 * k] * s[0] + A[3 * k + 1] * s[1] + A[3 * k + 2] * s[2] - raw[k];
            sq += e * e;
            for (int c = 0; c < 3; c++)
                grad[k][c] += e * s[c];
        }
    }
    double w[3];
    row_sums(A, w);
    for (int k = 0; k < 3; k++) {
        ASSERT_NEAR(w[k], white[k], 1e-9);
        ASSERT_NEAR(grad[k][0], grad[k][1], 1e-9);
        ASSERT_NEAR(grad[k][1], grad[k][2], 1e-9);
    }
    ASSERT_TRUE(sqrt(sq / 72.0) < 0.01);
}

/* A sky of rgb L [0.25 0.25 0.25] through pbrt-v4's nikon_d850 balanced at 5000 K with iso 200
 * renders every pixel as pbrt-v4's film white times 0.25 x 2 (the imaging ratio, iso / 100):
 * no noise, each sample sees the sky. */
TEST(nikon_d850_renders_grey_sky_as_pbrt)
{
    char msg[2048];
    cJSON *root = pbrt_translate("sky.pbrt",
                                 "Film \"rgb\" \"integer xresolution\" 4 \"integer yresolution\" 4 \"string sensor\" "
                                 "\"nikon_d850\" \"float whitebalance\" 5000 \"float iso\" 200\nSampler \"independent\" "
                                 "\"integer pixelsamples\" 2\n" VIEW "Camera \"perspective\"\nWorldBegin\n"
                                 "LightSource \"infinite\" \"rgb L\" [0.25 0.25 0.25]\n",
                                 msg, sizeof msg);
    if (!root)
        TEST_FAIL("%s", msg);
    const cJSON *r = cJSON_GetObjectItemCaseSensitive(root, "render");
    ASSERT_EQ_STR(cJSON_GetObjectItemCaseSensitive(r, "sensor")->valuestring, "nikon_d850");
    char *json = cJSON_PrintUnformatted(root);
    cJSON_Delete(root);
    brume_image *img = test_render_json(json, 1);
    free(json);
    const float *px = brume_image_pixels(img);
    for (int p = 0; p < 16; p++)
        for (int c = 0; c < 3; c++)
            ASSERT_NEAR(px[4 * p + c], 0.5 * refs[0].film_white[c], 2e-5);
    brume_image_release(img);
}

/* A grey diffuse quad (pbrt's default reflectance 0.5) facing a distant light of irradiance pi
 * (rgb L [1 1 1], scale pi) has radiance 0.5: through the nikon_d850 at 5000 K with iso 400
 * every pixel is pbrt-v4's film white times 0.5 x 4. The light is sampled exactly and the
 * paths that leave the quad find nothing, so the pixels carry no noise; the "gbuffer" film is
 * the same film. */
TEST(nikon_d850_renders_lit_grey_quad_as_pbrt)
{
    char msg[2048];
    cJSON *root = pbrt_translate("quad.pbrt",
                                 "Film \"gbuffer\" \"integer xresolution\" 4 \"integer yresolution\" 4 \"string sensor\" "
                                 "\"nikon_d850\" \"float whitebalance\" 5000 \"float iso\" 400\nSampler \"independent\" "
                                 "\"integer pixelsamples\" 4\n" VIEW "Camera \"perspective\" \"float fov\" 20\nWorldBegin\n"
                                 "LightSource \"distant\" \"point3 from\" [0 0 -1] \"point3 to\" [0 0 0] \"rgb L\" [1 1 1] "
                                 "\"float scale\" 3.14159265358979\nMaterial \"diffuse\"\nShape \"bilinearmesh\" "
                                 "\"point3 P\" [-10 -10 0  10 -10 0  -10 10 0  10 10 0]\n",
                                 msg, sizeof msg);
    if (!root)
        TEST_FAIL("%s", msg);
    char *json = cJSON_PrintUnformatted(root);
    cJSON_Delete(root);
    brume_image *img = test_render_json(json, 3);
    free(json);
    const float *px = brume_image_pixels(img);
    for (int p = 0; p < 16; p++)
        for (int c = 0; c < 3; c++)
            ASSERT_NEAR(px[4 * p + c], 2.0 * refs[0].film_white[c], 1e-4);
    brume_image_release(img);
}

/* render.max_component clamps a camera's raw values, not XYZ: a sky of (1, 1, 1) through the
 * canon_eos_100d (raw white 0.417, 0.968, 0.722 in pbrt-v4) clamped at 0.5 is pbrt-v4's film
 * white times 0.5 / 0.967898 (the clamp at Z = 1.089 would give 0.5 / 1.089). */
TEST(max_component_clamps_camera_values)
{
    brume_image *img = test_render_json("{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]}, \"background\": [1, 1, 1],"
                                        " \"render\": {\"width\": 2, \"height\": 2, \"spp\": 2, \"sensor\": \"canon_eos_100d\","
                                        " \"max_component\": 0.5}}",
                                        1);
    const float *px = brume_image_pixels(img);
    for (int c = 0; c < 3; c++)
        ASSERT_NEAR(px[c], refs[1].film_white[c] * 0.5 / refs[1].raw_white[1], 3e-5);
    brume_image_release(img);
}

/* Names brume does not know: refused by name, with the .pbrt file and line, or render.sensor. */
TEST(unknown_sensor_refused_by_name)
{
    char msg[2048], want[1200];
    ASSERT_TRUE(pbrt_translate("f.pbrt", "\nFilm \"rgb\" \"string sensor\" \"kodak_dcs\"\n" VIEW "Camera \"perspective\"\nWorldBegin\n",
                               msg, sizeof msg) == NULL);
    snprintf(want, sizeof want, "%s:2: ", test_tmp_path("f.pbrt"));
    ASSERT_CONTAINS(msg, want);
    ASSERT_CONTAINS(msg, "\"sensor\": \"kodak_dcs\"");
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    ASSERT_TRUE(brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = "{\"render\": {\"sensor\": \"kodak_dcs\"}}"},
                                 NULL, &s) != BRUME_OK);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "render.sensor: unknown sensor 'kodak_dcs'");
    brume_context_release(ctx);
}

TEST_MAIN(cie1931_is_the_identity_case, every_pbrt_camera_is_named, camera_film_is_pbrt_v4s,
          camera_uplift_is_constrained_least_squares, nikon_d850_renders_grey_sky_as_pbrt,
          nikon_d850_renders_lit_grey_quad_as_pbrt,
          max_component_clamps_camera_values, unknown_sensor_refused_by_name)
