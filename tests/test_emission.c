/* test_emission.c - emission as artists set it (docs/scene-format.md, "Emission"): a slab
 * emitting per unit length, clear and absorbing, against its closed forms; Cycles'
 * blackbody (Principled Volume) against Cycles' own formula at two temperatures; fire
 * files' grids picked by the names fire tools write, and listed by `brume info`; bad keys
 * refused in one line naming the file and the key. */
#include "test.h"

#include <stdint.h>
#include <unistd.h>

#include "brume.h"
#include "core/error.h"
#include "io/grid_io.h"
#include "io/grid_vdb.h"
#include "medium/blackbody.h"
#include "render/track.h"
#include "scene/scene.h"
#include "vdb_puffs.h"

/* A slab z in [-1, 1] (L = 2), wide, of constant density 1 seen along -z through a 1 degree
 * field of view (1 / cos of the widest ray is 1.00004), black background: every pixel sees
 * the radiance the slab emits along L. */
static void slab_means(double sigma_a, const char *emission, double mean[3], double se[3])
{
    char json[1024];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 10], \"look_at\": [0, 0, 0], \"fov\": 1},"
             " \"background\": [0, 0, 0],"
             " \"media\": [{\"sigma_a\": %g, \"sigma_s\": 0, %s, \"emission_units\": \"radiance_per_length\","
             "   \"density\": {\"type\": \"constant\", \"bounds\": [[-5, -5, -1], [5, 5, 1]]}}],"
             " \"render\": {\"width\": 32, \"height\": 32, \"spp\": 64}}",
             sigma_a, emission);
    brume_image *img = test_render_json(json, 7);
    for (int c = 0; c < 3; c++)
        test_channel_mean(brume_image_pixels(img), 32 * 32, c, &mean[c], &se[c]);
    brume_image_release(img);
}

/* Emission E per unit length with no extinction: the radiance is E L, whatever the density
 * (E = [0.5, 1, 2], L = 2). The estimate gathers E at tentative collisions: a Poisson count
 * of them times E / rate, so the check is to 5 standard errors of the pixels' spread. */
TEST(per_length_slab_clear)
{
    double mean[3], se[3];
    slab_means(0.0, "\"emission\": [0.5, 1, 2]", mean, se);
    const double E[3] = {0.5, 1.0, 2.0};
    for (int c = 0; c < 3; c++) {
        fprintf(stderr, "channel %d: %.5f expected %.5f (se %.5f)\n", c, mean[c], 2.0 * E[c], se[c]);
        ASSERT_TRUE(se[c] < 0.02 * E[c]); /* the estimate is resolved, and the test can fail */
        ASSERT_NEAR(mean[c], 2.0 * E[c], 5.0 * se[c]);
    }
}

/* With absorption sigma_a = 1.5 (no scattering): E (1 - exp(-sigma_a L)) / sigma_a, the
 * emission of each depth attenuated on its way out. */
TEST(per_length_slab_absorbing)
{
    double mean[3], se[3];
    slab_means(1.5, "\"emission\": [0.5, 1, 2]", mean, se);
    const double E[3] = {0.5, 1.0, 2.0}, f = (1.0 - exp(-1.5 * 2.0)) / 1.5;
    for (int c = 0; c < 3; c++) {
        fprintf(stderr, "channel %d: %.5f expected %.5f (se %.5f)\n", c, mean[c], E[c] * f, se[c]);
        ASSERT_TRUE(se[c] < 0.02 * E[c]);
        ASSERT_NEAR(mean[c], E[c] * f, 5.0 * se[c]);
    }
    /* pbrt-v4's units for the same numbers: sigma_a Le at each point, so the slab shows
     * Le (1 - exp(-sigma_a L)), not the per-length value */
    char json[1024];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 10], \"look_at\": [0, 0, 0], \"fov\": 1},"
             " \"background\": [0, 0, 0],"
             " \"media\": [{\"sigma_a\": 1.5, \"sigma_s\": 0, \"emission\": [0.5, 1, 2],"
             "   \"density\": {\"type\": \"constant\", \"bounds\": [[-5, -5, -1], [5, 5, 1]]}}],"
             " \"render\": {\"width\": 32, \"height\": 32, \"spp\": 64}}");
    brume_image *img = test_render_json(json, 7);
    for (int c = 0; c < 3; c++) {
        double m, s;
        test_channel_mean(brume_image_pixels(img), 32 * 32, c, &m, &s);
        ASSERT_NEAR(m, E[c] * (1.0 - exp(-3.0)), 5.0 * s + 1e-9);
    }
    brume_image_release(img);
}

/* "temperature": 3000 K over [-7, 7]^3 voxels of size 1, as "heat" and "temperature" */
static void fill_two_temperatures(gridvdb_writer *w, const void *user)
{
    (void)user;
    int g = gridvdb_writer_add(w, "temperature", 0, 1.0, origin0);
    int h = gridvdb_writer_add(w, "heat", 0, 1.0, origin0);
    float t = 3000.0f, q = 1.0f;
    for (int k = -7; k <= 7; k++)
        for (int j = -7; j <= 7; j++)
            for (int i = -7; i <= 7; i++) {
                gridvdb_writer_set(w, g, i, j, k, &t);
                gridvdb_writer_set(w, h, i, j, k, &q);
            }
}

/* The emission per unit length at the origin of a medium with the given blackbody object
 * and "temperature": {} (the file's grids picked by name: "temperature" before "heat"). */
static color blackbody_at(const char *vdb, const char *blackbody)
{
    char json[1024];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 30], \"look_at\": [0, 0, 0]},"
             " \"media\": [{\"sigma_a\": 1, \"sigma_s\": 0, \"emission_units\": \"radiance_per_length\","
             "   \"density\": {\"type\": \"constant\", \"bounds\": [[-2, -2, -2], [2, 2, 2]], \"value\": 0.01},"
             "   \"temperature\": {\"file\": \"%s\"}, \"blackbody\": %s}]}",
             vdb, blackbody);
    brume_scene *s = test_scene_json(json);
    brume_context *ctx = brume_context_new();
    if (brume_scene_commit(ctx, s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    medium_sample ms;
    media_at(s, 0, v3(0.2, 0.1, -0.3), 0.0, &ms);
    brume_scene_release(s);
    brume_context_release(ctx);
    return ms.emission;
}

/* Cycles' Principled Volume (svm_node_principled_volume): T = Temperature x the attribute,
 * intensity = sigma mix(1, T^4, Blackbody Intensity) with sigma = 5.670373e-8 1e-6 / pi,
 * emitted per unit length: tint x intensity x blackbody colour. Cycles' colour
 * (svm_math_blackbody_color_rec709, Blender 3.4) written out at two temperatures: from
 * 12000 K its constant (0.8262954810464208, 0.9945080501520986, 1.566307710274283); at
 * 2000 K its fit, (2.5201, 0.6469, 0.0204). brume computes the colour from Planck's law
 * (luminance 1) with the CIE 1931 table: within 0.5 % of the largest channel (Cycles' fit
 * is good to 1e-3 absolute). The emission does not follow the density (0.01 here). */
TEST(blackbody_blender_convention)
{
    if (!grid_have_openvdb())
        return;
    const char *path = test_tmp_path("temps.vdb");
    write_vdb(path, 0, fill_two_temperatures, NULL);
    const struct {
        double tscale, intensity, tol;
        double rgb[3];
    } cases[] = {{2000.0 / 3000.0, 1.0, 0.005, {2.5201, 0.6469, 0.0204}},
                 {15000.0 / 3000.0, 1.0, 0.005, {0.8262954810464208, 0.9945080501520986, 1.566307710274283}},
                 {15000.0 / 3000.0, 0.25, 0.005, {0.8262954810464208, 0.9945080501520986, 1.566307710274283}}};
    const double tint[3] = {1.0, 0.5, 0.25};
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        char bb[256];
        snprintf(bb, sizeof bb, "{\"model\": \"blender\", \"intensity\": %.17g, \"tint\": [1, 0.5, 0.25],"
                                " \"temperature_scale\": %.17g}", cases[i].intensity, cases[i].tscale);
        color got = blackbody_at(path, bb);
        double T = 3000.0 * cases[i].tscale, T4 = T * T * T * T;
        double sigma = 5.670373e-8 * 1e-6 / 3.14159265358979323846;
        double intensity = sigma * ((1.0 - cases[i].intensity) + cases[i].intensity * T4);
        double big = fmax(fabs(cases[i].rgb[0]), fmax(fabs(cases[i].rgb[1]), fabs(cases[i].rgb[2])));
        for (int c = 0; c < 3; c++) {
            double want = tint[c] * intensity * cases[i].rgb[c];
            fprintf(stderr, "%.0f K, intensity %.2f, channel %d: %.6g expected %.6g\n", T, cases[i].intensity, c,
                    got.c[c], want);
            ASSERT_NEAR(got.c[c], want, cases[i].tol * tint[c] * intensity * big);
        }
    }
    /* pbrt-v4's convention on the same grid: scale B(T'), B peak-normalized, at sigma_a rho */
    color p = blackbody_at(path, "{\"scale\": 2}");
    blackbody_init();
    color B = blackbody_rgb(3000.0);
    for (int c = 0; c < 3; c++)
        ASSERT_NEAR(p.c[c], 2.0 * B.c[c], 1e-9 + 1e-6 * fabs(B.c[c]));
    unlink(path);
}

/* Fire files' grids: "density", "heat" and "temp" floats, "temperature" float, "flame"
 * float, "Cd" and "color" vec3, "vel" vec3. */
static void fill_fire_names(gridvdb_writer *w, const void *user)
{
    const char *const *names = user;
    for (int n = 0; names[n]; n++) {
        bool is_vec3 = strcmp(names[n], "Cd") == 0 || strcmp(names[n], "color") == 0 || strcmp(names[n], "vel") == 0;
        int g = gridvdb_writer_add(w, names[n], is_vec3, 0.1, origin0);
        float v[3] = {(float)(n + 1), (float)(n + 1), (float)(n + 1)};
        for (int i = -3; i <= 3; i++)
            gridvdb_writer_set(w, g, i, 0, 0, v);
    }
}

static int list_grids(const char *path, brume_grid_entry *e, int max)
{
    int n = 0;
    brume_context *ctx = brume_context_new();
    if (brume_grid_file_list(ctx, path, NULL, e, max, &n) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    brume_context_release(ctx);
    return n;
}

static const char *picked(const brume_grid_entry *e, int n, const char *role)
{
    int i = brume_grid_pick(e, n, role);
    return i < 0 ? "(none)" : e[i].name;
}

/* Precedence (docs/grids.md): each role's names in order, with a fitting value type; a
 * scene's field without "grid" takes its role's grid; `brume info` prints each role. */
TEST(fire_grid_names)
{
    if (!grid_have_openvdb())
        return;
    const char *path = test_tmp_path("fire-names.vdb");
    static const char *const houdini[] = {"heat", "density", "flame", "color", "Cd", "temperature", "vel", NULL};
    write_vdb(path, 0, fill_fire_names, houdini);
    brume_grid_entry e[16];
    int n = list_grids(path, e, 16);
    ASSERT_TRUE(n == 7);
    ASSERT_EQ_STR(picked(e, n, "density"), "density");
    ASSERT_EQ_STR(picked(e, n, "temperature"), "temperature"); /* before heat */
    ASSERT_EQ_STR(picked(e, n, "emission"), "flame");
    ASSERT_EQ_STR(picked(e, n, "albedo"), "Cd"); /* before color */
    ASSERT_EQ_STR(picked(e, n, "velocity"), "vel");
    ASSERT_EQ_STR(picked(e, n, "nonsense"), "(none)");
    ASSERT_EQ_STR(brume_grid_role(e, n, 0), ""); /* heat loses to temperature */
    ASSERT_EQ_STR(brume_grid_role(e, n, 5), "temperature");
    /* Blender's and EmberGen's smaller sets: temp before heat; a vec3 "flame" still emits */
    static const char *const blender[] = {"density", "heat", "temp", "color", NULL};
    const char *path2 = test_tmp_path("fire-names2.vdb");
    write_vdb(path2, 0, fill_fire_names, blender);
    n = list_grids(path2, e, 16);
    ASSERT_EQ_STR(picked(e, n, "temperature"), "temp");
    ASSERT_EQ_STR(picked(e, n, "albedo"), "color");
    ASSERT_EQ_STR(picked(e, n, "emission"), "(none)");

    /* the scene: "temperature" and "emission_field" without "grid" read "temperature" (6 K
     * x 1000) and "flame" (3) from the density's file */
    char json[1024];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 30], \"look_at\": [0, 0, 0]},"
             " \"media\": [{\"sigma_a\": 1, \"sigma_s\": 0, \"emission_units\": \"radiance_per_length\","
             "   \"density\": {\"type\": \"grid\", \"file\": \"%s\", \"filter\": \"nearest\"},"
             "   \"temperature\": {}, \"blackbody\": {\"model\": \"blender\", \"temperature_scale\": 1000},"
             "   \"emission_field\": {\"color\": [0, 0, 2]}}]}",
             path);
    brume_scene *s = test_scene_json(json);
    brume_context *ctx = brume_context_new();
    if (brume_scene_commit(ctx, s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    medium_sample ms;
    media_at(s, 0, v3(0.1, 0.0, 0.0), 0.0, &ms);
    blackbody_init();
    color want = col_scale(blackbody_rgb_blender(6000.0), 5.670373e-14 / 3.14159265358979323846 * pow(6000.0, 4));
    want.c[2] += 2.0 * 3.0;
    for (int c = 0; c < 3; c++)
        ASSERT_NEAR(ms.emission.c[c], want.c[c], 1e-6 * fabs(want.c[c]) + 1e-9);
    brume_scene_release(s);
    brume_context_release(ctx);

    /* brume info: each grid with its role */
    char cmd[2048], out[1024];
    snprintf(out, sizeof out, "%s", test_tmp_path("info.txt"));
    snprintf(cmd, sizeof cmd, "%s info %s > %s", BRUME_EXE, path, out);
    ASSERT_TRUE(test_system(cmd) == 0);
    size_t len = 0;
    char *text = test_slurp(out, &len);
    ASSERT_CONTAINS(text, "grid \"temperature\": float");
    ASSERT_CONTAINS(strstr(text, "grid \"temperature\""), "role temperature\n");
    ASSERT_CONTAINS(strstr(text, "grid \"heat\""), "role none\n");
    ASSERT_CONTAINS(strstr(text, "grid \"flame\""), "role emission\n");
    ASSERT_CONTAINS(strstr(text, "grid \"Cd\""), "role albedo\n");
    ASSERT_CONTAINS(strstr(text, "grid \"vel\""), "role velocity\n");
    free(text);
    unlink(out);
    unlink(path);
    unlink(path2);
}

/* A fire for pbrt's nanovdb medium: density 0.5 and temperature 2000 K over voxels
 * [0, 11]^3, 430 K over [40, 51]^3, voxels of 0.1, in the grids named user[0] and user[1]. */
static void fill_pbrt_fire(gridvdb_writer *w, const void *user)
{
    const char *const *names = user;
    int d = gridvdb_writer_add(w, names[0], 0, 0.1, origin0), t = gridvdb_writer_add(w, names[1], 0, 0.1, origin0);
    const float rho = 0.5f, hot = 2000.0f, cool = 430.0f;
    for (int b = 0; b < 2; b++)
        for (int k = 40 * b; k < 40 * b + 12; k++)
            for (int j = 40 * b; j < 40 * b + 12; j++)
                for (int i = 40 * b; i < 40 * b + 12; i++) {
                    gridvdb_writer_set(w, d, i, j, k, &rho);
                    gridvdb_writer_set(w, t, i, j, k, b ? &cool : &hot);
                }
}

/* pbrt-v4's NanoVDBMedium, written out: sigma_a(x) = sigma_a scale rho(x); the temperature
 * T' = (T(x) - temperatureoffset) temperaturescale, temperatureoffset defaulting to
 * temperaturecutoff; Le(x) = LeScale B(T') where T' > 100 K (else 0), B the peak-normalized
 * blackbody; emitted at the rate sigma_a(x) Le(x). pbrt-v4's RGB film records the integral
 * of y-bar (unnormalized) times the spectrum as Y, where brume's blackbody colour divides
 * it by the integral of y-bar, CIE_Y_integral = 106.856895 (the lights divide the spectrum's
 * own luminance out; this Le does not). Here scale 2, sigma_a 1.5, LeScale 3 ("Lescale",
 * pbrt-v4's spelling), temperaturescale 2, temperaturecutoff 400: 2000 K gives T' = 3200 K
 * and emits 1.5 x 2 x 0.5 x 3 x 106.856895 B(3200 K); 430 K gives 60 K, nothing. The grids
 * are "density" and "temperature", or as pbrt-v4's "gridname" and "temperaturename" name
 * them. */
static void pbrt_nanovdb_case(const char *const names[2], const char *naming)
{
    const char *grid = test_tmp_path("pbrt-fire.nvdb");
    write_vdb(grid, 1, fill_pbrt_fire, names);
    char text[2048], scene[1100];
    snprintf(scene, sizeof scene, "%s", test_tmp_path("fire.pbrt"));
    snprintf(text, sizeof text,
             "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
             "MakeNamedMedium \"f\" \"string type\" \"nanovdb\" \"string filename\" \"%s\" \"float scale\" 2\n"
             "  \"rgb sigma_a\" [1.5 1.5 1.5] \"rgb sigma_s\" [0 0 0] \"float Lescale\" 3\n"
             "  \"float temperaturescale\" 2 \"float temperaturecutoff\" 400 %s\n"
             "MediumInterface \"f\" \"\"\nMaterial \"interface\"\nShape \"sphere\" \"float radius\" 50\n",
             grid, naming);
    test_write_file(scene, text);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = scene}, NULL, &s) != BRUME_OK ||
        brume_scene_commit(ctx, s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    blackbody_init();
    color B = blackbody_rgb(3200.0);
    medium_sample hot, cool;
    media_at(s, 0, v3(-0.55, 0.55, 0.55), 0.0, &hot); /* a bare LookAt mirrors x (docs/pbrt.md) */
    media_at(s, 0, v3(-4.55, 4.55, 4.55), 0.0, &cool);
    for (int c = 0; c < 3; c++) {
        double want = 1.5 * 2.0 * 0.5 * 3.0 * 106.856895 * B.c[c];
        fprintf(stderr, "channel %d: %.6g expected %.6g; at 430 K %.3g\n", c, hot.emission.c[c], want,
                cool.emission.c[c]);
        ASSERT_NEAR(hot.emission.c[c], want, 1e-6 * fabs(want) + 1e-12);
        ASSERT_NEAR(hot.sigma_a.c[c], 1.5, 1e-6);
        ASSERT_NEAR(cool.sigma_a.c[c], 1.5, 1e-6);
        ASSERT_TRUE(cool.emission.c[c] == 0.0);
    }
    brume_scene_release(s);
    brume_context_release(ctx);
    unlink(scene);
    unlink(grid);
}

TEST(pbrt_nanovdb_temperature)
{
    if (!grid_have_openvdb())
        return;
    static const char *const plain[2] = {"density", "temperature"}, *const named[2] = {"smoke", "T_kelvin"};
    pbrt_nanovdb_case(plain, "");
    pbrt_nanovdb_case(named, "\"string gridname\" \"smoke\" \"string temperaturename\" \"T_kelvin\"");
}

/* Bad emission keys: one line naming the file and the key. */
TEST(bad_emission_keys)
{
    const struct {
        const char *keys, *needle;
    } bad[] = {
        {"\"emission_units\": \"watts\"", "media[0].emission_units"},
        {"\"emission_units\": 1", "media[0].emission_units"},
        {"\"temperature\": {\"type\": \"constant\"}, \"blackbody\": {\"model\": \"cycles\"}", "blackbody.model"},
        {"\"temperature\": {\"type\": \"constant\"}, \"blackbody\": {\"model\": \"blender\", \"scale\": 2}",
         "blackbody.scale"},
        {"\"temperature\": {\"type\": \"constant\"}, \"blackbody\": {\"intensity\": 1}", "blackbody.intensity"},
        {"\"temperature\": {\"type\": \"constant\"}, \"blackbody\": {\"model\": \"blender\", \"intensity\": 2}",
         "blackbody.intensity"},
        {"\"temperature\": {\"type\": \"constant\"}, \"blackbody\": {\"model\": \"blender\", \"tint\": [1, -1, 0]}",
         "blackbody.tint"},
        {"\"temperature\": {\"type\": \"constant\"}, \"blackbody\": 3", "blackbody"},
    };
    brume_context *ctx = brume_context_new();
    for (size_t b = 0; b < sizeof bad / sizeof *bad; b++) {
        char json[1024];
        snprintf(json, sizeof json,
                 "{\"camera\": {\"position\": [0, 0, 30], \"look_at\": [0, 0, 0]},"
                 " \"media\": [{\"sigma_a\": 1, \"sigma_s\": 1,"
                 "  \"density\": {\"type\": \"constant\", \"bounds\": [[-1, -1, -1], [1, 1, 1]]}, %s}]}",
                 bad[b].keys);
        brume_scene *s = NULL;
        ASSERT_TRUE(brume_scene_load(ctx, &(brume_source){.path = "bad.json", .text = json}, NULL, &s) != BRUME_OK);
        const char *msg = brume_context_last_error(ctx);
        fprintf(stderr, "%s\n", msg);
        ASSERT_CONTAINS(msg, "bad.json");
        ASSERT_CONTAINS(msg, bad[b].needle);
        ASSERT_TRUE(!strchr(msg, '\n'));
    }
    brume_context_release(ctx);
}

TEST_MAIN(per_length_slab_clear, per_length_slab_absorbing, blackbody_blender_convention, fire_grid_names,
          pbrt_nanovdb_temperature, bad_emission_keys)
