/* test_pbrt_textures.c - textures (brume.h "TEXTURES", docs/surfaces.md): an imagemap
 * written here as a PNG of known sRGB bytes looked up against the sRGB decoding written out;
 * scale, mix and checkerboard against their formulas; a checkerboard plane rendered under a
 * sun; pbrt-v4's Texture directive translated and refused by name; the GPU's refusal. */
#include "test.h"

#include <math.h>
#include <stdint.h>

#include "brume.h"
#include "core/error.h"
#include "gpu/device_scene.h"
#include "render/integrator.h"
#include "scene/scene.h"
#include "surface/texture.h"

#define PI_ 3.14159265358979323846

/* ---- a PNG written byte by byte: zlib stored blocks, CRC-32 and Adler-32 ------------------ */

static uint32_t crc32_of(const unsigned char *p, size_t n)
{
    uint32_t c = 0xffffffffu;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++)
            c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
}

static void put32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24), p[1] = (unsigned char)(v >> 16), p[2] = (unsigned char)(v >> 8),
    p[3] = (unsigned char)v;
}

/* chunk: length, type, data, CRC of type and data; returns the bytes written at out */
static size_t chunk(unsigned char *out, const char *type, const unsigned char *data, size_t n)
{
    put32(out, (uint32_t)n);
    memcpy(out + 4, type, 4);
    if (n) /* IEND has no data (and NULL for it) */
        memcpy(out + 8, data, n);
    put32(out + 8 + n, crc32_of(out + 4, n + 4));
    return n + 12;
}

/* An 8-bit RGB PNG of w x h pixels (rgb: rows top first), no sRGB or gamma chunk. */
static void write_png(const char *path, int w, int h, const unsigned char *rgb)
{
    size_t raw_n = (size_t)h * (1 + 3 * (size_t)w);
    unsigned char raw[1024], z[1100], file[2048];
    ASSERT_TRUE(raw_n + 11 < sizeof z);
    for (int y = 0, k = 0; y < h; y++) {
        raw[k++] = 0; /* filter: none */
        memcpy(raw + k, rgb + 3 * (size_t)y * (size_t)w, 3 * (size_t)w);
        k += 3 * w;
    }
    size_t zn = 0;
    z[zn++] = 0x78, z[zn++] = 0x01;                       /* deflate, 32K window, check bits */
    z[zn++] = 1;                                          /* final stored block */
    z[zn++] = (unsigned char)raw_n, z[zn++] = (unsigned char)(raw_n >> 8);
    z[zn++] = (unsigned char)~raw_n, z[zn++] = (unsigned char)(~raw_n >> 8);
    memcpy(z + zn, raw, raw_n);
    zn += raw_n;
    uint32_t a = 1, b = 0;
    for (size_t i = 0; i < raw_n; i++)
        a = (a + raw[i]) % 65521u, b = (b + a) % 65521u;
    put32(z + zn, (b << 16) | a);
    zn += 4;
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    unsigned char ihdr[13] = {0};
    put32(ihdr, (uint32_t)w);
    put32(ihdr + 4, (uint32_t)h);
    ihdr[8] = 8, ihdr[9] = 2; /* 8 bits, RGB */
    size_t n = 0;
    memcpy(file, sig, 8);
    n = 8;
    n += chunk(file + n, "IHDR", ihdr, sizeof ihdr);
    n += chunk(file + n, "IDAT", z, zn);
    n += chunk(file + n, "IEND", NULL, 0);
    test_write_bytes(path, file, n);
}

/* The sRGB transfer function's inverse (IEC 61966-2-1), written out. */
static double srgb_to_linear(int code)
{
    double c = code / 255.0;
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

/* 2 x 2: top row red, green; bottom row blue, grey 128. */
static const unsigned char quad_rgb[12] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 128, 128, 128};

static texture *image_texture(const char *png, double gamma, brume_texture_wrap wrap)
{
    brume_texture_node n = {.type = BRUME_TEXTURE_IMAGEMAP, .tex1 = -1, .tex2 = -1, .amount = -1,
                            .filename = png, .gamma = gamma, .wrap = wrap};
    brume_image *img = NULL;
    if (brume_image_read(NULL, png, &img) != BRUME_OK)
        TEST_FAIL("brume_image_read: %s", err_message());
    texture *t = texture_build(&(brume_texture){&n, 1}, &img, "test", "albedo_texture");
    brume_image_release(img);
    if (!t)
        TEST_FAIL("texture_build: %s", err_message());
    return t;
}

static void expect_rgb(color got, const double want[3], const char *where)
{
    for (int c = 0; c < 3; c++)
        if (!(fabs(got.c[c] - want[c]) <= 2e-6))
            TEST_FAIL("%s: channel %d: %.9g, want %.9g", where, c, got.c[c], want[c]);
}

/* pbrt-v4's lookup: (s, 1 - t) with pixel centres at (i + 0.5) / size, bilinear between
 * them; v = 0 is the image's bottom row. The 8-bit codes decode by sRGB (default), as
 * linear and by a gamma; repeat, clamp and black outside [0, 1]. */
TEST(imagemap_is_pbrt_lookup_of_decoded_bytes)
{
    const char *png = test_tmp_path("quad.png");
    write_png(png, 2, 2, quad_rgb);
    double lin[4][3]; /* top-left, top-right, bottom-left, bottom-right */
    for (int p = 0; p < 4; p++)
        for (int c = 0; c < 3; c++)
            lin[p][c] = srgb_to_linear(quad_rgb[3 * p + c]);
    texture *t = image_texture(png, 0.0, BRUME_WRAP_REPEAT);
    expect_rgb(texture_eval(t, 0.25, 0.75), lin[0], "u 0.25 v 0.75 (top-left centre)");
    expect_rgb(texture_eval(t, 0.75, 0.75), lin[1], "top-right centre");
    expect_rgb(texture_eval(t, 0.25, 0.25), lin[2], "bottom-left centre");
    expect_rgb(texture_eval(t, 0.75, 0.25), lin[3], "bottom-right centre");
    double mid[3], quarter[3];
    for (int c = 0; c < 3; c++) {
        mid[c] = 0.25 * (lin[0][c] + lin[1][c] + lin[2][c] + lin[3][c]);
        /* u 0.375, v 0.75: x = 0.25 between the top row's two centres */
        quarter[c] = 0.75 * lin[0][c] + 0.25 * lin[1][c];
    }
    expect_rgb(texture_eval(t, 0.5, 0.5), mid, "the middle");
    expect_rgb(texture_eval(t, 0.375, 0.75), quarter, "a quarter along the top row");
    expect_rgb(texture_eval(t, 1.25, 1.75), lin[0], "repeat");
    texture_free(t);

    t = image_texture(png, 0.0, BRUME_WRAP_CLAMP);
    expect_rgb(texture_eval(t, -3.0, 0.25), lin[2], "clamp");
    texture_free(t);
    t = image_texture(png, 0.0, BRUME_WRAP_BLACK);
    expect_rgb(texture_eval(t, -1.0, 0.25), (double[3]){0, 0, 0}, "black");
    texture_free(t);

    t = image_texture(png, 1.0, BRUME_WRAP_REPEAT);
    expect_rgb(texture_eval(t, 0.75, 0.25), (double[3]){128 / 255.0, 128 / 255.0, 128 / 255.0}, "linear");
    texture_free(t);
    t = image_texture(png, 2.2, BRUME_WRAP_REPEAT);
    double g = pow(128 / 255.0, 2.2);
    expect_rgb(texture_eval(t, 0.75, 0.25), (double[3]){g, g, g}, "gamma 2.2");
    texture_free(t);
}

/* scale = tex x scale; mix = (1 - amount) tex1 + amount tex2, its amount itself a texture
 * (a checkerboard of 0.25 and 1); the defaults where an input is -1. */
TEST(scale_mix_and_checkerboard_follow_their_formulas)
{
    brume_texture_node n[6] = {
        {.type = BRUME_TEXTURE_MIX, .tex1 = 1, .tex2 = 2, .amount = 3},
        {.type = BRUME_TEXTURE_CONSTANT, .value = {0.2, 0.4, 0.6}, .tex1 = -1, .tex2 = -1, .amount = -1},
        {.type = BRUME_TEXTURE_SCALE, .tex1 = 4, .tex2 = -1, .amount = 5},
        {.type = BRUME_TEXTURE_CHECKERBOARD, .is_float = true, .tex1 = -1, .tex2 = -1, .amount = -1,
         .uscale = 4, .vscale = 4},
        {.type = BRUME_TEXTURE_CONSTANT, .value = {1.0, 0.5, 0.25}, .tex1 = -1, .tex2 = -1, .amount = -1},
        {.type = BRUME_TEXTURE_CONSTANT, .is_float = true, .value = {0.5}, .tex1 = -1, .tex2 = -1, .amount = -1},
    };
    /* the checkerboard (node 3) takes its defaults: 1 where floor(4u) + floor(4v) is even, else 0 */
    texture *t = texture_build(&(brume_texture){n, 6}, NULL, "test", "albedo_texture");
    ASSERT_TRUE(t != NULL);
    const double uv[4][2] = {{0.1, 0.1}, {0.3, 0.1}, {0.3, 0.3}, {0.6, 0.1}};
    for (int k = 0; k < 4; k++) {
        double amount = ((int)floor(4 * uv[k][0]) + (int)floor(4 * uv[k][1])) % 2 == 0 ? 1.0 : 0.0;
        double want[3];
        for (int c = 0; c < 3; c++)
            want[c] = (1 - amount) * n[1].value[c] + amount * (n[4].value[c] * 0.5);
        expect_rgb(texture_eval(t, uv[k][0], uv[k][1]), want, "mix of constant and scale by a checkerboard");
    }
    texture_free(t);

    brume_texture_node d[1] = {{.type = BRUME_TEXTURE_MIX, .tex1 = -1, .tex2 = -1, .amount = -1}};
    t = texture_build(&(brume_texture){d, 1}, NULL, "test", "albedo_texture");
    expect_rgb(texture_eval(t, 0.3, 0.7), (double[3]){0.5, 0.5, 0.5}, "mix of its defaults 0, 1 at 0.5");
    texture_free(t);
}

/* A node whose input is not a later node, an unknown type, NaN, a missing file: refused with
 * the node and the field. */
TEST(texture_trees_checked)
{
    brume_texture_node loop[2] = {
        {.type = BRUME_TEXTURE_SCALE, .tex1 = 1, .tex2 = -1, .amount = -1},
        {.type = BRUME_TEXTURE_SCALE, .tex1 = 0, .tex2 = -1, .amount = -1},
    };
    ASSERT_TRUE(texture_build(&(brume_texture){loop, 2}, NULL, "f", "t") == NULL);
    ASSERT_CONTAINS(err_message(), "f: t.nodes[1].tex1: 0 is not -1 or a later node");
    brume_texture_node nan1 = {.type = BRUME_TEXTURE_CONSTANT, .value = {NAN, 0, 0}, .tex1 = -1, .tex2 = -1,
                               .amount = -1};
    ASSERT_TRUE(texture_build(&(brume_texture){&nan1, 1}, NULL, "f", "t") == NULL);
    ASSERT_CONTAINS(err_message(), "f: t.nodes[0].value");
    brume_texture_node file = {.type = BRUME_TEXTURE_IMAGEMAP, .filename = "/nonexistent/x.png", .tex1 = -1,
                               .tex2 = -1, .amount = -1};
    brume_scene *s = test_scene_json("{\"camera\": {\"position\": [0, 0, 2], \"look_at\": [0, 0, 0]}}");
    brume_context *ctx = brume_context_new();
    brume_material m;
    brume_material_default(&m);
    m.albedo_texture = &(brume_texture){&file, 1};
    ASSERT_EQ_INT(brume_scene_add_quad(ctx, s, (double[3]){0, 0, 0}, (double[3]){1, 0, 0}, (double[3]){0, 1, 0},
                                       NULL, &m, NULL),
                  BRUME_ERROR_IO);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "brume_scene_add_quad: material.albedo_texture.nodes[0]");
    ASSERT_CONTAINS(brume_context_last_error(ctx), "/nonexistent/x.png");
    ASSERT_EQ_INT(brume_scene_surface_count(s), 0);
    brume_context_release(ctx);
    brume_scene_release(s);
}

/* The mean of the pixels of each class (0: sign x = sign y, 1: otherwise) of a square image
 * seeing [-0.9, 0.9]^2 of the plane z = 0, those within `margin` of the axes left out. */
static void quadrant_means(const brume_image *img, double margin, double mean[2][3], double se[2][3])
{
    int w = brume_image_width(img), h = brume_image_height(img);
    const float *px = brume_image_pixels(img);
    double sum[2][3] = {{0}}, sq[2][3] = {{0}};
    int n[2] = {0, 0};
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            /* row 0 is the image's top: world +y (the camera's up) */
            double x = 0.9 * (2.0 * (i + 0.5) / w - 1.0), y = 0.9 * (1.0 - 2.0 * (j + 0.5) / h);
            if (fabs(x) < margin || fabs(y) < margin)
                continue;
            int k = (x < 0) == (y < 0) ? 0 : 1;
            n[k]++;
            for (int c = 0; c < 3; c++) {
                double v = px[4 * ((size_t)j * (size_t)w + (size_t)i) + (size_t)c];
                sum[k][c] += v;
                sq[k][c] += v * v;
            }
        }
    for (int k = 0; k < 2; k++)
        for (int c = 0; c < 3; c++) {
            mean[k][c] = sum[k][c] / n[k];
            se[k][c] = sqrt(fmax(sq[k][c] / n[k] - mean[k][c] * mean[k][c], 0.0) / n[k]);
        }
}

#define SUN_SCENE(ALBEDO)                                                                                     \
    "{\"camera\": {\"position\": [0, 0, 2], \"look_at\": [0, 0, 0], \"up\": [0, 1, 0], \"fov\": 48.4555},"   \
    " \"lights\": [{\"type\": \"distant\", \"direction\": [0, 0, -1], \"irradiance\": [3, 3, 3]}],"             \
    " \"surfaces\": [{\"type\": \"quad\", \"corner\": [-1, -1, 0], \"edge_u\": [2, 0, 0], \"edge_v\": [0, 2, 0]," \
    "   \"material\": {\"albedo\": " ALBEDO "}}],"                                                              \
    " \"render\": {\"width\": 32, \"height\": 32, \"spp\": 4, \"method\": \"path\"}}"

/* A checkerboard of 0.8 and 0.2 (2 x 2 squares of side 1 on the quad [-1, 1]^2) lit by a sun
 * along the normal: a Lambertian surface's radiance is albedo E / pi, so the light squares
 * (floor(s) + floor(t) even: x and y of one sign) render 0.8 x 3 / pi and the dark ones
 * 0.2 x 3 / pi, their ratio 4. The camera at 2 with a vertical fov of 2 atan(0.45) sees
 * [-0.9, 0.9]^2; pixels within 0.1 of a square's edge are left out (the filter mixes them).
 * The path tracer's samples of it are noisy (a bounce's roulette), so the tolerance is 4
 * standard errors of the pixel means plus float rounding. */
TEST(checkerboard_plane_under_a_sun)
{
    brume_image *img = test_render_json(
        SUN_SCENE("{\"type\": \"checkerboard\", \"tex1\": 0.8, \"tex2\": 0.2, \"uscale\": 2, \"vscale\": 2}"), 5);
    double mean[2][3], se[2][3];
    quadrant_means(img, 0.1, mean, se);
    const double want[2] = {0.8 * 3 / PI_, 0.2 * 3 / PI_};
    for (int k = 0; k < 2; k++)
        for (int c = 0; c < 3; c++)
            if (!(fabs(mean[k][c] - want[k]) <= 4 * se[k][c] + 1e-5 * want[k]))
                TEST_FAIL("squares %d channel %d: mean %.7f, want %.7f (se %g)", k, c, mean[k][c], want[k], se[k][c]);
    double ratio = mean[0][1] / mean[1][1];
    ASSERT_NEAR(ratio, 4.0, 4 * ratio * hypot(se[0][1] / mean[0][1], se[1][1] / mean[1][1]));
    brume_image_release(img);
}

/* The same plane through pbrt-v4's Texture directive: a checkerboard of two spectrum
 * constants with pbrt's uscale, on a bilinear patch (pbrt's default patch uv), named by the
 * material's "texture reflectance". */
TEST(pbrt_checkerboard_translates_and_renders)
{
    const char *path = test_tmp_path("checker.pbrt");
    test_write_file(path,
                    "LookAt 0 0 2  0 0 0  0 1 0\n"
                    "Camera \"perspective\" \"float fov\" [48.4555]\n"
                    "Film \"rgb\" \"integer xresolution\" [32] \"integer yresolution\" [32]\n"
                    "Sampler \"sobol\" \"integer pixelsamples\" [4]\n"
                    "WorldBegin\n"
                    "LightSource \"distant\" \"point3 from\" [0 0 1] \"point3 to\" [0 0 0] \"rgb L\" [3 3 3]\n"
                    "Texture \"light\" \"spectrum\" \"constant\" \"rgb value\" [0.8 0.8 0.8]\n"
                    "Texture \"checks\" \"spectrum\" \"checkerboard\" \"texture tex1\" \"light\"\n"
                    "  \"rgb tex2\" [0.2 0.2 0.2] \"float uscale\" [2] \"float vscale\" [2]\n"
                    "Material \"diffuse\" \"texture reflectance\" \"checks\"\n"
                    "Shape \"bilinearmesh\" \"point3 P\" [-1 -1 0  1 -1 0  -1 1 0  1 1 0]\n");
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    brume_image *img = test_render_scene(s, 2, 5);
    double mean[2][3], se[2][3];
    quadrant_means(img, 0.1, mean, se);
    /* which diagonal holds the light squares depends on pbrt's view (docs/pbrt.md, the
       mirrored translation); each diagonal holds one reflectance */
    int b = mean[0][0] > mean[1][0] ? 0 : 1;
    ASSERT_NEAR(mean[b][0], 0.8 * 3 / PI_, 4 * se[b][0] + 1e-5);
    ASSERT_NEAR(mean[1 - b][0], 0.2 * 3 / PI_, 4 * se[1 - b][0] + 1e-5);
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* What brume cannot honour is refused with the file, the line and the construct. */
static void expect_pbrt_refusal(const char *world, int line, const char *frag)
{
    char text[2048];
    snprintf(text, sizeof text, "LookAt 0 0 2  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n%s", world);
    const char *path = test_tmp_path("refused.pbrt");
    test_write_file(path, text);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    ASSERT_TRUE(brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK);
    char want[1200];
    snprintf(want, sizeof want, "%s:%d: ", path, line);
    ASSERT_CONTAINS(brume_context_last_error(ctx), want);
    ASSERT_CONTAINS(brume_context_last_error(ctx), frag);
    brume_context_release(ctx);
}

TEST(pbrt_texture_refusals_name_file_and_line)
{
    expect_pbrt_refusal("Texture \"n\" \"spectrum\" \"fbm\"\n", 4, "Texture \"n\" \"spectrum\" \"fbm\": not supported");
    expect_pbrt_refusal("Texture \"c\" \"spectrum\" \"checkerboard\" \"string mapping\" \"spherical\"\n", 4,
                        "parameter \"mapping\": \"spherical\"");
    expect_pbrt_refusal("Texture \"c\" \"spectrum\" \"checkerboard\" \"integer dimension\" [3]\n", 4,
                        "parameter \"dimension\": 3");
    expect_pbrt_refusal("Texture \"f\" \"float\" \"constant\" \"float value\" [0.5]\n"
                        "Material \"diffuse\" \"texture reflectance\" \"f\"\n",
                        5, "no spectrum Texture named \"f\"");
    expect_pbrt_refusal("Texture \"c\" \"spectrum\" \"mix\" \"texture amount\" \"none\"\n", 4,
                        "no float Texture named \"none\"");
    expect_pbrt_refusal("Texture \"i\" \"spectrum\" \"imagemap\" \"string filename\" \"missing.png\"\n", 4,
                        "missing.png");
}

/* JSON texture keys are checked where they stand. */
TEST(json_texture_keys_checked)
{
    static const struct {
        const char *albedo, *frag;
    } bad[] = {
        {"{\"type\": \"wood\"}", "surfaces[0].material.albedo.type: unknown texture 'wood'"},
        {"{\"type\": \"mix\", \"amount\": [1, 2, 3]}", "surfaces[0].material.albedo.amount: expected a number"},
        {"{\"type\": \"imagemap\"}", "surfaces[0].material.albedo"},
        {"{\"type\": \"checkerboard\", \"tex1\": 0.5, \"colour\": 1}", "colour"},
        {"{\"type\": \"imagemap\", \"file\": \"x.png\", \"wrap\": \"mirror\"}", "wrap: 'mirror'"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char json[2048];
        snprintf(json, sizeof json, SUN_SCENE("%s"), bad[k].albedo);
        brume_context *ctx = brume_context_new();
        brume_scene *s = NULL;
        ASSERT_TRUE(brume_scene_load(ctx, &(brume_source){.text = json}, NULL, &s) != BRUME_OK);
        ASSERT_CONTAINS(brume_context_last_error(ctx), bad[k].frag);
        brume_context_release(ctx);
    }
}

/* The GPU refuses a textured surface by name (textures render on the CPU only). */
TEST(gpu_refuses_textures)
{
    brume_scene *s = test_scene_json(SUN_SCENE("{\"type\": \"checkerboard\"}"));
    ASSERT_EQ_INT(device_scene_check(s, INTEGRATOR_PATH), BRUME_ERROR_UNSUPPORTED);
    ASSERT_CONTAINS(err_message(), "textures render on the CPU only");
    ASSERT_CONTAINS(err_message(), "--device cpu");
    brume_scene_release(s);
    brume_scene *plain = test_scene_json(SUN_SCENE("0.5"));
    ASSERT_EQ_INT(device_scene_check(plain, INTEGRATOR_PATH), BRUME_OK);
    brume_scene_release(plain);
}

TEST_MAIN(imagemap_is_pbrt_lookup_of_decoded_bytes, scale_mix_and_checkerboard_follow_their_formulas,
          texture_trees_checked, checkerboard_plane_under_a_sun, pbrt_checkerboard_translates_and_renders,
          pbrt_texture_refusals_name_file_and_line, json_texture_keys_checked, gpu_refuses_textures)
