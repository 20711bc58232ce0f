/* test_pbrt_geo.c - pbrt-v4's ReverseOrientation and the front of its shapes, media bound by
 * dielectric shapes and MediumInterface names defined later in the file (docs/pbrt.md). The
 * expected values are worked out from the geometry: which side of a shape faces the camera,
 * and the transmittance exp(-sigma_a d) of an absorbing slab. */
#include "test.h"

#include <math.h>
#include <string.h>

#include "brume.h"
#include "core/error.h"
#include "gpu/device_scene.h"
#include "io/json.h"
#include "render/integrator.h"
#include "scene/scene.h"
#include "scene/scene_pbrt.h"

/* pbrt's right-handed view (Scale -1 1 1) and its bare LookAt, which the reader translates as
 * a mirrored world: the camera at z = -5 looks along +z through a 1-degree view. */
static const char *const views[2] = {"Scale -1 1 1\nLookAt 0 0 -5  0 0 0  0 1 0\n", "LookAt 0 0 -5  0 0 0  0 1 0\n"};

/* The scene of a .pbrt text (written to a temporary file), or NULL with the message. */
static brume_scene *load(brume_context *ctx, const char *text, char *msg, size_t cap)
{
    const char *path = test_tmp_path("geo.pbrt");
    test_write_file(path, text);
    brume_scene *s = NULL;
    brume_status st = brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s);
    snprintf(msg, cap, "%s", st == BRUME_OK ? "" : brume_context_last_error(ctx));
    remove(path);
    return st == BRUME_OK ? s : NULL;
}

/* Each channel's mean (and its standard error) of the image of a pbrt text, seed 29. */
static void render_means(const char *text, double mean[3], double se[3])
{
    char msg[2048];
    brume_context *ctx = brume_context_new();
    brume_scene *s = load(ctx, text, msg, sizeof msg);
    if (!s)
        TEST_FAIL("%s", msg);
    brume_image *img = test_render_scene(s, -1, 29);
    for (int c = 0; c < 3; c++)
        test_channel_mean(brume_image_pixels(img), brume_image_width(img) * brume_image_height(img), c, &mean[c],
                          &se[c]);
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* A one-sided area light (L (1, 2, 3), scale 2) on a black shape that fills the view: each
 * pixel's blue is 6 where pbrt-v4's geometric normal faces the camera (-z), else 0. The
 * object's normal is +z for the disk and the mesh (wound counter-clockwise seen from +z) and
 * outward for the sphere (the camera sees its -z cap). pbrt-v4 (shapes.h): a triangle's normal
 * is its object normal carried through the transform as a normal, reversed by
 * ReverseOrientation, then turned toward the shading normals N (which ReverseOrientation
 * reverses too); a quadric's is reversed again where the transform swaps handedness
 * (flipNormal = reverseOrientation ^ transformSwapsHandedness, in object space). Scale 1 1 -1
 * carries +z to -z and swaps handedness. */
TEST(reverse_orientation_faces_as_pbrt)
{
    static const struct {
        const char *xf, *shape;
        bool lit;
    } cases[] = {
        {"", "disk\" \"float radius\" 100", false},
        {"ReverseOrientation\n", "disk\" \"float radius\" 100", true},
        {"Scale 1 1 -1\n", "disk\" \"float radius\" 100", false},
        {"ReverseOrientation\nScale 1 1 -1\n", "disk\" \"float radius\" 100", true},
        {"", "sphere\"", true},
        {"ReverseOrientation\n", "sphere\"", false},
        {"Scale 1 1 -1\n", "sphere\"", false},
        {"Scale 1 1 -1\nReverseOrientation\n", "sphere\"", true},
        {"", "trianglemesh\" \"point3 P\" [-99 -99 0 99 -99 0 99 99 0 -99 99 0] \"integer indices\" [0 1 2 0 2 3]", false},
        {"ReverseOrientation\n",
         "trianglemesh\" \"point3 P\" [-99 -99 0 99 -99 0 99 99 0 -99 99 0] \"integer indices\" [0 1 2 0 2 3]", true},
        {"Scale 1 1 -1\n",
         "trianglemesh\" \"point3 P\" [-99 -99 0 99 -99 0 99 99 0 -99 99 0] \"integer indices\" [0 1 2 0 2 3]", true},
        {"ReverseOrientation\nScale 1 1 -1\n",
         "trianglemesh\" \"point3 P\" [-99 -99 0 99 -99 0 99 99 0 -99 99 0] \"integer indices\" [0 1 2 0 2 3]", false},
        {"", "trianglemesh\" \"point3 P\" [-99 -99 0 99 -99 0 99 99 0 -99 99 0] \"integer indices\" [0 1 2 0 2 3]"
             " \"normal N\" [0 0 -1 0 0 -1 0 0 -1 0 0 -1]", true},
        {"ReverseOrientation\n",
         "trianglemesh\" \"point3 P\" [-99 -99 0 99 -99 0 99 99 0 -99 99 0] \"integer indices\" [0 1 2 0 2 3]"
         " \"normal N\" [0 0 -1 0 0 -1 0 0 -1 0 0 -1]", false},
        {"Scale 1 1 -1\n",
         "trianglemesh\" \"point3 P\" [-99 -99 0 99 -99 0 99 99 0 -99 99 0] \"integer indices\" [0 1 2 0 2 3]"
         " \"normal N\" [0 0 -1 0 0 -1 0 0 -1 0 0 -1]", false},
    };
    for (int v = 0; v < 2; v++)
        for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
            char text[2048];
            snprintf(text, sizeof text,
                     "Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\n"
                     "Sampler \"halton\" \"integer pixelsamples\" 2\n%sCamera \"perspective\" \"float fov\" 1\n"
                     "WorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 2 3] \"float scale\" 2\n"
                     "Material \"diffuse\" \"rgb reflectance\" [0 0 0]\n%sShape \"%s\nAttributeEnd\n",
                     views[v], cases[i].xf, cases[i].shape);
            double mean[3], se[3], want = cases[i].lit ? 6.0 : 0.0;
            render_means(text, mean, se);
            if (!(fabs(mean[2] - want) <= 1e-5 * 6.0))
                TEST_FAIL("view %d, case %zu (%s%.20s): blue %g, want %g", v, i, cases[i].xf, cases[i].shape, mean[2],
                          want);
        }
}

/* AreaLightSource "power": pbrt-v4 (DiffuseAreaLight::Create) scales L (1, 2, 3) by power /
 * (pi A) for one-sided emission, A the shape's Area(): a quadric's in object space (a disk of
 * radius 5 under Scale 2 2 2 is pi 25 there), a triangle's in the world (each triangle of a
 * mesh is a shape of its own and gets the whole power). The powers are chosen for a radiance
 * of 6 (1, 2, 3): blue 18; a two-sided disk spreads it over both sides: blue 9. */
TEST(area_light_power_per_shape)
{
    static const struct {
        const char *light, *shape;
        double blue;
    } cases[] = {
        {"\"float power\" 5921.762640653615", "Shape \"disk\" \"float radius\" 10", 18.0},       /* 6 pi pi 100 */
        {"\"float power\" 1480.4406601634037", "Scale 2 2 2\nShape \"disk\" \"float radius\" 5", 18.0}, /* 6 pi pi 25 */
        {"\"float power\" 5921.762640653615 \"bool twosided\" true", "Shape \"disk\" \"float radius\" 10", 9.0},
        {"\"float power\" 369488.9951740028", /* 6 pi 19602: each triangle's area */
         "Shape \"trianglemesh\" \"point3 P\" [-99 -99 0 99 -99 0 99 99 0 -99 99 0] \"integer indices\" [0 1 2 0 2 3]",
         18.0},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[2048];
        snprintf(text, sizeof text,
                 "Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\n"
                 "Sampler \"halton\" \"integer pixelsamples\" 2\n%sCamera \"perspective\" \"float fov\" 1\n"
                 "WorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 2 3] %s\n"
                 "Material \"diffuse\" \"rgb reflectance\" [0 0 0]\nReverseOrientation\n%s\nAttributeEnd\n",
                 views[0], cases[i].light, cases[i].shape);
        double mean[3], se[3];
        render_means(text, mean, se);
        if (!(fabs(mean[2] - cases[i].blue) <= 1e-5 * cases[i].blue))
            TEST_FAIL("case %zu: blue %g, want %g", i, mean[2], cases[i].blue);
    }
}

/* A closed box, x and y in [-9, 9], z in [-1, 1], wound counter-clockwise seen from outside
 * (its front outward), as a trianglemesh. */
#define SLAB                                                                                                   \
    "Shape \"trianglemesh\" \"point3 P\" [-9 -9 -1  9 -9 -1  -9 9 -1  9 9 -1  -9 -9 1  9 -9 1  -9 9 1  9 9 1]" \
    " \"integer indices\" [0 2 3 0 3 1  4 5 7 4 7 6  0 1 5 0 5 4  2 6 7 2 7 3  0 4 6 0 6 2  1 3 7 1 7 5]\n"

/* dambreak's liquid: a dielectric shape (eta 1: no refraction, no reflection) whose
 * MediumInterface puts an absorbing ink inside it, seen through against a sky of radiance 1:
 * each channel is exp(-2 sigma_a) (the slab is 2 deep; the 1-degree view's rays are longer by
 * 4e-5 at most), within 4 standard errors. The ink is defined after the shape, which pbrt-v4
 * resolves when it creates the scene. The same with the box's front turned in by
 * ReverseOrientation and the ink named as the outside medium (dambreak's own binding), and
 * under a mirror of the shape (Scale -1 1 1, which carries the front as it is). */
TEST(dielectric_binds_medium_defined_later)
{
    static const char *const binding[] = {"MediumInterface \"ink\" \"\"\n",
                                          "MediumInterface \"\" \"ink\"\nReverseOrientation\n",
                                          "MediumInterface \"\" \"ink\"\nReverseOrientation\nScale -1 1 1\n"};
    const double sigma_a[3] = {0.2, 0.5, 1.0};
    for (int b = 0; b < 3; b++) {
        char text[4096];
        snprintf(text, sizeof text,
                 "Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\n"
                 "Sampler \"independent\" \"integer pixelsamples\" 128\n%sCamera \"perspective\" \"float fov\" 1\n"
                 "WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n"
                 "AttributeBegin\nMaterial \"dielectric\" \"float eta\" 1\n%s" SLAB "AttributeEnd\n"
                 "MakeNamedMedium \"ink\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [%g %g %g]"
                 " \"rgb sigma_s\" [0 0 0]\n",
                 views[b % 2], binding[b], sigma_a[0], sigma_a[1], sigma_a[2]);
        double mean[3], se[3];
        render_means(text, mean, se);
        for (int c = 0; c < 3; c++) {
            double want = exp(-2.0 * sigma_a[c]);
            fprintf(stderr, "binding %d, channel %d: %.5f (se %.2g), want %.5f\n", b, c, mean[c], se[c], want);
            ASSERT_NEAR(mean[c], want, 4.0 * se[c] + 1e-4 * want);
        }
    }
}

/* The translation of the slab above: the dielectric surface names the ink as its inside
 * medium; the GPU refuses the bounded medium by name. */
TEST(dielectric_medium_json_and_gpu)
{
    char text[4096], msg[2048];
    snprintf(text, sizeof text,
             "Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\n%sCamera \"perspective\"\n"
             "WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n"
             "MakeNamedMedium \"ink\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [1 1 1] \"rgb sigma_s\" [0 0 0]\n"
             "Material \"dielectric\" \"float eta\" 1.33\nMediumInterface \"ink\" \"\"\n" SLAB,
             views[0]);
    const char *path = test_tmp_path("geo_json.pbrt");
    test_write_file(path, text);
    char *json = NULL;
    if (scene_pbrt_json(path, &json) != BRUME_OK)
        TEST_FAIL("%s", err_message());
    cJSON *root = cJSON_Parse(json);
    free(json);
    const cJSON *s = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "surfaces"), 0);
    const cJSON *in = cJSON_GetObjectItemCaseSensitive(s, "medium_inside");
    ASSERT_TRUE(cJSON_IsString(in) && strcmp(in->valuestring, "ink") == 0);
    ASSERT_TRUE(!cJSON_HasObjectItem(s, "medium_outside"));
    const cJSON *type = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(s, "material"), "type");
    ASSERT_TRUE(cJSON_IsString(type) && strcmp(type->valuestring, "dielectric") == 0);
    cJSON_Delete(root);
    brume_context *ctx = brume_context_new();
    brume_scene *sc = load(ctx, text, msg, sizeof msg);
    if (!sc)
        TEST_FAIL("%s", msg);
    ASSERT_TRUE(brume_scene_commit(ctx, sc) == BRUME_OK);
    ASSERT_TRUE(device_scene_check(sc, INTEGRATOR_PATH) != BRUME_OK);
    ASSERT_CONTAINS(err_message(), "media bounded by surfaces (medium_inside/medium_outside) render on the CPU only");
    brume_scene_release(sc);
    brume_context_release(ctx);
    remove(path);
}

/* A MediumInterface name that no MakeNamedMedium gives, anywhere in the file, is refused with
 * the Shape's file and line; one given later is not (above). */
TEST(medium_never_defined_refused_at_shape)
{
    char text[2048], want[256];
    snprintf(text, sizeof text,
             "%sCamera \"perspective\"\nWorldBegin\n"
             "MakeNamedMedium \"ink\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [1 1 1] \"rgb sigma_s\" [0 0 0]\n"
             "Material \"interface\"\nMediumInterface \"inc\" \"\"\nShape \"sphere\"\n",
             views[0]);
    const char *path = test_tmp_path("geo_bad.pbrt");
    test_write_file(path, text);
    char *json = NULL;
    ASSERT_TRUE(scene_pbrt_json(path, &json) != BRUME_OK);
    snprintf(want, sizeof want, "%s:8: MediumInterface: no medium named \"inc\"", path);
    ASSERT_CONTAINS(err_message(), want);
    remove(path);
}

TEST_MAIN(reverse_orientation_faces_as_pbrt, area_light_power_per_shape, dielectric_binds_medium_defined_later, dielectric_medium_json_and_gpu,
          medium_never_defined_refused_at_shape)
