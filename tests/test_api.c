/* test_api.c - the public scene builders: a scene built through them renders byte for byte
 * as the same scene read from JSON (the reader is their client), an array density as the
 * same values read from a raw file, borrowed memory is released once, and every builder
 * rejects bad arguments with a message naming itself and the argument, changing nothing. */
#include "test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brume.h"
#include "core/vec.h"
#include "core/xform.h"

#define OK(call) ASSERT_EQ_INT((call), BRUME_OK)

static const char *write_text(const char *name, const char *text)
{
    const char *path = test_tmp_path(name);
    FILE *fp = fopen(path, "wb");
    ASSERT_TRUE(fp != NULL);
    fputs(text, fp);
    fclose(fp);
    return path;
}

static brume_image *render(brume_context *ctx, brume_scene *s)
{
    brume_image *img = NULL;
    if (brume_scene_commit(ctx, s) != BRUME_OK || brume_render(ctx, s, &img) != BRUME_OK)
        TEST_FAIL("render: %s", brume_context_last_error(ctx));
    return img;
}

static void assert_same_image(const brume_image *a, const brume_image *b)
{
    ASSERT_EQ_INT(brume_image_width(a), brume_image_width(b));
    ASSERT_EQ_INT(brume_image_height(a), brume_image_height(b));
    size_t n = (size_t)brume_image_width(a) * (size_t)brume_image_height(a) * 4;
    const float *pa = brume_image_pixels(a), *pb = brume_image_pixels(b);
    double sum = 0.0;
    for (size_t i = 0; i < n; i++) {
        if (memcmp(&pa[i], &pb[i], sizeof *pa) != 0)
            TEST_FAIL("pixel value %zu differs: %.9g vs %.9g", i, (double)pa[i], (double)pb[i]);
        sum += pa[i];
    }
    ASSERT_TRUE(sum > 0.0); /* a black picture would prove nothing */
}

/* Renders a and b (committing them), asserts the same bytes, releases both. */
static void assert_same_render(brume_context *ctx, brume_scene *a, brume_scene *b)
{
    brume_image *ia = render(ctx, a), *ib = render(ctx, b);
    assert_same_image(ia, ib);
    brume_image_release(ia);
    brume_image_release(ib);
    brume_scene_release(a);
    brume_scene_release(b);
}

static brume_scene *load_text(brume_context *ctx, const char *json, double time)
{
    brume_scene *s = NULL;
    brume_source src = {.path = "api-test.json", .text = json};
    if (brume_scene_load(ctx, &src, &(brume_load_options){.time = time}, &s) != BRUME_OK)
        TEST_FAIL("load: %s", brume_context_last_error(ctx));
    return s;
}

/* The JSON side of every_feature_equals_json; the mesh file name is %s. */
static const char EVERY_FEATURE_JSON[] =
    "{\"render\": {\"width\": 40, \"height\": 30, \"spp\": 4, \"seed\": 7, \"max_depth\": 8, \"fps\": 10},"
    " \"camera\": {\"position\": [0, 0.5, 6], \"look_at\": [0, 0, 0], \"fov\": 35, \"aperture_radius\": 0.02,"
    "   \"focus_distance\": 6, \"shutter\": [0, 0.05],"
    "   \"keyframes\": [{\"time\": 0, \"position\": [0, 0.5, 6]}, {\"time\": 1, \"position\": [0.5, 0.5, 6]}]},"
    " \"background\": [0.05, 0.1, 0.2],"
    " \"lights\": ["
    "  {\"type\": \"distant\", \"direction\": [-1, -1, -0.5], \"irradiance\": [2, 2, 1.8], \"angular_radius\": 1},"
    "  {\"type\": \"point\", \"position\": [2, 2, 2], \"intensity\": 3,"
    "   \"keyframes\": [{\"time\": 0, \"intensity\": 1}, {\"time\": 1, \"intensity\": 3}]},"
    "  {\"type\": \"spot\", \"position\": [-2, 2, 2], \"direction\": [1, -1, -1], \"intensity\": 5,"
    "   \"cone_angle\": 40, \"falloff_start\": 30},"
    "  {\"type\": \"spot\", \"position\": [0, 3, 0], \"direction\": [0, -1, 0], \"intensity\": 4,"
    "   \"profile\": [[0, 1], [20, 0.5], [45, 0]]},"
    "  {\"type\": \"sphere\", \"position\": [0, 3, 3], \"radius\": 0.3, \"radiance\": 2},"
    "  {\"type\": \"disk\", \"position\": [3, 0, 0], \"direction\": [-1, 0, 0], \"radius\": 0.5,"
    "   \"radiance\": [1, 0.5, 0.5]}],"
    " \"media\": ["
    "  {\"name\": \"fog\", \"density\": {\"type\": \"constant\", \"value\": 0.2,"
    "   \"bounds\": [[-3, -1, -3], [3, -0.5, 3]]}, \"sigma_a\": 0.1, \"sigma_s\": [0.5, 0.6, 0.7],"
    "   \"phase\": {\"type\": \"hg\", \"g\": 0.3}},"
    "  {\"density\": {\"type\": \"procedural_cloud\", \"resolution\": 16, \"seed\": 3,"
    "   \"bounds\": [[-1, -0.5, -1], [1, 0.5, 1]]}, \"sigma_a\": 0.5, \"sigma_s\": 4,"
    "   \"phase\": {\"type\": \"mixture\", \"lobes\": [{\"weight\": 0.7, \"phase\": {\"type\": \"schlick\", \"k\": 0.5}},"
    "     {\"weight\": 0.3, \"phase\": {\"type\": \"rayleigh\"}}]},"
    "   \"keyframes\": [{\"time\": 0, \"transform\": {\"translate\": [0, 0, 0]}},"
    "     {\"time\": 1, \"transform\": {\"translate\": [0.2, 0, 0], \"rotate\": {\"axis\": [0, 1, 0], \"angle\": 10}}}]},"
    "  {\"density\": {\"type\": \"fractal_cloud\", \"dims\": [8, 8, 4], \"seed\": 2, \"threshold_rate\": 0.5,"
    "   \"bounds\": [[1, 0, -1], [2, 1, 0]], \"filter\": \"trilinear\"}, \"sigma_a\": 1, \"sigma_s\": 2,"
    "   \"emission\": [0.5, 0.2, 0], \"phase\": {\"type\": \"schlick_mix\", \"r\": 0.5, \"k\": 0.3, \"kprime\": -0.2}},"
    "  {\"density\": {\"type\": \"blobs\", \"blobs\": [[-1.5, 0.5, 0, 1, 0.3]], \"velocity\": [0.1, 0, 0],"
    "   \"generators\": [{\"type\": \"cloud\", \"center\": [-1.5, 1, 0], \"radii\": 0.4, \"count\": 10, \"seed\": 4}]},"
    "   \"sigma_a\": 0.2, \"sigma_s\": 2, \"phase\": {\"type\": \"murky\"}}],"
    " \"surfaces\": ["
    "  {\"type\": \"plane\", \"point\": [0, -1, 0], \"normal\": [0, 1, 0], \"size\": 20,"
    "   \"material\": {\"albedo\": [0.5, 0.5, 0.4]}},"
    "  {\"type\": \"sphere\", \"center\": [1, -0.5, 1], \"radius\": 0.4, \"name\": \"ball\","
    "   \"material\": {\"albedo\": 0.3, \"specular\": 0.5, \"exponent\": 20}},"
    "  {\"type\": \"box\", \"min\": [-2, -1, -1], \"max\": [-1.5, -0.2, -0.5],"
    "   \"transform\": {\"rotate\": {\"axis\": [0, 1, 0], \"angle\": 30}},"
    "   \"keyframes\": [{\"time\": 0, \"transform\": {\"translate\": [0, 0, 0]}},"
    "     {\"time\": 1, \"transform\": {\"translate\": [0, 0.3, 0]}}]},"
    "  {\"type\": \"quad\", \"corner\": [-1, -1, -2], \"edge_u\": [2, 0, 0], \"edge_v\": [0, 1, 0],"
    "   \"material\": {\"emission\": [0.5, 0.5, 0.5], \"two_sided\": true}},"
    "  {\"type\": \"mesh\", \"file\": \"%s\"}],"
    " \"stam\": {\"time\": 0.5}}";

static const char TRIANGLE_OBJ[] = "v 0.5 -1 0.5\nv 1.5 -1 0.5\nv 1 0 0.5\nf 1 2 3\n";

/* The settings (frame 3 at 10 fps: the time it returns), the camera and its keys, the
 * background of the scene below, through the builders. */
static double every_feature_settings(brume_context *ctx, brume_scene *s)
{
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    rs.width = 40;
    rs.height = 30;
    rs.spp = 4;
    rs.seed = 7;
    rs.max_depth = 8;
    rs.fps = 10;
    OK(brume_scene_set_settings(ctx, s, &rs));
    double t = 3.0 / 10.0; /* frame 3 */
    OK(brume_scene_set_time(ctx, s, t));
    brume_camera cam = {.position = {0, 0.5, 6}, .look_at = {0, 0, 0}, .up = {0, 1, 0}, .fov = 35,
                        .aperture_radius = 0.02, .focus_distance = 6, .shutter_open = 0, .shutter_close = 0.05};
    OK(brume_scene_set_camera(ctx, s, &cam));
    brume_camera_key keys[2] = {
        {.time = 0, .position = {0, 0.5, 6}, .look_at = {0, 0, 0}, .up = {0, 1, 0}, .fov = 35,
         .aperture_radius = 0.02, .focus_distance = 6},
        {.time = 1, .position = {0.5, 0.5, 6}, .look_at = {0, 0, 0}, .up = {0, 1, 0}, .fov = 35,
         .aperture_radius = 0.02, .focus_distance = 6}};
    OK(brume_scene_set_camera_keys(ctx, s, keys, 2));
    OK(brume_scene_set_background_color(ctx, s, (double[3]){0.05, 0.1, 0.2}));
    return t;
}

/* Its lights at time t. */
static void every_feature_lights(brume_context *ctx, brume_scene *s, double t)
{
    OK(brume_scene_add_distant_light(ctx, s, (double[3]){-1, -1, -0.5}, (double[3]){2, 2, 1.8}, 1.0));
    double I = 1.0 + (3.0 - 1.0) * ((t - 0.0) / (1.0 - 0.0)); /* the key's linear interpolation at t */
    OK(brume_scene_add_point_light(ctx, s, (double[3]){2, 2, 2}, (double[3]){I, I, I}));
    OK(brume_scene_set_animated(ctx, s));
    OK(brume_scene_add_spot_light(ctx, s, (double[3]){-2, 2, 2}, (double[3]){1, -1, -1}, (double[3]){5, 5, 5}, 40, 30));
    OK(brume_scene_add_spot_light_profile(ctx, s, (double[3]){0, 3, 0}, (double[3]){0, -1, 0}, (double[3]){4, 4, 4},
                                          (double[]){0, 20, 45}, (double[]){1, 0.5, 0}, 3));
    OK(brume_scene_add_sphere_light(ctx, s, (double[3]){0, 3, 3}, 0.3, (double[3]){2, 2, 2}));
    OK(brume_scene_add_disk_light(ctx, s, (double[3]){3, 0, 0}, (double[3]){-1, 0, 0}, 0.5, (double[3]){1, 0.5, 0.5}));
}

/* Its media at time t. */
static void every_feature_media(brume_context *ctx, brume_scene *s, double t)
{
    brume_density *d = NULL;
    brume_phase *p = NULL, *lobes[2] = {NULL, NULL};
    brume_medium fog = {.name = "fog", .sigma_a = {0.1, 0.1, 0.1}, .sigma_s = {0.5, 0.6, 0.7}};
    OK(brume_density_new_constant(ctx, 0.2, (double[6]){-3, -1, -3, 3, -0.5, 3}, &d));
    OK(brume_phase_new_hg(ctx, 0.3, &p));
    OK(brume_scene_add_medium(ctx, s, &fog, d, p));

    brume_medium cloud = {.sigma_a = {0.5, 0.5, 0.5}, .sigma_s = {4, 4, 4}};
    OK(brume_density_new_procedural_cloud(ctx, 16, 3, (double[6]){-1, -0.5, -1, 1, 0.5, 1}, &d));
    OK(brume_phase_new_schlick(ctx, 0.5, &lobes[0]));
    OK(brume_phase_new_preset(ctx, BRUME_PHASE_RAYLEIGH, &lobes[1]));
    OK(brume_phase_new_mixture(ctx, (double[]){0.7, 0.3}, lobes, 2, &p));
    OK(brume_scene_add_medium(ctx, s, &cloud, d, p));
    brume_transform_key mk[2] = {{.time = 0, .translate = {0, 0, 0}, .axis = {0, 0, 1}, .angle = 0, .scale = {1, 1, 1}},
                                 {.time = 1, .translate = {0.2, 0, 0}, .axis = {0, 1, 0}, .angle = 10, .scale = {1, 1, 1}}};
    OK(brume_scene_set_medium_motion(ctx, s, 1, mk, 2));

    brume_fractal f;
    brume_fractal_default(&f);
    f.dims[0] = 8, f.dims[1] = 8, f.dims[2] = 4;
    f.seed = 2;
    f.threshold_rate = 0.5;
    f.time = t; /* the reader evaluates a fractal at its own time + the frame's */
    memcpy(f.bounds, (double[6]){1, 0, -1, 2, 1, 0}, sizeof f.bounds);
    f.filter = BRUME_GRID_TRILINEAR;
    OK(brume_density_new_fractal(ctx, &f, &d));
    OK(brume_phase_new_schlick_mix(ctx, 0.5, 0.3, -0.2, &p));
    brume_medium fire = {.sigma_a = {1, 1, 1}, .sigma_s = {2, 2, 2}, .emission = {0.5, 0.2, 0}};
    OK(brume_scene_add_medium(ctx, s, &fire, d, p));

    brume_blob_generator g;
    brume_blob_generator_default(&g, BRUME_BLOBS_CLOUD);
    memcpy(g.center, (double[3]){-1.5, 1, 0}, sizeof g.center);
    g.radii[0] = g.radii[1] = g.radii[2] = 0.4;
    g.count = 10;
    g.seed = 4;
    OK(brume_density_new_blobs(ctx, (double[]){-1.5, 0.5, 0, 1, 0.3}, 1, &g, 1, 0.0, (double[3]){0.1, 0, 0}, &d));
    OK(brume_phase_new_preset(ctx, BRUME_PHASE_MURKY, &p));
    brume_medium puff = {.sigma_a = {0.2, 0.2, 0.2}, .sigma_s = {2, 2, 2}};
    OK(brume_scene_add_medium(ctx, s, &puff, d, p));
}

/* Its surfaces and the option after them. */
static void every_feature_surfaces(brume_context *ctx, brume_scene *s, const char *mesh_path)
{
    brume_material m;
    brume_material_default(&m);
    memcpy(m.albedo, (double[3]){0.5, 0.5, 0.4}, sizeof m.albedo);
    OK(brume_scene_add_plane(ctx, s, (double[3]){0, -1, 0}, (double[3]){0, 1, 0}, 20, NULL, &m, "surfaces[0]"));
    brume_material_default(&m);
    m.albedo[0] = m.albedo[1] = m.albedo[2] = 0.3;
    m.specular[0] = m.specular[1] = m.specular[2] = 0.5;
    m.exponent = 20;
    OK(brume_scene_add_sphere(ctx, s, (double[3]){1, -0.5, 1}, 0.4, NULL, &m, "ball"));
    affine3 rot = affine3_rotate(v3(0, 1, 0), 30);
    OK(brume_scene_add_box(ctx, s, (double[3]){-2, -1, -1}, (double[3]){-1.5, -0.2, -0.5}, rot.m, NULL,
                           "surfaces[2]"));
    brume_transform_key sk[2] = {{.time = 0, .translate = {0, 0, 0}, .axis = {0, 0, 1}, .angle = 0, .scale = {1, 1, 1}},
                                 {.time = 1, .translate = {0, 0.3, 0}, .axis = {0, 0, 1}, .angle = 0, .scale = {1, 1, 1}}};
    OK(brume_scene_set_surface_motion(ctx, s, 2, sk, 2));
    brume_material_default(&m);
    m.emission[0] = m.emission[1] = m.emission[2] = 0.5;
    m.two_sided = true;
    OK(brume_scene_add_quad(ctx, s, (double[3]){-1, -1, -2}, (double[3]){2, 0, 0}, (double[3]){0, 1, 0}, NULL, &m,
                            "surfaces[3]"));
    OK(brume_scene_add_mesh_file(ctx, s, mesh_path, NULL, NULL, "surfaces[4]"));
    OK(brume_scene_set_option(ctx, s, "stam.time", "0.5"));
}

/* The same scene through the builders, in the reader's order. */
static brume_scene *every_feature_api(brume_context *ctx, const char *mesh_path)
{
    brume_scene *s = NULL;
    OK(brume_scene_new(ctx, "api", &s));
    double t = every_feature_settings(ctx, s);
    every_feature_lights(ctx, s, t);
    every_feature_media(ctx, s, t);
    every_feature_surfaces(ctx, s, mesh_path);
    return s;
}

TEST(every_feature_equals_json)
{
    const char *mesh = write_text("tri.obj", TRIANGLE_OBJ);
    char *json = malloc(sizeof EVERY_FEATURE_JSON + strlen(mesh));
    ASSERT_TRUE(json != NULL);
    sprintf(json, EVERY_FEATURE_JSON, mesh);
    brume_context *ctx = brume_context_new();
    brume_scene *a = load_text(ctx, json, 0.3);
    brume_scene *b = every_feature_api(ctx, mesh);
    ASSERT_EQ_INT(brume_scene_medium_count(a), 4);
    ASSERT_EQ_INT(brume_scene_surface_count(a), 5);
    ASSERT_TRUE(brume_scene_time(a) == brume_scene_time(b));
    ASSERT_TRUE(!brume_scene_world_is_static(a) && !brume_scene_world_is_static(b));
    assert_same_render(ctx, a, b);
    brume_context_release(ctx);
    free(json);
    remove(mesh);
}

/* Stam's method, its options set as the "stam" object and through brume_scene_set_option. */
TEST(stam_options_equal_json)
{
    static const char json[] =
        "{\"render\": {\"width\": 32, \"height\": 24, \"spp\": 2, \"method\": \"stam\"},"
        " \"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0]},"
        " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, -1], \"irradiance\": 3}],"
        " \"media\": [{\"density\": {\"type\": \"blobs\", \"generators\": [{\"type\": \"cloud\", \"center\": [0, 0, 0],"
        "   \"radii\": [1, 0.6, 0.6], \"count\": 30, \"seed\": 9}]}, \"sigma_a\": 0.5, \"sigma_s\": 3}],"
        " \"stam\": {\"eps\": 0.2, \"lattice\": 8, \"alpha\": 0.2, \"steps\": 6, \"ambient\": [0.1, 0.2, 0.3],"
        "   \"light_grid\": 0, \"seed\": 5}}";
    brume_context *ctx = brume_context_new();
    brume_scene *a = load_text(ctx, json, 0.0), *b = NULL;
    OK(brume_scene_new(ctx, NULL, &b));
    brume_render_settings rs;
    brume_scene_settings(b, &rs);
    rs.width = 32, rs.height = 24, rs.spp = 2;
    rs.method = BRUME_METHOD_STAM;
    OK(brume_scene_set_settings(ctx, b, &rs));
    brume_camera cam;
    brume_camera_default(&cam);
    cam.position[2] = 4;
    OK(brume_scene_set_camera(ctx, b, &cam));
    OK(brume_scene_add_distant_light(ctx, b, (double[3]){0, -1, -1}, (double[3]){3, 3, 3}, 0));
    brume_blob_generator g;
    brume_blob_generator_default(&g, BRUME_BLOBS_CLOUD);
    g.radii[0] = 1, g.radii[1] = 0.6, g.radii[2] = 0.6;
    g.count = 30;
    g.seed = 9;
    brume_density *d = NULL;
    OK(brume_density_new_blobs(ctx, NULL, 0, &g, 1, 0, NULL, &d));
    brume_medium m = {.sigma_a = {0.5, 0.5, 0.5}, .sigma_s = {3, 3, 3}};
    OK(brume_scene_add_medium(ctx, b, &m, d, NULL));
    static const char *const opts[][2] = {{"stam.eps", "0.2"}, {"stam.lattice", "8"}, {"stam.alpha", "0.2"},
                                          {"stam.steps", "6"}, {"stam.ambient", "0.1,0.2,0.3"},
                                          {"stam.light_grid", "0"}, {"stam.seed", "5"}};
    for (size_t i = 0; i < sizeof opts / sizeof opts[0]; i++)
        OK(brume_scene_set_option(ctx, b, opts[i][0], opts[i][1]));
    assert_same_render(ctx, a, b);
    brume_context_release(ctx);
}

/* A triangle mesh from arrays is the quad the quad builder makes. */
TEST(mesh_arrays_equal_quad)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s[2] = {NULL, NULL};
    brume_image *img[2];
    for (int k = 0; k < 2; k++) {
        OK(brume_scene_new(ctx, NULL, &s[k]));
        brume_render_settings rs;
        brume_scene_settings(s[k], &rs);
        rs.width = 24, rs.height = 16, rs.spp = 2;
        OK(brume_scene_set_settings(ctx, s[k], &rs));
        OK(brume_scene_add_distant_light(ctx, s[k], (double[3]){0, 0, -1}, (double[3]){1, 1, 1}, 0));
        if (k == 0) {
            OK(brume_scene_add_quad(ctx, s[k], (double[3]){-1, -1, 0}, (double[3]){2, 0, 0}, (double[3]){0, 2, 0},
                                    NULL, NULL, "q"));
        } else {
            double pos[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
            int idx[6] = {0, 1, 2, 0, 2, 3};
            OK(brume_scene_add_mesh(ctx, s[k], pos, 4, idx, 2, NULL, NULL, "q"));
        }
        img[k] = render(ctx, s[k]);
    }
    assert_same_image(img[0], img[1]);
    for (int k = 0; k < 2; k++) {
        brume_image_release(img[k]);
        brume_scene_release(s[k]);
    }
    brume_context_release(ctx);
}

static int releases;
static void count_release(void *user)
{
    ASSERT_TRUE(user == &releases);
    releases++;
}

#define NX 12
#define NY 10
#define NZ 8

/* A density given as an array (borrowed, and copied) renders as the same values read from a
 * raw file; a scene file's placeholder replaced by the array does too. */
TEST(array_density_equals_raw_file)
{
    static float v[NZ][NY][NX];
    for (int k = 0; k < NZ; k++)
        for (int j = 0; j < NY; j++)
            for (int i = 0; i < NX; i++) {
                double r = sqrt((i - 5.5) * (i - 5.5) + (j - 4.5) * (j - 4.5) + 2.0 * (k - 3.5) * (k - 3.5));
                v[k][j][i] = r < 5.0 ? (float)((5.0 - r) * (1.0 + 0.3 * sin(i + 2.0 * j + 3.0 * k))) : 0.0f;
            }
    const char *raw = test_tmp_path("cloud.raw");
    FILE *fp = fopen(raw, "wb");
    ASSERT_TRUE(fp && fwrite(v, sizeof v, 1, fp) == 1);
    fclose(fp);
    static const char head[] =
        "{\"render\": {\"width\": 32, \"height\": 24, \"spp\": 4},"
        " \"camera\": {\"position\": [0.3, 0.5, 4], \"look_at\": [0, 0, 0]},"
        " \"lights\": [{\"type\": \"distant\", \"direction\": [-1, -1, -1], \"irradiance\": 3}],"
        " \"media\": [{\"sigma_a\": 0.3, \"sigma_s\": 2, \"density\": ";
    char json[2048], placeholder[1024];
    snprintf(json, sizeof json,
             "%s{\"type\": \"grid\", \"file\": \"%s\", \"format\": \"raw\", \"dims\": [%d, %d, %d],"
             " \"bounds\": [[-1, -0.8, -0.6], [1.2, 0.8, 0.6]], \"filter\": \"trilinear\"}}]}",
             head, raw, NX, NY, NZ);
    snprintf(placeholder, sizeof placeholder,
             "%s{\"type\": \"constant\", \"value\": 0, \"bounds\": [[-1, -0.8, -0.6], [1.2, 0.8, 0.6]]}}]}", head);
    const double bounds[6] = {-1, -0.8, -0.6, 1.2, 0.8, 0.6};
    brume_context *ctx = brume_context_new();
    brume_scene *file = load_text(ctx, json, 0.0);
    brume_image *want = render(ctx, file);
    brume_scene_release(file);

    releases = 0;
    for (int mode = 0; mode < 2; mode++) {
        brume_scene *s = NULL;
        OK(brume_scene_new(ctx, NULL, &s));
        brume_render_settings rs;
        brume_scene_settings(s, &rs);
        rs.width = 32, rs.height = 24, rs.spp = 4;
        OK(brume_scene_set_settings(ctx, s, &rs));
        brume_camera cam;
        brume_camera_default(&cam);
        cam.position[0] = 0.3, cam.position[1] = 0.5, cam.position[2] = 4;
        OK(brume_scene_set_camera(ctx, s, &cam));
        OK(brume_scene_add_distant_light(ctx, s, (double[3]){-1, -1, -1}, (double[3]){3, 3, 3}, 0));
        brume_density *d = NULL;
        OK(brume_density_new_array(ctx, &v[0][0][0], NX, NY, NZ, bounds, BRUME_GRID_TRILINEAR,
                                   mode == 0 ? count_release : NULL, &releases, &d));
        brume_medium m = {.sigma_a = {0.3, 0.3, 0.3}, .sigma_s = {2, 2, 2}};
        OK(brume_scene_add_medium(ctx, s, &m, d, NULL));
        brume_image *got = render(ctx, s);
        assert_same_image(want, got);
        brume_image_release(got);
        ASSERT_EQ_INT(releases, mode); /* borrowed until the scene goes; a copy is never released */
        brume_scene_release(s);
        ASSERT_EQ_INT(releases, 1);
    }
    brume_scene *s = load_text(ctx, placeholder, 0.0);
    brume_density *d = NULL;
    OK(brume_density_new_array(ctx, &v[0][0][0], NX, NY, NZ, bounds, BRUME_GRID_TRILINEAR, NULL, NULL, &d));
    OK(brume_scene_set_medium_density(ctx, s, 0, d));
    brume_image *got = render(ctx, s);
    assert_same_image(want, got);
    brume_image_release(got);
    brume_scene_release(s);

    /* a failed borrow keeps nothing and releases nothing */
    v[1][2][3] = NAN;
    ASSERT_EQ_INT(brume_density_new_array(ctx, &v[0][0][0], NX, NY, NZ, bounds, BRUME_GRID_TRILINEAR, count_release,
                                          &releases, &d),
                  BRUME_ERROR_RANGE);
    ASSERT_TRUE(d == NULL);
    ASSERT_EQ_INT(releases, 1);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "brume_density_new_array: data");
    brume_image_release(want);
    brume_context_release(ctx);
    remove(raw);
}

/* A failing call returns its status, names the function and the argument on one line. */
static void expect(brume_context *ctx, brume_status got, brume_status want, const char *frag1, const char *frag2)
{
    const char *msg = brume_context_last_error(ctx);
    if (got != want)
        TEST_FAIL("status %d, want %d: %s", (int)got, (int)want, msg);
    ASSERT_CONTAINS(msg, frag1);
    ASSERT_CONTAINS(msg, frag2);
    ASSERT_TRUE(strchr(msg, '\n') == NULL);
}

TEST(builders_reject_bad_arguments)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    OK(brume_scene_new(ctx, NULL, &s));
    brume_density *d = (brume_density *)1;
    const double box[6] = {-1, -1, -1, 1, 1, 1};
    float one = 1.0f;
    expect(ctx, brume_density_new_array(ctx, &one, 0, 1, 1, box, BRUME_GRID_NEAREST, NULL, NULL, &d),
           BRUME_ERROR_RANGE, "brume_density_new_array", "nx");
    ASSERT_TRUE(d == NULL);
    expect(ctx, brume_density_new_array(ctx, &one, 1, 1, 100000, box, BRUME_GRID_NEAREST, NULL, NULL, &d),
           BRUME_ERROR_RANGE, "brume_density_new_array", "nz");
    expect(ctx, brume_density_new_array(ctx, &one, 1, 1, 1, (double[6]){-1, -1, -1, NAN, 1, 1}, BRUME_GRID_NEAREST,
                                        NULL, NULL, &d),
           BRUME_ERROR_RANGE, "brume_density_new_array", "bounds");
    expect(ctx, brume_density_new_array(ctx, &one, 1, 1, 1, (double[6]){1, -1, -1, -1, 1, 1}, BRUME_GRID_NEAREST,
                                        NULL, NULL, &d),
           BRUME_ERROR_RANGE, "brume_density_new_array", "min < max");
    expect(ctx, brume_density_new_constant(ctx, -1, box, &d), BRUME_ERROR_RANGE, "brume_density_new_constant", "value");
    expect(ctx, brume_density_new_procedural_cloud(ctx, 100000, 1, box, &d), BRUME_ERROR_RANGE,
           "brume_density_new_procedural_cloud", "resolution");
    brume_fractal f;
    brume_fractal_default(&f);
    f.dims[0] = 2000;
    expect(ctx, brume_density_new_fractal(ctx, &f, &d), BRUME_ERROR_RANGE, "brume_density_new_fractal",
           "fractal.dims[0]");
    brume_fractal_default(&f);
    f.hurst = NAN;
    expect(ctx, brume_density_new_fractal(ctx, &f, &d), BRUME_ERROR_RANGE, "brume_density_new_fractal", "hurst");
    expect(ctx, brume_density_new_blobs(ctx, (double[]){0, 0, 0, 1, -1}, 1, NULL, 0, 0, NULL, &d), BRUME_ERROR_RANGE,
           "brume_density_new_blobs", "blobs[0]");
    expect(ctx, brume_density_new_blobs(ctx, NULL, 0, NULL, 0, 0, NULL, &d), BRUME_ERROR_RANGE,
           "brume_density_new_blobs", "no blobs");
    expect(ctx, brume_density_new_nanovdb(ctx, "not a grid, not at all", 23, BRUME_GRID_NEAREST, 1, &d),
           BRUME_ERROR_PARSE, "brume_density_new_nanovdb", "");
    brume_phase *p = (brume_phase *)1;
    expect(ctx, brume_phase_new_hg(ctx, 1.5, &p), BRUME_ERROR_RANGE, "brume_phase_new_hg", "g");
    ASSERT_TRUE(p == NULL);
    expect(ctx, brume_phase_new_preset(ctx, (brume_phase_preset)4, &p), BRUME_ERROR_RANGE, "brume_phase_new_preset", "preset");

    brume_camera c;
    brume_camera_default(&c);
    c.fov = 400;
    expect(ctx, brume_scene_set_camera(ctx, s, &c), BRUME_ERROR_RANGE, "brume_scene_set_camera", "fov");
    brume_camera_default(&c);
    c.position[1] = INFINITY;
    expect(ctx, brume_scene_set_camera(ctx, s, &c), BRUME_ERROR_RANGE, "brume_scene_set_camera", "position");
    expect(ctx, brume_scene_add_point_light(ctx, s, (double[3]){0, 0, 0}, (double[3]){-1, 1, 1}), BRUME_ERROR_RANGE,
           "brume_scene_add_point_light", "intensity[0]");
    expect(ctx, brume_scene_add_distant_light(ctx, s, (double[3]){0, 0, 0}, (double[3]){1, 1, 1}, 0),
           BRUME_ERROR_RANGE, "brume_scene_add_distant_light", "direction");
    expect(ctx, brume_scene_add_spot_light_profile(ctx, s, (double[3]){0, 0, 0}, (double[3]){0, -1, 0},
                                                   (double[3]){1, 1, 1}, (double[]){10, 5}, (double[]){1, 1}, 2),
           BRUME_ERROR_RANGE, "brume_scene_add_spot_light_profile", "angle[1]");

    OK(brume_density_new_constant(ctx, 1, box, &d));
    brume_medium m = {.sigma_a = {NAN, 0, 0}};
    expect(ctx, brume_scene_add_medium(ctx, s, &m, d, NULL), BRUME_ERROR_RANGE, "brume_scene_add_medium", "sigma_a");
    ASSERT_EQ_INT(brume_scene_medium_count(s), 0); /* nothing half-built; the caller keeps d */
    brume_density_release(d);
    expect(ctx, brume_scene_add_sphere(ctx, s, (double[3]){0, 0, 0}, -1, NULL, NULL, NULL), BRUME_ERROR_RANGE,
           "brume_scene_add_sphere", "radius");
    brume_material mat;
    brume_material_default(&mat);
    mat.specular[1] = 0.5;
    expect(ctx, brume_scene_add_sphere(ctx, s, (double[3]){0, 0, 0}, 1, NULL, &mat, NULL), BRUME_ERROR_RANGE,
           "brume_scene_add_sphere", "material");
    expect(ctx, brume_scene_add_mesh(ctx, s, (double[9]){0, 0, 0, 1, 0, 0, 0, 1, 0}, 3, (int[3]){0, 1, 3}, 1, NULL,
                                     NULL, NULL),
           BRUME_ERROR_RANGE, "brume_scene_add_mesh", "indices[2]");
    expect(ctx, brume_scene_add_box(ctx, s, (double[3]){0, 0, 0}, (double[3]){1, 1, 1},
                                    (double[12]){0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, NULL, NULL),
           BRUME_ERROR_RANGE, "brume_scene_add_box", "transform");
    ASSERT_EQ_INT(brume_scene_surface_count(s), 0);
    expect(ctx, brume_scene_set_option(ctx, s, "stam.eps", "-1"), BRUME_ERROR_RANGE, "stam.eps", "-1");
    expect(ctx, brume_scene_set_option(ctx, s, "path.eps", "1"), BRUME_ERROR_PARSE, "path.eps", "unknown key");
    brume_transform_key key = {.axis = {0, 0, 1}, .scale = {1, 1, 1}};
    expect(ctx, brume_scene_set_medium_motion(ctx, s, 0, &key, 1), BRUME_ERROR_RANGE,
           "brume_scene_set_medium_motion", "medium");
    expect(ctx, brume_scene_set_medium_motion(ctx, s, 0, NULL, 1), BRUME_ERROR_INVALID_ARGUMENT,
           "brume_scene_set_medium_motion", "keys: NULL");

    brume_scene *j = (brume_scene *)1;
    expect(ctx, brume_scene_load(ctx, &(brume_source){.text = "{\"camera\": {\"position\": [0, 0, 1]}}"}, NULL, &j),
           BRUME_ERROR_PARSE, "<json>", "camera.look_at");
    ASSERT_TRUE(j == NULL);

    OK(brume_scene_commit(ctx, s));
    expect(ctx, brume_scene_add_point_light(ctx, s, (double[3]){0, 0, 0}, (double[3]){1, 1, 1}), BRUME_ERROR_STATE,
           "brume_scene_add_point_light", "commit");
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* The one loader: a file and the same text (named as the file) give the same image byte for
 * byte; the text takes overrides as a file does; frame and time place the scene in its
 * animation; a NULL source, or an empty one, is the default scene; bad options are refused
 * naming the source. */
static const char SMALL_SCENE[] =
    "{\"render\": {\"width\": 12, \"height\": 9, \"spp\": 2, \"seed\": 3, \"fps\": 8},"
    " \"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
    " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, -1], \"irradiance\": 3}],"
    " \"media\": [{\"density\": {\"type\": \"constant\", \"value\": 1, \"bounds\": [[-1, -1, -1], [1, 1, 1]]},"
    "   \"sigma_a\": 0.2, \"sigma_s\": 1.5}]}";

TEST(one_loader_takes_every_source)
{
    brume_context *ctx = brume_context_new();
    const char *path = write_text("one-loader.json", SMALL_SCENE);
    brume_scene *a = NULL, *b = NULL;
    OK(brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &a));
    OK(brume_scene_load(ctx, &(brume_source){.path = path, .text = SMALL_SCENE}, NULL, &b));
    assert_same_render(ctx, a, b);

    /* overrides, frame and time on a text */
    const char *set[] = {"render.width=17", "camera.fov=30"};
    brume_render_settings rs;
    OK(brume_scene_load(ctx, &(brume_source){.text = SMALL_SCENE},
                        &(brume_load_options){.frame = 3, .overrides = set, .noverrides = 2}, &a));
    brume_scene_settings(a, &rs);
    ASSERT_EQ_INT(rs.width, 17);
    ASSERT_NEAR(brume_scene_time(a), 3.0 / 8.0, 1e-15);
    brume_scene_release(a);
    OK(brume_scene_load(ctx, &(brume_source){.path = path}, &(brume_load_options){.time = 0.25}, &a));
    ASSERT_NEAR(brume_scene_time(a), 0.25, 1e-15);
    brume_scene_release(a);

    /* the default scene: no source, or an empty one */
    OK(brume_scene_load(ctx, NULL, NULL, &a));
    OK(brume_scene_load(ctx, &(brume_source){0}, NULL, &b));
    brume_render_settings ra, rb;
    brume_scene_settings(a, &ra);
    brume_scene_settings(b, &rb);
    ASSERT_EQ_INT(ra.width, rb.width);
    ASSERT_TRUE(ra.noise_target > 0.0 && ra.noise_target == rb.noise_target);
    ASSERT_EQ_INT(brume_scene_medium_count(a), brume_scene_medium_count(b));
    ASSERT_TRUE(brume_scene_medium_count(a) > 0);
    brume_scene_release(a);
    brume_scene_release(b);

    /* refusals name the source and leave *out NULL */
    a = (brume_scene *)1;
    expect(ctx, brume_scene_load(ctx, &(brume_source){.path = path}, &(brume_load_options){.frame = -1}, &a),
           BRUME_ERROR_RANGE, "one-loader.json", "frame -1");
    ASSERT_TRUE(a == NULL);
    expect(ctx, brume_scene_load(ctx, &(brume_source){.text = "{}", .path = "named.json"},
                                 &(brume_load_options){.time = NAN}, &a),
           BRUME_ERROR_RANGE, "named.json", "not finite");
    expect(ctx, brume_scene_load(ctx, NULL, &(brume_load_options){.noverrides = 1}, &a), BRUME_ERROR_INVALID_ARGUMENT,
           "brume_scene_load", "overrides");
    expect(ctx, brume_scene_load(ctx, &(brume_source){.text = SMALL_SCENE, .path = "t.json"},
                                 &(brume_load_options){.overrides = (const char *[]){"camera.nope=1"}, .noverrides = 1},
                                 &a),
           BRUME_ERROR_PARSE, "t.json", "nope");
    ASSERT_TRUE(a == NULL);
    brume_context_release(ctx);
}

/* brume_method: every value has a name that parses back to it; other names and values are
 * refused. */
TEST(method_names_round_trip)
{
    brume_context *ctx = brume_context_new();
    const brume_method all[] = {BRUME_METHOD_PATH, BRUME_METHOD_SINGLE, BRUME_METHOD_BLASI, BRUME_METHOD_STAM};
    const char *names[] = {"path", "single", "blasi", "stam"};
    for (int i = 0; i < 4; i++) {
        ASSERT_TRUE(brume_method_name(all[i]) != NULL);
        ASSERT_TRUE(strcmp(brume_method_name(all[i]), names[i]) == 0);
        brume_method back = (brume_method)99;
        OK(brume_method_from_name(ctx, names[i], &back));
        ASSERT_EQ_INT((int)back, (int)all[i]);
    }
    ASSERT_TRUE(brume_method_name((brume_method)4) == NULL);
    /* brume_option_kind, the same way */
    const char *kinds[] = {"number", "integer", "enum", "bool", "color", "path"};
    for (int k = 0; k < 6; k++)
        ASSERT_TRUE(brume_option_kind_name((brume_option_kind)k) && strcmp(brume_option_kind_name((brume_option_kind)k), kinds[k]) == 0);
    ASSERT_TRUE(brume_option_kind_name((brume_option_kind)6) == NULL);
    ASSERT_TRUE(brume_method_name((brume_method)-1) == NULL);
    brume_method m = BRUME_METHOD_STAM;
    expect(ctx, brume_method_from_name(ctx, "pathh", &m), BRUME_ERROR_INVALID_ARGUMENT, "pathh", "path, single");
    ASSERT_EQ_INT((int)m, (int)BRUME_METHOD_STAM);
    brume_context_release(ctx);
}

/* Closed sets are enums, checked where they enter: a grid file's format, the render
 * method, a phase preset; the scene file's names map onto them or are refused naming the key. */
TEST(closed_sets_are_checked_enums)
{
    brume_context *ctx = brume_context_new();
    const char *raw = test_tmp_path("enum-grid.raw");
    FILE *fp = fopen(raw, "wb");
    ASSERT_TRUE(fp != NULL);
    const float v[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    ASSERT_TRUE(fwrite(v, sizeof v, 1, fp) == 1);
    fclose(fp);
    brume_grid_file_options o;
    brume_grid_file_options_default(&o);
    ASSERT_EQ_INT((int)o.format, (int)BRUME_GRID_FORMAT_AUTO);
    o.format = BRUME_GRID_FORMAT_RAW;
    o.dims[0] = o.dims[1] = o.dims[2] = 2;
    brume_density *d = NULL;
    OK(brume_density_load(ctx, raw, &o, &d));
    brume_density_release(d);
    d = NULL;
    o.format = (brume_grid_format)6;
    expect(ctx, brume_density_load(ctx, raw, &o, &d), BRUME_ERROR_RANGE, "opts.format", "brume_grid_format");
    ASSERT_TRUE(d == NULL);

    char json[1024];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0]}, \"media\": [{\"density\": {\"type\": "
             "\"grid\", \"file\": \"%s\", \"format\": \"rawx\", \"dims\": [2, 2, 2]}, \"sigma_a\": 0, \"sigma_s\": 1}]}",
             raw);
    brume_scene *s = NULL;
    expect(ctx, brume_scene_load(ctx, &(brume_source){.text = json, .path = "g.json"}, NULL, &s), BRUME_ERROR_PARSE,
           "g.json: media[0].density.format", "rawx");
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0]}, \"media\": [{\"density\": {\"type\": "
             "\"grid\", \"file\": \"%s\", \"format\": \"raw\", \"dims\": [2, 2, 2]}, \"sigma_a\": 0, \"sigma_s\": 1}],"
             " \"render\": {\"method\": \"single\"}}",
             raw);
    OK(brume_scene_load(ctx, &(brume_source){.text = json, .path = "g.json"}, NULL, &s));
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    ASSERT_EQ_INT((int)rs.method, (int)BRUME_METHOD_SINGLE);
    rs.method = (brume_method)4;
    expect(ctx, brume_scene_set_settings(ctx, s, &rs), BRUME_ERROR_UNSUPPORTED, "render.method", "brume_method");
    brume_scene_release(s);
    expect(ctx, brume_scene_load(ctx, &(brume_source){.text = "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": "
                                                              "[0, 0, 0]}, \"render\": {\"method\": \"magic\"}}"},
                                 NULL, &s),
           BRUME_ERROR_UNSUPPORTED, "render.method", "magic");

    /* brume_scene_text shows what the loader reads: the text itself, or the default scene */
    char *text = NULL;
    OK(brume_scene_text(ctx, &(brume_source){.text = json}, NULL, &text));
    ASSERT_TRUE(strcmp(text, json) == 0);
    free(text);
    OK(brume_scene_text(ctx, NULL, NULL, &text));
    ASSERT_CONTAINS(text, "\"media\"");
    free(text);
    brume_context_release(ctx);
}

TEST_MAIN(one_loader_takes_every_source, method_names_round_trip, closed_sets_are_checked_enums, every_feature_equals_json, stam_options_equal_json, mesh_arrays_equal_quad, array_density_equals_raw_file,
          builders_reject_bad_arguments)
