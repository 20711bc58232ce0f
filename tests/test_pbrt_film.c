/* test_pbrt_film.c - pbrt-v4's film, light spectra and files as brume reads them
 * (docs/pbrt.md): the exposure (imaging ratio), the cie1931 sensor and what is refused,
 * blackbody L and I against the Planckian locus' chromaticities from the CIE tables,
 * the nanovdb emission scale's two spellings, Include/Import; and a scene whose grid file
 * brume makes saying so when the file is missing. */
#include "test.h"
#include "pbrt_translate.h"

#include <math.h>

#include "brume.h"
#include "core/error.h"
#include "io/json.h"
#include "scene/scene_pbrt.h"

#define VIEW "Scale -1 1 1\nLookAt 0 0 -5  0 0 0  0 1 0\n"

/* The translation of text (a whole file), parsed; NULL and *msg set when it is refused. */
static cJSON *translate(const char *name, const char *text, char *msg, size_t cap)
{
    return pbrt_translate(name, text, msg, cap);
}

static cJSON *translate_ok(const char *text)
{
    char msg[2048];
    cJSON *root = translate("f.pbrt", text, msg, sizeof msg);
    if (!root)
        TEST_FAIL("%s", msg);
    return root;
}

/* text refused with "FILE:LINE: " (FILE f.pbrt) and frag. */
static void expect_refusal(const char *text, int line, const char *frag)
{
    char msg[2048], want[1200];
    ASSERT_TRUE(translate("f.pbrt", text, msg, sizeof msg) == NULL);
    snprintf(want, sizeof want, "%s:%d: ", test_tmp_path("f.pbrt"), line);
    ASSERT_CONTAINS(msg, want);
    ASSERT_CONTAINS(msg, frag);
}

static double item(const cJSON *o, const char *key, int i)
{
    const cJSON *v = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(o, key), i);
    if (!cJSON_IsNumber(v))
        TEST_FAIL("%s[%d]: not a number", key, i);
    return v->valuedouble;
}

static const cJSON *light(const cJSON *root, int i)
{
    return cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "lights"), i);
}

/* pbrt-v4's imaging ratio: (shutterclose - shutteropen) iso / 100, here 0.5 x 400 / 100 = 2,
 * multiplies every source (a distant light's irradiance, a point light's intensity, the
 * sky); by default (iso 100, shutter [0, 1]) it is 1. */
TEST(film_imaging_ratio_scales_sources)
{
    cJSON *root = translate_ok("Film \"rgb\" \"float iso\" 400 \"string sensor\" \"cie1931\" \"float whitebalance\" 0\n" VIEW
                               "Camera \"perspective\" \"float shutteropen\" 0.25 \"float shutterclose\" 0.75\n"
                               "WorldBegin\nLightSource \"distant\" \"rgb L\" [1 2 3]\n"
                               "LightSource \"point\" \"rgb I\" [4 5 6]\nLightSource \"infinite\" \"rgb L\" [0.5 0.5 0.5]\n");
    ASSERT_NEAR(item(light(root, 0), "irradiance", 2), 6.0, 1e-12);
    ASSERT_NEAR(item(light(root, 1), "intensity", 0), 8.0, 1e-12);
    ASSERT_NEAR(item(root, "background", 1), 1.0, 1e-12);
    cJSON_Delete(root);
    root = translate_ok("Film \"rgb\"\n" VIEW "Camera \"perspective\"\nWorldBegin\nLightSource \"distant\" \"rgb L\" [1 2 3]\n");
    ASSERT_NEAR(item(light(root, 0), "irradiance", 2), 3.0, 1e-12);
    cJSON_Delete(root);
}

/* A sensor pbrt-v4 does not name, and a white balance outside [1000, 100000] K, which is none
 * brume makes: each refused by name with the Film's line (the sensors pbrt-v4 names are read:
 * tests/test_pbrt_sensor.c; a white balance inside the range: tests/test_pbrt_leftovers.c). */
TEST(film_sensor_and_whitebalance_refused_by_name)
{
    expect_refusal("Film \"rgb\" \"string sensor\" \"nikon_d9000\"\n" VIEW "Camera \"perspective\"\nWorldBegin\n", 1,
                   "\"sensor\": \"nikon_d9000\"");
    expect_refusal("Film \"rgb\" \"float whitebalance\" 500\n" VIEW "Camera \"perspective\"\nWorldBegin\n", 1,
                   "\"whitebalance\": 500 K");
}

/* PixelFilter "box" of radius r is brume's box filter of side 2 r; pbrt's other filters are
 * refused by name. */
TEST(box_pixel_filter_read)
{
    cJSON *root = translate_ok("PixelFilter \"box\" \"float xradius\" 1 \"float yradius\" 1\nFilm \"rgb\"\n" VIEW
                               "Camera \"perspective\"\nWorldBegin\n");
    const cJSON *f = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(root, "render"), "filter");
    ASSERT_EQ_STR(cJSON_GetObjectItemCaseSensitive(f, "type")->valuestring, "box");
    ASSERT_NEAR(cJSON_GetObjectItemCaseSensitive(f, "width")->valuedouble, 2.0, 0);
    cJSON_Delete(root);
    expect_refusal("PixelFilter \"mitchell\"\nFilm \"rgb\"\n" VIEW "Camera \"perspective\"\nWorldBegin\n", 1,
                   "PixelFilter \"mitchell\"");
}

/* The chromaticity (x, y) of a linear Rec. 709 colour, and its luminance Y. */
static void rec709_xyY(const cJSON *o, const char *key, double *x, double *y, double *Y)
{
    double r = item(o, key, 0), g = item(o, key, 1), b = item(o, key, 2);
    double X = 0.4124564 * r + 0.3575761 * g + 0.1804375 * b;
    *Y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
    double Z = 0.0193339 * r + 0.1191920 * g + 0.9503041 * b;
    *x = X / (X + *Y + Z);
    *y = *Y / (X + *Y + Z);
}

/* "blackbody L" [T] as pbrt-v4 gives an RGB film: luminance Y = scale (pbrt-v4 divides every
 * light's scale by its spectrum's luminance) and the chromaticity of the Planckian locus at
 * T: CIE 1931 2-degree tables give (0.5267, 0.4133) at 2000 K and (0.3135, 0.3237) at
 * 6500 K. brume's colour matching functions are those tables every 5 nm (docs/grids.md):
 * within 4e-3 of the tables' chromaticities. */
TEST(blackbody_lights_as_pbrt)
{
    cJSON *root = translate_ok("Film \"rgb\"\n" VIEW "Camera \"perspective\"\nWorldBegin\n"
                               "LightSource \"distant\" \"blackbody L\" [6500] \"float scale\" 3\n"
                               "LightSource \"point\" \"blackbody I\" 2000\n"
                               "LightSource \"infinite\" \"blackbody L\" [6500]\n");
    double x, y, Y;
    rec709_xyY(light(root, 0), "irradiance", &x, &y, &Y);
    ASSERT_NEAR(Y, 3.0, 1e-6);
    ASSERT_NEAR(x, 0.3135, 4e-3);
    ASSERT_NEAR(y, 0.3237, 4e-3);
    rec709_xyY(light(root, 1), "intensity", &x, &y, &Y);
    ASSERT_NEAR(Y, 1.0, 1e-6);
    ASSERT_NEAR(x, 0.5267, 4e-3);
    ASSERT_NEAR(y, 0.4133, 4e-3);
    rec709_xyY(root, "background", &x, &y, &Y);
    ASSERT_NEAR(Y, 1.0, 1e-6);
    cJSON_Delete(root);
    expect_refusal("Film \"rgb\"\n" VIEW "Camera \"perspective\"\nWorldBegin\n"
                   "LightSource \"point\" \"blackbody I\" [10]\n", 6, "\"blackbody I\"");
}

/* "spot": pbrt-v4's cone, I times SmoothStep(cos coneangle, cos(coneangle - conedeltaangle),
 * cos theta), is brume's smooth cone with cone_angle = coneangle and falloff_start =
 * coneangle - conedeltaangle; from and to through the transform (Rotate 90 about y takes
 * +z to +x); a blackbody I as for the point light (Y = scale). A non-uniform scale, which
 * would make pbrt's cone elliptical, is refused. */
TEST(spot_light_as_pbrt)
{
    cJSON *root = translate_ok("Film \"rgb\"\n" VIEW "Camera \"perspective\"\nWorldBegin\nRotate 90 0 1 0\n"
                               "LightSource \"spot\" \"point3 from\" [0 0 1] \"point3 to\" [0 0 3] \"float coneangle\" 20 "
                               "\"float conedeltaangle\" 8 \"blackbody I\" 4000 \"float scale\" 2\n");
    const cJSON *l = light(root, 0);
    ASSERT_EQ_STR(cJSON_GetObjectItemCaseSensitive(l, "type")->valuestring, "spot");
    ASSERT_NEAR(item(l, "position", 0), 1.0, 1e-12);
    ASSERT_NEAR(item(l, "direction", 0), 1.0, 1e-12);
    ASSERT_NEAR(item(l, "direction", 2), 0.0, 1e-12);
    ASSERT_NEAR(cJSON_GetObjectItemCaseSensitive(l, "cone_angle")->valuedouble, 20.0, 0);
    ASSERT_NEAR(cJSON_GetObjectItemCaseSensitive(l, "falloff_start")->valuedouble, 12.0, 0);
    double x, y, Y;
    rec709_xyY(l, "intensity", &x, &y, &Y);
    ASSERT_NEAR(Y, 2.0, 1e-6);
    cJSON_Delete(root);
    expect_refusal("Film \"rgb\"\n" VIEW "Camera \"perspective\"\nWorldBegin\nScale 1 2 1\nLightSource \"spot\"\n", 7,
                   "elliptical");
}

/* A constant spectrum on a light or a medium's Le: pbrt-v4 divides the scale by the
 * spectrum's luminance, so [200 5 900 5] emits luminance Y = scale (not 5 scale), and it is
 * the equal-energy white, chromaticity (1/3, 1/3) by the CIE's definition. */
TEST(constant_spectrum_sources_as_pbrt)
{
    cJSON *root = translate_ok("Film \"rgb\"\n" VIEW "Camera \"perspective\"\nWorldBegin\n"
                               "LightSource \"distant\" \"spectrum L\" [200 5 900 5] \"float scale\" 2\n"
                               "MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"spectrum Le\" [200 3 900 3] "
                               "\"float Lescale\" 0.5\nMaterial \"interface\"\nMediumInterface \"m\" \"\"\n"
                               "Shape \"bilinearmesh\" \"point3 P\" [-1 -1 -1  1 -1 -1  -1 1 -1  1 1 -1  -1 -1 1  1 -1 1  "
                               "-1 1 1  1 1 1]\n  \"integer indices\" [0 2 1 3  4 5 6 7  0 1 4 5  2 6 3 7  0 4 2 6  1 3 5 7]\n");
    double x, y, Y;
    rec709_xyY(light(root, 0), "irradiance", &x, &y, &Y);
    ASSERT_NEAR(Y, 2.0, 1e-6);
    ASSERT_NEAR(x, 1.0 / 3.0, 1e-6);
    ASSERT_NEAR(y, 1.0 / 3.0, 1e-6);
    rec709_xyY(cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "media"), 0), "emission", &x, &y, &Y);
    ASSERT_NEAR(Y, 0.5, 1e-6);
    ASSERT_NEAR(x, 1.0 / 3.0, 1e-6);
    cJSON_Delete(root);
}

/* nanovdb's emission scale spelled "Lescale" (pbrt-v4) or "LeScale" (pbrt-v4-scenes'
 * explosion): the blackbody scale of a fire's temperature grid, times pbrt-v4's
 * CIE_Y_integral (test_emission.c says why); both at once refused. */
TEST(nanovdb_emission_scale_spellings)
{
    const char *grid = test_tmp_path("fire16.nvdb");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "%s gen fire --resolution 16 -o %s > /dev/null", BRUME_EXE, grid);
    ASSERT_EQ_INT(test_system(cmd), 0);
    const char *spell[2] = {"Lescale", "LeScale"};
    for (int i = 0; i < 2; i++) {
        char text[2048];
        snprintf(text, sizeof text,
                 "Film \"rgb\"\n" VIEW "Camera \"perspective\"\nWorldBegin\n"
                 "MakeNamedMedium \"f\" \"string type\" \"nanovdb\" \"string filename\" \"%s\" \"float %s\" %d\n"
                 "Material \"interface\"\nMediumInterface \"f\" \"\"\nShape \"sphere\" \"float radius\" 9\n",
                 grid, spell[i], 5 + i);
        cJSON *root = translate_ok(text);
        const cJSON *m = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "media"), 0);
        const cJSON *scale = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(m, "blackbody"), "scale");
        ASSERT_TRUE(cJSON_IsNumber(scale));
        ASSERT_NEAR(scale->valuedouble, (5.0 + i) * 106.856895, 1e-9);
        cJSON_Delete(root);
    }
    char text[2048];
    snprintf(text, sizeof text,
             "Film \"rgb\"\n" VIEW "Camera \"perspective\"\nWorldBegin\n"
             "MakeNamedMedium \"f\" \"string type\" \"nanovdb\" \"string filename\" \"%s\" \"float Lescale\" 1 "
             "\"float LeScale\" 2\n", grid);
    expect_refusal(text, 6, "both \"Lescale\" and \"LeScale\"");
    remove(grid);
}

/* Include reads a file's directives in place, sharing the graphics state; Import on a copy
 * of it (its Translate does not come back); a refusal inside names the included file and its
 * line. */
TEST(include_and_import_read_in_place)
{
    test_write_file(test_tmp_path("inc.pbrt"), "# lights\nTranslate 0 1 0\nLightSource \"point\" \"rgb I\" [1 1 1]\n");
    test_write_file(test_tmp_path("imp.pbrt"), "Translate 0 0 7\nLightSource \"point\" \"rgb I\" [2 2 2]\n");
    char text[4096];
    snprintf(text, sizeof text, "Film \"rgb\"\n" VIEW "Camera \"perspective\"\nWorldBegin\nInclude \"%s\"\n"
             "Import \"%s\"\nLightSource \"point\" \"rgb I\" [3 3 3]\n", test_tmp_path("inc.pbrt"),
             test_tmp_path("imp.pbrt"));
    cJSON *root = translate_ok(text);
    ASSERT_EQ_INT(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "lights")), 3);
    ASSERT_NEAR(item(light(root, 0), "position", 1), 1.0, 1e-12);
    ASSERT_NEAR(item(light(root, 1), "position", 1), 1.0, 1e-12); /* the included Translate holds */
    ASSERT_NEAR(item(light(root, 1), "position", 2), 7.0, 1e-12);
    ASSERT_NEAR(item(light(root, 2), "position", 2), 0.0, 1e-12); /* the imported one does not */
    ASSERT_NEAR(item(light(root, 2), "intensity", 0), 3.0, 1e-12);
    cJSON_Delete(root);
    test_write_file(test_tmp_path("bad-inc.pbrt"), "\nShape \"cone\"\n");
    char msg[2048], want[1200];
    snprintf(text, sizeof text, "Film \"rgb\"\n" VIEW "Camera \"perspective\"\nWorldBegin\nInclude \"%s\"\n",
             test_tmp_path("bad-inc.pbrt"));
    ASSERT_TRUE(translate("f.pbrt", text, msg, sizeof msg) == NULL);
    snprintf(want, sizeof want, "%s:2: Shape \"cone\"", test_tmp_path("bad-inc.pbrt"));
    ASSERT_CONTAINS(msg, want);
    expect_refusal("Film \"rgb\"\n" VIEW "Camera \"perspective\"\nWorldBegin\nInclude \"none.pbrt\"\n", 6, "none.pbrt");
    remove(test_tmp_path("inc.pbrt"));
    remove(test_tmp_path("imp.pbrt"));
    remove(test_tmp_path("bad-inc.pbrt"));
}

/* pbrt-v4-scenes' smoke-plume: an Include whose file ends in a directive's parameter list, the
 * list going on after the Include (pbrt-v4's tokenizer reads on into the including file); as
 * well when the included directive has no parameter of its own yet. An Import does not. */
TEST(include_continues_parameter_lists)
{
    test_write_file(test_tmp_path("cont1.pbrt"), "LightSource \"point\" \"rgb I\" [1 2 3]");
    test_write_file(test_tmp_path("cont2.pbrt"), "LightSource \"point\"\n");
    char text[4096];
    snprintf(text, sizeof text, "Film \"rgb\"\n" VIEW "Camera \"perspective\"\nWorldBegin\nInclude \"%s\"\n"
             "  \"point3 from\" [0 5 0]\nInclude \"%s\" \"rgb I\" [4 4 4]\nLightSource \"point\" \"rgb I\" [7 7 7]\n",
             test_tmp_path("cont1.pbrt"), test_tmp_path("cont2.pbrt"));
    cJSON *root = translate_ok(text);
    ASSERT_EQ_INT(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "lights")), 3);
    ASSERT_NEAR(item(light(root, 0), "position", 1), 5.0, 1e-12); /* the continued "from" */
    ASSERT_NEAR(item(light(root, 0), "intensity", 2), 3.0, 1e-12); /* the included "I" */
    ASSERT_NEAR(item(light(root, 1), "intensity", 0), 4.0, 1e-12);
    ASSERT_NEAR(item(light(root, 2), "intensity", 0), 7.0, 1e-12);
    cJSON_Delete(root);
    snprintf(text, sizeof text, "Film \"rgb\"\n" VIEW "Camera \"perspective\"\nWorldBegin\nImport \"%s\" \"rgb I\" [4 4 4]\n",
             test_tmp_path("cont2.pbrt"));
    expect_refusal(text, 6, "expected a directive");
    remove(test_tmp_path("cont1.pbrt"));
    remove(test_tmp_path("cont2.pbrt"));
}

/* scenes/fire-vdb.json read where its fire.vdb is not: the error names the file and the
 * command that makes it. */
TEST(missing_grid_names_its_command)
{
    FILE *f = fopen(BRUME_SOURCE_DIR "/scenes/fire-vdb.json", "rb");
    ASSERT_TRUE(f != NULL);
    static char text[1 << 16];
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    const char *path = test_tmp_path("fire-vdb.json");
    remove(test_tmp_path("fire.vdb"));
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    ASSERT_TRUE(brume_scene_load(ctx, &(brume_source){.path = path, .text = text}, NULL, &s) != BRUME_OK);
    const char *msg = brume_context_last_error(ctx);
    ASSERT_CONTAINS(msg, "media[0].density.file");
    ASSERT_CONTAINS(msg, "fire.vdb");
    ASSERT_CONTAINS(msg, "(make it with: brume gen fire -o scenes/fire.vdb)");
    ASSERT_TRUE(strchr(msg, '\n') == NULL);
    brume_context_release(ctx);
}

TEST_MAIN(film_imaging_ratio_scales_sources, box_pixel_filter_read, film_sensor_and_whitebalance_refused_by_name, blackbody_lights_as_pbrt,
          spot_light_as_pbrt, constant_spectrum_sources_as_pbrt, nanovdb_emission_scale_spellings, include_and_import_read_in_place, include_continues_parameter_lists, missing_grid_names_its_command)
