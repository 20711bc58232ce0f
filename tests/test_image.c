/* test_image.c - image files: EXR, PNG and PFM round trips, sRGB and tone curves, atomic
 * writes, and hostile input (truncated, garbage, absurd headers). */
#include "test.h"

#include <OpenEXR/openexr.h>
#include <dirent.h>
#include <png.h>
#include <stdint.h>
#include <sys/stat.h>
#include <unistd.h>

#include "brume.h"
#include "io/atomic.h"
#include "io/image_formats.h"

/* ---- helpers ------------------------------------------------------------------------------ */

/* Index of the first float of pixel (x, y) in an image of width w. */
#define IDX(w, x, y) (((size_t)(y) * (size_t)(w) + (size_t)(x)) * 4)

static brume_image *make_image(int w, int h)
{
    brume_image *img = NULL;
    ASSERT_EQ_INT(brume_image_new(NULL, w, h, &img), BRUME_OK);
    return img;
}

static long file_size(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 ? (long)sb.st_size : -1;
}

static void spit(const char *path, const void *data, size_t n)
{
    FILE *fp = fopen(path, "wb");
    ASSERT_TRUE(fp != NULL);
    ASSERT_EQ_INT(fwrite(data, 1, n, fp), n);
    ASSERT_EQ_INT(fclose(fp), 0);
}

/* Number of "<dir>/.<base>.tmp-*" files, the atomic writer's temporaries for path. */
static int count_temps(const char *path)
{
    char dir[512], prefix[512];
    const char *slash = strrchr(path, '/');
    ASSERT_TRUE(slash != NULL);
    snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    snprintf(prefix, sizeof prefix, ".%s.tmp-", slash + 1);
    DIR *d = opendir(dir);
    if (!d)
        return 0;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        if (strncmp(e->d_name, prefix, strlen(prefix)) == 0)
            n++;
    closedir(d);
    return n;
}

static void write_ok(brume_context *ctx, const brume_image *img, const char *path,
                     const brume_write_options *opts)
{
    brume_status st = brume_image_write(ctx, img, path, opts);
    if (st != BRUME_OK)
        TEST_FAIL("writing %s: %s", path, brume_context_last_error(ctx));
    ASSERT_EQ_INT(count_temps(path), 0);
}

static brume_image *read_ok(brume_context *ctx, const char *path)
{
    brume_image *img = NULL;
    brume_status st = brume_image_read(ctx, path, &img);
    if (st != BRUME_OK)
        TEST_FAIL("reading %s: %s", path, brume_context_last_error(ctx));
    ASSERT_TRUE(img != NULL);
    return img;
}

/* Reading path must fail with a parse or I/O error whose one-line message names path. */
static void read_fails(brume_context *ctx, const char *path)
{
    brume_image *img = (brume_image *)&img; /* must be reset to NULL */
    brume_status st = brume_image_read(ctx, path, &img);
    if (st == BRUME_OK)
        TEST_FAIL("reading %s (%ld bytes) succeeded, expected an error", path, file_size(path));
    ASSERT_TRUE(img == NULL);
    ASSERT_TRUE(st == BRUME_ERROR_PARSE || st == BRUME_ERROR_IO);
    const char *msg = brume_context_last_error(ctx);
    ASSERT_CONTAINS(msg, path);
    ASSERT_TRUE(strchr(msg, '\n') == NULL);
}

/* sRGB encoding, IEC 61966-2-1, written out here independently of src/image/image.c. */
static int srgb8_reference(double linear)
{
    double v = linear <= 0.0031308 ? 12.92 * linear : 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
    return (int)floor(255.0 * v + 0.5);
}

static double srgb_reference(double linear)
{
    return linear <= 0.0031308 ? 12.92 * linear : 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
}

/* ---- the image object -------------------------------------------------------------------- */

TEST(image_new_validates_size)
{
    brume_context *ctx = brume_context_new();
    const int bad[][2] = {{0, 5}, {5, 0}, {-1, 5}, {65537, 1}, {1, 65537}};
    brume_image *img = NULL;
    for (int k = 0; k < 5; k++) {
        img = (brume_image *)1;
        ASSERT_EQ_INT(brume_image_new(ctx, bad[k][0], bad[k][1], &img), BRUME_ERROR_RANGE);
        ASSERT_TRUE(img == NULL);
        ASSERT_CONTAINS(brume_context_last_error(ctx), "brume_image_new: size");
    }
    ASSERT_EQ_INT(brume_image_new(ctx, 65536, 2, &img), BRUME_OK);
    brume_context_release(ctx);
    ASSERT_EQ_INT(brume_image_width(img), 65536);
    ASSERT_EQ_INT(brume_image_height(img), 2);
    const float *p = brume_image_pixels(img);
    for (size_t i = 0; i < (size_t)65536 * 2 * 4; i++)
        ASSERT_TRUE(p[i] == 0.0f);
    ASSERT_TRUE(brume_image_pixels(img) == p);
    brume_image_release(img);
    brume_image_release(NULL);
}

/* ---- OpenEXR ------------------------------------------------------------------------------ */

/* Values that a lossy or half-float path would change: negative, huge, tiny, denormal. */
static float exr_test_value(int x, int y, int c)
{
    static const float special[] = {0.0f, -0.0f, 1.0f, -1.0f, 3.0e38f, -2.5e37f, 1.0e-30f,
                                    1.0e-40f /* denormal */, 65504.0f, 123456.789f, 0.1f, -7.25e-5f};
    int i = (x * 7 + y * 13 + c * 5) % 40;
    if (i < (int)(sizeof special / sizeof special[0]))
        return special[i];
    return (float)sin(0.37 * x + 1.3 * y + 2.1 * c) * powf(10.0f, (float)((x + y + c) % 9 - 4));
}

TEST(exr_round_trip_exact)
{
    brume_context *ctx = brume_context_new();
    const int w = 37, h = 23; /* non-square, not a multiple of the 16-line ZIP chunk */
    brume_image *img = make_image(w, h);
    float *p = brume_image_pixels(img);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 4; c++)
                p[IDX(w, x, y) + (size_t)c] = exr_test_value(x, y, c);
    const char *path = test_tmp_path("rt.exr");
    write_ok(ctx, img, path, NULL);
    brume_image *back = read_ok(ctx, path);
    ASSERT_EQ_INT(brume_image_width(back), w);
    ASSERT_EQ_INT(brume_image_height(back), h);
    const float *q = brume_image_pixels(back);
    for (size_t i = 0; i < (size_t)w * (size_t)h * 4; i++)
        if (memcmp(&p[i], &q[i], sizeof(float)) != 0)
            TEST_FAIL("pixel %zu channel %zu: wrote %.9g, read %.9g", i / 4, i % 4, (double)p[i], (double)q[i]);

    /* The file itself: one scanline part, ZIP, four FLOAT channels (sorted A, B, G, R). */
    exr_context_t f = NULL;
    ASSERT_EQ_INT(exr_start_read(&f, path, NULL), EXR_ERR_SUCCESS);
    exr_compression_t comp;
    ASSERT_EQ_INT(exr_get_compression(f, 0, &comp), EXR_ERR_SUCCESS);
    ASSERT_EQ_INT(comp, EXR_COMPRESSION_ZIP);
    const exr_attr_chlist_t *chl = NULL;
    ASSERT_EQ_INT(exr_get_channels(f, 0, &chl), EXR_ERR_SUCCESS);
    ASSERT_EQ_INT(chl->num_channels, 4);
    const char *names[4] = {"A", "B", "G", "R"};
    for (int c = 0; c < 4; c++) {
        ASSERT_EQ_STR(chl->entries[c].name.str, names[c]);
        ASSERT_EQ_INT(chl->entries[c].pixel_type, EXR_PIXEL_FLOAT);
    }
    exr_finish(&f);
    remove(path);
    brume_image_release(img);
    brume_image_release(back);
    brume_context_release(ctx);
}

/* A file as another program might write it: HALF R, G, B and no A, written here with the
 * core API directly. The reader must convert half to float and set A = 1. */
TEST(exr_reads_half_rgb_without_alpha)
{
    const int w = 5, h = 3;
    /* half bit patterns: 1.0, 0.5, -1.25, 2.0, 0.0 */
    static const uint16_t hv[5] = {0x3C00, 0x3800, 0xBD00, 0x4000, 0x0000};
    static const float fv[5] = {1.0f, 0.5f, -1.25f, 2.0f, 0.0f};
    uint16_t pix[3][5][3]; /* y, x, RGB */
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 3; c++)
                pix[y][x][c] = hv[(x + 2 * y + c) % 5];

    const char *path = test_tmp_path("half.exr");
    exr_context_t f = NULL;
    int part = 0;
    ASSERT_EQ_INT(exr_start_write(&f, path, EXR_WRITE_FILE_DIRECTLY, NULL), EXR_ERR_SUCCESS);
    ASSERT_EQ_INT(exr_add_part(f, "rgb", EXR_STORAGE_SCANLINE, &part), EXR_ERR_SUCCESS);
    ASSERT_EQ_INT(exr_initialize_required_attr_simple(f, part, w, h, EXR_COMPRESSION_NONE), EXR_ERR_SUCCESS);
    const char *names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; c++)
        ASSERT_EQ_INT(exr_add_channel(f, part, names[c], EXR_PIXEL_HALF, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1),
                      EXR_ERR_SUCCESS);
    ASSERT_EQ_INT(exr_set_version(f, part, 1), EXR_ERR_SUCCESS);
    ASSERT_EQ_INT(exr_write_header(f), EXR_ERR_SUCCESS);
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    for (int y = 0; y < h; y++) { /* uncompressed: one line per chunk */
        exr_chunk_info_t ci;
        ASSERT_EQ_INT(exr_write_scanline_chunk_info(f, part, y, &ci), EXR_ERR_SUCCESS);
        if (y == 0)
            ASSERT_EQ_INT(exr_encoding_initialize(f, part, &ci, &enc), EXR_ERR_SUCCESS);
        else
            ASSERT_EQ_INT(exr_encoding_update(f, part, &ci, &enc), EXR_ERR_SUCCESS);
        for (int c = 0; c < enc.channel_count; c++) { /* sorted: B, G, R */
            int k = enc.channels[c].channel_name[0] == 'R' ? 0 : enc.channels[c].channel_name[0] == 'G' ? 1 : 2;
            enc.channels[c].encode_from_ptr = (const uint8_t *)&pix[y][0][k];
            enc.channels[c].user_pixel_stride = 6;
            enc.channels[c].user_line_stride = 6 * w;
        }
        if (y == 0)
            ASSERT_EQ_INT(exr_encoding_choose_default_routines(f, part, &enc), EXR_ERR_SUCCESS);
        ASSERT_EQ_INT(exr_encoding_run(f, part, &enc), EXR_ERR_SUCCESS);
    }
    exr_encoding_destroy(f, &enc);
    ASSERT_EQ_INT(exr_finish(&f), EXR_ERR_SUCCESS);

    brume_context *ctx = brume_context_new();
    brume_image *img = read_ok(ctx, path);
    ASSERT_EQ_INT(brume_image_width(img), w);
    ASSERT_EQ_INT(brume_image_height(img), h);
    const float *p = brume_image_pixels(img);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            for (int c = 0; c < 3; c++)
                ASSERT_NEAR(p[IDX(w, x, y) + (size_t)c], fv[(x + 2 * y + c) % 5], 0.0);
            ASSERT_NEAR(p[IDX(w, x, y) + 3], 1.0, 0.0);
        }
    remove(path);
    brume_image_release(img);
    brume_context_release(ctx);
}

/* ---- PFM ------------------------------------------------------------------------------------ */

TEST(pfm_round_trip_exact)
{
    brume_context *ctx = brume_context_new();
    const int w = 37, h = 23;
    brume_image *img = make_image(w, h);
    float *p = brume_image_pixels(img);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 4; c++)
                p[IDX(w, x, y) + (size_t)c] = exr_test_value(x, y, c);
    const char *path = test_tmp_path("rt.pfm");
    write_ok(ctx, img, path, NULL);
    ASSERT_EQ_INT(file_size(path), (long)strlen("PF\n37 23\n-1.0\n") + 37 * 23 * 12);
    brume_image *back = read_ok(ctx, path);
    ASSERT_EQ_INT(brume_image_width(back), w);
    ASSERT_EQ_INT(brume_image_height(back), h);
    const float *q = brume_image_pixels(back);
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++) {
        for (size_t c = 0; c < 3; c++)
            if (memcmp(&p[4 * i + c], &q[4 * i + c], sizeof(float)) != 0)
                TEST_FAIL("pixel %zu channel %zu: wrote %.9g, read %.9g", i, c, (double)p[4 * i + c],
                          (double)q[4 * i + c]);
        ASSERT_NEAR(q[4 * i + 3], 1.0, 0.0); /* PFM has no alpha */
    }
    remove(path);
    brume_image_release(img);
    brume_image_release(back);
    brume_context_release(ctx);
}

static void put_le(unsigned char *p, float v)
{
    uint32_t u;
    memcpy(&u, &v, 4);
    for (int i = 0; i < 4; i++)
        p[i] = (unsigned char)(u >> (8 * i));
}

static void put_be(unsigned char *p, float v)
{
    uint32_t u;
    memcpy(&u, &v, 4);
    for (int i = 0; i < 4; i++)
        p[i] = (unsigned char)(u >> (24 - 8 * i));
}

/* PFM stores the bottom row first. A 2 x 3 image whose pixel (x, y) (y = 0 at the top) has
 * R = 10 y + x, G = 100 + R, B = 200 + R, written by hand; then the writer must produce
 * the same bytes, and the reader the same pixels. */
TEST(pfm_row_order)
{
    const int w = 2, h = 3;
    const char header[] = "PF\n2 3\n-1.0\n";
    unsigned char file[sizeof header - 1 + 2 * 3 * 12];
    memcpy(file, header, sizeof header - 1);
    unsigned char *d = file + sizeof header - 1;
    for (int fy = 0; fy < h; fy++) { /* file row 0 = bottom = image row h - 1 */
        int y = h - 1 - fy;
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 3; c++, d += 4)
                put_le(d, (float)(100 * c + 10 * y + x));
    }
    brume_context *ctx = brume_context_new();
    const char *path = test_tmp_path("order.pfm");
    spit(path, file, sizeof file);
    brume_image *img = read_ok(ctx, path);
    ASSERT_EQ_INT(brume_image_width(img), w);
    ASSERT_EQ_INT(brume_image_height(img), h);
    const float *p = brume_image_pixels(img);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 3; c++)
                ASSERT_NEAR(p[IDX(w, x, y) + (size_t)c], 100 * c + 10 * y + x, 0.0);

    const char *path2 = test_tmp_path("order2.pfm");
    write_ok(ctx, img, path2, NULL);
    size_t n = 0;
    unsigned char *written = (unsigned char *)test_slurp(path2, &n);
    ASSERT_EQ_INT(n, sizeof file);
    ASSERT_TRUE(memcmp(written, file, sizeof file) == 0);
    free(written);
    remove(path);
    remove(path2);
    brume_image_release(img);
    brume_context_release(ctx);
}

/* "Pf" is gray; a positive scale means big-endian. */
TEST(pfm_gray_big_endian)
{
    const char header[] = "Pf\n3 2\n1.0\n";
    unsigned char file[sizeof header - 1 + 3 * 2 * 4];
    memcpy(file, header, sizeof header - 1);
    const float v[2][3] = {{0.25f, -2.0f, 1e-20f}, {7.0f, 0.0f, 3.5e30f}}; /* file order: bottom first */
    for (int i = 0; i < 6; i++)
        put_be(file + sizeof header - 1 + 4 * i, v[i / 3][i % 3]);
    brume_context *ctx = brume_context_new();
    const char *path = test_tmp_path("gray.pfm");
    spit(path, file, sizeof file);
    brume_image *img = read_ok(ctx, path);
    ASSERT_EQ_INT(brume_image_width(img), 3);
    ASSERT_EQ_INT(brume_image_height(img), 2);
    const float *p = brume_image_pixels(img);
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 3; x++) {
            for (int c = 0; c < 3; c++)
                ASSERT_NEAR(p[IDX(3, x, y) + (size_t)c], v[1 - y][x], 0.0);
            ASSERT_NEAR(p[IDX(3, x, y) + 3], 1.0, 0.0);
        }
    remove(path);
    brume_image_release(img);
    brume_context_release(ctx);
}

/* ---- PNG and sRGB ------------------------------------------------------------------------ */

TEST(srgb_known_values)
{
    /* By hand: 1.055 * 0.5^(1/2.4) - 0.055 = 0.73536, * 255 = 187.5 -> 188;
     * 12.92 * 0.0031308 = 0.040450, * 255 = 10.31 -> 10. */
    ASSERT_EQ_INT(srgb8_reference(0.5), 188);
    ASSERT_EQ_INT(srgb8_reference(0.0031308), 10);
    ASSERT_EQ_INT(image_encode_srgb8(0.5, NULL), 188);
    ASSERT_EQ_INT(image_encode_srgb8(0.0031308, NULL), 10);
    ASSERT_EQ_INT(image_encode_srgb8(1.0, NULL), 255);
    ASSERT_EQ_INT(image_encode_srgb8(0.0, NULL), 0);
    ASSERT_EQ_INT(image_encode_srgb8(-3.0, NULL), 0);
    ASSERT_EQ_INT(image_encode_srgb8(7.0, NULL), 255);
    ASSERT_EQ_INT(image_encode_srgb8(NAN, NULL), 0);
    ASSERT_EQ_INT(image_encode_srgb8(INFINITY, NULL), 255);
    for (int i = 0; i <= 1000; i++) {
        double v = i / 1000.0;
        ASSERT_EQ_INT(image_encode_srgb8(v, NULL), srgb8_reference(v));
    }
    /* decode inverts encode */
    for (int i = 0; i <= 255; i++)
        ASSERT_NEAR(image_srgb_encode(image_srgb_decode(i / 255.0)), i / 255.0, 1e-12);
}

/* The bytes in the file, decoded by libpng's simplified API without any conversion. */
TEST(png_file_is_srgb8)
{
    brume_context *ctx = brume_context_new();
    brume_image *img = make_image(4, 1);
    float *p = brume_image_pixels(img);
    const float lin[4] = {0.0f, 0.0031308f, 0.5f, 1.0f};
    const float alpha[4] = {0.0f, 0.5f, 0.25f, 1.0f}; /* not stored: PNG output is opaque */
    for (int i = 0; i < 4; i++) {
        p[4 * i] = p[4 * i + 1] = p[4 * i + 2] = lin[i];
        p[4 * i + 3] = alpha[i];
    }
    const char *path = test_tmp_path("srgb.png");
    write_ok(ctx, img, path, NULL);

    size_t n = 0;
    unsigned char *bytes = (unsigned char *)test_slurp(path, &n);
    int has_srgb_chunk = 0;
    for (size_t i = 0; i + 4 <= n; i++)
        has_srgb_chunk |= memcmp(bytes + i, "sRGB", 4) == 0;
    ASSERT_TRUE(has_srgb_chunk);
    free(bytes);

    png_image pi;
    memset(&pi, 0, sizeof pi);
    pi.version = PNG_IMAGE_VERSION;
    ASSERT_TRUE(png_image_begin_read_from_file(&pi, path));
    ASSERT_EQ_INT(pi.width, 4);
    ASSERT_EQ_INT(pi.height, 1);
    pi.format = PNG_FORMAT_RGBA;
    unsigned char px[16];
    ASSERT_TRUE(png_image_finish_read(&pi, NULL, px, 0, NULL));
    const int want[4] = {0, 10, 188, 255}, want_a[4] = {255, 255, 255, 255};
    for (int i = 0; i < 4; i++) {
        ASSERT_EQ_INT(px[4 * i], want[i]);
        ASSERT_EQ_INT(px[4 * i + 1], want[i]);
        ASSERT_EQ_INT(px[4 * i + 2], want[i]);
        ASSERT_EQ_INT(px[4 * i + 3], want_a[i]);
    }
    remove(path);
    brume_image_release(img);
    brume_context_release(ctx);
}

/* Values in [0, 1] come back within half an 8-bit step of their sRGB encoding; alpha is
 * not stored (opaque PNG) and reads back as 1. */
TEST(png_round_trip)
{
    brume_context *ctx = brume_context_new();
    const int w = 37, h = 23;
    brume_image *img = make_image(w, h);
    float *p = brume_image_pixels(img);
    for (size_t i = 0; i < (size_t)w * (size_t)h * 4; i++)
        p[i] = (float)((double)((i * 7919) % 1009) / 1008.0);
    const char *path = test_tmp_path("rt.png");
    write_ok(ctx, img, path, NULL);
    brume_image *back = read_ok(ctx, path);
    ASSERT_EQ_INT(brume_image_width(back), w);
    ASSERT_EQ_INT(brume_image_height(back), h);
    const float *q = brume_image_pixels(back);
    const double tol = 0.5 / 255.0 + 1e-6;
    for (size_t i = 0; i < (size_t)w * (size_t)h * 4; i++) {
        if (i % 4 == 3)
            ASSERT_NEAR(q[i], 1.0, 0.0);
        else
            ASSERT_NEAR(srgb_reference(q[i]), srgb_reference(p[i]), tol);
    }
    remove(path);
    brume_image_release(img);
    brume_image_release(back);
    brume_context_release(ctx);
}

TEST(exposure_scales_by_powers_of_two)
{
    brume_write_options plus = {1.0, BRUME_TONEMAP_CLAMP}, minus = {-2.0, BRUME_TONEMAP_CLAMP};
    int differs = 0;
    for (int i = 0; i <= 2000; i++) {
        double v = i / 2000.0;
        ASSERT_EQ_INT(image_encode_srgb8(v, &plus), image_encode_srgb8(2.0 * v, NULL));
        ASSERT_EQ_INT(image_encode_srgb8(v, &minus), image_encode_srgb8(0.25 * v, NULL));
        differs += image_encode_srgb8(v, &plus) != image_encode_srgb8(v, NULL);
    }
    ASSERT_TRUE(differs > 1000);

    /* and the PNG writer applies it */
    brume_context *ctx = brume_context_new();
    brume_image *img = make_image(1, 1);
    float *p = brume_image_pixels(img);
    p[0] = p[1] = p[2] = 0.25f;
    p[3] = 1.0f;
    const char *path = test_tmp_path("exposure.png");
    write_ok(ctx, img, path, &plus);
    brume_image *back = read_ok(ctx, path);
    ASSERT_NEAR(srgb_reference(brume_image_pixels(back)[0]), srgb_reference(0.5), 0.5 / 255.0);
    remove(path);
    brume_image_release(img);
    brume_image_release(back);
    brume_context_release(ctx);
}

TEST(filmic_curve)
{
    brume_write_options filmic = {0.0, BRUME_TONEMAP_FILMIC};
    ASSERT_EQ_INT(image_encode_srgb8(0.0, &filmic), 0);
    ASSERT_EQ_INT(image_encode_srgb8(-1.0, &filmic), 0);
    ASSERT_EQ_INT(image_encode_srgb8(NAN, &filmic), 0);
    ASSERT_EQ_INT(image_encode_srgb8(INFINITY, &filmic), 255);
    int prev = 0;
    for (int i = 0; i <= 100000; i++) { /* 0 .. 100, denser near 0 */
        double x = 100.0 * pow(i / 100000.0, 3.0);
        int v = image_encode_srgb8(x, &filmic);
        if (v < prev)
            TEST_FAIL("filmic not monotonic at %g: %d after %d", x, v, prev);
        prev = v;
        /* Narkowicz 2015, computed here independently */
        double f = (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14);
        ASSERT_EQ_INT(v, f >= 1.0 ? 255 : srgb8_reference(f));
    }
    ASSERT_EQ_INT(prev, 255);
    /* the curve compresses highlights: 1.0 no longer saturates */
    ASSERT_TRUE(image_encode_srgb8(1.0, &filmic) < 255);
    ASSERT_TRUE(image_encode_srgb8(1.0, &filmic) > 200);
}

/* The PNG writer's table gives image_encode_srgb8's byte for every float: checked float by
 * float around every bound (where a wrong bound would show), at 2^-12 of all positive floats
 * elsewhere, at the special values, and with every guess of the neighbour's code, under
 * exposures that are and are not powers of two and under the tone curve. */
TEST(srgb8_table_matches_the_function)
{
    const brume_write_options opts[4] = {
        {0.0, BRUME_TONEMAP_CLAMP}, {1.3, BRUME_TONEMAP_CLAMP}, {-2.7, BRUME_TONEMAP_CLAMP}, {0.5, BRUME_TONEMAP_FILMIC}};
    for (int o = 0; o < 4; o++) {
        image_srgb8_table t;
        image_srgb8_table_init(&t, &opts[o]);
        long checked = 0;
        for (int k = 1; k < 256; k++) {
            ASSERT_TRUE(t.first[k] > t.first[k - 1]); /* every code is reached by some float */
            for (int64_t d = -64; d <= 64; d++) {
                int64_t b = (int64_t)t.first[k] + d;
                if (b < 1 || b > 0x7f800000)
                    continue;
                uint32_t u = (uint32_t)b;
                float f;
                memcpy(&f, &u, sizeof f);
                unsigned char want = image_encode_srgb8((double)f, &opts[o]);
                if (image_srgb8_lookup(&t, f, 0) != want || image_srgb8_lookup(&t, f, 255) != want ||
                    image_srgb8_lookup(&t, f, (unsigned char)k) != want)
                    TEST_FAIL("options %d: %.9g (bits 0x%08x) gives %d by table, %d by function", o, (double)f,
                              (unsigned)u, image_srgb8_lookup(&t, f, 0), want);
                checked++;
            }
        }
        for (uint32_t u = 1; u <= 0x7f800000u - 4096u; u += 4096u) {
            float f;
            memcpy(&f, &u, sizeof f);
            ASSERT_EQ_INT(image_srgb8_lookup(&t, f, (unsigned char)(u >> 12)), image_encode_srgb8((double)f, &opts[o]));
            checked++;
        }
        const float special[] = {0.0f, -0.0f, -1.0f, -INFINITY, NAN, -NAN, INFINITY, 1e-45f, 1.0f, 3e38f};
        for (size_t i = 0; i < sizeof special / sizeof special[0]; i++)
            for (int near = 0; near < 256; near += 51)
                ASSERT_EQ_INT(image_srgb8_lookup(&t, special[i], (unsigned char)near),
                              image_encode_srgb8((double)special[i], &opts[o]));
        ASSERT_TRUE(checked > 500000);
    }
}

/* ---- dispatch ----------------------------------------------------------------------------- */

TEST(unknown_extension)
{
    brume_context *ctx = brume_context_new();
    brume_image *img = make_image(2, 2);
    const char *path = test_tmp_path("picture.xyz");
    ASSERT_EQ_INT(brume_image_write(ctx, img, path, NULL), BRUME_ERROR_UNSUPPORTED);
    char want[600];
    snprintf(want, sizeof want, "%s: unknown image format '.xyz' (use .exr, .png or .pfm)", path);
    ASSERT_EQ_STR(brume_context_last_error(ctx), want);
    ASSERT_TRUE(file_size(path) < 0);
    brume_image *out = NULL;
    ASSERT_EQ_INT(brume_image_read(ctx, path, &out), BRUME_ERROR_UNSUPPORTED);
    ASSERT_TRUE(out == NULL);

    /* extensions are case-insensitive */
    const char *upper[3] = {"upper.EXR", "upper.Png", "upper.PFM"};
    for (int i = 0; i < 3; i++) {
        const char *p = test_tmp_path(upper[i]);
        write_ok(ctx, img, p, NULL);
        brume_image *back = read_ok(ctx, p);
        brume_image_release(back);
        remove(p);
    }
    brume_write_options bad = {NAN, BRUME_TONEMAP_CLAMP};
    ASSERT_EQ_INT(brume_image_write(ctx, img, test_tmp_path("bad.png"), &bad), BRUME_ERROR_RANGE);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "exposure");
    brume_image_release(img);
    brume_context_release(ctx);
}

/* ---- atomic writes ------------------------------------------------------------------------ */

TEST(write_into_missing_folder_fails)
{
    brume_context *ctx = brume_context_new();
    brume_image *img = make_image(3, 2);
    const char *exts[3] = {"exr", "png", "pfm"};
    for (int i = 0; i < 3; i++) {
        char path[600];
        snprintf(path, sizeof path, "%s/sub/out.%s", test_tmp_path("no-such-folder"), exts[i]);
        ASSERT_EQ_INT(brume_image_write(ctx, img, path, NULL), BRUME_ERROR_IO);
        ASSERT_CONTAINS(brume_context_last_error(ctx), path);
        ASSERT_TRUE(file_size(path) < 0);
        ASSERT_TRUE(file_size(test_tmp_path("no-such-folder")) < 0);
    }
    brume_image_release(img);
    brume_context_release(ctx);
}

TEST(failed_write_keeps_old_file)
{
    /* An aborted atomic write leaves the destination as it was. */
    const char *path = test_tmp_path("keep.pfm");
    const char old[] = "the old contents";
    spit(path, old, sizeof old - 1);
    atomic_file f;
    ASSERT_EQ_INT(atomic_open(&f, path), BRUME_OK);
    ASSERT_EQ_INT(count_temps(path), 1);
    fputs("PF\n2 2\n-1.0\npartial", f.fp);
    fflush(f.fp);
    atomic_abort(&f);
    ASSERT_EQ_INT(count_temps(path), 0);
    size_t n = 0;
    unsigned char *now = (unsigned char *)test_slurp(path, &n);
    ASSERT_EQ_INT(n, sizeof old - 1);
    ASSERT_TRUE(memcmp(now, old, n) == 0);
    free(now);
    remove(path);

    /* A commit that cannot rename (the destination is a non-empty folder) fails, names the
     * path, removes its temporary file and leaves the destination alone. */
    brume_context *ctx = brume_context_new();
    brume_image *img = make_image(4, 4);
    const char *exts[3] = {"dir.exr", "dir.png", "dir.pfm"};
    for (int i = 0; i < 3; i++) {
        const char *dir = test_tmp_path(exts[i]);
        char inner[600];
        snprintf(inner, sizeof inner, "%s/inside", dir);
        ASSERT_EQ_INT(mkdir(dir, 0755), 0);
        spit(inner, old, sizeof old - 1);
        ASSERT_EQ_INT(brume_image_write(ctx, img, dir, NULL), BRUME_ERROR_IO);
        ASSERT_CONTAINS(brume_context_last_error(ctx), dir);
        ASSERT_EQ_INT(count_temps(dir), 0);
        ASSERT_EQ_INT(file_size(inner), (long)(sizeof old - 1));
        remove(inner);
        rmdir(dir);
    }
    brume_image_release(img);
    brume_context_release(ctx);
}

TEST(write_replaces_and_leaves_no_temp)
{
    brume_context *ctx = brume_context_new();
    brume_image *img = make_image(8, 8);
    const char *exts[3] = {"replace.exr", "replace.png", "replace.pfm"};
    for (int i = 0; i < 3; i++) {
        const char *path = test_tmp_path(exts[i]);
        float *p = brume_image_pixels(img);
        p[0] = 0.25f;
        write_ok(ctx, img, path, NULL); /* an image replaces only an image (docs/render-jobs.md) */
        chmod(path, 0640);
        p[0] = 0.75f;
        write_ok(ctx, img, path, NULL);
        struct stat sb;
        ASSERT_EQ_INT(stat(path, &sb), 0);
        ASSERT_EQ_INT(sb.st_mode & 0777, 0640); /* the replaced file's mode is kept */
        brume_image *back = read_ok(ctx, path);
        ASSERT_NEAR(brume_image_pixels(back)[0], 0.75, 0.01);
        brume_image_release(back);
        remove(path);
        ASSERT_EQ_INT(count_temps(path), 0);
    }
    brume_image_release(img);
    brume_context_release(ctx);
}

/* ---- hostile input -------------------------------------------------------------------------- */

TEST(truncated_files_fail)
{
    brume_context *ctx = brume_context_new();
    brume_image *img = make_image(37, 23);
    float *p = brume_image_pixels(img);
    for (size_t i = 0; i < (size_t)37 * 23 * 4; i++)
        p[i] = (float)((i * 2654435761u) % 1000) / 999.0f;
    const char *names[3] = {"full.exr", "full.png", "full.pfm"};
    const char *cut_names[3] = {"cut.exr", "cut.png", "cut.pfm"};
    for (int k = 0; k < 3; k++) {
        const char *full = test_tmp_path(names[k]);
        const char *cut = test_tmp_path(cut_names[k]);
        write_ok(ctx, img, full, NULL);
        size_t n = 0;
        unsigned char *bytes = (unsigned char *)test_slurp(full, &n);
        const size_t lengths[] = {0, 1, 4, 8, 20, n / 4, n / 2, n - 100, n - 13, n - 1};
        for (size_t j = 0; j < sizeof lengths / sizeof lengths[0]; j++) {
            ASSERT_TRUE(lengths[j] < n);
            spit(cut, bytes, lengths[j]);
            read_fails(ctx, cut);
        }
        free(bytes);
        remove(cut);
        remove(full);
    }
    brume_image_release(img);
    brume_context_release(ctx);
}

TEST(garbage_and_wrong_magic_fail)
{
    brume_context *ctx = brume_context_new();
    unsigned char junk[4096];
    uint32_t s = 12345;
    for (size_t i = 0; i < sizeof junk; i++) {
        s = s * 1664525u + 1013904223u;
        junk[i] = (unsigned char)(s >> 24);
    }
    const char *names[3] = {"junk.exr", "junk.png", "junk.pfm"};
    for (int k = 0; k < 3; k++) {
        const char *path = test_tmp_path(names[k]);
        spit(path, junk, sizeof junk);
        read_fails(ctx, path);
        /* valid magic, garbage after it */
        static const unsigned char magic[3][8] = {{0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0},
                                                  {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'},
                                                  {'P', 'F', '\n', 0, 0, 0, 0, 0}};
        memcpy(junk, magic[k], 8);
        spit(path, junk, sizeof junk);
        read_fails(ctx, path);
        remove(path);
    }
    /* a PNG named .pfm and a PFM named .exr */
    brume_image *img = make_image(2, 2);
    const char *png = test_tmp_path("real.png"), *pfm = test_tmp_path("real.pfm");
    write_ok(ctx, img, png, NULL);
    write_ok(ctx, img, pfm, NULL);
    const char *as_pfm = test_tmp_path("png-as.pfm"), *as_exr = test_tmp_path("pfm-as.exr");
    ASSERT_EQ_INT(rename(png, as_pfm), 0);
    ASSERT_EQ_INT(rename(pfm, as_exr), 0);
    read_fails(ctx, as_pfm);
    read_fails(ctx, as_exr);
    remove(as_pfm);
    remove(as_exr);
    read_fails(ctx, test_tmp_path("does-not-exist.png"));
    ASSERT_EQ_INT(brume_context_last_status(ctx), BRUME_ERROR_IO);
    brume_image_release(img);
    brume_context_release(ctx);
}

TEST(pfm_bad_headers_fail)
{
    brume_context *ctx = brume_context_new();
    const char *headers[] = {
        "PF\n100000000 100000000\n-1.0\n", /* 10^16 pixels */
        "PF\n65537 1\n-1.0\n",             /* a side too long */
        "PF\n40000 40000\n-1.0\n",         /* sides fine, 1.6e9 pixels > 2^28 */
        "PF\n99999999999999999999 2\n-1.0\n",
        "PF\n0 5\n-1.0\n",
        "PF\n-3 5\n-1.0\n",
        "PF\n4 x\n-1.0\n",
        "PF\n2 2\nnan\n",
        "PF\n2 2\ninf\n",
        "PF\n2 2\n0\n",
        "PF\n2 2\n-1.0abc\n",
        "PF\n2 2\n-1.0", /* no byte after the scale */
        "PF\n2 2\n-1.0\n\x01\x02",  /* 2 bytes of 48 */
        "P6\n2 2\n255\n",
        "",
    };
    const char *path = test_tmp_path("header.pfm");
    for (size_t i = 0; i < sizeof headers / sizeof headers[0]; i++) {
        spit(path, headers[i], strlen(headers[i]));
        read_fails(ctx, path);
        ASSERT_EQ_INT(brume_context_last_status(ctx), BRUME_ERROR_PARSE);
    }
    /* The 10^8 x 10^8 message says what is wrong. */
    spit(path, headers[0], strlen(headers[0]));
    read_fails(ctx, path);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "100000000 x 100000000");
    remove(path);
    brume_context_release(ctx);
}

TEST_MAIN(image_new_validates_size, exr_round_trip_exact, exr_reads_half_rgb_without_alpha,
          pfm_round_trip_exact, pfm_row_order, pfm_gray_big_endian, srgb_known_values,
          srgb8_table_matches_the_function, png_file_is_srgb8, png_round_trip, exposure_scales_by_powers_of_two,
          filmic_curve,
          unknown_extension, write_into_missing_folder_fails, failed_write_keeps_old_file,
          write_replaces_and_leaves_no_temp, truncated_files_fail, garbage_and_wrong_magic_fail,
          pfm_bad_headers_fail)
