/* test_pbrt_sky.c - image skies as pbrt-v4 writes them (docs/pbrt.md, docs/scene-format.md
 * "background"): the equal-area octahedral map against pbrt-v4's EqualAreaSquareToSphere,
 * written out here from its definition, and its area measured by finite differences; a
 * constant map against a constant background; one bright texel lighting a diffuse plane
 * against the irradiance integrated here over the texel; pbrt-v4's "illuminance"
 * normalisation; sampling against evaluation (chi-square); the refusals. */
#include "test.h"
#include "pbrt_translate.h"

#include <math.h>

#include "brume.h"
#include "core/error.h"
#include "core/rng.h"
#include "io/json.h"
#include "scene/background.h"
#include "scene/scene.h"
#include "scene/scene_pbrt.h"

#define PI_D 3.14159265358979323846

/* pbrt-v4's EqualAreaSquareToSphere (util/math.cpp), as its source writes it. */
static void pbrt_square_to_sphere(double px, double py, double w[3])
{
    double u = 2 * px - 1, v = 2 * py - 1;
    double up = fabs(u), vp = fabs(v);
    double signed_distance = 1 - (up + vp);
    double d = fabs(signed_distance);
    double r = 1 - d;
    double phi = (r == 0 ? 1 : (vp - up) / r + 1) * PI_D / 4;
    double z = copysign(1 - r * r, signed_distance);
    double cos_phi = copysign(cos(phi), u), sin_phi = copysign(sin(phi), v);
    double k = r * sqrt(fmax(0.0, 2 - r * r));
    w[0] = cos_phi * k;
    w[1] = sin_phi * k;
    w[2] = z;
}

/* An N x N image of value v everywhere but texel (bx, by), which has bright (grey). */
static void write_map(const char *path, int n, double v, int bx, int by, double bright)
{
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    ASSERT_EQ_INT(brume_image_new(ctx, n, n, &img), BRUME_OK);
    float *px = brume_image_pixels(img);
    for (int i = 0; i < n * n; i++) {
        double x = (i % n == bx && i / n == by) ? bright : v;
        px[4 * i] = px[4 * i + 1] = px[4 * i + 2] = (float)x;
        px[4 * i + 3] = 1.0f;
    }
    if (brume_image_write(ctx, img, path, NULL) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    brume_image_release(img);
    brume_context_release(ctx);
}

/* pbrt-v4's map at its anchors (the centre +z, the edges' midpoints +-x and +-y, the corners
 * -z), brume's map equal to pbrt-v4's over a grid, and its inverse the inverse. */
TEST(equal_area_map_is_pbrt_and_round_trips)
{
    const double anchors[][5] = {{0.5, 0.5, 0, 0, 1}, {1, 0.5, 1, 0, 0}, {0, 0.5, -1, 0, 0}, {0.5, 1, 0, 1, 0},
                                 {0.5, 0, 0, -1, 0},  {0, 0, 0, 0, -1},  {1, 1, 0, 0, -1}};
    for (int i = 0; i < 7; i++) {
        vec3 w = bg_equal_area_to_sphere(anchors[i][0], anchors[i][1]);
        ASSERT_NEAR(w.x, anchors[i][2], 1e-12);
        ASSERT_NEAR(w.y, anchors[i][3], 1e-12);
        ASSERT_NEAR(w.z, anchors[i][4], 1e-12);
    }
    const int n = 97;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double u = (i + 0.37) / n, v = (j + 0.61) / n, p[3], bu, bv;
            pbrt_square_to_sphere(u, v, p);
            vec3 w = bg_equal_area_to_sphere(u, v);
            ASSERT_NEAR(w.x, p[0], 1e-12);
            ASSERT_NEAR(w.y, p[1], 1e-12);
            ASSERT_NEAR(w.z, p[2], 1e-12);
            ASSERT_NEAR(v3_length(w), 1.0, 1e-12);
            bg_sphere_to_equal_area(w, &bu, &bv);
            ASSERT_NEAR(bu, u, 1e-9);
            ASSERT_NEAR(bv, v, 1e-9);
        }
}

/* Equal area: the map's Jacobian |dw/du x dw/dv|, by central differences of pbrt-v4's map
 * written out above, is 4 pi everywhere off its folds (the axes and the diagonals of the
 * square, where it is not differentiable). */
TEST(equal_area_map_is_equal_area)
{
    rng g = rng_make(7, 0, 0);
    const double h = 1e-6;
    int checked = 0;
    for (int i = 0; i < 4000; i++) {
        double u = rng_next(&g), v = rng_next(&g), a = 2 * u - 1, b = 2 * v - 1;
        if (fabs(a) < 1e-3 || fabs(b) < 1e-3 || fabs(fabs(a) + fabs(b) - 1) < 1e-3 || u < h || v < h || u > 1 - h ||
            v > 1 - h)
            continue;
        double up[3], um[3], vp[3], vm[3];
        pbrt_square_to_sphere(u + h, v, up);
        pbrt_square_to_sphere(u - h, v, um);
        pbrt_square_to_sphere(u, v + h, vp);
        pbrt_square_to_sphere(u, v - h, vm);
        vec3 du = v3_scale(v3(up[0] - um[0], up[1] - um[1], up[2] - um[2]), 0.5 / h);
        vec3 dv = v3_scale(v3(vp[0] - vm[0], vp[1] - vm[1], vp[2] - vm[2]), 0.5 / h);
        ASSERT_NEAR(v3_length(v3_cross(du, dv)), 4 * PI_D, 1e-4);
        checked++;
    }
    ASSERT_TRUE(checked > 3800);
}

/* A diffuse plane of albedo 0.5 seen from above under a constant sky L sends 0.5 L: the same
 * for an equal-area map of one value everywhere (turned and mirrored) and for the constant
 * background, each within 4 standard errors. */
TEST(constant_map_equals_constant_background)
{
    char map[512];
    snprintf(map, sizeof map, "%s", test_tmp_path("const.pfm"));
    write_map(map, 8, 0.6, 0, 0, 0.6);
    char json[2048];
    for (int k = 0; k < 2; k++) {
        char sky[1200];
        if (k == 0)
            snprintf(sky, sizeof sky,
                     "{\"file\": \"%s\", \"mapping\": \"equal_area\", \"scale\": 2,"
                     " \"transform\": {\"rotate\": {\"axis\": [1, 1, 0], \"angle\": 30}, \"scale\": [-1, 1, 1]}}",
                     map);
        else
            snprintf(sky, sizeof sky, "[1.2, 1.2, 1.2]");
        snprintf(json, sizeof json,
                 "{\"camera\": {\"position\": [0, 10, 0], \"look_at\": [0, 0, 0], \"up\": [0, 0, -1], \"fov\": 5},"
                 " \"background\": %s,"
                 " \"surfaces\": [{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 1, 0], \"size\": 400,"
                 "                 \"material\": {\"albedo\": 0.5}}],"
                 " \"render\": {\"width\": 16, \"height\": 16, \"spp\": 64, \"max_depth\": 1}}",
                 sky);
        brume_image *img = test_render_json(json, 3);
        double mean, se;
        test_channel_mean(brume_image_pixels(img), 256, 1, &mean, &se);
        fprintf(stderr, "%s sky: %.6f +- %.6f, expected 0.6\n", k == 0 ? "equal-area" : "constant", mean, se);
        ASSERT_NEAR(mean, 0.6, 4 * se + 1e-6);
        brume_image_release(img);
    }
    remove(map);
}

/* The irradiance on a surface whose normal is the map's +z, from texel (bx, by) of an n x n
 * map of radiance V: V 4 pi times the integral of cos theta over the texel's part of the unit
 * square (4 pi steradians per unit square), by the midpoint rule on 128 x 128 sub-cells. */
static double texel_irradiance(int n, int bx, int by, double V)
{
    const int m = 128;
    double sum = 0.0;
    for (int i = 0; i < m; i++)
        for (int j = 0; j < m; j++) {
            double w[3];
            pbrt_square_to_sphere((bx + (i + 0.5) / m) / n, (by + (j + 0.5) / m) / n, w);
            sum += fmax(0.0, w[2]);
        }
    return V * 4 * PI_D * sum / ((double)m * m * n * n);
}

/* One bright texel of an equal-area map turned so its +z is world +y lights a diffuse plane
 * facing +y with albedo / pi times the irradiance integrated over the texel; the map is also
 * mirrored in x, which the plane does not see but a direct look-up does. */
TEST(one_bright_texel_lights_plane)
{
    const int n = 16, bx = 9, by = 6;
    const double V = 40.0;
    char map[512];
    snprintf(map, sizeof map, "%s", test_tmp_path("texel.exr"));
    write_map(map, n, 0.0, bx, by, V);
    char json[2048];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 10, 0], \"look_at\": [0, 0, 0], \"up\": [0, 0, -1], \"fov\": 5},"
             " \"background\": {\"file\": \"%s\", \"mapping\": \"equal_area\","
             "   \"transform\": {\"rotate\": {\"axis\": [1, 0, 0], \"angle\": -90}, \"scale\": [-1, 1, 1]}},"
             " \"surfaces\": [{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 1, 0], \"size\": 400,"
             "                 \"material\": {\"albedo\": 0.5}}],"
             " \"render\": {\"width\": 16, \"height\": 16, \"spp\": 64, \"max_depth\": 1}}",
             map);
    brume_scene *s = test_scene_json(json);
    /* the texel's centre in the map's frame, then in the world: (x, y, z) -> (-x, z, -y) */
    double c[3];
    pbrt_square_to_sphere((bx + 0.5) / n, (by + 0.5) / n, c);
    ASSERT_NEAR(background_eval(&s->bg, v3(-c[0], c[2], -c[1])).c[0], V, 1e-6);
    ASSERT_NEAR(background_eval(&s->bg, v3(c[0], c[2], -c[1])).c[0], 0.0, 0); /* not mirrored: another texel */
    brume_image *img = test_render_scene(s, -1, 5);
    double mean, se, want = 0.5 / PI_D * texel_irradiance(n, bx, by, V);
    test_channel_mean(brume_image_pixels(img), 256, 0, &mean, &se);
    fprintf(stderr, "plane under one texel: %.6f +- %.6f, expected %.6f\n", mean, se, want);
    ASSERT_NEAR(mean, want, 4 * se + 1e-6 * want);
    ASSERT_TRUE(4 * se < 0.02 * want);
    brume_image_release(img);
    brume_scene_release(s);
    remove(map);
}

/* Sampling follows the map's luminance: the texel of each sampled direction, counted over
 * 200000 samples of a map of 64 texels of varying values (turned and mirrored), against the
 * luminance share of each texel (chi-square, 63 degrees of freedom, p = 0.001); and each
 * sample's pdf is the pdf of its direction, proportional to the radiance evaluated there. */
TEST(sampling_pdf_matches_eval)
{
    const int n = 8;
    char map[512];
    snprintf(map, sizeof map, "%s", test_tmp_path("chi.pfm"));
    brume_context *ctx = brume_context_new();
    brume_image *im = NULL;
    ASSERT_EQ_INT(brume_image_new(ctx, n, n, &im), BRUME_OK);
    float *px = brume_image_pixels(im);
    double lum[64], total = 0.0;
    for (int i = 0; i < n * n; i++) {
        double r = 0.1 + (i * 37 % 11), g = 0.5 + (i * 13 % 7), b = (i % 5 == 0) ? 20.0 : 0.2;
        px[4 * i] = (float)r, px[4 * i + 1] = (float)g, px[4 * i + 2] = (float)b, px[4 * i + 3] = 1.0f;
        lum[i] = ((double)(float)r + (double)(float)g + (double)(float)b) / 3.0;
        total += lum[i];
    }
    ASSERT_EQ_INT(brume_image_write(ctx, im, map, NULL), BRUME_OK);
    brume_image_release(im);
    char json[2048];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},"
             " \"background\": {\"file\": \"%s\", \"mapping\": \"equal_area\", \"scale\": 3,"
             " \"transform\": {\"rotate\": {\"axis\": [1, 2, 3], \"angle\": 70}, \"scale\": [1, -1, 1]}}}",
             map);
    brume_scene *s = test_scene_json(json);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    const background *bg = &s->bg;
    double count[64] = {0};
    const int N = 200000;
    rng g = rng_make(11, 0, 0);
    int off = 0;
    for (int i = 0; i < N; i++) {
        double pdf;
        color L;
        vec3 w = background_sample(bg, rng_next(&g), rng_next(&g), &pdf, &L);
        double u, v;
        bg_sphere_to_equal_area(frame_to_local(&bg->f, w), &u, &v);
        int t = (int)(v * n) * n + (int)(u * n);
        count[t] += 1;
        double want = lum[t] / total * n * n / (4 * PI_D);
        if (fabs(pdf - want) > 1e-9 * want || fabs(background_pdf(bg, w) - pdf) > 1e-9 * pdf ||
            fabs(col_avg(L) / 3.0 - lum[t]) > 1e-6 * lum[t])
            off++; /* a sample on a texel's edge, which a rounding may put in its neighbour */
    }
    ASSERT_TRUE(off < 10);
    double chi2 = 0.0;
    for (int t = 0; t < n * n; t++) {
        double e = N * lum[t] / total;
        chi2 += (count[t] - e) * (count[t] - e) / e;
    }
    fprintf(stderr, "chi-square %.2f over 63 degrees of freedom (p = 0.001 at 103.4)\n", chi2);
    ASSERT_TRUE(chi2 < 103.4);
    brume_scene_release(s);
    brume_context_release(ctx);
    remove(map);
}

/* The translation of a .pbrt text; NULL and *msg set when it is refused. */
static cJSON *translate(const char *text, char *msg, size_t cap)
{
    return pbrt_translate("sky.pbrt", text, msg, cap);
}

#define SKY_VIEW                                                                                 \
    "Film \"rgb\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"                   \
    "Sampler \"halton\" \"integer pixelsamples\" [64]\n"                                         \
    "LookAt 0 0 10  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [5]\nWorldBegin\n"

/* pbrt-v4's "illuminance" E_v on an image sky: the scale becomes E_v / k_e, k_e pbrt-v4's sum
 * 2 pi / texels x sum over the texels of the upper half of Y cos theta at their centres
 * (lights.cpp); the bare LookAt's mirrored world leaves a plane facing +z lit alike. The
 * plane's radiance is albedo / pi times the texel's irradiance at that scale: about 2 E_v,
 * since pbrt-v4's sum weighs a texel by half its solid angle. */
TEST(illuminance_scales_sky_as_pbrt)
{
    const int n = 16, bx = 9, by = 6;
    const double V = 40.0, E_v = 3.0;
    char map[512];
    snprintf(map, sizeof map, "%s", test_tmp_path("sky.pfm"));
    write_map(map, n, 0.0, bx, by, V);
    char text[2048], msg[2048];
    snprintf(text, sizeof text,
             SKY_VIEW "LightSource \"infinite\" \"string filename\" \"%s\" \"float illuminance\" [%g]\n"
                      "Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n"
                      "Shape \"bilinearmesh\" \"point3 P\" [-50 -50 0  50 -50 0  -50 50 0  50 50 0]\n",
             map, E_v);
    cJSON *root = translate(text, msg, sizeof msg);
    if (!root)
        TEST_FAIL("%s", msg);
    double c[3];
    pbrt_square_to_sphere((bx + 0.5) / n, (by + 0.5) / n, c);
    double k_e = 2 * PI_D / (n * n) * V * (0.212639 + 0.715169 + 0.072192) * c[2], scale = E_v / k_e;
    const cJSON *b = cJSON_GetObjectItemCaseSensitive(root, "background");
    ASSERT_EQ_STR(cJSON_GetObjectItemCaseSensitive(b, "mapping")->valuestring, "equal_area");
    ASSERT_NEAR(cJSON_GetObjectItemCaseSensitive(b, "scale")->valuedouble, scale, 1e-9 * scale);
    cJSON_Delete(root);

    const char *path = test_tmp_path("sky.pbrt");
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    brume_image *img = test_render_scene(s, -1, 17);
    double E = scale * texel_irradiance(n, bx, by, V), mean, se;
    ASSERT_NEAR(E / E_v, 2.0, 0.02);
    test_channel_mean(brume_image_pixels(img), 256, 1, &mean, &se);
    fprintf(stderr, "plane under the sky of illuminance %g: %.6f +- %.6f, expected %.6f\n", E_v, mean, se,
            0.5 / PI_D * E);
    ASSERT_NEAR(mean, 0.5 / PI_D * E, 4 * se + 1e-6 * E);
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
    remove(path);
    remove(map);
}

/* What pbrt-v4 refuses or brume cannot follow, each with the LightSource's line. */
TEST(sky_refusals_name_file_and_line)
{
    char sq[512], wide[512];
    snprintf(sq, sizeof sq, "%s", test_tmp_path("sq.pfm"));
    snprintf(wide, sizeof wide, "%s", test_tmp_path("wide.pfm"));
    write_map(sq, 4, 1.0, 0, 0, 1.0);
    brume_context *ctx = brume_context_new();
    brume_image *im = NULL;
    ASSERT_EQ_INT(brume_image_new(ctx, 8, 4, &im), BRUME_OK);
    ASSERT_EQ_INT(brume_image_write(ctx, im, wide, NULL), BRUME_OK);
    brume_image_release(im);
    brume_context_release(ctx);
    /* before the file's name, and after it */
    struct {
        const char *before, *after, *frag;
    } cases[] = {
        {"", "", "8 x 4 pixels: pbrt-v4 reads square"},
        {"", " \"point3 portal\" [0 0 0 1 0 0 1 1 0 0 1 0]", "\"portal\": not supported"},
        {"", " \"rgb L\" [1 1 1]", "both \"L\" and \"filename\""},
        {"LightSource \"infinite\" \"rgb L\" [1 1 1]\n", "", "a second infinite light with an image sky"},
        {"Scale 1 2 1\n", "", "not a rotation and a uniform scale"},
    };
    for (int i = 0; i < 5; i++) {
        char text[2048], msg[2048], want[1200];
        snprintf(text, sizeof text, SKY_VIEW "%sLightSource \"infinite\" \"string filename\" \"%s\"%s\n", cases[i].before,
                 i == 0 ? wide : sq, cases[i].after);
        ASSERT_TRUE(translate(text, msg, sizeof msg) == NULL);
        snprintf(want, sizeof want, "%s:%d: ", test_tmp_path("sky.pbrt"), i == 3 || i == 4 ? 7 : 6);
        ASSERT_CONTAINS(msg, want);
        ASSERT_CONTAINS(msg, cases[i].frag);
    }
    remove(sq);
    remove(wide);
    remove(test_tmp_path("sky.pbrt"));
}

TEST_MAIN(equal_area_map_is_pbrt_and_round_trips, equal_area_map_is_equal_area, constant_map_equals_constant_background,
          one_bright_texel_lights_plane, sampling_pdf_matches_eval, illuminance_scales_sky_as_pbrt,
          sky_refusals_name_file_and_line)
