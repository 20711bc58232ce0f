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
                  "  \"spectrum k\" \"metal-Au-k\" \"texture roughness\" \"rough\"\n"
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
    pbrt_refused(PBRT_HEAD "Texture \"b\" \"float\" \"constant\" \"float value\" [0.1]\n"
                           "Material \"conductor\" \"texture displacement\" \"b\"\n" PBRT_PATCH,
                 "\"displacement\"");
    pbrt_refused(PBRT_HEAD "Texture \"a\" \"float\" \"constant\" \"float value\" [0.1]\n"
                           "Texture \"b\" \"float\" \"constant\" \"float value\" [0.2]\n"
                           "Material \"dielectric\" \"texture uroughness\" \"a\" \"texture vroughness\" \"b\"\n" PBRT_PATCH,
                 "uroughness and vroughness differ");
    pbrt_refused(PBRT_HEAD "MakeNamedMaterial \"m\" \"string type\" \"mix\" \"string materials\" [\"x\" \"y\"]\n",
                 "no MakeNamedMaterial \"x\"");
    pbrt_refused(PBRT_HEAD "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
                           "MakeNamedMaterial \"m\" \"string type\" \"mix\" \"string materials\" [\"a\"]\n",
                 "two names");
    pbrt_refused(PBRT_HEAD "Texture \"e\" \"spectrum\" \"constant\" \"rgb value\" [1 1 1]\n"
                           "Material \"conductor\" \"texture eta\" \"e\"\n" PBRT_PATCH,
                 "\"eta\": a texture");
}

/* The GPU refuses a mix by name, and a textured roughness as a texture. */
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
}

TEST_MAIN(mix_renders_the_amount_weighted_mix, nested_mix_with_a_textured_amount, roughness_texture_is_read_at_the_hit,
          textured_reflectance_and_mix_bounds, json_mix_and_textures_checked, pbrt_mix_and_textured_parameters_translate,
          pbrt_mix_and_texture_refusals_name_them, gpu_refuses_mix_and_textured_parameters)
