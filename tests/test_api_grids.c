/* test_api_grids.c - brume.h's grid files, through the public API as `brume info`, `convert`
 * and `gen` use them: formats by name and by file, a density written and read back, its
 * info, the grids of a file, a sequence's extent, the generators' memory bounds, and the
 * message formatter the tool shares with the library. */
#include "test.h"

#include <stdarg.h>
#include <stdint.h>

#include "brume.h"

TEST(formats_by_name_and_by_file)
{
    brume_grid_format f = BRUME_GRID_FORMAT_RAW;
    ASSERT_TRUE(brume_grid_format_from_name("vdb", &f) && f == BRUME_GRID_FORMAT_VDB);
    ASSERT_TRUE(brume_grid_format_from_name("vol", &f) && f == BRUME_GRID_FORMAT_VOL);
    ASSERT_TRUE(!brume_grid_format_from_name("tiff", &f) && f == BRUME_GRID_FORMAT_VOL); /* unchanged */
    ASSERT_TRUE(!brume_grid_format_from_name(NULL, &f));
    ASSERT_EQ_STR(brume_grid_format_name(BRUME_GRID_FORMAT_DF3), "df3");
    ASSERT_TRUE(brume_grid_format_name((brume_grid_format)99) == NULL);
    ASSERT_EQ_INT(brume_grid_format_of("a/b/cloud.nvdb"), BRUME_GRID_FORMAT_NVDB);
    ASSERT_EQ_INT(brume_grid_format_of("no-such-file"), BRUME_GRID_FORMAT_AUTO);
    /* a .vol renamed without its extension is known by its magic number */
    brume_context *ctx = brume_context_new();
    const float v[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    const double box[6] = {0, 0, 0, 2, 2, 2};
    brume_density *d = NULL;
    ASSERT_EQ_INT(brume_density_new_array(ctx, v, 2, 2, 2, box, BRUME_GRID_TRILINEAR, NULL, NULL, &d), BRUME_OK);
    const char *vol = test_tmp_path("magic.vol"), *bare = test_tmp_path("magic-bare");
    remove(vol);
    remove(bare);
    ASSERT_EQ_INT(brume_density_write(ctx, d, vol, BRUME_GRID_FORMAT_AUTO), BRUME_OK);
    ASSERT_EQ_INT(rename(vol, bare), 0);
    ASSERT_EQ_INT(brume_grid_format_of(bare), BRUME_GRID_FORMAT_VOL);
    remove(bare);
    brume_density_release(d);
    brume_context_release(ctx);
}

/* A grid written as .vol and read back holds the same voxels and box; its info says so. */
TEST(density_written_reads_back_with_its_info)
{
    brume_context *ctx = brume_context_new();
    float v[3 * 2 * 4];
    for (int i = 0; i < 24; i++)
        v[i] = 0.25f * (float)i;
    const double box[6] = {-1, 0, 2, 2, 1, 6};
    brume_density *d = NULL, *back = NULL;
    ASSERT_EQ_INT(brume_density_new_array(ctx, v, 3, 2, 4, box, BRUME_GRID_TRILINEAR, NULL, NULL, &d), BRUME_OK);
    const char *path = test_tmp_path("written.vol");
    remove(path);
    ASSERT_EQ_INT(brume_density_write(ctx, d, path, BRUME_GRID_FORMAT_AUTO), BRUME_OK);
    ASSERT_EQ_INT(brume_density_load(ctx, path, NULL, &back), BRUME_OK);
    brume_density_info in;
    ASSERT_EQ_INT(brume_density_get_info(ctx, back, &in), BRUME_OK);
    ASSERT_TRUE(!in.sparse);
    ASSERT_EQ_INT(in.dims[0], 3);
    ASSERT_EQ_INT(in.dims[1], 2);
    ASSERT_EQ_INT(in.dims[2], 4);
    for (int k = 0; k < 6; k++)
        ASSERT_NEAR(in.bounds[k], box[k], 1e-6);
    ASSERT_NEAR(in.rho_min, 0.0, 0.0);
    ASSERT_NEAR(in.rho_max, 0.25 * 23, 1e-6);
    ASSERT_EQ_INT((int)in.active_voxels, 23); /* every voxel but the zero one */
    ASSERT_NEAR(in.voxel_to_world[0], 1.0, 1e-9); /* (2 - -1) / 3 world units per voxel in x */
    ASSERT_NEAR(in.voxel_to_world[3], -1.0, 1e-9);
    ASSERT_TRUE(in.memory_bytes >= 24 * sizeof(float));
    /* a file of another kind is never replaced */
    const char *notes = test_tmp_path("notes.vol");
    test_write_file(notes, "my notes\n");
    ASSERT_TRUE(brume_density_write(ctx, d, notes, BRUME_GRID_FORMAT_AUTO) != BRUME_OK);
    size_t n;
    char *kept = test_slurp(notes, &n);
    ASSERT_EQ_STR(kept, "my notes\n");
    free(kept);
    ASSERT_EQ_INT(brume_density_write(ctx, d, path, (brume_grid_format)42), BRUME_ERROR_RANGE);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "format");
    remove(notes);
    remove(path);
    brume_density_release(d);
    brume_density_release(back);
    brume_context_release(ctx);
}

/* Two frames of different boxes and peaks: the extent is their union and the larger peak. */
TEST(sequence_extent_spans_the_frames)
{
    brume_context *ctx = brume_context_new();
    const float a[1] = {2.0f}, b[1] = {5.0f};
    const double ba[6] = {0, 0, 0, 1, 1, 1}, bb[6] = {-3, 0.5, 0, 0.5, 4, 2};
    brume_density *da = NULL, *db = NULL;
    ASSERT_EQ_INT(brume_density_new_array(ctx, a, 1, 1, 1, ba, BRUME_GRID_NEAREST, NULL, NULL, &da), BRUME_OK);
    ASSERT_EQ_INT(brume_density_new_array(ctx, b, 1, 1, 1, bb, BRUME_GRID_NEAREST, NULL, NULL, &db), BRUME_OK);
    char p0[4096], p1[4096], pattern[4096];
    snprintf(p0, sizeof p0, "%s", test_tmp_path("ext_0001.vol"));
    snprintf(p1, sizeof p1, "%s", test_tmp_path("ext_0002.vol"));
    snprintf(pattern, sizeof pattern, "%s", test_tmp_path("ext_%04d.vol"));
    remove(p0);
    remove(p1);
    ASSERT_EQ_INT(brume_density_write(ctx, da, p0, BRUME_GRID_FORMAT_AUTO), BRUME_OK);
    ASSERT_EQ_INT(brume_density_write(ctx, db, p1, BRUME_GRID_FORMAT_AUTO), BRUME_OK);
    double bounds[6], rho_max = 0.0;
    ASSERT_EQ_INT(brume_grid_sequence_extent(ctx, pattern, 1, 2, NULL, bounds, &rho_max), BRUME_OK);
    const double want[6] = {-3, 0, 0, 1, 4, 2};
    for (int k = 0; k < 6; k++)
        ASSERT_NEAR(bounds[k], want[k], 1e-6);
    ASSERT_NEAR(rho_max, 5.0, 0.0);
    ASSERT_EQ_INT(brume_grid_sequence_extent(ctx, pattern, 1, 3, NULL, bounds, &rho_max), BRUME_ERROR_IO);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "ext_0003.vol");
    ASSERT_EQ_INT(brume_grid_sequence_extent(ctx, pattern, 2, 1, NULL, bounds, &rho_max), BRUME_ERROR_RANGE);
    remove(p0);
    remove(p1);
    brume_density_release(da);
    brume_density_release(db);
    brume_context_release(ctx);
}

/* The generators refuse, before any work, a request whose grids could exceed the memory
 * budget: a 2048-voxel flame could hold 2048 x 1024 x 1024 voxels in two grids, 17 GiB. */
TEST(generators_keep_to_the_memory_budget)
{
    brume_context *ctx = brume_context_new();
    brume_fire fire;
    brume_fire_default(&fire);
    ASSERT_EQ_INT(fire.resolution, 128);
    ASSERT_NEAR(brume_fire_rise(&fire), 0.0, 0.0);
    fire.time = 3.0; /* 1 world unit per second without an updraft: 3 / height 2 */
    ASSERT_NEAR(brume_fire_rise(&fire), 1.5, 1e-12);
    const char *out = test_tmp_path("fire-budget.nvdb");
    remove(out);
    brume_grid_gen_result r;
    fire.resolution = 2048;
    ASSERT_EQ_INT(brume_grid_gen_fire(ctx, &fire, out, &r), BRUME_ERROR_OUT_OF_MEMORY);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "fire.resolution 2048");
    ASSERT_CONTAINS(brume_context_last_error(ctx), "4096 MiB");
    fire.resolution = 64;
    fire.max_memory_mb = 0.5; /* 64 x 32 x 32 voxels in two grids take up to 0.6 MiB */
    ASSERT_EQ_INT(brume_grid_gen_fire(ctx, &fire, out, &r), BRUME_ERROR_OUT_OF_MEMORY);
    fire.resolution = 4;
    ASSERT_EQ_INT(brume_grid_gen_fire(ctx, &fire, out, &r), BRUME_ERROR_RANGE);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "fire.resolution");
    ASSERT_TRUE(!test_exists(out));
    fire.resolution = 32;
    fire.max_memory_mb = 0.0;
    if (brume_grid_have_openvdb()) {
        ASSERT_EQ_INT(brume_grid_gen_fire(ctx, &fire, out, &r), BRUME_OK);
        ASSERT_TRUE(r.active_voxels > 0 && r.box[1] == 32 && r.box[0] == 16);
        brume_grid_entry e[4];
        int n = 0;
        ASSERT_EQ_INT(brume_grid_file_list(ctx, out, NULL, e, 4, &n), BRUME_OK);
        ASSERT_EQ_INT(n, 2);
        ASSERT_EQ_STR(e[0].name, "density");
        ASSERT_EQ_INT((long long)e[0].active_voxels, (long long)r.active_voxels);
        ASSERT_EQ_STR(e[1].name, "temperature");
        /* upsampled 16 times per axis, the flame needs more than 4 MiB */
        brume_grid_file_options o;
        brume_grid_file_options_default(&o);
        o.max_memory_mb = 4.0; /* the flame file (2.4 MiB) loads; its upsampling needs more */
        const char *up = test_tmp_path("fire-up.nvdb");
        ASSERT_EQ_INT(brume_grid_gen_upres(ctx, out, &o, 16, 1, 0.5, up, &r), BRUME_ERROR_OUT_OF_MEMORY);
        ASSERT_CONTAINS(brume_context_last_error(ctx), "factor 16");
        ASSERT_TRUE(!test_exists(up));
        remove(out);
    } else {
        ASSERT_EQ_INT(brume_grid_gen_fire(ctx, &fire, out, &r), BRUME_ERROR_UNSUPPORTED);
    }
    brume_context_release(ctx);
}

static void format(char *out, size_t n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    brume_vformat_message(out, n, fmt, ap);
    va_end(ap);
}

/* The tool's messages are formatted as the library's: control characters escaped. */
TEST(messages_escape_control_characters)
{
    char out[64];
    format(out, sizeof out, "%s: %d", "a\nb\x1b[2J", 7);
    ASSERT_TRUE(strchr(out, '\n') == NULL && strchr(out, '\x1b') == NULL);
    ASSERT_CONTAINS(out, ": 7");
    format(out, 4, "%s", "abcdef");
    ASSERT_EQ_INT((int)strlen(out), 3);
    format(NULL, 8, "x"); /* NULL out: nothing written, no crash */
}

TEST_MAIN(formats_by_name_and_by_file, density_written_reads_back_with_its_info, sequence_extent_spans_the_frames,
          generators_keep_to_the_memory_budget, messages_escape_control_characters)
