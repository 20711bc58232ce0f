/* test_fractal.c - fractal clouds (statistics of the fBm bases, shaping, animation) and
 * the grid subcommands gen, info and convert, called as functions. */
#include "test.h"

#include <stdint.h>
#include <unistd.h>

#include "commands.h"
#include "core/error.h"
#include "density/fractal.h"
#include "io/grid_io.h"

/* Mean squared increment at lag r along x: for fBm, proportional to r^(2H). */
static double increment_var(const float *f, const int n[3], int lag)
{
    double s = 0;
    size_t c = 0;
    for (int k = 0; k < n[2]; k++)
        for (int j = 0; j < n[1]; j++)
            for (int i = 0; i + lag < n[0]; i++) {
                size_t o = (size_t)i + (size_t)n[0] * ((size_t)j + (size_t)n[1] * (size_t)k);
                double d = (double)f[o + (size_t)lag] - (double)f[o];
                s += d * d;
                c++;
            }
    return s / (double)c;
}

/* The structure function's log-log slope estimates 2H (small lags, away from the FFT's
 * periodic wrap and the midpoint lattice's coarse levels). */
static double estimated_h(const float *f, const int n[3])
{
    double v1 = increment_var(f, n, 2), v2 = increment_var(f, n, 8);
    return 0.5 * log(v2 / v1) / log(4.0);
}

TEST(spectral_hurst)
{
    int n[3] = {64, 64, 64};
    float *f = malloc(64 * 64 * 64 * sizeof *f);
    for (int h = 0; h < 2; h++) {
        double H = h ? 0.8 : 0.4;
        ASSERT_EQ_INT(fractal_spectral(n, H, 3, f), BRUME_OK);
        double est = estimated_h(f, n);
        printf("spectral H %.2f: estimated %.3f\n", H, est);
        ASSERT_NEAR(est, H, 0.12);
    }
    free(f);
}

TEST(midpoint_hurst_and_determinism)
{
    int n[3] = {65, 65, 65};
    float *f = malloc(65 * 65 * 65 * sizeof *f), *g = malloc(65 * 65 * 65 * sizeof *g);
    for (int h = 0; h < 2; h++) {
        double H = h ? 0.8 : 0.4;
        ASSERT_EQ_INT(fractal_midpoint(6, H, 5, 65, f), BRUME_OK);
        double est = estimated_h(f, n);
        printf("midpoint H %.2f: estimated %.3f\n", H, est);
        ASSERT_NEAR(est, H, 0.15);
    }
    ASSERT_EQ_INT(fractal_midpoint(6, 0.8, 5, 65, g), BRUME_OK);
    ASSERT_TRUE(memcmp(f, g, 65 * 65 * 65 * sizeof *f) == 0);
    ASSERT_EQ_INT(fractal_midpoint(6, 0.8, 6, 65, g), BRUME_OK);
    ASSERT_TRUE(memcmp(f, g, 65 * 65 * 65 * sizeof *f) != 0);
    ASSERT_TRUE(fractal_midpoint(11, 0.5, 1, 2049, g) != BRUME_OK);
    ASSERT_TRUE(fractal_midpoint(6, 0.5, 1, 0, g) != BRUME_OK);
    ASSERT_TRUE(fractal_midpoint(6, 0.5, 1, 66, g) != BRUME_OK);
    free(f);
    free(g);
}

/* The first planes alone are those of the whole lattice, bit for bit, at every count of
 * planes (the bounds of the substeps filled); the planes after them are not written. */
TEST(midpoint_first_planes_are_the_whole_lattices)
{
    const size_t plane = 33 * 33, all = 33 * plane;
    float *whole = malloc(all * sizeof *whole), *part = malloc(all * sizeof *part);
    ASSERT_EQ_INT(fractal_midpoint(5, 0.7, 11, 33, whole), BRUME_OK);
    for (int planes = 1; planes <= 33; planes++) {
        for (size_t i = 0; i < all; i++)
            part[i] = NAN;
        ASSERT_EQ_INT(fractal_midpoint(5, 0.7, 11, planes, part), BRUME_OK);
        ASSERT_TRUE(memcmp(part, whole, (size_t)planes * plane * sizeof *part) == 0);
        size_t filled = 0;
        for (size_t i = 0; i < all; i++)
            filled += isnan(part[i]) ? 0u : 1u;
        if (planes <= 10) { /* most of the lattice is left alone: (1, 1, 32), set at the last level, too */
            ASSERT_TRUE(isnan(part[1 + 33 + 32 * plane]));
            ASSERT_TRUE(filled < all / 2);
        }
        if (planes == 33)
            ASSERT_TRUE(filled == all);
    }
    free(whole);
    free(part);
}

TEST(perlin_noise_properties)
{
    perlin_table t;
    perlin_init(&t, 9);
    double lo = 1, hi = -1, mean_turb = 0;
    for (int i = 0; i < 20000; i++) {
        vec3 x = v3(i * 0.137, i * 0.0731, i * 0.0519);
        double v = perlin_noise(&t, x);
        lo = fmin(lo, v);
        hi = fmax(hi, v);
        mean_turb += perlin_turbulence(&t, x, 6);
    }
    mean_turb /= 20000;
    printf("perlin range [%.3f, %.3f], turbulence mean %.3f\n", lo, hi, mean_turb);
    ASSERT_TRUE(lo >= -1.0 && hi <= 1.0 && lo < -0.5 && hi > 0.5);
    ASSERT_NEAR(perlin_noise(&t, v3(3, 4, 5)), 0, 1e-12); /* zero at lattice points */
    ASSERT_NEAR(mean_turb, 0.44, 0.04);                   /* the mean fractal.c subtracts */
}

TEST(cloud_shape_threshold_time)
{
    fractal_params p;
    fractal_params_default(&p);
    p.n[0] = p.n[1] = p.n[2] = 33;
    for (int m = 0; m < 3; m++) {
        p.method = (fractal_method)m;
        float *v = fractal_cloud_voxels(&p);
        ASSERT_TRUE(v);
        size_t active = 0;
        for (size_t i = 0; i < 33 * 33 * 33; i++) {
            ASSERT_TRUE(v[i] >= 0.0f && v[i] <= 1.0f);
            active += v[i] > 0.0f;
        }
        /* the ellipsoid empties the corners; the cloud is neither empty nor full */
        ASSERT_NEAR(v[0], 0, 0);
        ASSERT_NEAR(v[33 * 33 * 33 - 1], 0, 0);
        ASSERT_TRUE(active > 300 && active < 33 * 33 * 33 / 2);
        free(v);
    }
    /* a rising threshold shrinks the cloud; turbulence with wind changes it over time */
    p.method = FRACTAL_MIDPOINT;
    p.threshold_rate = 0.1;
    p.turbulence = 0.3;
    p.wind = v3(1, 0, 0);
    size_t prev = SIZE_MAX;
    for (int t = 0; t < 4; t++) {
        p.time = t;
        float *v = fractal_cloud_voxels(&p);
        size_t active = 0;
        for (size_t i = 0; i < 33 * 33 * 33; i++)
            active += v[i] > 0.0f;
        ASSERT_TRUE(active < prev);
        prev = active;
        free(v);
    }
    p.hurst = 1.5;
    ASSERT_TRUE(!fractal_cloud_voxels(&p));
    ASSERT_CONTAINS(err_message(), "H in (0, 1)");
}

static int run(int (*cmd)(int, char **), const char *line)
{
    char buf[2048], *argv[64];
    int argc = 0;
    snprintf(buf, sizeof buf, "%s", line);
    for (char *s = strtok(buf, " "); s && argc < 63; s = strtok(NULL, " "))
        argv[argc++] = s;
    argv[argc] = NULL;
    fflush(stdout);
    return cmd(argc, argv);
}

TEST(cli_gen_info_convert)
{
    char line[1024];
    const char *vol = test_tmp_path("cloud.vol"), *raw = test_tmp_path("cloud.raw"), *df3 = test_tmp_path("cloud.df3");
    snprintf(line, sizeof line, "gen cloud --dims 65x65x10 --seed 1 -o %s", vol);
    ASSERT_EQ_INT(run(cmd_gen, line), 0);
    density *d = density_load_file(vol, NULL);
    ASSERT_TRUE(d);
    density_info in;
    density_get_info(d, &in);
    ASSERT_EQ_INT(in.n[0], 65);
    ASSERT_EQ_INT(in.n[2], 10);
    ASSERT_TRUE(in.rho_max > 0.2 && in.active_voxels > 1000);
    snprintf(line, sizeof line, "info %s", vol);
    ASSERT_EQ_INT(run(cmd_info, line), 0);
    snprintf(line, sizeof line, "convert %s %s", vol, raw);
    ASSERT_EQ_INT(run(cmd_convert, line), 0);
    snprintf(line, sizeof line, "convert %s %s", raw, df3);
    ASSERT_EQ_INT(run(cmd_convert, line), 0);
    density *r = density_load_file(raw, NULL);
    ASSERT_TRUE(r);
    for (int k = 0; k < 10; k++)
        for (int i = 0; i < 65; i++)
            ASSERT_NEAR(density_voxel(r, i, 32, k), density_voxel(d, i, 32, k), 0);
    box3 a = density_bounds(d), b = density_bounds(r);
    ASSERT_NEAR(a.lo.z, b.lo.z, 1e-7);
    density_release(r);
    density_release(d);
    /* usage errors exit 2, failures 1 */
    ASSERT_EQ_INT(run(cmd_gen, "gen cloud --hurst 2 -o x.vol"), 2);
    ASSERT_EQ_INT(run(cmd_gen, "gen smoke -o x.vol"), 2);
    ASSERT_EQ_INT(run(cmd_info, "info"), 2);
    ASSERT_EQ_INT(run(cmd_info, "info --filter blurry x.vol"), 2);
    ASSERT_EQ_INT(run(cmd_info, "info /nonexistent/grid.vol"), 1);
    ASSERT_EQ_INT(run(cmd_convert, "convert /nonexistent/a.vol b.raw"), 1);
    snprintf(line, sizeof line, "convert %s %s/nodir/x.raw", vol, test_tmp_path("none"));
    ASSERT_EQ_INT(run(cmd_convert, line), 1);
    if (grid_have_openvdb()) {
        const char *nv = test_tmp_path("wdas.nvdb");
        snprintf(line, sizeof line, "convert %s/wdas_cloud_sixteenth.vdb %s", BRUME_DATA_DIR, nv);
        ASSERT_EQ_INT(run(cmd_convert, line), 0);
        snprintf(line, sizeof line, "info %s", nv);
        ASSERT_EQ_INT(run(cmd_info, line), 0);
        remove(nv);
    }
    char hdr[600];
    snprintf(hdr, sizeof hdr, "%s.hdr", raw);
    remove(vol);
    remove(raw);
    remove(hdr);
    remove(df3);
}

TEST_MAIN(spectral_hurst, midpoint_hurst_and_determinism, midpoint_first_planes_are_the_whole_lattices,
          perlin_noise_properties, cloud_shape_threshold_time,
          cli_gen_info_convert)
