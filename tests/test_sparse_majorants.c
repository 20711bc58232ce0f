/* test_sparse_majorants.c - the majorants of sparse grids bound the field: along random
 * rays through the puffs of vdb_puffs.h and the Disney cloud, with the cell grid and with
 * the tree's walk, empty space in few segments; a small box's dense copy gives the tree's
 * values; trilinear bounds as tight as the filter allows; and a white furnace with the
 * sparse cloud stays at 1. */
#include "test.h"

#include <stdint.h>
#include <unistd.h>

#include "brume.h"
#include "core/error.h"
#include "core/rng.h"
#include "density/density.h"
#include "io/grid_io.h"
#include "vdb_puffs.h"

#define DATA(f) BRUME_DATA_DIR "/" f

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

TEST_MAIN(sparse_majorants_bound, sparse_small_box_dense_copy, sparse_trilinear_majorants_tight, sparse_furnace)
