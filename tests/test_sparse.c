/* test_sparse.c - sparse volumes end to end: multi-grid .vdb files written here through
 * OpenVDB, grids chosen by name, a 1200^3 index box rendered under a 512 MB address-space
 * limit, NanoVDB against dense, majorants from the tree, a furnace with a sparse grid, and
 * hostile .vdb files that must end in one-line errors within their time limit. */
#include "test.h"

#include <stdint.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "brume.h"
#include "core/error.h"
#include "core/rng.h"
#include "density/density.h"
#include "io/grid_io.h"
#include "io/grid_vdb.h"
#include "medium/blackbody.h"
#include "scene/scene.h"
#include "render/track.h"

#define DATA(f) BRUME_DATA_DIR "/" f

/* ---- files written through OpenVDB ------------------------------------------------------------ */

/* Two puffs far apart: centres (8, 8, 8) and (1213, 1213, 1213), radius 6 voxels, so the
 * active index box spans about 1218^3 voxels. Voxel size 0.01, centre of voxel 0 at 0. */
#define PUFF_R 6
static const int puff_c[2][3] = {{8, 8, 8}, {1213, 1213, 1213}};
#define VOXEL 0.01

/* The density of voxel (i, j, k): 0 outside the puffs. */
static double puff_density(int i, int j, int k)
{
    for (int p = 0; p < 2; p++) {
        double dx = i - puff_c[p][0], dy = j - puff_c[p][1], dz = k - puff_c[p][2];
        double r = sqrt(dx * dx + dy * dy + dz * dz);
        if (r <= PUFF_R)
            return (float)(0.25 + (p + 1) * 0.5 * (1.0 - r / PUFF_R));
    }
    return 0.0;
}
static double puff_temperature(int i, int j, int k) { return puff_density(i, j, k) > 0 ? 1000.0 + 10.0 * i + k : 0; }
static void puff_colour(int i, int j, int k, float c[3])
{
    c[0] = 0.2f + 0.001f * (float)i;
    c[1] = 0.5f;
    c[2] = 0.9f - 0.0005f * (float)k;
    (void)j;
}

/* Writes path through OpenVDB (as NanoVDB if nanovdb): fill adds the grids and their voxels.
 * In a child process: OpenVDB (and TBB) stay out of the test's own process, which later
 * forks the sandboxed reader. */
static void write_vdb(const char *path, int nanovdb, void (*fill)(gridvdb_writer *w, const void *user), const void *user)
{
    grid_before_fork(); /* no idle library thread holds a lock the child needs */
    pid_t pid = fork();
    ASSERT_TRUE(pid >= 0);
    if (pid == 0) {
        gridvdb_writer *w = gridvdb_writer_new();
        fill(w, user);
        _exit(gridvdb_writer_save(w, path, nanovdb) == BRUME_OK ? 0 : 1);
    }
    int st = 0;
    waitpid(pid, &st, 0);
    ASSERT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0);
}

static const double origin0[3] = {0, 0, 0};

/* The puffs, in the grids named by names ([0] density (float), [1] temperature (float),
 * [2] Cd (vec3); NULL skips one). */
static void fill_puffs(gridvdb_writer *w, const void *user)
{
    const char *const *names = user;
    int g[3];
    for (int q = 0; q < 3; q++)
        g[q] = names[q] ? gridvdb_writer_add(w, names[q], q == 2, VOXEL, origin0) : -1;
    for (int p = 0; p < 2; p++)
        for (int k = puff_c[p][2] - PUFF_R; k <= puff_c[p][2] + PUFF_R; k++)
            for (int j = puff_c[p][1] - PUFF_R; j <= puff_c[p][1] + PUFF_R; j++)
                for (int i = puff_c[p][0] - PUFF_R; i <= puff_c[p][0] + PUFF_R; i++) {
                    float v = (float)puff_density(i, j, k), t = (float)puff_temperature(i, j, k), c[3];
                    puff_colour(i, j, k, c);
                    if (v <= 0.0f)
                        continue;
                    if (g[0] >= 0)
                        gridvdb_writer_set(w, g[0], i, j, k, &v);
                    if (g[1] >= 0)
                        gridvdb_writer_set(w, g[1], i, j, k, &t);
                    if (g[2] >= 0)
                        gridvdb_writer_set(w, g[2], i, j, k, c);
                }
}

/* The puffs as .vdb (nanovdb 0) or .nvdb (1). */
static void write_puffs(const char *path, const char *const names[3], int nanovdb)
{
    write_vdb(path, nanovdb, fill_puffs, names);
}

/* "density": A (1 at (12, 12, 12)), B (0.5 at (23, 15, 15)), C (0.25 at (31, 23, 23)) */
static void fill_three_voxels(gridvdb_writer *w, const void *user)
{
    (void)user;
    int g = gridvdb_writer_add(w, "density", 0, VOXEL, origin0);
    const float a = 1.0f, b = 0.5f, c = 0.25f;
    gridvdb_writer_set(w, g, 12, 12, 12, &a);
    gridvdb_writer_set(w, g, 23, 15, 15, &b);
    gridvdb_writer_set(w, g, 31, 23, 23, &c);
}

/* "temperature": 3000 K over [-7, 7]^3 voxels of size 1 (a box covering the density's) */
static void fill_3000K(gridvdb_writer *w, const void *user)
{
    (void)user;
    int g = gridvdb_writer_add(w, "temperature", 0, 1.0, origin0);
    float t = 3000.0f;
    for (int k = -7; k <= 7; k++)
        for (int j = -7; j <= 7; j++)
            for (int i = -7; i <= 7; i++)
                gridvdb_writer_set(w, g, i, j, k, &t);
}

static const char *const all_names[3] = {"density", "temperature", "Cd"};

/* world centre of voxel (i, j, k) */
static vec3 centre(int i, int j, int k) { return v3(VOXEL * i, VOXEL * j, VOXEL * k); }

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

/* The majorant segments of r over [0, tmax]: in order, and the density at `per_seg` random
 * points of each no larger than its bound. Returns how many points had density > 0. */
static int check_segments(const density *d, ray r, double tmax, int per_seg, rng *g)
{
    majorant_iter mi;
    majorant_seg s;
    density_majorant_begin(d, r, 0, tmax, &mi);
    double last = -INFINITY;
    int positive = 0;
    while (majorant_next(&mi, &s)) {
        ASSERT_TRUE(s.t0 < s.t1 && s.t0 >= last - 1e-9);
        last = s.t1;
        for (int q = 0; q < per_seg; q++) {
            double tt = s.t0 + (s.t1 - s.t0) * rng_next(g);
            double rho = density_eval(d, ray_at(r, tt));
            if (rho > s.rho_maj)
                TEST_FAIL("rho %.9g > majorant %.9g at t %.9g on [%.9g, %.9g)", rho, s.rho_maj, tt, s.t0, s.t1);
            if (rho < s.rho_min * (1.0 - 1e-12))
                TEST_FAIL("rho %.9g < minorant %.9g at t %.9g on [%.9g, %.9g)", rho, s.rho_min, tt, s.t0, s.t1);
            positive += rho > 0;
        }
    }
    return positive;
}

/* Hierarchical majorants bound the field at random points of random rays, for both
 * filters, on the far-apart puffs and on the Disney cloud; and empty space is cheap: a ray
 * through both puffs (1200 voxels apart) takes few segments. */
static void check_majorants(const density *d, uint64_t seed, int rays, int min_positive)
{
    box3 b = density_bounds(d);
    vec3 ext = v3_sub(b.hi, b.lo);
    rng g = rng_make(seed, 0, 0);
    int positive = 0;
    for (int n = 0; n < rays; n++) {
        vec3 o = v3(b.lo.x - 0.2 * ext.x + 1.4 * ext.x * rng_next(&g), b.lo.y - 0.2 * ext.y + 1.4 * ext.y * rng_next(&g),
                    b.lo.z - 0.2 * ext.z + 1.4 * ext.z * rng_next(&g));
        vec3 t = v3(b.lo.x + ext.x * rng_next(&g), b.lo.y + ext.y * rng_next(&g), b.lo.z + ext.z * rng_next(&g));
        if (n % 4 == 0) /* through a puff or the middle: where the field is */
            t = v3_scale(v3_add(b.lo, b.hi), 0.5);
        vec3 dir = v3_normalize(v3_sub(t, o));
        positive += check_segments(d, (ray){o, dir, 0}, INFINITY, 4, &g);
    }
    ASSERT_TRUE(positive >= min_positive);
}

/* Rays through points within +-half_box/2 voxels of the points aim[] (in turn), each
 * `half_len` voxels either side: density at random points of every majorant segment must not
 * exceed its bound. Returns how many of those points had density > 0. */
static int check_near(const density *d, const vec3 *aim, int naim, double box, double half_len, uint64_t seed, int rays)
{
    rng g = rng_make(seed, 0, 0);
    int positive = 0;
    for (int n = 0; n < rays; n++) {
        vec3 a = v3_add(aim[n % naim], v3(VOXEL * box * (rng_next(&g) - 0.5), VOXEL * box * (rng_next(&g) - 0.5),
                                           VOXEL * box * (rng_next(&g) - 0.5)));
        vec3 dir = v3_normalize(v3(rng_next(&g) - 0.5, rng_next(&g) - 0.5, rng_next(&g) - 0.5));
        ray r = {v3_sub(a, v3_scale(dir, half_len * VOXEL)), dir, 0};
        positive += check_segments(d, r, 2.0 * half_len * VOXEL, 8, &g);
    }
    return positive;
}

TEST(sparse_majorants_bound)
{
    if (!grid_have_openvdb())
        return;
    const char *path = test_tmp_path("maj.vdb");
    write_puffs(path, all_names, 0);
    for (int f = 0; f < 2; f++) {
        density_load_options o;
        density_load_options_default(&o);
        o.filter = f ? GRID_TRILINEAR : GRID_NEAREST;
        o.scale = 3.7; /* majorants follow the scale, rounded up */
        density *d = density_load_file(path, &o);
        if (!d)
            TEST_FAIL("%s", err_message());
        /* rays aimed at the puffs' voxels: most points of interest are inside them */
        const vec3 aims[2] = {centre(puff_c[0][0], puff_c[0][1], puff_c[0][2]),
                              centre(puff_c[1][0], puff_c[1][1], puff_c[1][2])};
        ASSERT_TRUE(check_near(d, aims, 2, 8.0, 20.0, 3 + (uint64_t)f, 4000) > 10000);
        check_majorants(d, 11 + (uint64_t)f, 500, 0);
        /* the diagonal through both puffs: empty space between them in few segments */
        vec3 a = centre(puff_c[0][0], puff_c[0][1], puff_c[0][2]), b = centre(puff_c[1][0], puff_c[1][1], puff_c[1][2]);
        vec3 dir = v3_normalize(v3_sub(b, a));
        ray r = {v3_sub(a, v3_scale(dir, 0.2)), dir, 0};
        majorant_iter mi;
        majorant_seg s;
        int segs = 0;
        double covered = 0.0;
        density_majorant_begin(d, r, 0, INFINITY, &mi);
        while (majorant_next(&mi, &s)) {
            segs++;
            covered += s.t1 - s.t0;
        }
        fprintf(stderr, "filter %d: %d segments along the diagonal\n", f, segs);
        ASSERT_TRUE(segs < 100);
        ASSERT_TRUE(covered > v3_length(v3_sub(b, a))); /* the segments cover the way */
        density_release(d);
    }
    /* the Disney cloud's small box, with its cell grid and with the tree's walk */
    for (int f = 0; f < 4; f++) {
        density_load_options o;
        density_load_options_default(&o);
        o.filter = f % 2 ? GRID_TRILINEAR : GRID_NEAREST;
        uint64_t limit = nanovdb_set_cell_grid_limit(f < 2 ? UINT64_MAX : 0);
        density *d = density_load_file(DATA("wdas_cloud_sixteenth.vdb"), &o);
        nanovdb_set_cell_grid_limit(limit);
        if (!d)
            TEST_FAIL("%s", err_message());
        density_info in;
        density_get_info(d, &in);
        ASSERT_TRUE(in.majorant_tree == (f >= 2));
        check_majorants(d, 21 + (uint64_t)f, 1500, 1000);
        if (f < 2) { /* the cell grid's minorant is positive over much of the cloud's inside */
            box3 b = density_bounds(d);
            rng g = rng_make(31, 0, 0);
            double len_maj = 0.0, len_min = 0.0;
            for (int n = 0; n < 200; n++) {
                vec3 dir = v3_normalize(v3(rng_next(&g) - 0.5, rng_next(&g) - 0.5, rng_next(&g) - 0.5));
                vec3 c = v3_scale(v3_add(b.lo, b.hi), 0.5);
                majorant_iter mi;
                majorant_seg sg;
                density_majorant_begin(d, (ray){v3_sub(c, v3_scale(dir, 1e4)), dir, 0}, 0, INFINITY, &mi);
                while (majorant_next(&mi, &sg)) {
                    len_maj += sg.rho_maj > 0 ? sg.t1 - sg.t0 : 0.0;
                    len_min += sg.rho_min > 0 ? sg.t1 - sg.t0 : 0.0;
                }
            }
            fprintf(stderr, "filter %d: minorant > 0 on %.3f of the length where the majorant is\n", f % 2,
                    len_min / len_maj);
            ASSERT_TRUE(len_min > 0.1 * len_maj);
        }
        density_release(d);
    }
    unlink(path);
}

/* A small box's dense copy (nanovdb.c): lookups read it instead of the tree, and give the
 * tree's values (to float rounding when a scale multiplies them), with either filter; its
 * memory is counted; under a memory limit too small for it the grid keeps the tree. */
TEST(sparse_small_box_dense_copy)
{
    for (int f = 0; f < 4; f++) {
        density_load_options o;
        density_load_options_default(&o);
        o.filter = f % 2 ? GRID_TRILINEAR : GRID_NEAREST;
        o.scale = f < 2 ? 1.0 : 3.7;
        uint64_t limit = nanovdb_set_cell_grid_limit(0);
        density *tree = density_load_file(DATA("wdas_cloud_sixteenth.vdb"), &o);
        nanovdb_set_cell_grid_limit(UINT64_MAX);
        density *copy = density_load_file(DATA("wdas_cloud_sixteenth.vdb"), &o);
        o.max_memory = 8u << 20; /* the file and its cells fit; 4 bytes a voxel more do not */
        density *capped = density_load_file(DATA("wdas_cloud_sixteenth.vdb"), &o);
        nanovdb_set_cell_grid_limit(limit);
        if (!tree || !copy || !capped)
            TEST_FAIL("%s", err_message());
        density_info it, ic, ik;
        density_get_info(tree, &it);
        density_get_info(copy, &ic);
        density_get_info(capped, &ik);
        size_t nvox = (size_t)ic.n[0] * (size_t)ic.n[1] * (size_t)ic.n[2];
        ASSERT_TRUE(nvox > 1000000);
        ASSERT_TRUE(ic.memory_bytes >= ik.memory_bytes + 4 * nvox); /* the copy is counted */
        ASSERT_TRUE(ik.memory_bytes <= o.max_memory);
        box3 b = density_bounds(copy);
        rng g = rng_make(77, (uint64_t)f, 0);
        int inside = 0;
        for (int n = 0; n < 200000; n++) {
            vec3 p = v3(b.lo.x + (b.hi.x - b.lo.x) * (1.1 * rng_next(&g) - 0.05),
                        b.lo.y + (b.hi.y - b.lo.y) * (1.1 * rng_next(&g) - 0.05),
                        b.lo.z + (b.hi.z - b.lo.z) * (1.1 * rng_next(&g) - 0.05));
            double rt = density_eval(tree, p), rc = density_eval(copy, p), rk = density_eval(capped, p);
            inside += rt > 0.0;
            double tol = f < 2 ? 1e-12 : 1e-6; /* scale 3.7: the copy holds float(v * scale) */
            if (!(fabs(rc - rt) <= tol * fmax(1.0, rt)) || rk != rt)
                TEST_FAIL("filter %d at (%g, %g, %g): tree %.17g, copy %.17g, capped %.17g", f % 2, p.x, p.y, p.z,
                          rt, rc, rk);
        }
        ASSERT_TRUE(inside > 10000); /* the points reach the cloud */
        density_release(tree);
        density_release(copy);
        density_release(capped);
    }
}

/* Trilinear majorants are as tight as the filter allows: a lookup reads one voxel beyond its
 * 8^3 leaf cell, so a voxel in the middle of a leaf (A, value 1, at local (4, 4, 4)) raises
 * only its own cell's bound, while one on a leaf's face would raise the neighbour's. The
 * cell next to A's along +x holds B (value 0.5, at its far corner): its bound must be 0.5
 * (it was 1, the max over all 27 neighbouring cells, before the leaves' slabs). C (0.25, at
 * (31, 23, 23)) puts the cell diagonal to B's inside the box: lookups there near B read B
 * across a corner, which random rays check against the bounds. */
TEST(sparse_trilinear_majorants_tight)
{
    if (!grid_have_openvdb())
        return;
    const char *path = test_tmp_path("tight.vdb");
    write_vdb(path, 0, fill_three_voxels, NULL);
    density_load_options o;
    density_load_options_default(&o);
    o.filter = GRID_TRILINEAR;
    uint64_t limit = nanovdb_set_cell_grid_limit(0); /* the tree's leaf slabs, whatever the box */
    density *d = density_load_file(path, &o);
    nanovdb_set_cell_grid_limit(limit);
    if (!d)
        TEST_FAIL("%s", err_message());
    /* along +x through B's cell only (voxels 16 to 23), at B's y and z */
    ray r = {centre(16, 15, 15), v3(1, 0, 0), 0};
    majorant_iter mi;
    majorant_seg sg;
    density_majorant_begin(d, r, 0.0, 7.5 * VOXEL, &mi);
    int segs = 0;
    while (majorant_next(&mi, &sg)) {
        fprintf(stderr, "B's cell: [%g, %g) majorant %.9g\n", sg.t0, sg.t1, sg.rho_maj);
        ASSERT_TRUE(sg.rho_maj >= 0.5 && sg.rho_maj <= 0.5000001);
        segs++;
    }
    ASSERT_TRUE(segs >= 1);
    /* and through A's cell the bound holds A */
    r.o = centre(8, 12, 12);
    density_majorant_begin(d, r, 0.0, 7.5 * VOXEL, &mi);
    double mx = 0.0;
    while (majorant_next(&mi, &sg))
        mx = fmax(mx, sg.rho_maj);
    ASSERT_TRUE(mx >= 1.0);
    /* short rays around the three voxels, where the corners and faces matter */
    const vec3 aims[3] = {centre(12, 12, 12), centre(23, 15, 15), centre(31, 23, 23)};
    int positive = check_near(d, aims, 3, 3.0, 2.0, 41, 6000);
    fprintf(stderr, "%d points with density > 0 near the voxels\n", positive);
    ASSERT_TRUE(positive > 5000);
    density_release(d);
    unlink(path);
}

/* White furnace with the sparse Disney cloud: albedo 1 lit by a uniform background of 1,
 * every pixel's expectation is 1. A majorant below the field (or a gap) would bias it:
 * the mean must be within 5 standard errors of 1, and those below 2 %. */
TEST(sparse_furnace)
{
    if (!grid_have_openvdb())
        return;
    char json[2048];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 70, 700], \"look_at\": [0, 70, 0], \"fov\": 40},"
             " \"background\": 1.0,"
             " \"media\": [{\"sigma_a\": 0, \"sigma_s\": [0.4, 0.2, 0.1],"
             "   \"density\": {\"type\": \"grid\", \"file\": \"%s\"}, \"phase\": {\"type\": \"hg\", \"g\": 0.6}}],"
             " \"render\": {\"width\": 32, \"height\": 32, \"spp\": 64, \"max_depth\": 100000}}",
             DATA("wdas_cloud_sixteenth.vdb"));
    brume_image *img = test_render_json(json, 9);
    const float *px = brume_image_pixels(img);
    for (int c = 0; c < 3; c++) {
        double mean, se;
        test_channel_mean(px, 32 * 32, c, &mean, &se);
        fprintf(stderr, "channel %d: mean %.5f, standard error %.5f\n", c, mean, se);
        ASSERT_NEAR(mean, 1.0, 5.0 * se + 1e-6);
        ASSERT_TRUE(5.0 * se < 0.02); /* a 2 % energy error cannot pass */
    }
    /* the cloud is there: alpha (1 - transmittance) is well above 0 in the middle */
    ASSERT_TRUE(px[4 * (16 * 32 + 16) + 3] > 0.2f);
    brume_image_release(img);
}

/* ---- hostile .vdb ------------------------------------------------------------------------------ */

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Loads mutated bytes: must end (a field or a one-line error naming the input) within the
 * sandbox's wall-clock limit for a small input (2 x 10 s + 5 s), plus slack for the load. */
static void load_mutant(const unsigned char *b, size_t n, const char *what)
{
    density_load_options o;
    density_load_options_default(&o);
    o.format = GRID_FORMAT_VDB;
    o.max_memory = (size_t)64 << 20;
    double t0 = now();
    density *d = density_load_memory(b, n, "mutant.vdb", &o);
    double dt = now() - t0;
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
    double t0 = now();
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
    fprintf(stderr, "%d mutants in %.1f s\n", tried, now() - t0);
    free(b);
}


/* ---- temperature, blackbody, albedo and emission fields -------------------------------------- */

static void xy_of(double T, double *x, double *y)
{
    double v[3];
    blackbody_xyz(T, v);
    double sum = v[0] + v[1] + v[2];
    *x = v[0] / sum;
    *y = v[1] / sum;
}

/* 6500 K lands on D65 and the Planckian locus matches published chromaticities. D65
 * (x, y) = (0.31271, 0.32902) lies 0.0032 off the locus in CIE 1960 (u, v) (its Duv), so
 * the check is in (u, v): within 0.005. Published points (CIE 15:2004 and Wyszecki &
 * Stiles, table 1(3.11)): illuminant A, defined as Planck's law with c2 = 1.435e-2 m K at
 * 2848 K, (0.44757, 0.40745); the locus at 3000 K (0.4369, 0.4041), 5000 K (0.3451,
 * 0.3516), 10000 K (0.2807, 0.2884). Tolerance 0.0015: the colour matching functions are
 * an analytic fit (Wyman et al. 2013), good to about 1e-3 in chromaticity. */
TEST(blackbody_chromaticity)
{
    double x, y;
    xy_of(6500.0, &x, &y);
    double u = 4 * x / (-2 * x + 12 * y + 3), v = 6 * y / (-2 * x + 12 * y + 3);
    double xd = 0.31271, yd = 0.32902;
    double ud = 4 * xd / (-2 * xd + 12 * yd + 3), vd = 6 * yd / (-2 * xd + 12 * yd + 3);
    fprintf(stderr, "6500 K: x %.5f y %.5f, uv distance to D65 %.5f\n", x, y, hypot(u - ud, v - vd));
    ASSERT_TRUE(hypot(u - ud, v - vd) < 0.005);
    const struct {
        double T, x, y;
    } pts[] = {{2848.0 * 1.4387769e-2 / 1.435e-2, 0.44757, 0.40745},
               {3000.0, 0.4369, 0.4041},
               {5000.0, 0.3451, 0.3516},
               {10000.0, 0.2807, 0.2884}};
    for (size_t i = 0; i < sizeof pts / sizeof *pts; i++) {
        xy_of(pts[i].T, &x, &y);
        fprintf(stderr, "%.0f K: x %.5f (%.5f) y %.5f (%.5f)\n", pts[i].T, x, pts[i].x, y, pts[i].y);
        ASSERT_NEAR(x, pts[i].x, 0.0015);
        ASSERT_NEAR(y, pts[i].y, 0.0015);
    }
    /* the rendering table agrees with the direct integral, and D65's RGB is near white */
    blackbody_init();
    for (double T = 800.0; T < 40000.0; T *= 1.37) {
        color a = blackbody_rgb(T), b = blackbody_rgb_exact(T);
        for (int c = 0; c < 3; c++)
            ASSERT_NEAR(a.c[c], b.c[c], 2e-3 * fabs(b.c[c]) + 1e-6);
    }
    color w = blackbody_rgb_exact(6500.0);
    ASSERT_NEAR(w.c[0] / w.c[1], 1.0, 0.08); /* 6500 K sits a little below D65 (magenta-ward) */
    ASSERT_NEAR(w.c[2] / w.c[1], 1.0, 0.08);
    /* fire is red: at 1500 K red dominates blue by far */
    color f = blackbody_rgb_exact(1500.0);
    ASSERT_TRUE(f.c[0] > 10.0 * fabs(f.c[2]));
}

/* The fields of a medium from one .vdb through scene-file keys: albedo (Cd) scales
 * sigma_s per channel, temperature adds blackbody emission, each at the medium-local point;
 * the keys default to the density's file. */
TEST(medium_fields_from_scene_keys)
{
    if (!grid_have_openvdb())
        return;
    const char *path = test_tmp_path("fields.vdb");
    write_puffs(path, all_names, 0);
    char json[2048];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 30], \"look_at\": [0, 0, 0]},"
             " \"media\": [{\"sigma_a\": [0.5, 1, 2], \"sigma_s\": [3, 3, 3], \"emission\": [0.1, 0, 0],"
             "  \"density\": {\"type\": \"grid\", \"file\": \"%s\", \"filter\": \"nearest\"},"
             "  \"albedo\": {\"grid\": \"Cd\"}, \"temperature\": {\"grid\": \"temperature\"},"
             "  \"blackbody\": {\"scale\": 2, \"temperature_offset\": 100, \"temperature_scale\": 1.5},"
             "  \"emission_field\": {\"grid\": \"density\", \"color\": [0, 0, 4]}}]}",
             path);
    brume_scene *s = NULL;
    if (scene_parse_json(json, "<test>", &s) != BRUME_OK)
        TEST_FAIL("%s", err_message());
    brume_context *ctx = brume_context_new();
    ASSERT_TRUE(brume_scene_commit(ctx, s) == BRUME_OK);
    brume_context_release(ctx);
    ASSERT_TRUE(s->has_emission);
    rng g = rng_make(3, 0, 0);
    for (int n = 0; n < 200; n++) {
        int p = n & 1;
        int i = puff_c[p][0] + (int)(rng_next(&g) * 9) - 4, j = puff_c[p][1] + (int)(rng_next(&g) * 9) - 4,
            k = puff_c[p][2] + (int)(rng_next(&g) * 9) - 4;
        medium_sample ms;
        media_at(s, centre(i, j, k), 0.0, &ms);
        double rho = puff_density(i, j, k);
        float cd[3];
        puff_colour(i, j, k, cd);
        color Le = col_rgb(0.1, 0, 4.0 * rho);
        double T = (puff_temperature(i, j, k) - 100.0) * 1.5;
        if (rho > 0 && T > 100.0)
            Le = col_madd(Le, blackbody_rgb(T), 2.0);
        const double sa[3] = {0.5, 1, 2};
        for (int c = 0; c < 3; c++) {
            ASSERT_NEAR(ms.sigma_s.c[c], 3.0 * rho * (rho > 0 ? cd[c] : 0.0), 1e-6);
            ASSERT_NEAR(ms.emission.c[c], sa[c] * rho * Le.c[c], 1e-6 * (1 + fabs(sa[c] * rho * Le.c[c])));
        }
    }
    /* sigma_t_max follows the albedo's largest value (Cd red reaches 1.419 > 1) */
    ASSERT_TRUE(s->media[0].sigma_t_max >= 0.5 + 3.0 * 1.41);
    brume_scene_release(s);

    /* bad input: one-line errors naming the file and the key or grid */
    const struct {
        const char *fields, *needle;
    } bad[] = {{"\"temperature\": {\"grid\": \"Cd\"}", "vec3s"},
               {"\"temperature\": {\"grid\": \"heat\"}", "\"heat\""},
               {"\"temperature\": {\"grid\": \"temperature\"}, \"blackbody\": {\"scale\": 0}", "blackbody.scale"},
               {"\"blackbody\": {\"scale\": 1}", "blackbody"},
               {"\"albedo\": {\"grid\": \"nope\"}", "albedo"},
               {"\"emission_field\": {\"grid\": \"density\", \"color\": [1, -1, 0]}", "emission_field.color"}};
    for (size_t b = 0; b < sizeof bad / sizeof *bad; b++) {
        snprintf(json, sizeof json,
                 "{\"camera\": {\"position\": [0, 0, 30], \"look_at\": [0, 0, 0]},"
                 " \"media\": [{\"sigma_a\": 1, \"sigma_s\": 1,"
                 "  \"density\": {\"type\": \"grid\", \"file\": \"%s\"}, %s}]}",
                 path, bad[b].fields);
        s = NULL;
        ASSERT_TRUE(scene_parse_json(json, "bad.json", &s) != BRUME_OK);
        fprintf(stderr, "%s\n", err_message());
        ASSERT_CONTAINS(err_message(), "bad.json");
        ASSERT_CONTAINS(err_message(), bad[b].needle);
        ASSERT_TRUE(!strchr(err_message(), '\n'));
    }
    unlink(path);
}

/* Emission from a temperature grid, closed form: a purely absorbing box (sigma_a = 1.5,
 * 2 long along the view) holding a constant 3000 K, black background: a covered pixel's
 * expectation is scale B(3000 K) (1 - exp(-3)). With sigma_maj = sigma_a each sample is
 * scale B or 0, a Bernoulli with p = 1 - exp(-3): 5 standard errors. */
TEST(blackbody_emission_closed_form)
{
    if (!grid_have_openvdb())
        return;
    const char *path = test_tmp_path("hot.vdb");
    write_vdb(path, 0, fill_3000K, NULL);
    char json[2048];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 10], \"look_at\": [0, 0, 0], \"fov\": 5},"
             " \"background\": [0, 0, 0],"
             " \"media\": [{\"sigma_a\": 1.5, \"sigma_s\": 0,"
             "   \"density\": {\"type\": \"constant\", \"bounds\": [[-5, -5, -1], [5, 5, 1]]},"
             "   \"temperature\": {\"file\": \"%s\"}, \"blackbody\": {\"scale\": 3}}],"
             " \"render\": {\"width\": 32, \"height\": 32, \"spp\": 64}}",
             path);
    brume_image *img = test_render_json(json, 4);
    const float *px = brume_image_pixels(img);
    blackbody_init();
    color B = col_scale(blackbody_rgb(3000.0), 3.0);
    double p = 1.0 - exp(-3.0);
    for (int c = 0; c < 3; c++) {
        double mean = 0.0;
        for (int i = 0; i < 32 * 32; i++)
            mean += px[4 * i + c];
        mean /= 32 * 32;
        double se = fabs(B.c[c]) * sqrt(p * (1.0 - p) / (32 * 32 * 64.0));
        fprintf(stderr, "channel %d: %.5f expected %.5f (se %.5f)\n", c, mean, B.c[c] * p, se);
        ASSERT_NEAR(mean, B.c[c] * p, 5.0 * se + 1e-9);
    }
    ASSERT_TRUE(B.c[0] > B.c[1] && B.c[1] > B.c[2]); /* 3000 K is orange */
    brume_image_release(img);
    /* blasi and stam do not render fields: an error, not a silent omission */
    char json2[2300];
    snprintf(json2, sizeof json2, "%.*s, \"method\": \"blasi\"}}", (int)(strlen(json) - 2), json);
    brume_scene *s = NULL;
    ASSERT_TRUE(scene_parse_json(json2, "<test>", &s) == BRUME_OK);
    brume_context *ctx = brume_context_new();
    brume_image *none = NULL;
    ASSERT_TRUE(brume_scene_commit(ctx, s) != BRUME_OK || brume_render(ctx, s, &none) != BRUME_OK);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "path or single");
    brume_context_release(ctx);
    brume_scene_release(s);
    unlink(path);
}


/* brume gen upres with no detail is the trilinear source at the fine voxel centres (so the
 * placement is right); brume gen fire writes density and temperature grids, sparse. */
TEST(gen_upres_and_fire)
{
    if (!grid_have_openvdb())
        return;
    const char *up = test_tmp_path("up.nvdb"), *fire = test_tmp_path("fire.vdb");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "%s gen upres %s --factor 3 --detail 0 -o %s > /dev/null", BRUME_EXE,
             DATA("wdas_cloud_sixteenth.vdb"), up);
    ASSERT_EQ_INT(test_system(cmd), 0);
    density *src = density_load_file(DATA("wdas_cloud_sixteenth.vdb"), NULL), *fine = density_load_file(up, NULL);
    if (!src || !fine)
        TEST_FAIL("%s", err_message());
    density_info a, b;
    density_get_info(src, &a);
    density_get_info(fine, &b);
    ASSERT_NEAR(b.voxel_to_world.m[0] * 3.0, a.voxel_to_world.m[0], 1e-9);
    rng g = rng_make(9, 0, 0);
    int checked = 0;
    for (int n = 0; n < 20000 && checked < 2000; n++) {
        /* a fine voxel centre */
        vec3 u = v3((floor(rng_next(&g) * a.n[0] * 3) + 0.5) / 3, (floor(rng_next(&g) * a.n[1] * 3) + 0.5) / 3,
                    (floor(rng_next(&g) * a.n[2] * 3) + 0.5) / 3);
        vec3 p = affine3_apply(&a.voxel_to_world, u);
        double want = density_eval(src, p);
        if (want < 1e-3)
            continue;
        ASSERT_NEAR(density_eval(fine, p), want, 1e-5 * want + 1e-6);
        checked++;
    }
    ASSERT_TRUE(checked > 500);
    density_release(src);
    density_release(fine);

    snprintf(cmd, sizeof cmd, "%s gen fire --resolution 48 -o %s > /dev/null", BRUME_EXE, fire);
    ASSERT_EQ_INT(test_system(cmd), 0);
    gridvdb_info *gi;
    int count;
    ASSERT_TRUE(grid_list_file(fire, 0, &gi, &count) == BRUME_OK);
    ASSERT_EQ_INT(count, 2);
    for (int k = 0; k < 2; k++) {
        ASSERT_TRUE(gi[k].active > 1000 && gi[k].active < 24ull * 48 * 24); /* sparse: not the whole box */
        if (strcmp(gi[k].name, "temperature") == 0)
            ASSERT_TRUE(gi[k].vmin >= 299.0 && gi[k].vmax > 1200.0 && gi[k].vmax < 3000.0);
        else
            ASSERT_EQ_STR(gi[k].name, "density");
    }
    free(gi);
    unlink(up);
    unlink(fire);
}

/* brume gen fire --frames writes a file per frame at time f / fps through the reader's frame
 * patterns: frame 0 is the still flame (the same bytes), frame 1 the flame at 1/24 s (the
 * same bytes as --time 1/24), and the noise rises by S T: --velocity 2 --time 0.5 has the
 * density of --velocity 1 --time 1. Without a pattern, or with --time, --frames is refused. */
TEST(gen_fire_frames)
{
    if (!grid_have_openvdb())
        return;
    char pattern[600], f0[600], f1[600], still[600], at[600], a[600], b[600], cmd[4096];
    snprintf(pattern, sizeof pattern, "%s", test_tmp_path("fireseq_####.nvdb"));
    snprintf(f0, sizeof f0, "%s", test_tmp_path("fireseq_0000.nvdb"));
    snprintf(f1, sizeof f1, "%s", test_tmp_path("fireseq_0001.nvdb"));
    snprintf(still, sizeof still, "%s", test_tmp_path("firestill.nvdb"));
    snprintf(at, sizeof at, "%s", test_tmp_path("fireat.nvdb"));
    snprintf(a, sizeof a, "%s", test_tmp_path("firea.nvdb"));
    snprintf(b, sizeof b, "%s", test_tmp_path("fireb.nvdb"));
    const char *gen = "gen fire --resolution 24 --velocity 2";
    snprintf(cmd, sizeof cmd, "%s %s --frames 0-2 -o '%s' > /dev/null && %s %s -o %s > /dev/null && "
                              "%s %s --time 0.041666666666666664 -o %s > /dev/null && "
                              "%s gen fire --resolution 24 --velocity 2 --time 0.5 -o %s > /dev/null && "
                              "%s gen fire --resolution 24 --velocity 1 --time 1 -o %s > /dev/null",
             BRUME_EXE, gen, pattern, BRUME_EXE, gen, still, BRUME_EXE, gen, at, BRUME_EXE, a, BRUME_EXE, b);
    ASSERT_EQ_INT(test_system(cmd), 0);
    ASSERT_TRUE(test_exists(test_tmp_path("fireseq_0002.nvdb")));
    size_t n0, n1, ns, nt;
    char *c0 = test_slurp(f0, &n0), *c1 = test_slurp(f1, &n1), *cs = test_slurp(still, &ns), *ct = test_slurp(at, &nt);
    ASSERT_TRUE(n0 == ns && memcmp(c0, cs, n0) == 0);
    ASSERT_TRUE(n1 == nt && memcmp(c1, ct, n1) == 0);
    ASSERT_TRUE(n0 != n1 || memcmp(c0, c1, n0) != 0);
    free(c0), free(c1), free(cs), free(ct);
    /* the grid named "density" (the default) */
    density *da = density_load_file(a, NULL), *db = density_load_file(b, NULL), *d0 = density_load_file(f0, NULL);
    if (!da || !db || !d0)
        TEST_FAIL("%s", err_message());
    rng g = rng_make(4, 0, 0);
    int moved = 0;
    for (int n = 0; n < 4000; n++) {
        vec3 p = v3(0.4 * (rng_next(&g) - 0.5), 2.0 * rng_next(&g), 0.4 * (rng_next(&g) - 0.5));
        double va = density_eval(da, p);
        ASSERT_NEAR(density_eval(db, p), va, 1e-6 * va + 1e-9);
        moved += fabs(density_eval(d0, p) - va) > 1e-3;
    }
    ASSERT_TRUE(moved > 100); /* and the time moves it */
    density_release(da), density_release(db), density_release(d0);
    snprintf(cmd, sizeof cmd, "%s gen fire --frames 1-2 -o %s 2>/dev/null", BRUME_EXE, still);
    ASSERT_EQ_INT(test_system(cmd), 2);
    snprintf(cmd, sizeof cmd, "%s gen fire --frames 1-2 --time 1 -o '%s' 2>/dev/null", BRUME_EXE, pattern);
    ASSERT_EQ_INT(test_system(cmd), 2);
    /* a rise beyond the noise's range, for one time or the last frame: refused before any file */
    snprintf(cmd, sizeof cmd, "%s gen fire --time 1e6 --velocity 1e5 -o %s 2>/dev/null", BRUME_EXE, a);
    ASSERT_EQ_INT(test_system(cmd), 2);
    snprintf(cmd, sizeof cmd, "%s gen fire --frames 7-100000 --fps 0.001 -o '%s' 2>/dev/null", BRUME_EXE, pattern);
    ASSERT_EQ_INT(test_system(cmd), 2);
    ASSERT_TRUE(!test_exists(test_tmp_path("fireseq_0007.nvdb")));
}

TEST_MAIN(gen_upres_and_fire, gen_fire_frames, blackbody_chromaticity, medium_fields_from_scene_keys, blackbody_emission_closed_form, vdb_named_grids, vdb_ambiguous_float_grids, sparse_big_box_under_512mb, nanovdb_matches_dense, sparse_trilinear_majorants_tight,
          nanovdb_cached_lookups, sparse_majorants_bound, sparse_small_box_dense_copy, sparse_furnace, hostile_vdb_bit_flips, hostile_vdb_huge_counts)
