/* test_sparse.c - sparse volumes read whole: multi-grid .vdb files written here through
 * OpenVDB (vdb_puffs.h), grids chosen by name, a 1200^3 index box rendered under a 512 MB
 * address-space limit, NanoVDB against dense and its lookup cache, and hostile .vdb files
 * that must end in one-line errors within their time limit. Majorants and the furnace are
 * in test_sparse_majorants.c, the fields beside density and brume gen in
 * test_sparse_fields.c. */
#include "test.h"

#include <stdint.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "brume.h"
#include "core/error.h"
#include "core/rng.h"
#include "density/density.h"
#include "io/grid_io.h"
#include "io/grid_vdb.h"
#include "vdb_puffs.h"

#define DATA(f) BRUME_DATA_DIR "/" f

/* Values at voxel centres (trilinear there gives the voxel exactly) of both puffs and of
 * empty space between them. */
static void check_puff_values(const density *d, double (*f)(int, int, int))
{
    rng g = rng_make(5, 0, 0);
    for (int n = 0; n < 400; n++) {
        int p = n & 1;
        int i = puff_c[p][0] + (int)(rng_next(&g) * 15) - 7, j = puff_c[p][1] + (int)(rng_next(&g) * 15) - 7,
            k = puff_c[p][2] + (int)(rng_next(&g) * 15) - 7;
        ASSERT_NEAR(density_eval(d, centre(i, j, k)), f(i, j, k), 1e-6 * fabs(f(i, j, k)) + 1e-9);
    }
    ASSERT_NEAR(density_eval(d, centre(600, 610, 620)), 0.0, 0);
}

static double colour_r(int i, int j, int k)
{
    float c[3];
    puff_colour(i, j, k, c);
    return puff_density(i, j, k) > 0 ? c[0] : 0.0;
}
static double colour_b(int i, int j, int k)
{
    float c[3];
    puff_colour(i, j, k, c);
    return puff_density(i, j, k) > 0 ? c[2] : 0.0;
}

static void check_named_grids(const char *path)
{
    density_load_options o;
    density_load_options_default(&o);
    o.filter = GRID_NEAREST;
    density *d = density_load_file(path, &o); /* default: the grid named density */
    if (!d)
        TEST_FAIL("%s", err_message());
    density_info in;
    density_get_info(d, &in);
    ASSERT_EQ_INT(in.kind, DENSITY_NANOVDB);
    for (int a = 0; a < 3; a++)
        ASSERT_TRUE(in.n[a] > 1200);
    ASSERT_TRUE(in.memory_bytes < ((size_t)8 << 20)); /* sparse: far from 1218^3 floats (7 GB) */
    check_puff_values(d, puff_density);
    density_release(d);

    snprintf(o.grid, sizeof o.grid, "temperature");
    d = density_load_file(path, &o);
    if (!d)
        TEST_FAIL("%s", err_message());
    check_puff_values(d, puff_temperature);
    density_release(d);

    snprintf(o.grid, sizeof o.grid, "Cd");
    density *rgb[3];
    if (!density_load_file_fields(path, &o, 3, rgb))
        TEST_FAIL("%s", err_message());
    check_puff_values(rgb[0], colour_r);
    check_puff_values(rgb[2], colour_b);
    for (int c = 0; c < 3; c++)
        density_release(rgb[c]);

    /* a vec3 grid where a float grid is needed, a missing name: errors naming file and grids */
    ASSERT_TRUE(!density_load_file(path, &o));
    ASSERT_CONTAINS(err_message(), path);
    ASSERT_CONTAINS(err_message(), "\"Cd\"");
    ASSERT_CONTAINS(err_message(), "vec3s");
    ASSERT_TRUE(!strchr(err_message(), '\n'));
    snprintf(o.grid, sizeof o.grid, "flame");
    ASSERT_TRUE(!density_load_file(path, &o));
    ASSERT_CONTAINS(err_message(), path);
    ASSERT_CONTAINS(err_message(), "\"flame\"");
    ASSERT_CONTAINS(err_message(), "\"temperature\"");
    ASSERT_CONTAINS(err_message(), "\"Cd\"");

    gridvdb_info *gi;
    int count;
    if (grid_list_file(path, 0, &gi, &count) != BRUME_OK)
        TEST_FAIL("%s", err_message());
    ASSERT_EQ_INT(count, 3);
    unsigned long long active = 0;
    for (int p = 0; p < 2; p++)
        for (int k = -PUFF_R; k <= PUFF_R; k++)
            for (int j = -PUFF_R; j <= PUFF_R; j++)
                for (int i = -PUFF_R; i <= PUFF_R; i++)
                    active += puff_density(puff_c[p][0] + i, puff_c[p][1] + j, puff_c[p][2] + k) > 0;
    for (int q = 0; q < 3; q++) {
        int g = 0;
        while (g < 2 && strcmp(gi[g].name, all_names[q]) != 0)
            g++;
        ASSERT_EQ_STR(gi[g].name, all_names[q]);
        ASSERT_EQ_STR(gi[g].type, q == 2 ? "vec3s" : "float");
        ASSERT_EQ_STR(gi[g].cls, "fog volume");
        ASSERT_EQ_INT(gi[g].active, active);
        ASSERT_EQ_INT(gi[g].bbmin[0], puff_c[0][0] - PUFF_R);
        ASSERT_EQ_INT(gi[g].bbmax[2], puff_c[1][2] + PUFF_R);
        ASSERT_TRUE(gi[g].nano_bytes > 0 && gi[g].nano_bytes < ((unsigned long long)4 << 20));
        if (q == 0)
            ASSERT_NEAR(gi[g].vmax, 1.25, 1e-6); /* second puff's centre */
    }
    free(gi);
}

TEST(vdb_named_grids)
{
    if (!grid_have_openvdb())
        return;
    const char *path = test_tmp_path("puffs.vdb");
    write_puffs(path, all_names, 0);
    check_named_grids(path);
    /* .vdb to .nvdb keeps every grid and its name */
    const char *nv = test_tmp_path("puffs.nvdb");
    if (grid_convert_vdb_to_nvdb(path, nv, NULL) != BRUME_OK)
        TEST_FAIL("%s", err_message());
    check_named_grids(nv);
    /* and --grid keeps one */
    if (grid_convert_vdb_to_nvdb(path, nv, "temperature") != BRUME_OK)
        TEST_FAIL("%s", err_message());
    gridvdb_info *gi;
    int count;
    ASSERT_TRUE(grid_list_file(nv, 0, &gi, &count) == BRUME_OK);
    ASSERT_EQ_INT(count, 1);
    ASSERT_EQ_STR(gi[0].name, "temperature");
    free(gi);
    unlink(path);
    unlink(nv);
}

/* Several float grids and none named density: an error that lists them, never a pick. */
TEST(vdb_ambiguous_float_grids)
{
    if (!grid_have_openvdb())
        return;
    const char *path = test_tmp_path("smoke.vdb");
    const char *const names[3] = {"smoke", "temperature", NULL};
    write_puffs(path, names, 0);
    ASSERT_TRUE(!density_load_file(path, NULL));
    ASSERT_CONTAINS(err_message(), path);
    ASSERT_CONTAINS(err_message(), "\"smoke\"");
    ASSERT_CONTAINS(err_message(), "\"temperature\"");
    /* `brume info` lists them instead */
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "%s info %s > %s.txt 2>&1", BRUME_EXE, path, path);
    ASSERT_EQ_INT(test_system(cmd), 0);
    char txt[1024];
    snprintf(txt, sizeof txt, "%s.txt", path);
    size_t n;
    char *out = test_slurp(txt, &n);
    ASSERT_CONTAINS(out, "smoke");
    ASSERT_CONTAINS(out, "temperature");
    ASSERT_CONTAINS(out, "fog volume");
    free(out);
    /* the only float grid is the default */
    const char *const one[3] = {NULL, "heat", "Cd"};
    write_puffs(path, one, 0);
    density *d = density_load_file(path, NULL);
    if (!d)
        TEST_FAIL("%s", err_message());
    check_puff_values(d, puff_temperature);
    density_release(d);
    unlink(path);
    unlink(txt);
}

/* The 1218^3 index box would need 7 GB dense; sparse it loads and renders in a process
 * limited to 512 MB of address space. */
TEST(sparse_big_box_under_512mb)
{
    if (!grid_have_openvdb())
        return;
    const char *path = test_tmp_path("big.vdb");
    write_puffs(path, all_names, 0);
    grid_before_fork(); /* no idle library thread holds a lock the child needs */
    pid_t pid = fork();
    ASSERT_TRUE(pid >= 0);
    if (pid == 0) {
        struct rlimit r = {(rlim_t)512 << 20, (rlim_t)512 << 20};
#if !defined(__SANITIZE_ADDRESS__) /* AddressSanitizer's shadow needs terabytes of address space */
        if (setrlimit(RLIMIT_AS, &r) != 0)
            _exit(2);
#else
        (void)r;
#endif
        char json[2048];
        /* looking at the far puff, at (12.13, 12.13, 12.13), from +z */
        snprintf(json, sizeof json,
                 "{\"camera\": {\"position\": [12.13, 12.13, 14], \"look_at\": [12.13, 12.13, 12.13], \"fov\": 5},"
                 " \"background\": 1.0,"
                 " \"media\": [{\"sigma_a\": 20, \"sigma_s\": 0, \"density\": {\"type\": \"grid\", \"file\": \"%s\"}}],"
                 " \"render\": {\"width\": 16, \"height\": 16, \"spp\": 4, \"threads\": 1}}",
                 path);
        brume_image *img = test_render_json(json, 1);
        const float *px = brume_image_pixels(img);
        /* the centre is darkened by the puff (optical depth about 20 x 0.12 x 0.9), a corner is not */
        int c = 4 * (8 * 16 + 8);
        int ok = px[c] < 0.5f && px[0] > 0.99f;
        fprintf(stderr, "centre %g, corner %g\n", (double)px[c], (double)px[0]);
        brume_image_release(img);
        _exit(ok ? 0 : 3);
    }
    int st = 0;
    waitpid(pid, &st, 0);
    unlink(path);
    ASSERT_TRUE(WIFEXITED(st));
    ASSERT_EQ_INT(WEXITSTATUS(st), 0);
}

/* NanoVDB and dense paths agree: the Disney cloud read sparse, written dense (raw), read
 * again; lookups at random points match for both filters. */
TEST(nanovdb_matches_dense)
{
    if (!grid_have_openvdb())
        return;
    for (int f = 0; f < 2; f++) {
        density_load_options o;
        density_load_options_default(&o);
        o.filter = f ? GRID_TRILINEAR : GRID_NEAREST;
        density *nano = density_load_file(DATA("wdas_cloud_sixteenth.vdb"), &o);
        if (!nano)
            TEST_FAIL("%s", err_message());
        ASSERT_EQ_INT(density_get_kind(nano), DENSITY_NANOVDB);
        const char *raw = test_tmp_path("wdas.raw");
        ASSERT_TRUE(density_write_file(nano, raw, GRID_FORMAT_AUTO) == BRUME_OK);
        density *dense = density_load_file(raw, &o);
        if (!dense)
            TEST_FAIL("%s", err_message());
        ASSERT_EQ_INT(density_get_kind(dense), DENSITY_GRID);
        box3 b = density_bounds(nano);
        rng g = rng_make(7, (uint64_t)f, 0);
        int nonzero = 0;
        for (int n = 0; n < 20000; n++) {
            vec3 p = v3(b.lo.x + (b.hi.x - b.lo.x) * rng_next(&g), b.lo.y + (b.hi.y - b.lo.y) * rng_next(&g),
                        b.lo.z + (b.hi.z - b.lo.z) * rng_next(&g));
            double a = density_eval(nano, p), c = density_eval(dense, p);
            ASSERT_NEAR(a, c, 1e-6);
            nonzero += a > 0;
        }
        ASSERT_TRUE(nonzero > 1000);
        density_release(nano);
        density_release(dense);
        unlink(raw);
        char hdr[1024];
        snprintf(hdr, sizeof hdr, "%s.hdr", raw);
        unlink(hdr);
    }
}

/* The per-thread lookup cache (the path to the last leaf, one slot per grid) gives the
 * uncached values: lookups along rays at quarter-voxel steps (most share a leaf with the
 * previous one, the trilinear stencil often straddles two leaves), alternating between ten
 * NanoVDB grids, copies of two files on the same index box with different trees (the
 * Disney cloud, and the same with a slab emptied: every leaf past the slab sits elsewhere
 * in the buffer, so a leaf cached for one grid would give wrong values in the other), more
 * grids than cache slots so slots are shared and retaken, one released and reloaded
 * mid-way; each against the dense grid it was written from. */
TEST(nanovdb_cached_lookups)
{
    if (!grid_have_openvdb())
        return;
    enum { COPIES = 10 };
    density *src = density_load_file(DATA("wdas_cloud_sixteenth.vdb"), NULL);
    if (!src)
        TEST_FAIL("%s", err_message());
    density_info in;
    density_get_info(src, &in);
    const int *n = in.n;
    const size_t cells = (size_t)n[0] * (size_t)n[1] * (size_t)n[2];
    char file[2][1024];
    float *data[2];
    for (int k = 0; k < 2; k++) {
        snprintf(file[k], sizeof file[k], "%s", test_tmp_path(k ? "cache-b.nvdb" : "cache-a.nvdb"));
        data[k] = malloc(cells * sizeof(float));
        ASSERT_TRUE(data[k] != NULL);
        for (int z = 0; z < n[2]; z++)
            for (int y = 0; y < n[1]; y++)
                for (int x = 0; x < n[0]; x++)
                    data[k][(size_t)x + (size_t)n[0] * ((size_t)y + (size_t)n[1] * (size_t)z)] =
                        k && x >= 40 && x < 60 ? 0.0f : (float)density_voxel(src, x, y, z);
    }
    density_release(src);
    for (int f = 0; f < 2; f++) {
        grid_filter filter = f ? GRID_TRILINEAR : GRID_NEAREST;
        density *dense[2], *nano[COPIES];
        for (int k = 0; k < 2; k++) {
            float *copy = malloc(cells * sizeof(float));
            ASSERT_TRUE(copy != NULL);
            memcpy(copy, data[k], cells * sizeof(float));
            dense[k] = density_new_grid_affine(n[0], n[1], n[2], copy, &in.voxel_to_world, filter);
            if (!dense[k])
                TEST_FAIL("%s", err_message());
            if (f == 0)
                ASSERT_TRUE(density_write_file(dense[k], file[k], GRID_FORMAT_NVDB) == BRUME_OK);
        }
        density_load_options o;
        density_load_options_default(&o);
        o.filter = filter;
        for (int c = 0; c < COPIES; c++) {
            nano[c] = density_load_file(file[c % 2], &o);
            if (!nano[c])
                TEST_FAIL("%s", err_message());
            ASSERT_EQ_INT(density_get_kind(nano[c]), DENSITY_NANOVDB);
        }
        box3 bx = density_bounds(dense[0]);
        vec3 ext = v3_sub(bx.hi, bx.lo), mid = v3_scale(v3_add(bx.lo, bx.hi), 0.5);
        double step = 0.25 * ext.x / n[0];
        rng g = rng_make(11, (uint64_t)f, 0);
        long count = 0, nonzero = 0;
        for (int r = 0; r < 200; r++) {
            if (r == 100) { /* a released grid's slot must not serve the grid loaded after it */
                density_release(nano[3]);
                nano[3] = density_load_file(file[1], &o);
                if (!nano[3])
                    TEST_FAIL("%s", err_message());
            }
            vec3 p = v3(bx.lo.x + ext.x * rng_next(&g), bx.lo.y + ext.y * rng_next(&g), bx.lo.z + ext.z * rng_next(&g));
            vec3 d = v3_normalize(v3_sub(mid, p));
            for (int k = 0; k < 2000; k++, count++) {
                vec3 q = v3_madd(p, d, step * k);
                int c = (k / 3 + r) % COPIES; /* a few lookups per grid, then the next */
                double a = density_eval(nano[c], q), e = density_eval(dense[c % 2], q);
                if (fabs(a - e) > 1e-6)
                    TEST_FAIL("filter %d, ray %d, step %d, grid %d: cached NanoVDB %.9g, dense %.9g", f, r, k, c, a, e);
                nonzero += a > 0;
            }
        }
        ASSERT_TRUE(nonzero > count / 10);
        for (int c = 0; c < COPIES; c++)
            density_release(nano[c]);
        density_release(dense[0]);
        density_release(dense[1]);
    }
    free(data[0]);
    free(data[1]);
    unlink(file[0]);
    unlink(file[1]);
}

/* ---- hostile .vdb ------------------------------------------------------------------------------ */

/* Loads mutated bytes: must end (a field or a one-line error naming the input) within the
 * sandbox's wall-clock limit for a small input (2 x 10 s + 5 s), plus slack for the load. */
static void load_mutant(const unsigned char *b, size_t n, const char *what)
{
    density_load_options o;
    density_load_options_default(&o);
    o.format = GRID_FORMAT_VDB;
    o.max_memory = (size_t)64 << 20;
    double t0 = test_now();
    density *d = density_load_memory(b, n, "mutant.vdb", &o);
    double dt = test_now() - t0;
    if (dt > 30.0)
        TEST_FAIL("%s: took %.1f s", what, dt);
    if (d) {
        vec3 c = v3_scale(v3_add(density_bounds(d).lo, density_bounds(d).hi), 0.5);
        (void)density_eval(d, c);
        density_release(d);
        return;
    }
    const char *m = err_message();
    if (strncmp(m, "mutant.vdb: ", 12) != 0 || strchr(m, '\n'))
        TEST_FAIL("%s: bad message \"%s\"", what, m);
}

TEST(hostile_vdb_bit_flips)
{
    if (!grid_have_openvdb())
        return;
    const char *path = test_tmp_path("hostile.vdb");
    const char *const names[3] = {"density", NULL, "Cd"};
    write_puffs(path, names, 0);
    size_t n;
    unsigned char *b = (unsigned char *)test_slurp(path, &n);
    unlink(path);
    rng g = rng_make(17, 0, 0);
    int errors = 0;
    for (int k = 0; k < 60; k++) {
        unsigned char *m = malloc(n);
        memcpy(m, b, n);
        /* headers and topology first (where OpenVDB trusts counts), then anywhere */
        size_t at = k < 40 ? (size_t)(rng_next(&g) * (double)(n < 4096 ? n : 4096)) : (size_t)(rng_next(&g) * (double)n);
        m[at] ^= (unsigned char)(1u << (int)(rng_next(&g) * 8));
        char what[64];
        snprintf(what, sizeof what, "flip at byte %zu", at);
        err_clear();
        load_mutant(m, n, what);
        errors += err_message()[0] != '\0';
        free(m);
    }
    fprintf(stderr, "%d of 60 mutants refused\n", errors);
    ASSERT_TRUE(errors > 0);
    free(b);
}

/* OpenVDB trusts the counts and sizes it reads: 0x7fffffff in one of them made it loop for
 * minutes or fill gigabytes (found by fuzzing; bytes 64 to 136 of this file). The sandbox
 * ends each within its limits: a read past the end throws, the address space is bounded. */
TEST(hostile_vdb_huge_counts)
{
    if (!grid_have_openvdb())
        return;
    size_t n;
    unsigned char *b = (unsigned char *)test_slurp(DATA("box_fog_21cube.vdb"), &n);
    int tried = 0;
    /* every 4-byte word of the first 256 bytes in turn set to 0x7fffffff: counts and sizes */
    double t0 = test_now();
    for (size_t at = 0; at + 4 <= n && at < 256; at += 4) {
        unsigned char *m = malloc(n);
        memcpy(m, b, n);
        m[at] = 0xff, m[at + 1] = 0xff, m[at + 2] = 0xff, m[at + 3] = 0x7f;
        char what[64];
        snprintf(what, sizeof what, "0x7fffffff at byte %zu", at);
        load_mutant(m, n, what);
        free(m);
        tried++;
    }
    fprintf(stderr, "%d mutants in %.1f s\n", tried, test_now() - t0);
    free(b);
}

TEST_MAIN(vdb_named_grids, vdb_ambiguous_float_grids, sparse_big_box_under_512mb, nanovdb_matches_dense,
          nanovdb_cached_lookups, hostile_vdb_bit_flips, hostile_vdb_huge_counts)
