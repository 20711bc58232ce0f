/* test_pbrt_conventions.c - pbrt-v4's conventions that the comparison with pbrt-v4's own
 * renders (bench/pbrt_scenes.sh on tests/pbrt_conventions/, docs/pbrt-scenes.md) showed brume
 * translating differently, each checked against a value worked out from pbrt-v4's
 * definition. */
#include "test.h"
#include "pbrt_translate.h"

#include <math.h>

#include "brume.h"
#include "density/density.h"
#include "medium/blackbody.h"
#include "scene/scene.h"

#define VIEW "Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n"

/* pbrt-v4's DistantLight::Create: scale /= SpectrumToPhotometric(L) (for an rgb L the colour
 * space's illuminant, so rgb is read as written), then scale *= E_v for an "illuminance"
 * E_v > 0. rgb L (1, 2, 3), scale 2 and illuminance 5 give the irradiance (10, 20, 30). */
TEST(distant_illuminance_as_pbrt)
{
    char msg[2048];
    cJSON *root = pbrt_translate("distant.pbrt",
                                 "Film \"rgb\"\n" VIEW "WorldBegin\n"
                                 "LightSource \"distant\" \"rgb L\" [1 2 3] \"float scale\" [2]"
                                 " \"float illuminance\" [5]\n"
                                 "LightSource \"distant\" \"rgb L\" [1 2 3] \"float scale\" [2]\n",
                                 msg, sizeof msg);
    if (!root)
        TEST_FAIL("%s", msg);
    const cJSON *lights = cJSON_GetObjectItemCaseSensitive(root, "lights");
    const cJSON *E = cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(lights, 0), "irradiance");
    const cJSON *E1 = cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(lights, 1), "irradiance");
    for (int c = 0; c < 3; c++) {
        ASSERT_NEAR(cJSON_GetArrayItem(E, c)->valuedouble, (c + 1) * 2 * 5, 1e-9);
        ASSERT_NEAR(cJSON_GetArrayItem(E1, c)->valuedouble, (c + 1) * 2, 1e-9); /* none: the scale alone */
    }
    cJSON_Delete(root);
}

/* pbrt-v4's NanoVDBMedium density at the world point q of a grid of n[0] x n[1] x n[2]
 * voxels v (x fastest) whose index-to-world map is q = b0 + (i + 1/2) h per axis (brume
 * convert's placement on --bounds b0..b0 + n h): pIndex = worldToIndexF(q), then NanoVDB's
 * SampleFromVoxels<1> (trilinear between the voxels at floor(pIndex) and the next, a voxel
 * outside the grid reading the background 0), and 0 outside the medium's bounds, the
 * grid's worldBBox: index [0, n] (NanoVDB's bounding box of voxels [0, n - 1] grown by one
 * on the upper side). */
static double nano_voxel(const double *v, const int n[3], int x, int y, int z)
{
    if (x < 0 || y < 0 || z < 0 || x >= n[0] || y >= n[1] || z >= n[2])
        return 0.0;
    return v[((size_t)z * (size_t)n[1] + (size_t)y) * (size_t)n[0] + (size_t)x];
}

static double pbrt_nanovdb_density(const double *v, const int n[3], const double b0[3], const double h[3],
                                   const double q[3])
{
    double s[3], d[3];
    int i[3];
    for (int k = 0; k < 3; k++) {
        s[k] = (q[k] - b0[k]) / h[k] - 0.5;
        if (s[k] < 0.0 || s[k] > n[k])
            return 0.0;
        i[k] = (int)floor(s[k]);
        d[k] = s[k] - i[k];
    }
    double r = 0.0;
    for (int c = 0; c < 8; c++) {
        int dx = c & 1, dy = (c >> 1) & 1, dz = c >> 2;
        double w = (dx ? d[0] : 1 - d[0]) * (dy ? d[1] : 1 - d[1]) * (dz ? d[2] : 1 - d[2]);
        r += w * nano_voxel(v, n, i[0] + dx, i[1] + dy, i[2] + dz);
    }
    return r;
}

/* A nanovdb medium of 4 x 4 x 4 voxels 1 + x + 4 y + 16 z (faces not zero) on [-1, 3] x
 * [0, 2] x [2, 3] (voxels 1, 0.5 and 0.25 wide), written by brume convert: brume's density is
 * pbrt-v4's lookup at every point of a lattice from 1.25 voxels before the box to 1.25
 * beyond it (stepping 1e-3 of a voxel off each face of pbrt-v4's bounds), and by hand: a
 * voxel centre (voxel (1, 2, 3): 58), pbrt-v4's lower bound in x (voxel (0, 1, 1): 21, where
 * a grid held to its voxel box reads it too), half a voxel past the upper face in x (half of
 * voxel (3, 1, 1): 12, where a held grid ends), and beyond pbrt-v4's bounds (0). Before the
 * lookup was pbrt-v4's, the lattice failed at its first point inside the box's lower half
 * voxel (brume 1, pbrt-v4 0). */
TEST(nanovdb_is_pbrt_lookup_to_the_faces)
{
    const int n[3] = {4, 4, 4};
    const double b0[3] = {-1, 0, 2}, h[3] = {1, 0.5, 0.25};
    double v[64];
    float vf[64];
    for (int i = 0; i < 64; i++)
        vf[i] = (float)(v[i] = 1 + i % 4 + 4 * (i / 4 % 4) + 16 * (i / 16));
    const char *dir = test_fresh_dir("nanovdb");
    char raw[4096], nvdb[4096], cmd[12288];
    snprintf(raw, sizeof raw, "%s/g.raw", dir);
    snprintf(nvdb, sizeof nvdb, "%s/g.nvdb", dir);
    test_write_bytes(raw, vf, sizeof vf);
    snprintf(cmd, sizeof cmd, "%s convert %s %s --dims 4x4x4 --bounds -1,0,2,3,2,3 > /dev/null", BRUME_EXE, raw, nvdb);
    ASSERT_EQ_INT(test_system(cmd), 0);
    char text[8192];
    snprintf(text, sizeof text,
             "Film \"rgb\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
             "Scale -1 1 1\nLookAt 0 0 -8  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
             "MakeNamedMedium \"g\" \"string type\" \"nanovdb\" \"string filename\" \"%s\"\n"
             "  \"rgb sigma_a\" [0.1 0.1 0.1] \"rgb sigma_s\" [0 0 0]\n"
             "AttributeBegin\nTranslate 0 0 2\nMaterial \"interface\"\nMediumInterface \"g\" \"\"\n"
             "Shape \"sphere\" \"float radius\" 6\nAttributeEnd\n",
             nvdb);
    const char *path = test_tmp_path("nanovdb.pbrt");
    test_write_file(path, text);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK ||
        brume_scene_commit(ctx, s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    const density *rho = s->media[0].rho;
    int checked = 0;
    for (int a = 0; a <= 26; a++)
        for (int b = 0; b <= 26; b++)
            for (int c = 0; c <= 26; c++) {
                const int t[3] = {a, b, c};
                double q[3];
                for (int k = 0; k < 3; k++) { /* voxel-box coordinate u from -1.25 to n + 1.25 */
                    double u = -1.25 + (n[k] + 2.5) * t[k] / 26.0;
                    if (fabs(u - 0.5) < 1e-9 || fabs(u - n[k] - 0.5) < 1e-9) /* pbrt-v4's faces: either side */
                        u += (t[k] % 2 ? 1e-3 : -1e-3);
                    q[k] = b0[k] + u * h[k];
                }
                double want = pbrt_nanovdb_density(v, n, b0, h, q), got = density_eval(rho, v3(q[0], q[1], q[2]));
                if (!(fabs(got - want) <= 1e-5 * (1 + want)))
                    TEST_FAIL("at (%g, %g, %g): brume %.9g, pbrt-v4's lookup %.9g", q[0], q[1], q[2], got, want);
                checked++;
            }
    ASSERT_EQ_INT(checked, 27 * 27 * 27);
    ASSERT_NEAR(density_eval(rho, v3(0.5, 1.25, 2.875)), 58.0, 1e-5);
    ASSERT_NEAR(density_eval(rho, v3(-0.5 + 1e-9, 0.75, 2.375)), 21.0, 1e-5);
    ASSERT_NEAR(density_eval(rho, v3(3.0, 0.75, 2.375)), 12.0, 1e-5);
    ASSERT_NEAR(density_eval(rho, v3(-0.5 - 1e-3, 0.75, 2.375)), 0.0, 0);
    ASSERT_NEAR(density_eval(rho, v3(3.5 + 1e-3, 0.75, 2.375)), 0.0, 0);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* An 8 x 8 map of rgba everywhere, written to path (brume writes OpenEXR's R, G, B, A). */
static void write_constant_map(const char *path, const float rgba[4])
{
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    ASSERT_EQ_INT(brume_image_new(ctx, 8, 8, &img), BRUME_OK);
    float *px = brume_image_pixels(img);
    for (int i = 0; i < 64; i++)
        for (int c = 0; c < 4; c++)
            px[4 * i + c] = rgba[c];
    if (brume_image_write(ctx, img, path, NULL) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    brume_image_release(img);
    brume_context_release(ctx);
}

/* The sky's scale in the translation of an image infinite light of illuminance 3 from map. */
static double sky_scale(const char *map)
{
    char text[4096], msg[2048];
    snprintf(text, sizeof text,
             "Film \"rgb\"\n" VIEW "WorldBegin\n"
             "LightSource \"infinite\" \"string filename\" \"%s\" \"float illuminance\" [3]\n",
             map);
    cJSON *root = pbrt_translate("sky.pbrt", text, msg, sizeof msg);
    if (!root)
        TEST_FAIL("%s", msg);
    const cJSON *bg = cJSON_GetObjectItemCaseSensitive(root, "background");
    double scale = cJSON_GetNumberValue(cJSON_GetObjectItemCaseSensitive(bg, "scale"));
    cJSON_Delete(root);
    return scale;
}

/* pbrt-v4's ImageInfiniteLight illuminance: scale = E_v / k_e, k_e the sum over the upper
 * half's texels of lum[c] x values[c] x cos theta (times 2 pi / texels), values[c] the
 * texel's first three channels in the order the image holds them: R, G, B from a PFM, and
 * OpenEXR's order, sorted by name, from an EXR (A, B, G for an RGBA file). For a constant
 * map the cos theta sum is common to both files, so with (r, g, b, a) = (1, 2, 4, 1) the EXR's
 * scale is the PFM's times (0.2126 r + 0.7152 g + 0.0722 b) / (0.2126 a + 0.7152 b +
 * 0.0722 g) = 1.9318 / 3.2178. Rec. 709's weights in RGB order would give 1 and render the
 * EXR 1.67 times as bright as pbrt-v4 does. */
TEST(sky_illuminance_reads_channels_in_file_order)
{
    const float rgba[4] = {1, 2, 4, 1};
    const char *exr = test_tmp_path("const.exr"), *pfm = test_tmp_path("const.pfm");
    write_constant_map(exr, rgba);
    write_constant_map(pfm, rgba);
    double s_exr = sky_scale(exr), s_pfm = sky_scale(pfm);
    const double lum[3] = {0.2126, 0.7152, 0.0722};
    double rgb_order = lum[0] * rgba[0] + lum[1] * rgba[1] + lum[2] * rgba[2];
    double exr_order = lum[0] * rgba[3] + lum[1] * rgba[2] + lum[2] * rgba[1];
    if (!(fabs(s_exr / s_pfm - rgb_order / exr_order) <= 1e-4))
        TEST_FAIL("EXR scale / PFM scale %.6f, want %.6f", s_exr / s_pfm, rgb_order / exr_order);
}

/* pbrt-v4's NanoVDBMedium is emissive only where it has a temperature grid and LeScale > 0
 * (IsEmissive): "Lescale" 0 on a fire file is a medium that emits nothing, which brume read
 * as a blackbody of scale 0 and refused ("0 outside [1e-30, 1e+30]"); a positive one emits. */
TEST(nanovdb_lescale_zero_emits_nothing)
{
    const char *dir = test_fresh_dir("lescale");
    char nvdb[4096], cmd[8192];
    snprintf(nvdb, sizeof nvdb, "%s/fire.nvdb", dir);
    snprintf(cmd, sizeof cmd, "%s gen fire --resolution 16 -o %s > /dev/null", BRUME_EXE, nvdb);
    ASSERT_EQ_INT(test_system(cmd), 0);
    for (int k = 0; k < 2; k++) {
        char text[8192], msg[2048];
        snprintf(text, sizeof text,
                 "Film \"rgb\"\n" VIEW "WorldBegin\n"
                 "MakeNamedMedium \"f\" \"string type\" \"nanovdb\" \"string filename\" \"%s\" \"float Lescale\" [%d]\n"
                 "AttributeBegin\nMaterial \"interface\"\nMediumInterface \"f\" \"\"\n"
                 "Shape \"sphere\" \"float radius\" 100\nAttributeEnd\n",
                 nvdb, k);
        cJSON *root = pbrt_translate("lescale.pbrt", text, msg, sizeof msg);
        if (!root)
            TEST_FAIL("Lescale %d: %s", k, msg);
        const cJSON *m = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "media"), 0);
        ASSERT_TRUE(cJSON_HasObjectItem(m, "blackbody") == (k == 1));
        cJSON_Delete(root);
        brume_context *ctx = brume_context_new();
        brume_scene *sc = NULL;
        if (brume_scene_load(ctx, &(brume_source){.path = test_tmp_path("lescale.pbrt")}, NULL, &sc) != BRUME_OK)
            TEST_FAIL("Lescale %d: %s", k, brume_context_last_error(ctx));
        brume_scene_release(sc);
        brume_context_release(ctx);
    }
}

/* pbrt-v4's BlackbodySpectrum has no upper temperature: pbrt-v4-scenes' explosion scales its
 * file's temperatures by 100, to 1e5 K and beyond, where the peak-normalized visible
 * spectrum keeps falling (as T^-4 in the limit). brume's rendering table, held at its 1e5 K
 * colour above 1e5 K, rendered a 2e5 K voxel 15 times too bright; it agrees with the direct
 * integral of Planck's law now, from 1e5 K to 1e8 K, and below as before. */
TEST(blackbody_table_follows_planck_past_1e5_kelvin)
{
    blackbody_init();
    for (double T = 20000.0; T < 1.2e8; T *= 1.19) { /* below, test_sparse_fields.c */
        color a = blackbody_rgb(T), b = blackbody_rgb_exact(T);
        for (int c = 0; c < BRUME_NSAMPLES; c++)
            if (!(fabs(a.c[c] - b.c[c]) <= 2e-3 * fabs(b.c[c]) + 1e-12))
                TEST_FAIL("%.4g K, channel %d: table %.6g, Planck %.6g", T, c, a.c[c], b.c[c]);
    }
}

TEST_MAIN(blackbody_table_follows_planck_past_1e5_kelvin, distant_illuminance_as_pbrt, nanovdb_is_pbrt_lookup_to_the_faces, sky_illuminance_reads_channels_in_file_order,
          nanovdb_lescale_zero_emits_nothing)
