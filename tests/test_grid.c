/* test_grid.c - voxel grids: majorants that bound the field, file formats (round trips,
 * the real files of data/, NanoVDB against OpenVDB). The DDA against brute force is in
 * test_grid_dda.c, hostile input in test_grid_hostile.c. */
#include "test.h"

#include <stdint.h>
#include <unistd.h>

#include "core/error.h"
#include "core/rng.h"
#include "density/density.h"
#include "io/grid_io.h"

#define DATA(f) BRUME_DATA_DIR "/" f

/* ---- majorants ------------------------------------------------------------------------------ */

/* Segments are contiguous, lie in the overlap of ray and grid, bound rho everywhere, and
 * leave out only stretches where rho is 0 (the walk starts and ends at the box of the
 * non-empty majorant cells). */
static void check_majorants(const density *d, uint64_t seed, int rays)
{
    rng r = rng_make(seed, 0, 0);
    box3 b = density_bounds(d);
    const box3 reach = density_reach_bounds(d);
    vec3 ext = v3_sub(b.hi, b.lo);
    for (int it = 0; it < rays; it++) {
        vec3 target = v3(b.lo.x + rng_next(&r) * ext.x, b.lo.y + rng_next(&r) * ext.y, b.lo.z + rng_next(&r) * ext.z);
        vec3 o = it % 3 ? v3_madd(target, v3(rng_next(&r) - 0.5, rng_next(&r) - 0.5, rng_next(&r) - 0.5), 2 * v3_length(ext))
                        : v3(b.lo.x + rng_next(&r) * ext.x, b.lo.y + rng_next(&r) * ext.y, b.lo.z + rng_next(&r) * ext.z);
        vec3 dir = v3_sub(target, o);
        if (v3_length(dir) == 0)
            continue;
        ray ry = {o, v3_normalize(dir), 0};
        double t0 = 0, t1 = 0;
        bool crosses = box3_intersect(b, ry, 0, INFINITY, &t0, &t1) && t1 > t0;
        majorant_iter mi;
        majorant_seg seg;
        density_majorant_begin(d, ry, 0, INFINITY, &mi);
        double prev = NAN, first = NAN;
        double reach_t0, reach_t1; /* a ray that misses the reach box finds no segment */
        const bool meets_reach = box3_intersect(reach, ry, 0, INFINITY, &reach_t0, &reach_t1);
        while (majorant_next(&mi, &seg)) {
            if (!meets_reach)
                TEST_FAIL("a segment [%.9g, %.9g] on a ray that misses density_reach_bounds", seg.t0, seg.t1);
            if (!box3_contains(reach, ray_at(ry, seg.t0)) || !box3_contains(reach, ray_at(ry, seg.t1)))
                TEST_FAIL("segment [%.9g, %.9g] leaves density_reach_bounds", seg.t0, seg.t1);
            if (isnan(first))
                first = seg.t0;
            else
                ASSERT_NEAR(seg.t0, prev, 1e-12 * (1 + fabs(prev)));
            ASSERT_TRUE(seg.t1 > seg.t0);
            /* a walk may end on an inner cell face (the box of non-empty cells), where the
             * accumulated crossing and the exact one differ by ulps (density/dda.h): a sliver
             * of the next cell that short is within the walk's documented tolerance */
            const bool sliver = seg.t1 - seg.t0 < 1e-12 * (1 + fabs(seg.t1));
            for (int q = 0; q < 16 && !sliver; q++) {
                double t = seg.t0 + (seg.t1 - seg.t0) * (q + 0.5) / 16;
                double rho = density_eval(d, ray_at(ry, t));
                if (rho > seg.rho_maj * (1 + 1e-6) + 1e-12)
                    TEST_FAIL("rho %.9g > majorant %.9g at t %.9g in [%.9g, %.9g]", rho, seg.rho_maj, t, seg.t0, seg.t1);
                if (rho < seg.rho_min * (1 - 1e-12))
                    TEST_FAIL("rho %.9g < minorant %.9g at t %.9g in [%.9g, %.9g]", rho, seg.rho_min, t, seg.t0, seg.t1);
            }
            ASSERT_TRUE(seg.rho_min >= 0.0 && seg.rho_min <= seg.rho_maj);
            ASSERT_TRUE(seg.rho_maj <= density_max(d) * (1 + 1e-6));
            prev = seg.t1;
        }
        if (crosses) { /* the walk may skip the grid's empty border, and only where rho is 0 */
            /* (a and z moved inwards by the tolerance of the grid's faces, whose crossings the
             * world box b and the voxel box round differently) */
            double a = (isnan(first) ? t1 : first) - 1e-9 * (1 + fabs(t1)), z = (isnan(first) ? t1 : prev) + 1e-9 * (1 + fabs(t1));
            ASSERT_TRUE(isnan(first) || (first >= t0 - 1e-9 * (1 + fabs(t0)) && prev <= t1 + 1e-9 * (1 + fabs(t1))));
            for (int q = 0; q < 64; q++) {
                double before = t0 + (a - t0) * (q + 0.5) / 64, after = z + (t1 - z) * (q + 0.5) / 64;
                if (a > t0 && density_eval(d, ray_at(ry, before)) != 0.0)
                    TEST_FAIL("rho %.9g > 0 at t %.9g before the walk's first segment at %.9g",
                              density_eval(d, ray_at(ry, before)), before, a);
                if (t1 > z && density_eval(d, ray_at(ry, after)) != 0.0)
                    TEST_FAIL("rho %.9g > 0 at t %.9g after the walk's last segment at %.9g",
                              density_eval(d, ray_at(ry, after)), after, z);
            }
        }
    }
}

static float *random_sparse_grid(int nx, int ny, int nz, uint64_t seed)
{
    float *v = malloc((size_t)nx * (size_t)ny * (size_t)nz * sizeof *v);
    rng r = rng_make(seed, 0, 0);
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++) {
                /* blobs of density in a mostly empty box, so that the cells differ */
                double x = (i - nx * 0.3) / nx, y = (j - ny * 0.6) / ny, z = (k - nz * 0.5) / nz;
                double e = exp(-30 * (x * x + y * y + z * z));
                v[i + nx * (j + ny * k)] = e > 0.05 ? (float)(e * (0.5 + rng_next(&r))) : 0.0f;
            }
    return v;
}

TEST(majorant_bounds_dense)
{
    for (int f = 0; f < 2; f++) {
        density *d = density_new_grid(37, 29, 41, random_sparse_grid(37, 29, 41, 5),
                                      (box3){v3(-1, -0.5, 0), v3(1, 0.7, 2)}, f ? GRID_TRILINEAR : GRID_NEAREST);
        ASSERT_TRUE(d);
        check_majorants(d, 11 + (uint64_t)f, 400);
        /* placed again after its cells were built (a scene's "transform" does this): rotated
         * and stretched, so the walk's map to cell space and its box must follow */
        density_info in;
        density_get_info(d, &in);
        affine3 turn = affine3_rotate(v3(1, 2, 3), 37.0), stretch = affine3_scale(v3(0.5, 1.5, 1.0));
        affine3 m = affine3_compose(&stretch, &in.voxel_to_world);
        m = affine3_compose(&turn, &m);
        ASSERT_TRUE(density_place(d, &m));
        check_majorants(d, 21 + (uint64_t)f, 400);
        density_release(d);
    }
}

/* The walk starts and ends at the box of the non-empty majorant cells: a grid that is 0 but
 * for voxels [12, 20)^3 of 32^3 (cells of 4 voxels; trilinear lookups reach one voxel
 * further, into cells 2 and 5) is walked over voxels [8, 24) only, a ray beside that box
 * and any ray through an empty grid find no segment. */
TEST(majorant_walk_skips_empty_border)
{
    for (int empty = 0; empty < 2; empty++) {
        float *v = calloc(32 * 32 * 32, sizeof *v);
        for (int k = 12; k < 20 && !empty; k++)
            for (int j = 12; j < 20; j++)
                for (int i = 12; i < 20; i++)
                    v[i + 32 * (j + 32 * k)] = 1.0f;
        density *d = density_new_grid(32, 32, 32, v, (box3){v3(0, 0, 0), v3(32, 32, 32)}, GRID_TRILINEAR);
        ASSERT_TRUE(d);
        majorant_iter mi;
        majorant_seg seg;
        density_majorant_begin(d, (ray){v3(-5, 16.3, 15.7), v3(1, 0, 0), 0}, 0, INFINITY, &mi);
        double first = NAN, last = NAN;
        while (majorant_next(&mi, &seg)) {
            first = isnan(first) ? seg.t0 : first;
            last = seg.t1;
        }
        if (empty) {
            ASSERT_TRUE(isnan(first));
        } else {
            ASSERT_NEAR(first, 5 + 8, 1e-12);
            ASSERT_NEAR(last, 5 + 24, 1e-12);
        }
        density_majorant_begin(d, (ray){v3(-5, 4.5, 15.7), v3(1, 0, 0), 0}, 0, INFINITY, &mi);
        ASSERT_TRUE(!majorant_next(&mi, &seg));
        /* the world box of the walks (what the path tracer culls camera rays by): voxels
         * [8, 24)^3 here, widened by no more than rounding's margin; empty for an empty grid */
        box3 reach = density_reach_bounds(d);
        if (empty) {
            ASSERT_TRUE(reach.lo.x > reach.hi.x && reach.lo.y > reach.hi.y && reach.lo.z > reach.hi.z);
        } else {
            const double lo[3] = {reach.lo.x, reach.lo.y, reach.lo.z}, hi[3] = {reach.hi.x, reach.hi.y, reach.hi.z};
            for (int a = 0; a < 3; a++) {
                ASSERT_TRUE(lo[a] < 8 && lo[a] > 8 - 1e-6);
                ASSERT_TRUE(hi[a] > 24 && hi[a] < 24 + 1e-6);
            }
        }
        density_release(d);
    }
}

/* The shadow rays' control (docs/path-tracer.md, "Shadow rays: the cell's mean as control"):
 * walked with by_ctl, every segment's rho_ctl lies in [rho_min, rho_maj], and the integral of
 * rho_ctl along a ray is that of the mean of the voxels of the majorant cell (4^3 voxels) the
 * ray is in, the means computed here from the data and integrated by a 20,000-point midpoint
 * rule. The minorant instead of the mean, the first cell's control for a merged segment, or
 * a mean over the dilated cell each miss by more than the tolerance. */
TEST(majorant_control_is_cell_mean)
{
    enum { NX = 37, NY = 29, NZ = 41, C = 4, Q = 20000 };
    float *v = random_sparse_grid(NX, NY, NZ, 5);
    static double mean[(NX + C - 1) / C][(NY + C - 1) / C][(NZ + C - 1) / C];
    memset(mean, 0, sizeof mean);
    for (int ci = 0; ci < (NX + C - 1) / C; ci++)
        for (int cj = 0; cj < (NY + C - 1) / C; cj++)
            for (int ck = 0; ck < (NZ + C - 1) / C; ck++) {
                double sum = 0.0;
                int n = 0;
                for (int i = ci * C; i < (ci + 1) * C && i < NX; i++)
                    for (int j = cj * C; j < (cj + 1) * C && j < NY; j++)
                        for (int k = ck * C; k < (ck + 1) * C && k < NZ; k++, n++)
                            sum += v[i + NX * (j + NY * k)];
                mean[ci][cj][ck] = sum / n;
            }
    const box3 b = {v3(-1, -0.5, 0), v3(1, 0.7, 2)};
    density *d = density_new_grid(NX, NY, NZ, v, b, GRID_TRILINEAR);
    ASSERT_TRUE(d);
    rng r = rng_make(23, 0, 0);
    int checked = 0;
    for (int it = 0; it < 200; it++) {
        vec3 o = v3(-2, rng_next(&r) * 1.2 - 0.5, rng_next(&r) * 2);
        vec3 target = v3(1, rng_next(&r) * 1.2 - 0.5, rng_next(&r) * 2);
        ray ry = {o, v3_normalize(v3_sub(target, o)), 0};
        double t0, t1;
        if (!box3_intersect(b, ry, 0, INFINITY, &t0, &t1) || !(t1 > t0))
            continue;
        majorant_iter mi;
        majorant_seg seg;
        density_majorant_begin(d, ry, 0, INFINITY, &mi);
        mi.by_ctl = true;
        double walked = 0.0;
        while (majorant_next(&mi, &seg)) {
            ASSERT_TRUE(seg.rho_min <= seg.rho_ctl && seg.rho_ctl <= seg.rho_maj);
            walked += seg.rho_ctl * (seg.t1 - seg.t0);
        }
        double expected = 0.0;
        for (int q = 0; q < Q; q++) {
            vec3 p = ray_at(ry, t0 + (t1 - t0) * (q + 0.5) / Q);
            int i = (int)((p.x - b.lo.x) / (b.hi.x - b.lo.x) * NX), j = (int)((p.y - b.lo.y) / (b.hi.y - b.lo.y) * NY),
                k = (int)((p.z - b.lo.z) / (b.hi.z - b.lo.z) * NZ);
            if (i >= 0 && i < NX && j >= 0 && j < NY && k >= 0 && k < NZ)
                expected += mean[i / C][j / C][k / C];
        }
        expected *= (t1 - t0) / Q;
        if (expected > 0.0)
            checked++;
        if (fabs(walked - expected) > 2e-3 * (t1 - t0) * density_max(d))
            TEST_FAIL("ray %d: integral of rho_ctl %.6g, of the cells' means %.6g", it, walked, expected);
    }
    ASSERT_TRUE(checked > 50);
    density_release(d);
}

/* The majorant grid must beat the global max on a sparse field: count the mean majorant. */
TEST(majorant_tighter_than_global)
{
    density *d = density_new_grid(64, 64, 64, random_sparse_grid(64, 64, 64, 9), (box3){v3(0, 0, 0), v3(1, 1, 1)},
                                  GRID_TRILINEAR);
    ASSERT_TRUE(d);
    rng r = rng_make(1, 0, 0);
    double sum_len = 0, sum_maj = 0;
    for (int it = 0; it < 200; it++) {
        ray ry = {v3(-1, rng_next(&r), rng_next(&r)), v3_normalize(v3(1, rng_next(&r) - 0.5, rng_next(&r) - 0.5)), 0};
        majorant_iter mi;
        majorant_seg s;
        density_majorant_begin(d, ry, 0, INFINITY, &mi);
        while (majorant_next(&mi, &s)) {
            sum_len += s.t1 - s.t0;
            sum_maj += (s.t1 - s.t0) * s.rho_maj;
        }
    }
    printf("mean majorant %.4f, global max %.4f\n", sum_maj / sum_len, density_max(d));
    ASSERT_TRUE(sum_maj / sum_len < 0.5 * density_max(d));
    density_release(d);
}

/* ---- formats: round trips --------------------------------------------------------------- */

static void check_same_voxels(const density *a, const density *b)
{
    density_info ia, ib;
    density_get_info(a, &ia);
    density_get_info(b, &ib);
    for (int x = 0; x < 3; x++)
        ASSERT_EQ_INT(ia.n[x], ib.n[x]);
    for (int k = 0; k < ia.n[2]; k++)
        for (int j = 0; j < ia.n[1]; j++)
            for (int i = 0; i < ia.n[0]; i++)
                if (density_voxel(a, i, j, k) != density_voxel(b, i, j, k))
                    TEST_FAIL("voxel (%d %d %d): %.9g != %.9g", i, j, k, density_voxel(a, i, j, k),
                              density_voxel(b, i, j, k));
}

TEST(roundtrip_raw_vol)
{
    const char *ext[] = {"rt.raw", "rt.vol"};
    for (int e = 0; e < 2; e++) {
        float *v = random_sparse_grid(13, 7, 11, 3);
        v[5] = 1e-30f; /* a denormal-ish tiny value and a large one survive */
        v[6] = 3.4e38f;
        density *d = density_new_grid(13, 7, 11, v, (box3){v3(-1, 2, 3), v3(0.3, 2.5, 4)}, GRID_NEAREST);
        ASSERT_TRUE(d);
        const char *path = test_tmp_path(ext[e]);
        ASSERT_EQ_INT(density_write_file(d, path, GRID_FORMAT_AUTO), BRUME_OK);
        density *b = density_load_file(path, NULL);
        if (!b)
            TEST_FAIL("%s", err_message());
        check_same_voxels(d, b);
        box3 x = density_bounds(d), y = density_bounds(b);
        ASSERT_NEAR(x.lo.x, y.lo.x, 1e-6);
        ASSERT_NEAR(x.hi.z, y.hi.z, 1e-6);
        density_release(b);
        density_release(d);
        remove(path);
        char hdr[600];
        snprintf(hdr, sizeof hdr, "%s.hdr", path);
        remove(hdr);
    }
}

TEST(roundtrip_df3)
{
    /* df3 holds [0, 1]: 8-bit values stay 8-bit and exact; others go to 16 or 32 bits */
    for (int w = 0; w < 3; w++) {
        float *v = malloc(9 * 4 * 3 * sizeof *v);
        for (int i = 0; i < 108; i++)
            v[i] = w == 0 ? (float)((i * 7 % 256) / 255.0) : w == 1 ? (float)((i * 911 % 65536) / 65535.0)
                                                                    : (float)(i / 107.0);
        density *d = density_new_grid(9, 4, 3, v, (box3){v3(0, 0, 0), v3(1, 1, 1)}, GRID_NEAREST);
        const char *path = test_tmp_path("rt.df3");
        ASSERT_EQ_INT(density_write_file(d, path, GRID_FORMAT_AUTO), BRUME_OK);
        density *b = density_load_file(path, NULL);
        ASSERT_TRUE(b);
        if (w < 2)
            check_same_voxels(d, b);
        else
            for (int i = 0; i < 9; i++)
                ASSERT_NEAR(density_voxel(b, i, 1, 2), density_voxel(d, i, 1, 2), 1e-7);
        FILE *f = fopen(path, "rb");
        fseek(f, 0, SEEK_END);
        ASSERT_EQ_INT(ftell(f), 6 + 108 * (w == 0 ? 1 : w == 1 ? 2 : 4));
        fclose(f);
        density_release(b);
        density_release(d);
        remove(path);
    }
    /* the real file is rewritten byte for byte */
    density *s = density_load_file(DATA("spiral.df3"), NULL);
    ASSERT_TRUE(s);
    const char *path = test_tmp_path("spiral.df3");
    ASSERT_EQ_INT(density_write_file(s, path, GRID_FORMAT_AUTO), BRUME_OK);
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "cmp -s '%s' '%s'", DATA("spiral.df3"), path);
    ASSERT_EQ_INT(test_system(cmd), 0);
    remove(path);
    density_release(s);
}

/* ---- the real files ------------------------------------------------------------------------- */

TEST(real_wdas_cloud)
{
    density *d = density_load_file(DATA("wdas_cloud_sixteenth.vdb"), NULL);
    if (!grid_have_openvdb()) {
        ASSERT_TRUE(!d);
        ASSERT_CONTAINS(err_message(), "without OpenVDB");
        return;
    }
    if (!d)
        TEST_FAIL("%s", err_message());
    density_info in;
    density_get_info(d, &in);
    ASSERT_EQ_INT(in.n[0], 126);
    ASSERT_EQ_INT(in.n[1], 86);
    ASSERT_EQ_INT(in.n[2], 154);
    /* index box (-66,-21,-90)..(59,64,63), voxel size 3.3333, cell-centred: +-1/2 voxel */
    double vs = in.voxel_to_world.m[0];
    ASSERT_NEAR(vs, 10.0 / 3.0, 1e-4);
    ASSERT_NEAR(in.bounds.lo.x, -66.5 * vs, 1e-9);
    ASSERT_NEAR(in.bounds.hi.z, 63.5 * vs, 1e-9);
    ASSERT_NEAR(in.rho_max, 1.0, 1e-6);
    ASSERT_TRUE(in.rho_min >= 0);
    check_majorants(d, 77, 100);
    density_release(d);
}

/* Constant density 1 in a box of 21 voxels of 0.05: optical depth along an axis through
 * the box is exactly 1.05 sigma_t, so T = exp(-1.05 sigma_t). */
TEST(real_box_fog_transmittance)
{
    density_load_options o;
    density_load_options_default(&o);
    o.filter = GRID_NEAREST;
    density *d = density_load_file(DATA("box_fog_21cube.vdb"), &o);
    if (!grid_have_openvdb()) {
        ASSERT_TRUE(!d);
        return;
    }
    if (!d)
        TEST_FAIL("%s", err_message());
    ASSERT_NEAR(density_max(d), 1.0, 0);
    const double sigma_t = 2.0;
    for (int axis = 0; axis < 3; axis++) {
        vec3 o3 = v3(0.01, -0.02, 0.03), dir = v3(0, 0, 0);
        if (axis == 0)
            o3.x = -3, dir.x = 1;
        else if (axis == 1)
            o3.y = -3, dir.y = 1;
        else
            o3.z = -3, dir.z = 1;
        ray r = {o3, dir, 0};
        grid_dda g;
        grid_dda_step s;
        double tau = 0;
        ASSERT_TRUE(density_voxel_dda_begin(d, r, 0, INFINITY, &g));
        while (grid_dda_next(&g, &s))
            tau += sigma_t * density_voxel(d, s.i, s.j, s.k) * (s.t1 - s.t0);
        ASSERT_NEAR(exp(-tau), exp(-1.05 * sigma_t), 1e-12);
        /* and through the majorant segments (constant field: majorant = density) */
        majorant_iter mi;
        majorant_seg seg;
        double tau_m = 0;
        density_majorant_begin(d, r, 0, INFINITY, &mi);
        while (majorant_next(&mi, &seg))
            tau_m += sigma_t * seg.rho_maj * (seg.t1 - seg.t0);
        ASSERT_NEAR(tau_m, 1.05 * sigma_t, 1e-12);
    }
    density_release(d);
}

TEST(real_spiral_df3)
{
    density *d = density_load_file(DATA("spiral.df3"), NULL);
    ASSERT_TRUE(d);
    FILE *f = fopen(DATA("spiral.df3"), "rb");
    unsigned char *b = malloc(12506);
    ASSERT_EQ_INT(fread(b, 1, 12506, f), 12506);
    fclose(f);
    int nonzero = 0;
    double sum = 0;
    for (int k = 0; k < 5; k++)
        for (int j = 0; j < 50; j++)
            for (int i = 0; i < 50; i++) {
                double want = b[6 + i + 50 * (j + 50 * k)] / 255.0;
                ASSERT_NEAR(density_voxel(d, i, j, k), want, 1e-7);
                nonzero += want > 0;
                sum += b[6 + i + 50 * (j + 50 * k)];
            }
    ASSERT_EQ_INT(nonzero, 1221);
    ASSERT_NEAR(sum / 12500, 13.68, 0.005);
    box3 bb = density_bounds(d);
    ASSERT_NEAR(bb.lo.x, 0, 0);
    ASSERT_NEAR(bb.hi.z, 1, 0);
    free(b);
    density_release(d);
}

TEST(real_cloud64_raw)
{
    density *d = density_load_file(DATA("cloud64.raw"), NULL);
    ASSERT_TRUE(d);
    density_info in;
    density_get_info(d, &in);
    ASSERT_EQ_INT(in.n[0] * in.n[1] * in.n[2], 64 * 64 * 64);
    ASSERT_NEAR(in.bounds.lo.x, -0.5, 1e-15);
    ASSERT_NEAR(in.bounds.hi.y, 0.5, 1e-15);
    ASSERT_NEAR(in.rho_max, 1.0, 1e-6);
    for (int a = 0; a < 64; a++) /* outermost layer is 0 */
        for (int b = 0; b < 64; b++) {
            ASSERT_NEAR(density_voxel(d, 0, a, b), 0, 0);
            ASSERT_NEAR(density_voxel(d, a, 63, b), 0, 0);
        }
    /* voxel (i, j, k) is sampled at -0.5 + (i + 0.5) / 64 */
    ASSERT_NEAR(density_eval(d, v3(-0.5 + 32.5 / 64, -0.5 + 30.5 / 64, -0.5 + 33.5 / 64)), density_voxel(d, 32, 30, 33),
                1e-12);
    check_majorants(d, 5, 200);
    density_release(d);
}

/* .vdb read by OpenVDB (densified) and the .nvdb made from it, read in C by PNanoVDB,
 * give the same densities, nearest and trilinear, everywhere in the box. */
TEST(nanovdb_matches_openvdb)
{
    if (!grid_have_openvdb())
        return;
    const char *files[] = {DATA("wdas_cloud_sixteenth.vdb"), DATA("box_fog_21cube.vdb")};
    for (int fi = 0; fi < 2; fi++) {
        const char *nv = test_tmp_path("conv.nvdb");
        if (grid_convert_vdb_to_nvdb(files[fi], nv, NULL) != BRUME_OK)
            TEST_FAIL("%s", err_message());
        for (int filter = 0; filter < 2; filter++) {
            density_load_options o;
            density_load_options_default(&o);
            o.filter = filter ? GRID_TRILINEAR : GRID_NEAREST;
            density *a = density_load_file(files[fi], &o), *b = density_load_file(nv, &o);
            if (!a || !b)
                TEST_FAIL("%s", err_message());
            ASSERT_EQ_INT(density_get_kind(b), DENSITY_NANOVDB);
            box3 ba = density_bounds(a), bb = density_bounds(b);
            ASSERT_NEAR(ba.lo.x, bb.lo.x, 1e-9);
            ASSERT_NEAR(ba.hi.y, bb.hi.y, 1e-9);
            ASSERT_NEAR(density_max(a), density_max(b), 0);
            rng r = rng_make(8, (uint64_t)fi, (uint64_t)filter);
            vec3 e = v3_sub(ba.hi, ba.lo);
            int nonzero = 0;
            for (int q = 0; q < 20000; q++) {
                vec3 p = v3(ba.lo.x + rng_next(&r) * e.x, ba.lo.y + rng_next(&r) * e.y, ba.lo.z + rng_next(&r) * e.z);
                double va = density_eval(a, p), vb = density_eval(b, p);
                ASSERT_NEAR(va, vb, 1e-6);
                nonzero += va > 0;
            }
            ASSERT_TRUE(nonzero > 100);
            check_majorants(b, 3 + (uint64_t)filter, 100);
            density_release(a);
            density_release(b);
        }
        remove(nv);
    }
}

/* A dense grid written as .nvdb by the C++ side and read back in C. */
TEST(nanovdb_write_dense)
{
    if (!grid_have_openvdb())
        return;
    density *d = density_new_grid(19, 9, 23, random_sparse_grid(19, 9, 23, 4), (box3){v3(-1, 0, 0), v3(1, 1, 3)},
                                  GRID_TRILINEAR);
    const char *p = test_tmp_path("dense.nvdb");
    if (density_write_file(d, p, GRID_FORMAT_AUTO) != BRUME_OK)
        TEST_FAIL("%s", err_message());
    density *b = density_load_file(p, NULL);
    if (!b)
        TEST_FAIL("%s", err_message());
    check_same_voxels(d, b);
    rng r = rng_make(1, 2, 3);
    for (int q = 0; q < 2000; q++) {
        vec3 x = v3(-1 + 2 * rng_next(&r), rng_next(&r), 3 * rng_next(&r));
        ASSERT_NEAR(density_eval(d, x), density_eval(b, x), 1e-6);
    }
    const char *pv = test_tmp_path("dense.vdb");
    ASSERT_EQ_INT(density_write_file(d, pv, GRID_FORMAT_AUTO), BRUME_OK);
    density *c = density_load_file(pv, NULL);
    ASSERT_TRUE(c);
    check_same_voxels(d, c);
    density_release(b);
    density_release(c);
    density_release(d);
    remove(p);
    remove(pv);
}

TEST(load_options_placement)
{
    density_load_options o;
    density_load_options_default(&o);
    o.has_bounds = true;
    o.bounds = (box3){v3(0, 0, 0), v3(2, 4, 8)};
    o.has_transform = true;
    o.transform = (affine3){{0, -1, 0, 10, 1, 0, 0, 0, 0, 0, 1, 0}}; /* rotate 90 degrees about z, shift x */
    o.scale = 2.0;
    o.filter = GRID_NEAREST;
    density *d = density_load_file(DATA("spiral.df3"), &o);
    ASSERT_TRUE(d);
    box3 b = density_bounds(d);
    ASSERT_NEAR(b.lo.x, 6, 1e-12);
    ASSERT_NEAR(b.hi.x, 10, 1e-12);
    ASSERT_NEAR(b.hi.y, 2, 1e-12);
    ASSERT_NEAR(b.hi.z, 8, 1e-12);
    /* voxel (25, 25, 2) centre: bounds-local (1.02, 2.04, 4) -> world (10 - 2.04, 1.02, 4) */
    ASSERT_NEAR(density_eval(d, v3(10 - 2.04, 1.02, 4)), density_voxel(d, 25, 25, 2), 0);
    density_release(d);
}

TEST_MAIN(majorant_bounds_dense, majorant_walk_skips_empty_border, majorant_control_is_cell_mean,
          majorant_tighter_than_global, roundtrip_raw_vol, roundtrip_df3, real_wdas_cloud, real_box_fog_transmittance,
          real_spiral_df3, real_cloud64_raw, nanovdb_matches_openvdb, nanovdb_write_dense, load_options_placement)
