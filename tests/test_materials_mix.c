/* test_materials_mix.c - pbrt-v4's mix material and textured material parameters
 * (brume.h's brume_material, docs/surfaces.md "Materials"): a mix under a sun renders the
 * amount-weighted mix of its two materials (nested, with a textured amount too); textured
 * roughness, coateddiffuse reflectance and conductor reflectance read at the hit as pbrt-v4
 * defines them; pbrt-v4's mix, named materials and textured parameters translated, and
 * what brume cannot honour refused by name; the GPU's refusals. */
#include "test.h"

#include <math.h>
#include <string.h>

#include "brume.h"
#include "core/error.h"
#include "gpu/device_scene.h"
#include "pbrt_translate.h"
#include "render/integrator.h"
#include "scene/scene.h"
#include "surface/surfaces.h"

#define PI_ 3.14159265358979323846

/* A quad [-1, 1]^2 at z = 0 facing +z under a sun of irradiance 3 along its normal, seen
 * whole by the camera (which sees [-0.9, 0.9]^2). */
#define SUN_SCENE(MAT)                                                                                        \
    "{\"camera\": {\"position\": [0, 0, 2], \"look_at\": [0, 0, 0], \"up\": [0, 1, 0], \"fov\": 48.4555},"   \
    " \"lights\": [{\"type\": \"distant\", \"direction\": [0, 0, -1], \"irradiance\": [3, 3, 3]}],"             \
    " \"surfaces\": [{\"type\": \"quad\", \"name\": \"plate\", \"corner\": [-1, -1, 0], \"edge_u\": [2, 0, 0],"  \
    " \"edge_v\": [0, 2, 0], \"material\": " MAT "}],"                                                          \
    " \"render\": {\"width\": 48, \"height\": 48, \"spp\": 4, \"method\": \"path\"}}"

#define WHITE "{\"albedo\": [0.8, 0.8, 0.8]}"
#define BLACK "{\"albedo\": [0, 0, 0]}"

/* The image's mean green and its standard error (pixels independent). */
static void image_mean(const char *json, double *mean, double *se)
{
    brume_image *img = test_render_json(json, 7);
    test_channel_mean(brume_image_pixels(img), brume_image_width(img) * brume_image_height(img), 1, mean, se);
    brume_image_release(img);
}

/* The mix's radiance against `fraction` of the white plate's (itself 0.8 x 3 / pi, Lambert's
 * albedo E / pi): the mix picks white or black per shading point, so its pixels carry the
 * choice's binomial noise, which their spread measures; 4 standard errors. */
static void expect_fraction(const char *mix_json, double fraction)
{
    double w, w_se, m, m_se;
    image_mean(SUN_SCENE(WHITE), &w, &w_se);
    ASSERT_NEAR(w, 0.8 * 3 / PI_, 4 * w_se + 1e-5);
    image_mean(mix_json, &m, &m_se);
    double tol = 4 * hypot(m_se, fraction * w_se) + 1e-5;
    if (!(fabs(m - fraction * w) <= tol))
        TEST_FAIL("mix: mean %.6f, want %.4f x %.6f = %.6f (tolerance %.6f)", m, fraction, w, fraction * w, tol);
    ASSERT_TRUE(m_se > 0.0); /* chosen per shading point, not once per surface */
}

/* pbrt-v4's MixMaterial: materials[1] with probability amount. mix(white, black, 0.3) is 0.7
 * white. */
TEST(mix_renders_the_amount_weighted_mix)
{
    expect_fraction(SUN_SCENE("{\"type\": \"mix\", \"materials\": [" WHITE ", " BLACK "], \"amount\": 0.3}"), 0.7);
}

/* Nested mixes choose independently; an amount given as a float texture: mix(mix(white,
 * black, 0.5), white, 0.25) is 0.75 x 0.5 + 0.25 = 0.625 white. */
TEST(nested_mix_with_a_textured_amount)
{
    expect_fraction(SUN_SCENE("{\"type\": \"mix\", \"materials\": [{\"type\": \"mix\", \"materials\": [" WHITE ", " BLACK
                              "], \"amount\": 0.5}, " WHITE "], \"amount\": {\"type\": \"constant\", \"value\": 0.25}}"),
                    0.625);
}

/* The green mean and standard error of the .pbrt text's render (its own film: 32 x 32). */
static void pbrt_mean(const char *name, const char *text, double *mean, double *se)
{
    const char *path = test_tmp_path(name);
    test_write_file(path, text);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    brume_image *img = test_render_scene(s, 2, 11);
    test_channel_mean(brume_image_pixels(img), brume_image_width(img) * brume_image_height(img), 1, mean, se);
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
}

#define DISK_HEAD                                                                                             \
    "LookAt 0 0 2  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [48.4555]\n"                            \
    "Film \"rgb\" \"integer xresolution\" [32] \"integer yresolution\" [32]\n"                                \
    "Sampler \"sobol\" \"integer pixelsamples\" [4]\nWorldBegin\n"                                          \
    "LightSource \"distant\" \"point3 from\" [0 0 1] \"point3 to\" [0 0 0] \"rgb L\" [3 3 3]\n"

/* The brief's disk through pbrt-v4's own directives: a disk (filling the view) of
 * MakeNamedMaterial "mix" of two named diffuse materials, white 0.8 and black, amount 0.3,
 * against the white disk: 0.7 x its radiance, 4 standard errors of both means. */
TEST(pbrt_mix_disk_is_the_amount_weighted_mix)
{
    double w, w_se, m, m_se;
    pbrt_mean("white.pbrt", DISK_HEAD "Material \"diffuse\" \"rgb reflectance\" [0.8 0.8 0.8]\n"
                                      "Shape \"disk\" \"float radius\" [2]\n", &w, &w_se);
    ASSERT_NEAR(w, 0.8 * 3 / PI_, 4 * w_se + 1e-5);
    pbrt_mean("mix.pbrt",
              DISK_HEAD "MakeNamedMaterial \"white\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.8 0.8 0.8]\n"
                        "MakeNamedMaterial \"black\" \"string type\" \"diffuse\" \"rgb reflectance\" [0 0 0]\n"
                        "MakeNamedMaterial \"m\" \"string type\" \"mix\" \"string materials\" [\"white\" \"black\"]\n"
                        "  \"float amount\" [0.3]\nNamedMaterial \"m\"\nShape \"disk\" \"float radius\" [2]\n",
              &m, &m_se);
    double tol = 4 * hypot(m_se, 0.7 * w_se) + 1e-5;
    if (!(fabs(m - 0.7 * w) <= tol))
        TEST_FAIL("mix disk: mean %.6f, want 0.7 x %.6f = %.6f (tolerance %.6f)", m, w, 0.7 * w, tol);
}

/* The material a ray straight down at (x, y) meets on the plate. */
static material hit_material(brume_scene *s, double x, double y)
{
    surface_hit h;
    ray r = {v3(x, y, 2), v3(0, 0, -1), 0.0};
    ASSERT_TRUE(surfaces_intersect(s->surf, r, 1e-6, 1e30, &h));
    return *h.mat;
}

static brume_scene *committed(const char *json)
{
    brume_scene *s = test_scene_json(json);
    brume_context *ctx = brume_context_new();
    if (brume_scene_commit(ctx, s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    brume_context_release(ctx);
    return s;
}

/* A roughness checkerboard (0.01 where floor(2u) + floor(2v) is even, else 0.25; the quad's
 * u runs along x from -1, v along y) is pbrt-v4's roughness at the hit: alpha = sqrt(r)
 * remapped, r itself without the remap. */
TEST(roughness_texture_is_read_at_the_hit)
{
    static const char *const remap[2] = {"true", "false"};
    for (int k = 0; k < 2; k++) {
        char json[2048];
        snprintf(json, sizeof json,
                 SUN_SCENE("{\"type\": \"conductor\", \"remaproughness\": %s, \"roughness\": {\"type\": "
                           "\"checkerboard\", \"tex1\": 0.01, \"tex2\": 0.25, \"uscale\": 2, \"vscale\": 2}}"),
                 remap[k]);
        brume_scene *s = committed(json);
        material even = hit_material(s, -0.5, -0.5), odd = hit_material(s, 0.5, -0.5);
        ASSERT_NEAR(even.alpha, k == 0 ? 0.1 : 0.01, 1e-12);
        ASSERT_NEAR(odd.alpha, k == 0 ? 0.5 : 0.25, 1e-12);
        ASSERT_EQ_INT(even.type, MATERIAL_CONDUCTOR);
        brume_scene_release(s);
    }
}

/* A conductor's textured reflectance r is pbrt-v4's: eta 1 and k = 2 sqrt(r) / sqrt(1 - r);
 * coateddiffuse's is the base's albedo; a mix of amount 0 is its first material, of 1 its
 * second (pbrt-v4 draws no number then). */
TEST(textured_reflectance_and_mix_bounds)
{
    brume_scene *s = committed(SUN_SCENE("{\"type\": \"conductor\", \"reflectance\": {\"type\": \"constant\", "
                                         "\"value\": [0.64, 0.36, 0.04]}}"));
    material m = hit_material(s, 0.1, 0.2);
    const double r[3] = {0.64, 0.36, 0.04};
    for (int c = 0; c < 3; c++) {
        ASSERT_NEAR(m.eta_c.c[c], 1.0, 1e-12);
        ASSERT_NEAR(m.k_c.c[c], 2 * sqrt(r[c]) / sqrt(1 - r[c]), 1e-6);
    }
    brume_scene_release(s);
    for (int amount = 0; amount <= 1; amount++) {
        char json[2048];
        snprintf(json, sizeof json,
                 SUN_SCENE("{\"type\": \"mix\", \"amount\": %d, \"materials\": [{\"type\": \"coateddiffuse\", "
                           "\"reflectance\": {\"type\": \"constant\", \"value\": [0.2, 0.4, 0.6]}}, "
                           "{\"type\": \"dielectric\"}]}"),
                 amount);
        s = committed(json);
        for (int i = 0; i < 16; i++) {
            material h = hit_material(s, -0.8 + 0.1 * i, 0.3);
            ASSERT_EQ_INT(h.type, amount ? MATERIAL_DIELECTRIC : MATERIAL_COATEDDIFFUSE);
            if (!amount)
                ASSERT_NEAR(h.albedo.c[2], 0.6, 1e-6);
        }
        brume_scene_release(s);
    }
}

/* What a scene file's mix and textured parameters refuse, naming the key. */
TEST(json_mix_and_textures_checked)
{
    static const struct {
        const char *json, *frag;
    } bad[] = {
        {SUN_SCENE("{\"type\": \"mix\", \"materials\": [" WHITE "]}"), "materials: expected an array of two"},
        {SUN_SCENE("{\"type\": \"mix\", \"materials\": [" WHITE ", " BLACK "], \"amount\": 1.5}"), "amount"},
        {SUN_SCENE("{\"type\": \"mix\", \"materials\": [" WHITE ", {\"type\": \"velvet\"}]}"),
         "materials[1].type"},
        {SUN_SCENE("{\"type\": \"dielectric\", \"roughness\": {\"type\": \"constant\", \"value\": 0.1}, "
                   "\"uroughness\": 0.1}"),
         "isotropic"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        const char *path = test_tmp_path("mix.json");
        test_write_file(path, bad[k].json);
        brume_context *ctx = brume_context_new();
        brume_scene *s = NULL;
        ASSERT_TRUE(brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK);
        ASSERT_CONTAINS(brume_context_last_error(ctx), bad[k].frag);
        brume_context_release(ctx);
    }
}

#define PBRT_HEAD                                                                                             \
    "LookAt 0 0 2  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [48.4555]\n"                            \
    "Film \"rgb\" \"integer xresolution\" [16] \"integer yresolution\" [16]\nWorldBegin\n"                     \
    "LightSource \"distant\" \"point3 from\" [0 0 1] \"point3 to\" [0 0 0] \"rgb L\" [3 3 3]\n"
#define PBRT_PATCH "Shape \"bilinearmesh\" \"point3 P\" [-1 -1 0  1 -1 0  -1 1 0  1 1 0]\n"

/* Crown's constructs: a mix of two named materials with a float texture amount, a
 * coateddiffuse with a spectrum texture reflectance, a conductor with named spectra and a
 * float texture roughness, equal uroughness and vroughness textures. */
TEST(pbrt_mix_and_textured_parameters_translate)
{
    char msg[1024];
    cJSON *root = pbrt_translate(
        "mix.pbrt",
        PBRT_HEAD "Texture \"mask\" \"float\" \"constant\" \"float value\" [0.25]\n"
                  "Texture \"rough\" \"float\" \"scale\" \"float scale\" [0.1] \"float tex\" [0.4]\n"
                  "Texture \"kd\" \"spectrum\" \"constant\" \"rgb value\" [0.2 0.4 0.6]\n"
                  "MakeNamedMaterial \"red\" \"string type\" \"coateddiffuse\" \"texture reflectance\" \"kd\"\n"
                  "  \"texture uroughness\" \"rough\" \"texture vroughness\" \"rough\"\n"
                  "MakeNamedMaterial \"gold\" \"string type\" \"conductor\" \"spectrum eta\" \"metal-Au-eta\"\n"
                  "  \"spectrum k\" \"metal-Au-k\" \"texture roughness\" \"rough\" \"texture displacement\" \"mask\"\n"
                  "MakeNamedMaterial \"both\" \"string type\" \"mix\" \"string materials\" [\"red\" \"gold\"]\n"
                  "  \"texture amount\" \"mask\"\n"
                  "NamedMaterial \"both\"\n" PBRT_PATCH,
        msg, sizeof msg);
    if (!root)
        TEST_FAIL("%s", msg);
    const cJSON *surf = cJSON_GetArrayItem(cJSON_GetObjectItem(root, "surfaces"), 0);
    const cJSON *mat = cJSON_GetObjectItem(surf, "material");
    ASSERT_TRUE(cJSON_GetObjectItem(surf, "uvs") != NULL);
    ASSERT_EQ_STR(cJSON_GetObjectItem(mat, "type")->valuestring, "mix");
    ASSERT_EQ_STR(cJSON_GetObjectItem(cJSON_GetObjectItem(mat, "amount"), "type")->valuestring, "constant");
    const cJSON *ms = cJSON_GetObjectItem(mat, "materials");
    const cJSON *red = cJSON_GetArrayItem(ms, 0), *gold = cJSON_GetArrayItem(ms, 1);
    ASSERT_EQ_STR(cJSON_GetObjectItem(red, "type")->valuestring, "coateddiffuse");
    ASSERT_EQ_STR(cJSON_GetObjectItem(cJSON_GetObjectItem(red, "reflectance"), "type")->valuestring, "constant");
    ASSERT_EQ_STR(cJSON_GetObjectItem(cJSON_GetObjectItem(red, "roughness"), "type")->valuestring, "scale");
    ASSERT_EQ_STR(cJSON_GetObjectItem(gold, "eta")->valuestring, "metal-Au-eta");
    ASSERT_EQ_STR(cJSON_GetObjectItem(cJSON_GetObjectItem(gold, "roughness"), "type")->valuestring, "scale");
    ASSERT_EQ_STR(cJSON_GetObjectItem(cJSON_GetObjectItem(gold, "displacement"), "type")->valuestring, "constant");
    cJSON_Delete(root);
    /* and the scene it makes loads, its roughness texture 0.1 x 0.4 remapped to sqrt(0.04) */
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = test_tmp_path("mix.pbrt")}, NULL, &s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    for (int i = 0; i < 8; i++) {
        material m = hit_material(s, -0.7 + 0.2 * i, 0.1);
        ASSERT_NEAR(m.alpha, 0.2, 1e-9);
    }
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* The other parameters pbrt-v4 textures: a conductor's eta and k (spectrum textures, kept in
 * [0, 100]), a coated diffuse's thickness, g (kept in [-0.999, 0.999]) and layer albedo (kept
 * in [0, 1]), each read at the hit from pbrt-v4's Texture directive. */
TEST(index_and_layer_textures_read_at_the_hit)
{
    char msg[1024];
    cJSON *root = pbrt_translate(
        "layer.pbrt",
        PBRT_HEAD "Texture \"eta\" \"spectrum\" \"constant\" \"rgb value\" [0.2 0.5 1.5]\n"
                  "Texture \"k\" \"spectrum\" \"constant\" \"rgb value\" [3 2 200]\n"
                  "Material \"conductor\" \"texture eta\" \"eta\" \"texture k\" \"k\"\n" PBRT_PATCH
                  "Texture \"t\" \"float\" \"constant\" \"float value\" [0.3]\n"
                  "Texture \"g\" \"float\" \"constant\" \"float value\" [1.5]\n"
                  "Texture \"a\" \"spectrum\" \"constant\" \"rgb value\" [0.1 0.6 1.2]\n"
                  "Material \"coateddiffuse\" \"texture thickness\" \"t\" \"texture g\" \"g\" \"texture albedo\" \"a\"\n"
                  "AttributeBegin\nTranslate 0 0 -1\n" PBRT_PATCH "AttributeEnd\n",
        msg, sizeof msg);
    if (!root)
        TEST_FAIL("%s", msg);
    const cJSON *surfs = cJSON_GetObjectItem(root, "surfaces");
    const cJSON *metal = cJSON_GetObjectItem(cJSON_GetArrayItem(surfs, 0), "material");
    const cJSON *coat = cJSON_GetObjectItem(cJSON_GetArrayItem(surfs, 1), "material");
    ASSERT_EQ_STR(cJSON_GetObjectItem(cJSON_GetObjectItem(metal, "eta"), "type")->valuestring, "constant");
    ASSERT_EQ_STR(cJSON_GetObjectItem(cJSON_GetObjectItem(coat, "layer_albedo"), "type")->valuestring, "constant");
    cJSON_Delete(root);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = test_tmp_path("layer.pbrt")}, NULL, &s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    material m = hit_material(s, 0.1, 0.2); /* the metal, at z = 0 */
    ASSERT_EQ_INT(m.type, MATERIAL_CONDUCTOR);
    const double eta[3] = {0.2, 0.5, 1.5}, k[3] = {3, 2, 100};
    for (int c = 0; c < 3; c++) {
        ASSERT_NEAR(m.eta_c.c[c], eta[c], 1e-9);
        ASSERT_NEAR(m.k_c.c[c], k[c], 1e-9);
    }
    brume_scene_release(s);
    brume_context_release(ctx);
    s = committed(SUN_SCENE("{\"type\": \"coateddiffuse\", \"thickness\": {\"type\": \"constant\", \"value\": 0.3},"
                            " \"g\": {\"type\": \"constant\", \"value\": 1.5}, \"layer_albedo\": {\"type\": \"constant\","
                            " \"value\": [0.1, 0.6, 1.2]}}"));
    m = hit_material(s, 0.1, 0.2);
    ASSERT_NEAR(m.thickness, 0.3, 1e-12);
    ASSERT_NEAR(m.g, 0.999, 1e-12);
    ASSERT_NEAR(m.layer_albedo.c[0], 0.1, 1e-12);
    ASSERT_NEAR(m.layer_albedo.c[2], 1.0, 1e-12);
    brume_scene_release(s);
}

/* A 2 x 1 RGB PFM ramp: 0 then 1 (pixel centres at u = 0.25 and 0.75), read bilinearly with
 * wrap clamp: d(u) = 2 scale (u - 0.25) over [0.25, 0.75]. */
static const char *ramp_pfm(void)
{
    const char *path = test_tmp_path("ramp.pfm");
    unsigned char bytes[64];
    const char head[] = "PF\n2 1\n-1.0\n";
    size_t n = sizeof head - 1;
    memcpy(bytes, head, n);
    const float px[6] = {0, 0, 0, 1, 1, 1}; /* little-endian floats, this machine's order */
    memcpy(bytes + n, px, sizeof px);
    test_write_bytes(path, bytes, n + sizeof px);
    return path;
}

/* pbrt-v4's BumpMap on a plate whose displacement rises along u: the quad's dp/du = (2, 0, 0)
 * and dp/dv = (0, 2, 0) (u and v run over 2 units), d(u) = g u + c with g = 2 x 0.5 = 1, so
 * dp/du' = (2, 0, g), dp/dv' = (0, 2, 0) and the shading normal (-2 g, 0, 4) / |.| leans
 * towards -x by atan(g / 2). Under a sun arriving from 30 degrees towards -x (direction of
 * travel (sin 30, 0, -cos 30)) the diffuse plate reflects albedo / pi x E x cos(theta'),
 * cos(theta') = (g sin 30 x 2 + 4 cos 30) / sqrt(4 g^2 + 16); unbumped it would be cos 30.
 * Pixels with |x| < 0.4 (u in [0.3, 0.7], off the ramp's kinks), 4 standard errors. */
TEST(bump_tilts_the_shading_normal_as_pbrt)
{
    char json[4096];
    const char *ramp = ramp_pfm();
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 2], \"look_at\": [0, 0, 0], \"up\": [0, 1, 0], \"fov\": 48.4555},"
             " \"lights\": [{\"type\": \"distant\", \"direction\": [0.5, 0, -0.8660254037844386], \"irradiance\": [3, 3, 3]}],"
             " \"surfaces\": [{\"type\": \"quad\", \"name\": \"plate\", \"corner\": [-1, -1, 0], \"edge_u\": [2, 0, 0],"
             " \"edge_v\": [0, 2, 0], \"material\": {\"albedo\": [0.8, 0.8, 0.8], \"displacement\": {\"type\": \"imagemap\","
             " \"file\": \"%s\", \"scale\": 0.5, \"wrap\": \"clamp\"}}}],"
             " \"render\": {\"width\": 40, \"height\": 40, \"spp\": 4, \"method\": \"path\"}}",
             ramp);
    const double g = 1.0, s30 = 0.5, c30 = 0.8660254037844386;
    const double cos_t = (2 * g * s30 + 4 * c30) / sqrt(4 * g * g + 16);
    brume_scene *s = committed(json);
    surface_hit h;
    ASSERT_TRUE(surfaces_intersect(s->surf, (ray){v3(0.1, 0.2, 2), v3(0, 0, -1), 0.0}, 1e-6, 1e30, &h));
    ASSERT_NEAR(h.ns.x, -2 * g / sqrt(4 * g * g + 16), 1e-4);
    ASSERT_NEAR(h.ns.y, 0.0, 1e-9);
    ASSERT_NEAR(h.ns.z, 4 / sqrt(4 * g * g + 16), 1e-4);
    brume_scene_release(s);
    brume_image *img = test_render_json(json, 3);
    int w = brume_image_width(img), ht = brume_image_height(img);
    const float *px = brume_image_pixels(img);
    double sum = 0, sq = 0;
    int n = 0;
    for (int j = 0; j < ht; j++)
        for (int i = 0; i < w; i++) {
            double x = 0.9 * (2.0 * (i + 0.5) / w - 1.0);
            if (fabs(x) >= 0.4)
                continue;
            double v = px[4 * ((size_t)j * (size_t)w + (size_t)i) + 1];
            sum += v, sq += v * v, n++;
        }
    double mean = sum / n, se = sqrt(fmax(sq / n - mean * mean, 0.0) / n);
    double want = 0.8 / PI_ * 3 * cos_t;
    if (!(fabs(mean - want) <= 4 * se + 1e-5 * want))
        TEST_FAIL("bumped plate: mean %.6f, want %.6f (cos %.5f; unbumped %.6f), se %g", mean, want, cos_t,
                  0.8 / PI_ * 3 * c30, se);
    brume_image_release(img);
}

/* A PLY file's texture coordinates are read (pbrt-v4's plymesh "u" "v"): a square of two
 * triangles whose (u, v) run from (0, 0) to (1, 1) over [-1, 1]^2, where pbrt-v4's default per
 * triangle would give the second triangle other values ((0.75, 0.5) at (-0.5, 0.5)). */
TEST(mesh_file_texture_coordinates_read)
{
    const char *ply = test_tmp_path("uv.ply");
    test_write_file(ply, "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                         "property float z\nproperty float u\nproperty float v\nelement face 2\n"
                         "property list uchar int vertex_indices\nend_header\n"
                         "-1 -1 0 0 0\n1 -1 0 1 0\n1 1 0 1 1\n-1 1 0 0 1\n3 0 1 2\n3 0 2 3\n");
    char json[2048];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 2], \"look_at\": [0, 0, 0]}, \"surfaces\": [{\"type\": \"mesh\","
             " \"file\": \"%s\", \"material\": {\"albedo\": {\"type\": \"checkerboard\", \"tex1\": 0.8,"
             " \"tex2\": 0.2, \"uscale\": 2, \"vscale\": 2}}}]}",
             ply);
    brume_scene *s = committed(json);
    surface_hit h;
    ASSERT_TRUE(surfaces_intersect(s->surf, (ray){v3(-0.5, 0.5, 2), v3(0, 0, -1), 0.0}, 1e-6, 1e30, &h));
    ASSERT_NEAR(h.uv[0], 0.25, 1e-6);
    ASSERT_NEAR(h.uv[1], 0.75, 1e-6);
    ASSERT_NEAR(h.mat->albedo.c[0], 0.2, 1e-6); /* floor(0.5) + floor(1.5) is odd */
    brume_scene_release(s);
}

static void pbrt_refused(const char *text, const char *frag)
{
    char msg[1024];
    cJSON *root = pbrt_translate("refuse.pbrt", text, msg, sizeof msg);
    if (root)
        TEST_FAIL("accepted; expected a refusal containing \"%s\"", frag);
    ASSERT_CONTAINS(msg, "refuse.pbrt:");
    ASSERT_CONTAINS(msg, frag);
}

TEST(pbrt_mix_and_texture_refusals_name_them)
{
    pbrt_refused(PBRT_HEAD "Material \"conductor\" \"texture displacement\" \"b\"\n" PBRT_PATCH,
                 "\"texture displacement\": no float Texture named \"b\"");
    pbrt_refused(PBRT_HEAD "Material \"conductor\" \"string normalmap\" \"n.png\"\n" PBRT_PATCH, "\"normalmap\"");
    pbrt_refused(PBRT_HEAD "Texture \"a\" \"float\" \"constant\" \"float value\" [0.1]\n"
                           "Texture \"b\" \"float\" \"constant\" \"float value\" [0.2]\n"
                           "Material \"dielectric\" \"texture uroughness\" \"a\" \"texture vroughness\" \"b\"\n" PBRT_PATCH,
                 "uroughness and vroughness differ");
    pbrt_refused(PBRT_HEAD "MakeNamedMaterial \"m\" \"string type\" \"mix\" \"string materials\" [\"x\" \"y\"]\n",
                 "no MakeNamedMaterial \"x\"");
    pbrt_refused(PBRT_HEAD "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
                           "MakeNamedMaterial \"m\" \"string type\" \"mix\" \"string materials\" [\"a\"]\n",
                 "two names");
    pbrt_refused(PBRT_HEAD "Texture \"e\" \"float\" \"constant\" \"float value\" [1.5]\n"
                           "Material \"dielectric\" \"texture eta\" \"e\"\n" PBRT_PATCH,
                 "\"eta\": a texture");
}

/* The GPU refuses a mix by name, and a textured roughness or a bump map as a texture. */
TEST(gpu_refuses_mix_and_textured_parameters)
{
    brume_scene *s = test_scene_json(SUN_SCENE("{\"type\": \"mix\", \"materials\": [" WHITE ", " BLACK "]}"));
    ASSERT_EQ_INT(device_scene_check(s, INTEGRATOR_PATH), BRUME_ERROR_UNSUPPORTED);
    ASSERT_CONTAINS(err_message(), "plate: material 'mix' renders on the CPU only (--device cpu)");
    brume_scene_release(s);
    s = test_scene_json(SUN_SCENE("{\"type\": \"conductor\", \"roughness\": {\"type\": \"constant\", \"value\": 0.1}}"));
    ASSERT_EQ_INT(device_scene_check(s, INTEGRATOR_PATH), BRUME_ERROR_UNSUPPORTED);
    ASSERT_CONTAINS(err_message(), "textures render on the CPU only (surface 'plate')");
    brume_scene_release(s);
    s = test_scene_json(SUN_SCENE("{\"displacement\": {\"type\": \"constant\", \"value\": 0.1}}"));
    ASSERT_EQ_INT(device_scene_check(s, INTEGRATOR_PATH), BRUME_ERROR_UNSUPPORTED);
    ASSERT_CONTAINS(err_message(), "textures render on the CPU only (surface 'plate')");
    brume_scene_release(s);
}

TEST_MAIN(mix_renders_the_amount_weighted_mix, nested_mix_with_a_textured_amount, roughness_texture_is_read_at_the_hit,
          textured_reflectance_and_mix_bounds, json_mix_and_textures_checked, pbrt_mix_and_textured_parameters_translate,
          pbrt_mix_and_texture_refusals_name_them, gpu_refuses_mix_and_textured_parameters,
          bump_tilts_the_shading_normal_as_pbrt, mesh_file_texture_coordinates_read,
          pbrt_mix_disk_is_the_amount_weighted_mix, index_and_layer_textures_read_at_the_hit)
