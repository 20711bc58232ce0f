/* test_grid_hostile.c - the grid readers under hostile input: truncated real files, bad
 * headers and bad values end in one-line errors naming the input; and OpenVDB is opened
 * only where first needed. */
#include "test.h"

#include <stdint.h>

#include "core/error.h"
#include "density/density.h"
#include "io/grid_io.h"

#define DATA(f) BRUME_DATA_DIR "/" f

static void expect_error(const void *bytes, size_t n, const char *name, const density_load_options *o, const char *why)
{
    density *d = density_load_memory(bytes, n, name, o);
    if (d)
        TEST_FAIL("%s (%zu bytes): loaded, expected an error (%s)", name, n, why);
    const char *m = err_message();
    ASSERT_CONTAINS(m, name);
    ASSERT_TRUE(!strchr(m, '\n'));
    if (why)
        ASSERT_CONTAINS(m, why);
}

TEST(hostile_truncated_real_files)
{
    const char *files[] = {"spiral.df3", "cloud64.raw", "box_fog_21cube.vdb", "wdas_cloud_sixteenth.vdb"};
    density_load_options o;
    density_load_options_default(&o);
    o.raw_dims[0] = o.raw_dims[1] = o.raw_dims[2] = 64;
    for (int fi = 0; fi < 4; fi++) {
        if (fi >= 2 && !grid_have_openvdb())
            continue;
        char path[512];
        snprintf(path, sizeof path, "%s/%s", BRUME_DATA_DIR, files[fi]);
        size_t n;
        unsigned char *b = (unsigned char *)test_slurp(path, &n);
        size_t cuts[] = {0, 1, 5, 7, 16, 100, n / 3, n / 2, n - 100, n - 1};
        for (size_t c = 0; c < sizeof cuts / sizeof *cuts; c++)
            expect_error(b, cuts[c], files[fi], &o, NULL);
        free(b);
    }
    /* .vol and .nvdb made from the real data, truncated */
    density *d = density_load_file(DATA("spiral.df3"), NULL);
    const char *formats[] = {"t.vol", "t.nvdb"};
    for (int fi = 0; fi < (grid_have_openvdb() ? 2 : 1); fi++) {
        const char *p = test_tmp_path(formats[fi]);
        ASSERT_EQ_INT(density_write_file(d, p, GRID_FORMAT_AUTO), BRUME_OK);
        size_t n;
        unsigned char *b = (unsigned char *)test_slurp(p, &n);
        size_t cuts[] = {0, 3, 15, 47, 100, 191, 800, n / 2, n - 1};
        for (size_t c = 0; c < sizeof cuts / sizeof *cuts; c++)
            expect_error(b, cuts[c], formats[fi], NULL, NULL);
        free(b);
        remove(p);
    }
    density_release(d);
}

TEST(hostile_headers)
{
    unsigned char vol[48 + 8] = {'V', 'O', 'L', 3, 1, 0, 0, 0};
    /* wrong magic */
    expect_error("XOL\3", 4, "a.vol", NULL, "magic");
    expect_error("NanoVDB1-not-a-grid-head", 24, "a.nvdb", NULL, "magic");
    expect_error("hello world, not a grid", 23, "x.bin", NULL, "unknown grid format");
    /* overflowing and oversized dimensions */
    int32_t big = 0x7fffffff;
    for (int a = 0; a < 3; a++)
        memcpy(vol + 8 + 4 * a, &big, 4);
    vol[20] = 1;
    expect_error(vol, sizeof vol, "big.vol", NULL, "overflow");
    int32_t mid = 2000;
    for (int a = 0; a < 3; a++)
        memcpy(vol + 8 + 4 * a, &mid, 4);
    expect_error(vol, sizeof vol, "mid.vol", NULL, "memory limit");
    int32_t neg = -5;
    memcpy(vol + 8, &neg, 4);
    expect_error(vol, sizeof vol, "neg.vol", NULL, "out of range");
    density_load_options o;
    density_load_options_default(&o);
    o.raw_dims[0] = o.raw_dims[1] = o.raw_dims[2] = 1 << 30;
    expect_error(vol, 8, "big.raw", &o, "overflow");
    o.raw_dims[0] = o.raw_dims[1] = o.raw_dims[2] = 64;
    o.max_memory = 1000;
    expect_error(vol, 8, "limit.raw", &o, "memory limit");
    unsigned char df3[6] = {0xff, 0xff, 0xff, 0xff, 0xff, 0xff};
    expect_error(df3, 6, "huge.df3", NULL, "memory limit");
}

TEST(hostile_values)
{
    float v[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    density_load_options o;
    density_load_options_default(&o);
    o.raw_dims[0] = o.raw_dims[1] = o.raw_dims[2] = 2;
    float bad[3] = {NAN, INFINITY, -0.5f};
    for (int b = 0; b < 3; b++) {
        v[6] = bad[b];
        expect_error(v, sizeof v, "bad.raw", &o, "voxel 6 (0, 1, 1)");
    }
    v[6] = 1e38f;
    o.scale = 1e10; /* finite values that the scale pushes to infinity */
    expect_error(v, sizeof v, "scaled.raw", &o, "voxel 6");
    /* NaN in a .nvdb, written through the dense path then patched */
    if (!grid_have_openvdb())
        return;
    float *g = calloc(8 * 8 * 8, sizeof *g);
    g[3 + 8 * (2 + 8 * 1)] = 0.75f;
    density *d = density_new_grid(8, 8, 8, g, (box3){v3(0, 0, 0), v3(1, 1, 1)}, GRID_NEAREST);
    const char *p = test_tmp_path("nan.nvdb");
    ASSERT_EQ_INT(density_write_file(d, p, GRID_FORMAT_AUTO), BRUME_OK);
    density_release(d);
    size_t n;
    unsigned char *b = (unsigned char *)test_slurp(p, &n);
    remove(p);
    float q = 0.75f, nan = NAN;
    int patched = 0;
    for (size_t i = 0; i + 4 <= n; i += 4)
        if (memcmp(b + i, &q, 4) == 0) {
            memcpy(b + i, &nan, 4);
            patched++;
        }
    ASSERT_TRUE(patched >= 1);
    expect_error(b, n, "nan.nvdb", NULL, "need finite");
    free(b);
}

/* OpenVDB is opened when first needed, not linked (io/grid_vdb.h): a fresh test process
 * holds neither the module nor libopenvdb; reading a .vdb opens them in the sandbox's child
 * only, so this process still holds neither; a writer opens them here. */
TEST(openvdb_opened_on_first_use)
{
    ASSERT_TRUE(!test_mapped("libbrume-openvdb") && !test_mapped("libopenvdb"));
    if (!grid_have_openvdb())
        return;
    gridvdb_info *gi = NULL;
    int count = 0;
    if (grid_list_file(DATA("box_fog_21cube.vdb"), 0, &gi, &count) != BRUME_OK)
        TEST_FAIL("%s", err_message());
    ASSERT_TRUE(count >= 1);
    free(gi);
    ASSERT_TRUE(!test_mapped("libbrume-openvdb") && !test_mapped("libopenvdb"));
    gridvdb_writer *w = gridvdb_writer_new();
    if (!w)
        TEST_FAIL("%s", err_message());
    gridvdb_writer_free(w);
    ASSERT_TRUE(test_mapped("libbrume-openvdb.so") && test_mapped("libopenvdb"));
}

TEST_MAIN(hostile_truncated_real_files, hostile_headers, hostile_values, openvdb_opened_on_first_use)
