/* test_pbrt_leftovers.c - pbrt-v4's Film "maxcomponentvalue" and "whitebalance" (brume's
 * render.max_component and render.white_balance, docs/scene-format.md and docs/pbrt.md),
 * PLY meshes under mirroring transforms and the "cloud" medium: the clamp against pbrt-v4's
 * RGBFilm::AddSample written out here (the largest of the sample's CIE X, Y, Z scaled to the
 * value), on a sample and in a render; the white balance's source white against the CIE's
 * published daylight whites, and its map taking it to D65; a PLY triangle written by the
 * test placed where pbrt-v4 places it, its front side pbrt-v4's geometric normal; the
 * cloud's density against pbrt-v4's CloudMedium::Density and Perlin noise written out here
 * from pbrt-v4's source. */
#include "test.h"
#include "pbrt_translate.h"

#include <math.h>

#include "brume.h"
#include "core/error.h"
#include "density/density.h"
#include "io/json.h"
#include "render/film.h"
#include "render/sample.h"
#include "scene/scene.h"
#include "scene/scene_pbrt.h"
#include "surface/surfaces.h"

/* the cie1931 sensor's values: CIE XYZ from linear Rec. 709 (render/sample.h, sample_clamp) */
static const double xyz_from_rgb[9] = {0.4124564, 0.3575761, 0.1804375, 0.2126729, 0.7151522,
                                       0.0721750, 0.0193339, 0.1191920, 0.9503041};

/* pbrt-v4's clamp with its cie1931 sensor: the sample's XYZ (from linear Rec. 709 by the
 * standard D65 matrix) scaled by m / max(X, Y, Z) when that exceeds m. */
static void pbrt_clamp(const double rgb[3], double m, double out[3])
{
    const double M[3][3] = {{0.4124564, 0.3575761, 0.1804375},
                            {0.2126729, 0.7151522, 0.0721750},
                            {0.0193339, 0.1191920, 0.9503041}};
    double top = 0.0;
    for (int i = 0; i < 3; i++)
        top = fmax(top, M[i][0] * rgb[0] + M[i][1] * rgb[1] + M[i][2] * rgb[2]);
    double k = top > m ? m / top : 1.0;
    for (int c = 0; c < 3; c++)
        out[c] = rgb[c] * k;
}

/* A sample's clamp: a grey (its Z largest), a red (its X largest), a green (its Y), one under
 * the value (unchanged), no clamp (0), and a NaN kept for sample_set to count. */
TEST(max_component_clamps_largest_xyz)
{
    const double cases[][4] = {{10, 10, 10, 5}, {8, 0.5, 0.2, 1}, {0.1, 9, 0.1, 2}, {0.3, 0.2, 0.1, 1}, {7, 7, 7, 0}};
    for (int i = 0; i < 5; i++) {
        double want[3];
        pbrt_clamp(cases[i], cases[i][3] > 0 ? cases[i][3] : INFINITY, want);
        color got = sample_clamp(col_rgb(cases[i][0], cases[i][1], cases[i][2]), cases[i][3], xyz_from_rgb);
        for (int c = 0; c < 3; c++)
            ASSERT_NEAR(got.c[c], want[c], 1e-12 * (1 + want[c]));
    }
    ASSERT_NEAR(sample_clamp(col_rgb(10, 10, 10), 5, xyz_from_rgb).c[0], 10 * 5 / (10 * (0.0193339 + 0.1191920 + 0.9503041)), 1e-12);
    ASSERT_TRUE(isnan(sample_clamp(col_rgb(NAN, 1, 1), 1, xyz_from_rgb).c[0]));
    sample_value v;
    sample_params sp = {.max_component = 1};
    sample_set(&v, &sp, col_rgb(INFINITY, 1, 1), true, col(1.0));
    ASSERT_TRUE(v.nonfinite);
}

/* Every camera sample of a sky of (3, 2, 1) is clamped before it is added: each pixel is
 * the clamped colour, (3, 2, 1) / Y with Y = 2.1405 the largest of X, Y, Z, for
 * render.max_component 1; and the sky as it is for a clamp above it. */
TEST(max_component_renders_clamped_samples)
{
    const double sky[3] = {3, 2, 1};
    for (int k = 0; k < 2; k++) {
        const double m = k == 0 ? 1.0 : 2.5;
        char json[1024];
        snprintf(json, sizeof json,
                 "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]}, \"background\": [3, 2, 1], \"render\": {\"width\": 4, \"height\": 4, \"spp\": 4, \"max_component\": %g}}",
                 m);
        brume_image *img = test_render_json(json, 1);
        double want[3];
        pbrt_clamp(sky, m, want);
        const float *px = brume_image_pixels(img);
        for (int i = 0; i < 16; i++)
            for (int c = 0; c < 3; c++)
                ASSERT_NEAR(px[4 * i + c], want[c], 1e-6 * want[c]);
        brume_image_release(img);
    }
}

/* The translation of a .pbrt text; NULL and *msg set when it is refused. */
static cJSON *translate(const char *text, char *msg, size_t cap)
{
    return pbrt_translate("left.pbrt", text, msg, cap);
}

#define VIEW "Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n"

/* Film "float maxcomponentvalue" is render.max_component; pbrt-v4's default (none) writes
 * none; a value <= 0 is refused with the Film's line. */
TEST(maxcomponentvalue_read_from_film)
{
    char msg[2048];
    cJSON *root = translate("Film \"rgb\" \"float maxcomponentvalue\" [10]\n" VIEW "WorldBegin\n", msg, sizeof msg);
    if (!root)
        TEST_FAIL("%s", msg);
    const cJSON *r = cJSON_GetObjectItemCaseSensitive(root, "render");
    ASSERT_NEAR(cJSON_GetObjectItemCaseSensitive(r, "max_component")->valuedouble, 10.0, 0);
    cJSON_Delete(root);
    root = translate("Film \"rgb\"\n" VIEW "WorldBegin\n", msg, sizeof msg);
    ASSERT_TRUE(root && !cJSON_HasObjectItem(cJSON_GetObjectItemCaseSensitive(root, "render"), "max_component"));
    cJSON_Delete(root);
    ASSERT_TRUE(translate("Film \"rgb\"\n  \"float maxcomponentvalue\" [0]\n" VIEW "WorldBegin\n", msg, sizeof msg) ==
                NULL);
    ASSERT_CONTAINS(msg, "left.pbrt:1: ");
    ASSERT_CONTAINS(msg, "\"maxcomponentvalue\"");
}

/* pbrt-v4's source white for Film "whitebalance" T (Spectra::D at T 1.4388 / 1.4380): the CIE
 * daylight illuminants' published chromaticities, D50 (0.34567, 0.35850), D65 (0.31271,
 * 0.32902) and D75 (0.29902, 0.31485), at their nominal 5000, 6500 and 7500 K, within 3e-4;
 * below 4000 K the Planckian locus: CIE illuminant A (0.44757, 0.40745), Planck's law at
 * 2856 K with c2 = 1.435e-2 m K, i.e. at 2856 x 1.4388 / 1.435 K with today's c2, within the
 * 2.5e-3 of brume's fitted colour matching functions (docs/grids.md). */
TEST(white_balance_source_white_is_cie_daylight)
{
    const double cases[4][4] = {{5000, 0.34567, 0.35850, 3e-4}, {6500, 0.31271, 0.32902, 3e-4},
                                {7500, 0.29902, 0.31485, 3e-4}, {2856 * 1.4380 / 1.435, 0.44757, 0.40745, 2.5e-3}};
    for (int i = 0; i < 4; i++) {
        double xy[2];
        film_daylight_xy(cases[i][0], xy);
        ASSERT_NEAR(xy[0], cases[i][1], cases[i][3]);
        ASSERT_NEAR(xy[1], cases[i][2], cases[i][3]);
    }
}

/* The white balance takes the source white to D65: the Rec. 709 colour of the daylight white
 * at T (luminance 1) becomes (1, 1, 1), Rec. 709's white, for T from 2500 to 20000 K; and at
 * D65's own temperature the map is the identity within the whites' difference. */
TEST(white_balance_maps_source_white_to_d65)
{
    const double ts[5] = {2500, 4000, 5000, 9000, 20000};
    for (int i = 0; i < 5; i++) {
        double xy[2], m[9];
        film_daylight_xy(ts[i], xy);
        film_white_balance(ts[i], m);
        double X = xy[0] / xy[1], Z = (1 - xy[0] - xy[1]) / xy[1];
        double rgb[3] = {3.2404542 * X - 1.5371385 - 0.4985314 * Z, -0.9692660 * X + 1.8760108 + 0.0415560 * Z,
                         0.0556434 * X - 0.2040259 + 1.0572252 * Z};
        for (int r = 0; r < 3; r++)
            ASSERT_NEAR(m[3 * r] * rgb[0] + m[3 * r + 1] * rgb[1] + m[3 * r + 2] * rgb[2], 1.0, 1e-3);
    }
    double m[9];
    film_white_balance(6500 * 1.4380 / 1.4388 * 6504.0 / 6500.0, m);
    for (int i = 0; i < 9; i++)
        ASSERT_NEAR(m[i], i % 4 == 0 ? 1.0 : 0.0, 3e-3);
}

/* render.white_balance maps every sample: a sky of (0.8, 0.6, 0.4) renders as the map times
 * it; Film "whitebalance" with the cie1931 sensor is read into it. */
TEST(white_balance_renders_and_reads_from_film)
{
    brume_image *img = test_render_json("{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]}, \"background\": [0.8, 0.6, 0.4],"
                                        " \"render\": {\"width\": 4, \"height\": 4, \"spp\": 2, \"white_balance\": 3200}}",
                                        1);
    double m[9], sky[3] = {0.8, 0.6, 0.4};
    film_white_balance(3200, m);
    const float *px = brume_image_pixels(img);
    for (int c = 0; c < 3; c++)
        ASSERT_NEAR(px[c], m[3 * c] * sky[0] + m[3 * c + 1] * sky[1] + m[3 * c + 2] * sky[2], 1e-6);
    ASSERT_TRUE(px[2] > 0.5 && px[0] < 0.75); /* a warm white made neutral: blue up, red down */
    brume_image_release(img);
    char msg[2048];
    cJSON *root = translate("Film \"rgb\" \"string sensor\" \"cie1931\" \"float whitebalance\" [5000]\n" VIEW "WorldBegin\n",
                            msg, sizeof msg);
    if (!root)
        TEST_FAIL("%s", msg);
    const cJSON *r = cJSON_GetObjectItemCaseSensitive(root, "render");
    ASSERT_NEAR(cJSON_GetObjectItemCaseSensitive(r, "white_balance")->valuedouble, 5000, 0);
    cJSON_Delete(root);
}

/* pbrt-v4's "power" on point and spot lights: I scale phi_v / k_e, k_e = 4 pi for a point and
 * 2 pi ((1 - cos start) + (cos start - cos end) / 2) for a spot (its falloff counted half),
 * start = coneangle - conedeltaangle and end = coneangle; I of luminance 1 (rgb is read as
 * it is). */
TEST(point_and_spot_power_as_pbrt)
{
    char msg[2048];
    cJSON *root = translate("Film \"rgb\"\n" VIEW "WorldBegin\n"
                            "LightSource \"point\" \"rgb I\" [1 2 3] \"float power\" [100] \"float scale\" [2]\n"
                            "LightSource \"spot\" \"rgb I\" [1 1 1] \"float power\" [50] \"float coneangle\" [40]"
                            " \"float conedeltaangle\" [10]\n",
                            msg, sizeof msg);
    if (!root)
        TEST_FAIL("%s", msg);
    const cJSON *lights = cJSON_GetObjectItemCaseSensitive(root, "lights");
    const cJSON *Ip = cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(lights, 0), "intensity");
    const cJSON *Is = cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(lights, 1), "intensity");
    for (int c = 0; c < 3; c++)
        ASSERT_NEAR(cJSON_GetArrayItem(Ip, c)->valuedouble, (c + 1) * 2 * 100 / (4 * PI), 1e-9);
    const double d2r = PI / 180, cs = cos(30 * d2r), ce = cos(40 * d2r);
    ASSERT_NEAR(cJSON_GetArrayItem(Is, 1)->valuedouble, 50 / (2 * PI * ((1 - cs) + (cs - ce) / 2)), 1e-9);
    cJSON_Delete(root);
}

/* A PLY triangle (0,0,0) (1,0,0) (0,1,0), counter-clockwise seen from +z, placed by
 * Translate 2 0 0 and Scale -1 1 1 lies at (2,0,0) (1,0,0) (2,1,0), where pbrt-v4 puts it, and
 * faces +z: pbrt-v4's normal cross(p0 - p2, p1 - p2), negated as the transform swaps
 * handedness. Without the mirror it lies at x in [2, 3], facing +z too; under the bare
 * LookAt's mirrored world the mirrored triangle is the reader's (it is x -> -x of pbrt's). */
TEST(plymesh_under_mirror_placed_and_facing_as_pbrt)
{
    char ply[512];
    snprintf(ply, sizeof ply, "%s", test_tmp_path("tri.ply"));
    test_write_file(ply, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                         "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    const char *views[3] = {VIEW, VIEW, "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n"};
    const char *scales[3] = {"Scale -1 1 1\n", "", "Scale -1 1 1\n"};
    const double xs[3] = {1.7, 2.3, -1.7}; /* a point of the triangle where each puts it */
    for (int k = 0; k < 3; k++) {
        char text[1024];
        snprintf(text, sizeof text,
                 "Film \"rgb\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n%sWorldBegin\n"
                 "Material \"diffuse\"\nTranslate 2 0 0\n%sShape \"plymesh\" \"string filename\" \"%s\"\n",
                 views[k], scales[k], ply);
        const char *path = test_tmp_path("left.pbrt");
        test_write_file(path, text);
        brume_context *ctx = brume_context_new();
        brume_scene *s = NULL;
        if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK)
            TEST_FAIL("view %d: %s", k, brume_context_last_error(ctx));
        ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
        surface_hit h;
        ray r = {v3(xs[k], 0.2, 5), v3(0, 0, -1), 0.0};
        ASSERT_TRUE(surfaces_intersect(s->surf, r, 0.0, 100.0, &h));
        ASSERT_NEAR(h.p.z, 0.0, 1e-5); /* Embree intersects in single precision */
        ASSERT_NEAR(h.ng.z, 1.0, 1e-6);
        r.o.x = -xs[k]; /* nothing at the unmirrored place */
        ASSERT_TRUE(!surfaces_intersect(s->surf, r, 0.0, 100.0, &h));
        brume_scene_release(s);
        brume_context_release(ctx);
    }
    remove(ply);
    remove(test_tmp_path("left.pbrt"));
}


/* pbrt-v4's NoisePerm: Perlin's reference permutation, twice. */
static const int NoisePerm[512] = {
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69, 142, 8, 99, 37, 240,
    21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219, 203, 117, 35, 11, 32, 57, 177, 33, 88,
    237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175, 74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83,
    111, 229, 122, 60, 211, 133, 230, 220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216,
    80, 73, 209, 76, 132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173, 186,
    3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206, 59, 227, 47, 16, 58,
    17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163, 70, 221, 153, 101, 155, 167, 43, 172, 9,
    129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232, 178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193,
    238, 210, 144, 12, 191, 179, 162, 241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157,
    184, 84, 204, 176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141, 128,
    195, 78, 66, 215, 61, 156, 180, 151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36,
    103, 30, 69, 142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219, 203,
    117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175, 74, 165, 71, 134, 139,
    48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60, 211, 133, 230, 220, 105, 92, 41, 55, 46, 245, 40, 244, 102,
    143, 54, 65, 25, 63, 161, 1, 216, 80, 73, 209, 76, 132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159,
    86, 164, 100, 109, 198, 173, 186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212,
    207, 206, 59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163, 70, 221,
    153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232, 178, 185, 112, 104, 218,
    246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162, 241, 81, 51, 145, 235, 249, 14, 239, 107, 49,
    192, 214, 31, 181, 199, 106, 157, 184, 84, 204, 176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222,
    114, 67, 29, 24, 72, 243, 141, 128, 195, 78, 66, 215, 61, 156, 180};

/* pbrt-v4's Grad, NoiseWeight and Noise (util/noise.cpp), as its source writes them. */
static double Grad(int x, int y, int z, double dx, double dy, double dz)
{
    int h = NoisePerm[NoisePerm[NoisePerm[x] + y] + z];
    h &= 15;
    double u = h < 8 || h == 12 || h == 13 ? dx : dy;
    double v = h < 4 || h == 12 || h == 13 ? dy : dz;
    return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}
static double NoiseWeight(double t) { return 6 * pow(t, 5) - 15 * pow(t, 4) + 10 * pow(t, 3); }
static double Lerp(double t, double a, double b) { return (1 - t) * a + t * b; }
static double Noise(double x, double y, double z)
{
    x = fmod(x, (double)(1 << 30)), y = fmod(y, (double)(1 << 30)), z = fmod(z, (double)(1 << 30));
    int ix = (int)floor(x), iy = (int)floor(y), iz = (int)floor(z);
    double dx = x - ix, dy = y - iy, dz = z - iz;
    ix &= 255, iy &= 255, iz &= 255;
    double w000 = Grad(ix, iy, iz, dx, dy, dz), w100 = Grad(ix + 1, iy, iz, dx - 1, dy, dz);
    double w010 = Grad(ix, iy + 1, iz, dx, dy - 1, dz), w110 = Grad(ix + 1, iy + 1, iz, dx - 1, dy - 1, dz);
    double w001 = Grad(ix, iy, iz + 1, dx, dy, dz - 1), w101 = Grad(ix + 1, iy, iz + 1, dx - 1, dy, dz - 1);
    double w011 = Grad(ix, iy + 1, iz + 1, dx, dy - 1, dz - 1), w111 = Grad(ix + 1, iy + 1, iz + 1, dx - 1, dy - 1, dz - 1);
    double wx = NoiseWeight(dx), wy = NoiseWeight(dy), wz = NoiseWeight(dz);
    double x00 = Lerp(wx, w000, w100), x10 = Lerp(wx, w010, w110), x01 = Lerp(wx, w001, w101), x11 = Lerp(wx, w011, w111);
    return Lerp(wz, Lerp(wy, x00, x10), Lerp(wy, x01, x11));
}

/* pbrt-v4's CloudMedium::Density at p in the medium's space (DNoise: forward differences of
 * step 0.01); the constants are pbrt-v4's floats. */
static double cloud_density(double dens, double wispiness, double frequency, const double p[3])
{
    double pp[3] = {frequency * p[0], frequency * p[1], frequency * p[2]};
    if (wispiness > 0) {
        double vomega = (double)0.05f * wispiness, vlambda = 10;
        for (int i = 0; i < 2; ++i) {
            double q[3] = {vlambda * pp[0], vlambda * pp[1], vlambda * pp[2]}, delta = (double)0.01f;
            double n = Noise(q[0], q[1], q[2]);
            double dn[3] = {(Noise(q[0] + delta, q[1], q[2]) - n) / delta, (Noise(q[0], q[1] + delta, q[2]) - n) / delta,
                            (Noise(q[0], q[1], q[2] + delta) - n) / delta};
            for (int a = 0; a < 3; a++)
                pp[a] += vomega * dn[a];
            vomega *= 0.5;
            vlambda *= (double)1.99f;
        }
    }
    double d = 0, omega = 0.5, lambda = 1;
    for (int i = 0; i < 5; ++i) {
        d += omega * Noise(lambda * pp[0], lambda * pp[1], lambda * pp[2]);
        omega *= 0.5;
        lambda *= (double)1.99f;
    }
    d = fmin(1.0, fmax(0.0, (1 - p[1]) * 4.5 * dens * d));
    d += 2 * fmax(0.0, 0.5 - p[1]);
    return fmin(1.0, fmax(0.0, d));
}

/* brume's pbrt_cloud density, placed as pbrt's MakeNamedMedium places it (Translate, Scale
 * through the JSON transform after the box), against pbrt-v4's Density at 400 points of the
 * box [p0, p1] (some near y = 0.5 and 1, where the fall-off bends) and 0 outside it. */
TEST(pbrt_cloud_density_is_pbrt)
{
    const double params[3][3] = {{1, 1, 5}, {3, 0, 2}, {0.5, 2.5, 7}}; /* density, wispiness, frequency */
    for (int k = 0; k < 3; k++) {
        char json[1024];
        snprintf(json, sizeof json,
                 "{\"camera\": {\"position\": [0, 0, 9], \"look_at\": [0, 0, 0]}, \"media\": [{\"sigma_a\": 1, \"sigma_s\": 1, \"density\": {\"type\": \"pbrt_cloud\", \"density\": %g,"
                 " \"wispiness\": %g, \"frequency\": %g, \"bounds\": [[-1, 0, -2], [2, 1.5, 1]],"
                 " \"transform\": {\"translate\": [5, -1, 2], \"scale\": [2, -1, 0.5]}}}]}",
                 params[k][0], params[k][1], params[k][2]);
        brume_scene *s = test_scene_json(json);
        const density *d = s->media[0].rho;
        unsigned long long h = 12345 + (unsigned long long)k;
        int between = 0;
        for (int i = 0; i < 400; i++) {
            double p[3];
            for (int a = 0; a < 3; a++) {
                h = h * 6364136223846793005ULL + 1442695040888963407ULL;
                p[a] = (double)(h >> 11) * 0x1.0p-53;
            }
            p[0] = -1 + 3 * p[0], p[1] = i % 4 == 0 ? 0.5 + 0.02 * (p[1] - 0.5) : 1.5 * p[1], p[2] = -2 + 3 * p[2];
            vec3 w = v3(5 + 2 * p[0], -1 - p[1], 2 + 0.5 * p[2]);
            double want = cloud_density(params[k][0], params[k][1], params[k][2], p);
            ASSERT_NEAR(density_eval(d, w), want, 1e-9);
            between += want > 0.05 && want < 0.95;
        }
        ASSERT_TRUE(between > 40); /* the noise's range, not only the clamps' 0 and 1 */
        ASSERT_NEAR(density_eval(d, v3(5 + 2 * 2.1, -1 - 0.7, 2)), 0.0, 0); /* beyond p1.x */
        ASSERT_NEAR(density_eval(d, v3(5, -1 + 0.1, 2)), 0.0, 0);          /* below p0.y */
        brume_scene_release(s);
    }
}

/* MakeNamedMedium "cloud" becomes a medium of sigma_a, sigma_s and HG g with a pbrt_cloud
 * density of pbrt's parameters over [p0, p1], placed by the transform at the directive;
 * pbrt-v4's cloud reads no scale or emission: those are refused by name with the line. */
TEST(pbrt_cloud_medium_translates)
{
    char msg[2048];
    cJSON *root = translate("Film \"rgb\"\n" VIEW "WorldBegin\nAttributeBegin\nTranslate 1 2 3\n"
                            "MakeNamedMedium \"c\" \"string type\" \"cloud\" \"float density\" [2] \"float wispiness\" [0.5]\n"
                            "  \"float frequency\" [3] \"rgb sigma_a\" [0.1 0.2 0.3] \"rgb sigma_s\" [4 5 6] \"float g\" [0.3]\n"
                            "  \"point3 p0\" [-1 -1 -1] \"point3 p1\" [1 2 1]\n"
                            "Material \"interface\"\nMediumInterface \"c\" \"\"\nShape \"sphere\" \"float radius\" [3]\nAttributeEnd\n",
                            msg, sizeof msg);
    if (!root)
        TEST_FAIL("%s", msg);
    const cJSON *m = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "media"), 0);
    const cJSON *d = cJSON_GetObjectItemCaseSensitive(m, "density");
    ASSERT_EQ_STR(cJSON_GetObjectItemCaseSensitive(d, "type")->valuestring, "pbrt_cloud");
    ASSERT_NEAR(cJSON_GetObjectItemCaseSensitive(d, "density")->valuedouble, 2, 0);
    ASSERT_NEAR(cJSON_GetObjectItemCaseSensitive(d, "wispiness")->valuedouble, 0.5, 0);
    ASSERT_NEAR(cJSON_GetObjectItemCaseSensitive(d, "frequency")->valuedouble, 3, 0);
    ASSERT_NEAR(cJSON_GetArrayItem(cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(d, "bounds"), 1), 1)->valuedouble, 2, 0);
    ASSERT_NEAR(cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(
                    cJSON_GetObjectItemCaseSensitive(d, "transform"), "translate"), 2)->valuedouble, 3, 1e-12);
    ASSERT_NEAR(cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(m, "sigma_s"), 1)->valuedouble, 5, 0);
    ASSERT_NEAR(cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(m, "phase"), "g")->valuedouble, 0.3, 0);
    cJSON_Delete(root);
    const char *bad[2] = {"\"float scale\" [2]", "\"float Lescale\" [2]"};
    for (int i = 0; i < 2; i++) {
        char text[512];
        snprintf(text, sizeof text, "Film \"rgb\"\n" VIEW "WorldBegin\nMakeNamedMedium \"c\" \"string type\" \"cloud\"\n  %s\n",
                 bad[i]);
        ASSERT_TRUE(translate(text, msg, sizeof msg) == NULL);
        ASSERT_CONTAINS(msg, "left.pbrt:");
        ASSERT_CONTAINS(msg, i == 0 ? "scale" : "Lescale");
    }
}

TEST_MAIN(max_component_clamps_largest_xyz, max_component_renders_clamped_samples, maxcomponentvalue_read_from_film,
          white_balance_source_white_is_cie_daylight, white_balance_maps_source_white_to_d65,
          white_balance_renders_and_reads_from_film, point_and_spot_power_as_pbrt,
          plymesh_under_mirror_placed_and_facing_as_pbrt,
          pbrt_cloud_density_is_pbrt, pbrt_cloud_medium_translates)
