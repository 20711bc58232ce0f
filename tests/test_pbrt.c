/* test_pbrt.c - pbrt-v4 scenes read by brume (docs/pbrt.md): the
 * homogeneous, uniformgrid and rgbgrid media, the triangle, bilinear and PLY meshes, each
 * against values worked out here by hand from pbrt-v4's definitions; a homogeneous box's
 * transmittance against exp(-sigma_t d); and the refusals, each one line with FILE:LINE. */
#include "test.h"

#include <math.h>

#include "brume.h"
#include "core/error.h"
#include "io/json.h"
#include "scene/scene.h"
#include "scene/scene_pbrt.h"

/* A camera on -z looking at the origin, pbrt-v4-scenes' right-handed way (Scale -1 1 1). */
#define HEAD                                                                                     \
    "Film \"rgb\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"                   \
    "Sampler \"halton\" \"integer pixelsamples\" [64]\n"                                         \
    "Scale -1 1 1\n"                                                                             \
    "LookAt 0 0 -5  0 0 0  0 1 0\n"                                                              \
    "Camera \"perspective\" \"float fov\" [1]\n"                                                 \
    "WorldBegin\n"                                                                               \
    "LightSource \"infinite\" \"rgb L\" [1 1 1]\n"
#define HEAD_LINES 7

/* The cube [-1, 1]^3 as six bilinear patches facing out: corner k at x = k & 1, y = k & 2,
 * z = k & 4 (0 -> -1, else 1); a patch (p00, p10, p01, p11) faces (p10 - p00) x (p01 - p00),
 * e.g. the z = -1 face (0, 2, 1, 3): +y x +x = -z. */
#define CUBE                                                                                     \
    "Shape \"bilinearmesh\" \"point3 P\" [-1 -1 -1  1 -1 -1  -1 1 -1  1 1 -1  -1 -1 1  1 -1 1  " \
    "-1 1 1  1 1 1]\n"                                                                           \
    "  \"integer indices\" [0 2 1 3  4 5 6 7  0 1 4 5  2 6 3 7  0 4 2 6  1 3 5 7]\n"

static const char *write_scene(const char *name, const char *world)
{
    char text[8192];
    snprintf(text, sizeof text, "%s%s", HEAD, world);
    const char *path = test_tmp_path(name);
    test_write_file(path, text);
    return path;
}

/* The translation of HEAD + world, parsed. */
static cJSON *translate(const char *world)
{
    const char *path = write_scene("t.pbrt", world);
    char *json = NULL;
    if (scene_pbrt_json(path, &json) != BRUME_OK)
        TEST_FAIL("%s", err_message());
    cJSON *root = cJSON_Parse(json);
    ASSERT_TRUE(root != NULL);
    free(json);
    remove(path);
    return root;
}

static double num(const cJSON *obj, const char *key, int i)
{
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (i >= 0)
        it = cJSON_GetArrayItem(it, i);
    if (!cJSON_IsNumber(it))
        TEST_FAIL("%s[%d]: not a number", key, i);
    return it->valuedouble;
}

/* bounds[side][axis] of a density object */
static double bound(const cJSON *d, int side, int axis)
{
    const cJSON *b = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(d, "bounds"), side);
    const cJSON *v = cJSON_GetArrayItem(b, axis);
    if (!cJSON_IsNumber(v))
        TEST_FAIL("bounds[%d][%d]: not a number", side, axis);
    return v->valuedouble;
}

static const cJSON *medium_j(const cJSON *root, int i)
{
    return cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "media"), i);
}

/* homogeneous: sigma x scale per unit length, Le x Lescale, g; the density a constant 1 in
 * the box the interface cube makes (moved by the transform at the Shape). */
TEST(homogeneous_medium_maps_units)
{
    cJSON *root = translate("MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [0.1 0.2 0.3]\n"
                            "  \"spectrum sigma_s\" [200 1.5 900 1.5] \"float scale\" 2 \"float g\" -0.4\n"
                            "  \"rgb Le\" [1 0.5 0.25] \"float Lescale\" 4\n"
                            "AttributeBegin\n"
                            "Translate 3 0 0\n"
                            "Scale 2 1 1\n"
                            "Material \"interface\"\n"
                            "MediumInterface \"fog\" \"\"\n" CUBE "AttributeEnd\n");
    const cJSON *m = medium_j(root, 0);
    ASSERT_NEAR(num(m, "sigma_a", 0), 0.2, 1e-12);
    ASSERT_NEAR(num(m, "sigma_a", 2), 0.6, 1e-12);
    ASSERT_NEAR(num(m, "sigma_s", 1), 3.0, 1e-12);
    ASSERT_NEAR(num(m, "emission", 0), 4.0, 1e-12);
    ASSERT_NEAR(num(m, "emission", 2), 1.0, 1e-12);
    ASSERT_NEAR(num(cJSON_GetObjectItemCaseSensitive(m, "phase"), "g", -1), -0.4, 1e-12);
    const cJSON *d = cJSON_GetObjectItemCaseSensitive(m, "density");
    ASSERT_EQ_STR(cJSON_GetObjectItemCaseSensitive(d, "type")->valuestring, "constant");
    ASSERT_NEAR(num(d, "value", -1), 1.0, 0);
    /* x: 3 + 2 [-1, 1] = [1, 5], held with a margin of 1e-4 of the size */
    ASSERT_NEAR(bound(d, 0, 0), 1.0 - 4e-4, 1e-8);
    ASSERT_NEAR(bound(d, 1, 0), 5.0 + 4e-4, 1e-8);
    ASSERT_NEAR(bound(d, 0, 1), -1.0 - 4e-4, 1e-8);
    ASSERT_NEAR(bound(d, 1, 2), 1.0 + 4e-4, 1e-8);
    /* the cube is an interface that bounds the fog (not drawn) */
    const cJSON *surfs = cJSON_GetObjectItemCaseSensitive(root, "surfaces");
    ASSERT_EQ_INT(cJSON_GetArraySize(surfs), 1);
    const cJSON *sf = cJSON_GetArrayItem(surfs, 0);
    ASSERT_EQ_STR(cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(sf, "material"), "type")->valuestring,
                  "interface");
    ASSERT_EQ_STR(cJSON_GetObjectItemCaseSensitive(sf, "medium_inside")->valuestring, "fog");
    cJSON_Delete(root);
}

/* The committed scene of HEAD + world. */
static brume_scene *load(const char *world)
{
    const char *path = write_scene("l.pbrt", world);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK ||
        brume_scene_commit(ctx, s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    brume_context_release(ctx);
    remove(path);
    return s;
}

/* uniformgrid: samples d at the cell centres of [p0, p1], trilinear, samples beyond the grid
 * 0 (pbrt-v4's SampledGrid), placed by the transform at MakeNamedMedium. Two samples
 * d = (0.5, 1) along x over [0, 2] x [0, 1] x [0, 1], moved by +1 in x: in medium space
 * (x, 0.5, 0.5), world x - 1, the centres are x = 0.5 and 1.5; at the face x = 0 pbrt reads halfway from
 * the sample 0 beyond to 0.5, 0.25; between the centres 0.75; at the face y = 0 (x = 0.5)
 * halfway from 0 to 0.5, 0.25; at x = 2, 0.5. sigma = sigma scale per unit density. */
TEST(uniformgrid_matches_pbrt_lookup)
{
    brume_scene *s = load("AttributeBegin\nTranslate 1 0 0\n"
                          "MakeNamedMedium \"g\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \"float density\" "
                          "[0.5 1]\n  \"point3 p1\" [2 1 1] \"rgb sigma_a\" [1 2 3] \"rgb sigma_s\" [0.5 0.5 0.5] "
                          "\"float scale\" 3\nAttributeEnd\n"
                          "Material \"interface\"\nMediumInterface \"g\" \"\"\nShape \"sphere\" \"float radius\" 3\n");
    const medium *m = &s->media[0];
    ASSERT_NEAR(m->sigma_a.c[1], 6.0, 1e-12);
    ASSERT_NEAR(m->sigma_s.c[0], 1.5, 1e-12);
    const struct { double x, y, want; } at[] = {
        {1.5, 0.5, 0.5}, {2.5, 0.5, 1.0}, {1.0, 0.5, 0.25}, {2.0, 0.5, 0.75}, {1.5, 0.0, 0.25},
        {3.0, 0.5, 0.5}, {1.75, 0.5, 0.625}, {-1.0, 0.5, 0.0}, {5.0, 0.5, 0.0}};
    for (size_t i = 0; i < sizeof at / sizeof at[0]; i++)
        ASSERT_NEAR(density_eval(m->rho, v3(at[i].x, at[i].y, 0.5)), at[i].want, 1e-6);
    brume_scene_release(s);
}

/* rgbgrid: samples sigma_s = (1, 2, 3) and (2, 4, 6), sigma_a = (0.1, 0, 0) and (0.2, 0, 0)
 * are d (c_a, c_s) with d = each sample's largest value, 3 and 6, c_s = (1/3, 2/3, 1),
 * c_a = (1/30, 0, 0); brume's sigma = c scale (scale 2) and rho = d. A grid whose colour
 * changes is refused. */
TEST(rgbgrid_one_colour_times_density)
{
    brume_scene *s = load("MakeNamedMedium \"c\" \"string type\" \"rgbgrid\" \"integer nx\" 2\n"
                          "  \"rgb sigma_s\" [1 2 3 2 4 6] \"rgb sigma_a\" [0.1 0 0 0.2 0 0] \"float scale\" 2\n"
                          "Material \"interface\"\nMediumInterface \"c\" \"\"\nShape \"sphere\"\n");
    const medium *m = &s->media[0];
    ASSERT_NEAR(m->sigma_s.c[0], 2.0 / 3.0, 1e-12);
    ASSERT_NEAR(m->sigma_s.c[2], 2.0, 1e-12);
    ASSERT_NEAR(m->sigma_a.c[0], 2.0 / 30.0, 1e-12);
    ASSERT_NEAR(m->sigma_a.c[1], 0.0, 0);
    ASSERT_NEAR(density_eval(m->rho, v3(0.25, 0.5, 0.5)), 3.0, 1e-6); /* first cell centre */
    ASSERT_NEAR(density_eval(m->rho, v3(0.75, 0.5, 0.5)), 6.0, 1e-6);
    brume_scene_release(s);
}

/* trianglemesh: P through the current transform, indices as given, the diffuse reflectance;
 * bilinearmesh: a planar patch (p00, p10, p01, p11) is the triangles (0, 1, 3), (0, 3, 2);
 * plymesh: the file beside the scene, the transform as brume's transform object. */
TEST(meshes_translate)
{
    test_write_file(test_tmp_path("tri.ply"), "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                              "property float y\nproperty float z\nelement face 1\n"
                                              "property list uchar int vertex_indices\nend_header\n"
                                              "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    char world[1024];
    snprintf(world, sizeof world, "%s%s%s", "Material \"diffuse\" \"rgb reflectance\" [0.2 0.4 0.6]\n"
                            "AttributeBegin\nTranslate 0 -2 0\nScale 2 2 2\n"
                            "Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  1 0 1  0 0 1] \"integer indices\" "
                            "[0 2 1  0 3 2] \"normal N\" [0 1 0 0 1 0 0 1 0 0 1 0] \"point2 uv\" [0 0 1 0 1 1 0 1]\n"
                            "AttributeEnd\n"
                            "Shape \"bilinearmesh\" \"point3 P\" [0 0 5  1 0 5  0 1 5  1 1 5]\n"
                            "Translate 0 0 9\nShape \"plymesh\" \"string filename\" \"",
             test_tmp_path("tri.ply"), "\"\n");
    cJSON *root = translate(world);
    const cJSON *surf = cJSON_GetObjectItemCaseSensitive(root, "surfaces");
    ASSERT_EQ_INT(cJSON_GetArraySize(surf), 3);
    const cJSON *t = cJSON_GetArrayItem(surf, 0);
    ASSERT_EQ_STR(cJSON_GetObjectItemCaseSensitive(t, "type")->valuestring, "mesh");
    ASSERT_EQ_INT(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(t, "positions")), 12);
    ASSERT_NEAR(num(t, "positions", 6), 2.0, 1e-12); /* (1, 0, 1) -> (2, -2, 2) */
    ASSERT_NEAR(num(t, "positions", 7), -2.0, 1e-12);
    ASSERT_NEAR(num(t, "positions", 8), 2.0, 1e-12);
    const int want_t[6] = {0, 2, 1, 0, 3, 2};
    for (int i = 0; i < 6; i++)
        ASSERT_EQ_INT((int)num(t, "indices", i), want_t[i]);
    ASSERT_NEAR(num(cJSON_GetObjectItemCaseSensitive(t, "material"), "albedo", 1), 0.4, 1e-12);
    const cJSON *b = cJSON_GetArrayItem(surf, 1);
    const int want_b[6] = {0, 1, 3, 0, 3, 2};
    ASSERT_EQ_INT(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(b, "indices")), 6);
    for (int i = 0; i < 6; i++)
        ASSERT_EQ_INT((int)num(b, "indices", i), want_b[i]);
    const cJSON *p = cJSON_GetArrayItem(surf, 2);
    ASSERT_CONTAINS(cJSON_GetObjectItemCaseSensitive(p, "file")->valuestring, "tri.ply");
    ASSERT_NEAR(num(cJSON_GetObjectItemCaseSensitive(p, "transform"), "translate", 2), 9.0, 1e-12);
    cJSON_Delete(root);
    remove(test_tmp_path("tri.ply"));
}

/* A homogeneous absorbing cube of side 2 (sigma_a 0.35, scale 2: sigma_t = 0.7), moved by
 * Translate, seen through its centre against a sky of radiance 1: every pixel is the
 * transmittance exp(-0.7 x 2) = exp(-1.4) (the 1-degree view makes the paths longer by at
 * most 1 / cos(0.71 deg) - 1 = 8e-5). Tolerance: 4 standard errors of the pixel mean, plus
 * the path-length spread. */
TEST(homogeneous_box_transmittance)
{
    const char *path = write_scene("tr.pbrt", "MakeNamedMedium \"ink\" \"string type\" \"homogeneous\" \"rgb sigma_a\" "
                                              "[0.35 0.35 0.35] \"rgb sigma_s\" [0 0 0] \"float scale\" 2\n"
                                              "Translate 0 0 0.5\nMaterial \"interface\"\n"
                                              "MediumInterface \"ink\" \"\"\n" CUBE);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    brume_image *img = test_render_scene(s, -1, 7);
    int n = brume_image_width(img) * brume_image_height(img);
    ASSERT_EQ_INT(n, 256);
    double want = exp(-1.4);
    for (int c = 0; c < 3; c++) {
        double mean, se;
        test_channel_mean(brume_image_pixels(img), n, c, &mean, &se);
        if (!(fabs(mean - want) <= 4.0 * se + 2e-4 * want))
            TEST_FAIL("channel %d: mean %g, want exp(-1.4) = %g (se %g)", c, mean, want, se);
    }
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
    remove(path);
}

/* The world of HEAD + world refused: one line, "FILE:LINE: " and frag. */
static void expect_refusal(const char *world, int line, const char *frag)
{
    const char *path = write_scene("bad.pbrt", world);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    ASSERT_TRUE(brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK);
    const char *msg = brume_context_last_error(ctx);
    char want[1200];
    snprintf(want, sizeof want, "%s:%d: ", path, HEAD_LINES + line);
    ASSERT_CONTAINS(msg, want);
    ASSERT_CONTAINS(msg, frag);
    ASSERT_TRUE(strchr(msg, '\n') == NULL);
    brume_context_release(ctx);
    remove(path);
}

#define HOMOG "MakeNamedMedium \"h\" \"string type\" \"homogeneous\"\n"
#define GRID "MakeNamedMedium \"g\" \"string type\" \"uniformgrid\" "

/* What brume cannot honour exactly, each refused with the line of the directive. */
TEST(refusals_name_file_and_line)
{
    expect_refusal("MakeNamedMedium \"h\" \"string type\" \"homogeneous\" \"string preset\" \"Skin1\"\n", 1, "preset");
    expect_refusal(GRID "\"float density\" [1] \"float temperature\" [900]\n", 1, "temperature");
    expect_refusal(GRID "\"float density\" [1] \"rgb Le\" [1 1 1]\n", 1, "Lescale grid");
    expect_refusal("MakeNamedMedium \"c\" \"string type\" \"rgbgrid\" \"integer nx\" 2 \"rgb sigma_s\" [1 2 3 3 2 1] "
                   "\"rgb sigma_a\" [0 0 0 0 0 0]\n",
                   1, "changes colour");
    expect_refusal("MakeNamedMedium \"c\" \"string type\" \"rgbgrid\" \"rgb sigma_s\" [1 1 1] \"rgb Le\" [1 0 0]\n", 1,
                   "\"Le\"");
    expect_refusal("MakeNamedMedium \"c\" \"string type\" \"rgbgrid\" \"rgb sigma_s\" [1 1 1]\n", 1,
                   "no \"rgb sigma_a\" grid");
    expect_refusal("MakeNamedMedium \"c\" \"string type\" \"fog\"\n", 1, "type \"fog\"");
    expect_refusal("Shape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 1]\n", 1, "not planar");
    expect_refusal("Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0] \"integer indices\" [0 1 3]\n", 1,
                   "index 2: 3 is not a point");
    expect_refusal("Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 0]\n", 1, "no \"integer indices\"");
    expect_refusal("Shape \"cone\"\n", 1, "Shape \"cone\"");
    expect_refusal("Shape \"plymesh\" \"string filename\" \"none.ply\" \"float edgelength\" 1\n", 1,
                   "\"float edgelength\"");
}

static void expect_big_refused(const char *head, size_t n, const char *frag);

/* Inline grids an attacker could write: counts that overflow int, counts that do not match,
 * NaN, negative densities, more samples than brume takes inline. */
TEST(hostile_inline_grids_are_refused)
{
    expect_refusal(GRID "\"integer nx\" 65536 \"integer ny\" 65536 \"integer nz\" 65536 \"float density\" [1 2]\n",
                   1, "2 values for nx ny nz = 65536 x 65536 x 65536");
    expect_refusal(GRID "\"integer nx\" 3 \"float density\" [1 2]\n", 1, "2 values for nx ny nz = 3 x 1 x 1");
    expect_refusal(GRID "\"integer nx\" 2 \"float density\" [nan 1]\n", 1, "expected a number");
    expect_refusal(GRID "\"integer nx\" 2 \"float density\" [1 -1]\n", 1, "density value 1: -1 outside");
    expect_refusal(GRID "\"integer nx\" 0 \"float density\" [1]\n", 1, "\"nx\": 0 is not an integer");
    expect_refusal(GRID "\"float density\" [1] \"point3 p0\" [0 0 0] \"point3 p1\" [1 0 1]\n", 1, "p1 must exceed");
    /* 128^3 samples: within the parameter's limit, over the inline grid's with the zero layer */
    expect_big_refused(GRID "\"integer nx\" 128 \"integer ny\" 128 \"integer nz\" 128 \"float density\" [",
                       128 * 128 * 128, "over the 2097152 brume takes inline");
}

/* HEAD, head, n values "1" and "]": translated, it is refused with the line and frag. */
static void expect_big_refused(const char *head, size_t n, const char *frag)
{
    char *text = malloc(2 * n + 1024);
    ASSERT_TRUE(text != NULL);
    int k = snprintf(text, 1024, "%s%s", HEAD, head);
    for (size_t i = 0; i < n; i++) {
        text[k++] = '1';
        text[k++] = ' ';
    }
    strcpy(text + k, "]\n");
    const char *path = test_tmp_path("big.pbrt");
    test_write_file(path, text);
    free(text);
    char *json = NULL;
    ASSERT_TRUE(scene_pbrt_json(path, &json) != BRUME_OK);
    char want[1200];
    snprintf(want, sizeof want, "%s:%d: ", path, HEAD_LINES + 1);
    ASSERT_CONTAINS(err_message(), want);
    ASSERT_CONTAINS(err_message(), frag);
    remove(path);
}

/* Grids each within the limit that together pass the scene's: four of 100^3 samples (102^3
 * with the zero layer, 4.24e6 > 2^22) are refused at the fourth. */
TEST(inline_data_bounded_per_scene)
{
    size_t n = 100 * 100 * 100, cap = strlen(HEAD) + 4 * (2 * n + 256);
    char *text = malloc(cap);
    ASSERT_TRUE(text != NULL);
    size_t k = (size_t)snprintf(text, cap, "%s", HEAD);
    for (int g = 0; g < 4; g++) {
        k += (size_t)snprintf(text + k, cap - k, "MakeNamedMedium \"g%d\" \"string type\" \"uniformgrid\" \"integer nx\" "
                              "100 \"integer ny\" 100 \"integer nz\" 100 \"float density\" [", g);
        for (size_t i = 0; i < n; i++) {
            text[k++] = '1';
            text[k++] = ' ';
        }
        text[k++] = ']';
        text[k++] = '\n';
    }
    text[k] = '\0';
    const char *path = test_tmp_path("four.pbrt");
    test_write_file(path, text);
    free(text);
    char *json = NULL;
    ASSERT_TRUE(scene_pbrt_json(path, &json) != BRUME_OK);
    char want[1200];
    snprintf(want, sizeof want, "%s:%d: MakeNamedMedium \"g3\": the scene's inline grids and meshes", path,
             HEAD_LINES + 4);
    ASSERT_CONTAINS(err_message(), want);
    remove(path);
}

/* A triangle mesh of more coordinates than the scene format takes inline is refused by the
 * reader with its line, not later by the scene reader. */
TEST(oversized_mesh_is_refused)
{
    expect_big_refused("Shape \"trianglemesh\" \"integer indices\" [0 1 2] \"point3 P\" [", 3 * 700000,
                       "more than the 2097152 coordinates");
}

#define CAM "\"camera\": {\"position\": [0, 0, 9], \"look_at\": [0, 0, 0]}, "

/* The scene format's inline arrays, which the translations use, check their data. */
TEST(inline_json_arrays_are_checked)
{
    static const char *const bad[][2] = {
        {"{\"type\": \"array\", \"dims\": [2, 1, 1], \"data\": [1]}", "media[0].density.data: 1 values"},
        {"{\"type\": \"array\", \"dims\": [2, 1, 1], \"data\": [1, -2]}", "media[0].density.data[1]"},
        {"{\"type\": \"array\", \"dims\": [2000, 2000, 1], \"data\": [1]}", "over the 2097152"},
        {"{\"type\": \"array\", \"dims\": [1.5, 1, 1], \"data\": [1]}", "dims[0]: 1.5 is not an integer"},
    };
    brume_context *ctx = brume_context_new();
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char json[512];
        snprintf(json, sizeof json, "{" CAM "\"media\": [{\"density\": %s, \"sigma_a\": 0, \"sigma_s\": 1}]}", bad[i][0]);
        brume_scene *s = NULL;
        ASSERT_TRUE(brume_scene_load(ctx, &(brume_source){.path = "<t>", .text = json}, NULL, &s) != BRUME_OK);
        ASSERT_CONTAINS(brume_context_last_error(ctx), bad[i][1]);
    }
    brume_scene *s = NULL;
    const char *mesh = "{" CAM "\"surfaces\": [{\"type\": \"mesh\", \"positions\": [0, 0, 0, 1, 0, 0, 0, 1, 0], "
                       "\"indices\": [0, 1, 3]}]}";
    ASSERT_TRUE(brume_scene_load(ctx, &(brume_source){.path = "<t>", .text = mesh}, NULL, &s) != BRUME_OK);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "surfaces[0].indices[2]: expected a vertex index in [0, 3)");
    /* placed by bounds then transform, as a grid file: [0, 2] x ... scaled by 3 and moved by 1 */
    const char *placed = "{" CAM "\"media\": [{\"density\": {\"type\": \"array\", \"dims\": [2, 1, 1], \"data\": [1, 3], "
                         "\"bounds\": [[0, 0, 0], [2, 1, 1]], \"transform\": {\"translate\": [1, 0, 0], "
                         "\"scale\": 3}}, \"sigma_a\": 0, \"sigma_s\": 1}]}";
    if (brume_scene_load(ctx, &(brume_source){.path = "<t>", .text = placed}, NULL, &s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    brume_context_release(ctx);
    ASSERT_EQ_INT(brume_scene_commit(NULL, s), BRUME_OK);
    ASSERT_NEAR(density_bounds(s->media[0].rho).hi.x, 7.0, 1e-9);
    ASSERT_NEAR(density_eval(s->media[0].rho, v3(5.5, 1.5, 1.5)), 3.0, 1e-6); /* the second cell's centre */
    brume_scene_release(s);
}

/* pbrt's LookAt without a mirror looks left-handed (image right = up x forward): most of
 * pbrt-v4-scenes. brume translates the whole world mirrored in x, the camera too, so the
 * picture is pbrt's. Worked by hand: looking from (0, 0, -5) at the origin, up +y, pbrt's
 * image right is y x z = +x, so a sphere at x = +1 is on the right; the same picture is the
 * right-handed view (Scale -1 1 1 before LookAt) of a sphere at x = -1. The two files must
 * translate to the same scene (camera and sphere; -0 and 0 alike), and in the rendered
 * picture the sphere is on the right. */
TEST(left_handed_view_translates_mirrored)
{
#define LH_SCENE(PREFIX, X)                                                                     \
    "Film \"rgb\" \"integer xresolution\" [32] \"integer yresolution\" [16]\n"                   \
    "Sampler \"halton\" \"integer pixelsamples\" [4]\n" PREFIX "LookAt 0 0 -5  0 0 0  0 1 0\n"     \
    "Camera \"perspective\" \"float fov\" [30]\n"                                                \
    "WorldBegin\n"                                                                              \
    "LightSource \"distant\" \"point3 from\" [0.5 1 -1] \"point3 to\" [0 0 0] \"rgb L\" [3 3 3]\n" \
    "AttributeBegin\n"                                                                          \
    "  Translate " X " 0 0\n"                                                                   \
    "  Material \"diffuse\" \"rgb reflectance\" [0.8 0.8 0.8]\n"                                 \
    "  Shape \"sphere\" \"float radius\" 0.6\n"                                                  \
    "AttributeEnd\n"
    const char *text[2] = {LH_SCENE("", "1"), LH_SCENE("Scale -1 1 1\n", "-1")};
    cJSON *root[2];
    for (int k = 0; k < 2; k++) {
        const char *path = test_tmp_path(k ? "rh.pbrt" : "lh.pbrt");
        test_write_file(path, text[k]);
        char *json = NULL;
        if (scene_pbrt_json(path, &json) != BRUME_OK)
            TEST_FAIL("%s", err_message());
        ASSERT_TRUE((root[k] = cJSON_Parse(json)) != NULL);
        free(json);
    }
    const cJSON *cam[2] = {cJSON_GetObjectItemCaseSensitive(root[0], "camera"),
                           cJSON_GetObjectItemCaseSensitive(root[1], "camera")};
    const char *keys[] = {"position", "look_at", "up"};
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < 3; i++)
            ASSERT_NEAR(num(cam[0], keys[k], i), num(cam[1], keys[k], i), 1e-12);
    const cJSON *sf[2] = {cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root[0], "surfaces"), 0),
                          cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root[1], "surfaces"), 0)};
    ASSERT_TRUE(sf[0] && sf[1]);
    /* the same sphere: centre and radius (the mirrored one carries the mirror x -> -x in its
     * transform's scale, the same set of points) */
    const cJSON *t[2] = {cJSON_GetObjectItemCaseSensitive(sf[0], "transform"),
                         cJSON_GetObjectItemCaseSensitive(sf[1], "transform")};
    for (int i = 0; i < 3; i++) {
        ASSERT_NEAR(num(t[0], "translate", i), num(t[1], "translate", i), 1e-12);
        ASSERT_NEAR(fabs(num(t[0], "scale", i)), fabs(num(t[1], "scale", i)), 1e-12);
    }
    ASSERT_NEAR(num(sf[0], "radius", -1), num(sf[1], "radius", -1), 1e-12);
    ASSERT_NEAR(num(cam[0], "position", 0), 0.0, 1e-12);
    cJSON_Delete(root[0]), cJSON_Delete(root[1]);
    /* rendered: the sphere lights the right half */
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = test_tmp_path("lh.pbrt")}, NULL, &s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    brume_image *img = test_render_scene(s, -1, 5);
    const float *px = brume_image_pixels(img);
    double half[2] = {0, 0};
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 32; x++)
            half[x >= 16] += px[4 * (y * 32 + x) + 1];
    printf("left half %.3f, right half %.3f\n", half[0], half[1]);
    ASSERT_TRUE(half[1] > 10.0 * half[0] + 1e-3);
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
}

TEST_MAIN(homogeneous_medium_maps_units, left_handed_view_translates_mirrored, uniformgrid_matches_pbrt_lookup, rgbgrid_one_colour_times_density,
          meshes_translate, homogeneous_box_transmittance, refusals_name_file_and_line,
          hostile_inline_grids_are_refused, oversized_mesh_is_refused, inline_data_bounded_per_scene,
          inline_json_arrays_are_checked)
