/* test_sobol.c - the padded, Owen-scrambled Sobol sampler of camera samples (core/sobol.h,
 * rng_make_qmc in core/rng.h, render.sampler): the net property, uniformity, independence
 * of pairs, the variance it saves on a smooth integral, and the option. */
#include "test.h"

#include "brume.h"
#include "core/rng.h"
#include "core/sobol.h"
#include "render/slab.h"

/* Dimension 1's direction numbers by the recurrence of the primitive polynomial x + 1:
 * m_1 = 1, m_k = 2 m_{k-1} xor m_{k-1}, v_k = m_k 2^(32-k) (Bratley and Fox 1988). */
static uint32_t sobol1_by_recurrence(uint32_t i)
{
    uint64_t m = 1;
    uint32_t x = 0;
    for (int k = 1; k <= 32; k++) {
        if (k > 1)
            m = (m << 1) ^ m;
        if (i >> (k - 1) & 1u)
            x ^= (uint32_t)((m << (32 - k)) & 0xffffffffu);
    }
    return x;
}

TEST(sobol_direction_numbers)
{
    for (uint32_t n = 0; n < 100000; n++) {
        uint32_t i = n < 50000 ? n : n * 2654435761u; /* small indices, then all 32 bits */
        uint32_t rev = 0;
        for (int b = 0; b < 32; b++)
            rev |= (i >> b & 1u) << (31 - b);
        if (sobol_u32(i, 0) != rev)
            TEST_FAIL("dimension 0 of index %u: %08x, expected %08x", i, sobol_u32(i, 0), rev);
        if (sobol_u32(i, 1) != sobol1_by_recurrence(i))
            TEST_FAIL("dimension 1 of index %u: %08x, expected %08x", i, sobol_u32(i, 1), sobol1_by_recurrence(i));
    }
}

/* The coordinate scramble is a nested one: a bijection of 32-bit values under which the
 * top k bits of the output depend on the top k bits of the input only. */
TEST(sobol_scramble_nested)
{
    for (uint32_t seed = 1; seed < 2000000000u; seed += 199999999u)
        for (int k = 1; k <= 12; k++) {
            uint32_t shift = 32u - (uint32_t)k;
            static unsigned char seen[4096];
            memset(seen, 0, sizeof seen);
            for (uint32_t top = 0; top < (1u << k); top++) {
                uint32_t a = sobol_owen_scramble(top << shift, seed) >> shift;
                uint32_t b = sobol_owen_scramble((top << shift) | (0x9e3779b9u >> k), seed) >> shift;
                ASSERT_EQ_INT(a, b);
                ASSERT_EQ_INT(seen[a], 0); /* onto: each top block once */
                seen[a] = 1;
            }
        }
}

/* The first 2^m samples of a pixel, and the next 2^m, in each pair of dimensions: every
 * elementary interval of area 2^-m (2^a x 2^(m-a) cells) holds exactly one point, for
 * m = 1..12, several seeds and pixels, the pairs (0,1), (2,3), (6,7). */
TEST(sobol_pairs_are_02_nets)
{
    enum { MMAX = 12, N = 1 << MMAX };
    static double u[2 * N][8];
    static unsigned char cell[N];
    const uint64_t seeds[] = {1, 77}, pixels[] = {0, 12345, 999999};
    const int pairs[] = {0, 1, 3};
    for (int si = 0; si < 2; si++)
        for (int pi = 0; pi < 3; pi++) {
            for (uint32_t i = 0; i < 2 * N; i++) {
                rng g = rng_make_qmc(seeds[si], pixels[pi], i, 8);
                for (int d = 0; d < 8; d++)
                    u[i][d] = rng_next(&g);
            }
            for (int m = 1; m <= MMAX; m++)
                for (uint32_t start = 0; start <= (1u << m); start += 1u << m)
                    for (int q = 0; q < 3; q++)
                        for (int a = 0; a <= m; a++) {
                            int d0 = 2 * pairs[q], d1 = d0 + 1;
                            memset(cell, 0, (size_t)1 << m);
                            for (uint32_t i = start; i < start + (1u << m); i++) {
                                uint32_t cx = (uint32_t)(u[i][d0] * (double)(1u << a));
                                uint32_t cy = (uint32_t)(u[i][d1] * (double)(1u << (m - a)));
                                uint32_t c = (cx << (m - a)) | cy;
                                if (cell[c])
                                    TEST_FAIL("seed %llu pixel %llu dims (%d,%d) samples [%u, %u): two points in "
                                              "cell %u of the %d x %d grid",
                                              (unsigned long long)seeds[si], (unsigned long long)pixels[pi], d0, d1,
                                              start, start + (1u << m), c, 1 << a, 1 << (m - a));
                                cell[c] = 1;
                            }
                        }
        }
}

/* Pearson correlation of n pairs. */
static double correlation(const double *x, const double *y, int n)
{
    double mx = 0.0, my = 0.0;
    for (int i = 0; i < n; i++) {
        mx += x[i];
        my += y[i];
    }
    mx /= n;
    my /= n;
    double sxy = 0.0, sxx = 0.0, syy = 0.0;
    for (int i = 0; i < n; i++) {
        sxy += (x[i] - mx) * (y[i] - my);
        sxx += (x[i] - mx) * (x[i] - mx);
        syy += (y[i] - my) * (y[i] - my);
    }
    return sxy / sqrt(sxx * syy);
}

/* Over many pixels, one sample index: each scrambled coordinate is uniform (chi-square, 64
 * bins, 63 degrees of freedom, reject above ~116, the 0.9999 quantile), and coordinates
 * of different dimensions are uncorrelated: the correlation of n independent pairs has
 * standard error 1 / sqrt(n), bound 5 / sqrt(n). */
TEST(sobol_uniform_over_pixels)
{
    enum { BINS = 64, NPIX = 128000, DIMS = 8 };
    static double u[DIMS][NPIX];
    const uint32_t indices[] = {0, 5, 1000};
    for (int k = 0; k < 3; k++) {
        for (int p = 0; p < NPIX; p++) {
            rng g = rng_make_qmc(3, (uint64_t)p, indices[k], DIMS);
            for (int d = 0; d < DIMS; d++) {
                u[d][p] = rng_next(&g);
                ASSERT_TRUE(u[d][p] >= 0.0 && u[d][p] < 1.0);
            }
        }
        for (int d = 0; d < DIMS; d++) {
            long hist[BINS] = {0};
            for (int p = 0; p < NPIX; p++)
                hist[(int)(u[d][p] * BINS)]++;
            double chi2 = 0.0, expect = (double)NPIX / BINS;
            for (int b = 0; b < BINS; b++)
                chi2 += ((double)hist[b] - expect) * ((double)hist[b] - expect) / expect;
            if (chi2 > 116.0)
                TEST_FAIL("index %u dimension %d: chi-square %.1f > 116 over %d pixels", indices[k], d, chi2, NPIX);
        }
        const int da[] = {0, 0, 1, 2, 0}, db[] = {1, 2, 3, 5, 7};
        for (int c = 0; c < 5; c++) {
            double r = correlation(u[da[c]], u[db[c]], NPIX);
            if (fabs(r) > 5.0 / sqrt((double)NPIX))
                TEST_FAIL("index %u: correlation of dimensions %d and %d over pixels %.4f > %.4f", indices[k], da[c],
                          db[c], r, 5.0 / sqrt((double)NPIX));
        }
    }
}

/* Within one pixel, dimensions of different pairs come from independently shuffled
 * sequences: their correlation over a pixel's n samples has mean 0 and a mean square of
 * order 1 / (n - 1) (that of a uniformly random pairing; nested shuffles give about 1.6
 * times it). Were the pairs not shuffled, dimensions 0 and 2 would both be scrambles of the
 * same van der Corput points, with a mean square correlation near 0.5. Checked over 2000
 * pixels: |mean| below 5 standard errors (from the spread over pixels), mean square below
 * 3 / (n - 1). */
TEST(sobol_pairs_independent_within_pixel)
{
    enum { NPIX = 2000, NS = 64 };
    double x[NS], y[NS], z[NS], sum = 0.0, sum2 = 0.0, sum_z2 = 0.0;
    for (int p = 0; p < NPIX; p++) {
        for (uint32_t i = 0; i < NS; i++) {
            rng g = rng_make_qmc(9, (uint64_t)p, i, 6);
            x[i] = rng_next(&g);
            (void)rng_next(&g);
            y[i] = rng_next(&g);
            (void)rng_next(&g);
            z[i] = rng_next(&g);
        }
        double r = correlation(x, y, NS), rz = correlation(x, z, NS);
        sum += r;
        sum2 += r * r;
        sum_z2 += rz * rz;
    }
    double mean = sum / NPIX, se = sqrt((sum2 / NPIX - mean * mean) / (NPIX - 1));
    fprintf(stderr, "dims 0, 2 within a pixel: mean correlation %.4f (se %.4f), mean square %.4f, dims 0, 4: %.4f; "
                    "1 / (n - 1) = %.4f\n",
            mean, se, sum2 / NPIX, sum_z2 / NPIX, 1.0 / (NS - 1));
    ASSERT_TRUE(fabs(mean) < 5.0 * se);
    ASSERT_TRUE(sum2 / NPIX < 3.0 / (NS - 1));
    ASSERT_TRUE(sum_z2 / NPIX < 3.0 / (NS - 1));
}

/* f(x, y) = exp(x) cos(y) - x y^2, whose integral over the unit square is (e - 1) sin 1 - 1/6. */
static double smooth(double x, double y) { return exp(x) * cos(y) - x * y * y; }

/* The estimate of a smooth 2-D integral with N = 1024 samples of one pixel, over 64 seeds:
 * from the Sobol pair (0,1), and from the pair (4,5), its spread is far below that of the
 * plain hash (Owen-scrambled nets: variance O(N^-3) against O(N^-1); the bound asks for a
 * variance ratio below 1/100, where theory gives ~1/1000 or less), and both are unbiased
 * (mean within 5 standard errors of the exact value). */
TEST(sobol_smooth_integral_variance)
{
    enum { N = 1024, SEEDS = 64 };
    const double exact = (exp(1.0) - 1.0) * sin(1.0) - 1.0 / 6.0;
    double est[3][SEEDS];
    for (int s = 0; s < SEEDS; s++) {
        double acc[3] = {0.0, 0.0, 0.0};
        for (uint32_t i = 0; i < N; i++) {
            rng q = rng_make_qmc(100 + (uint64_t)s, 42, i, 6);
            double u[6];
            for (int d = 0; d < 6; d++)
                u[d] = rng_next(&q);
            acc[0] += smooth(u[0], u[1]);
            acc[1] += smooth(u[4], u[5]);
            rng g = rng_make(100 + (uint64_t)s, 42, i);
            double a = rng_next(&g), b = rng_next(&g);
            acc[2] += smooth(a, b);
        }
        for (int k = 0; k < 3; k++)
            est[k][s] = acc[k] / N;
    }
    double mean[3], var[3];
    for (int k = 0; k < 3; k++) {
        mean[k] = 0.0;
        for (int s = 0; s < SEEDS; s++)
            mean[k] += est[k][s] / SEEDS;
        var[k] = 0.0;
        for (int s = 0; s < SEEDS; s++)
            var[k] += (est[k][s] - mean[k]) * (est[k][s] - mean[k]) / (SEEDS - 1);
        ASSERT_NEAR(mean[k], exact, 5.0 * sqrt(var[k] / SEEDS) + 1e-12);
    }
    fprintf(stderr, "variance of the estimate: sobol (0,1) %.3g, (4,5) %.3g, hash %.3g\n", var[0], var[1], var[2]);
    ASSERT_TRUE(var[0] < 0.01 * var[2]);
    ASSERT_TRUE(var[1] < 0.01 * var[2]);
}

/* Past its Sobol dimensions, and with none, a QMC sequence is rng_make's. */
TEST(sobol_tail_is_the_hash)
{
    rng a = rng_make(5, 17, 3), b = rng_make_qmc(5, 17, 3, 8), c = rng_make_qmc(5, 17, 3, 0);
    int differ = 0;
    for (int d = 0; d < 40; d++) {
        double x = rng_next(&a), y = rng_next(&b), z = rng_next(&c);
        ASSERT_TRUE(x == z);
        if (d >= 8)
            ASSERT_TRUE(x == y);
        else
            differ += x != y;
    }
    ASSERT_EQ_INT(differ, 8);
}

/* The path tracer's walk (brume slab) driven by the Sobol sampler still meets the published
 * slab tables of tests/test_validation.c within 5 standard errors (the standard error of
 * independent samples, which scrambled nets do not exceed here), keeps energy when nothing
 * is absorbed, and does not depend on the thread count. */
static slab_result slab_sobol(double albedo, double tau, double g, uint64_t samples, int threads)
{
    phase *ph = phase_new_hg(g);
    slab_params p = {albedo, tau, ph, samples, 12345, threads, 1 << 30, BRUME_SAMPLER_SOBOL};
    slab_result r;
    ASSERT_EQ_INT(slab_run(&p, &r), BRUME_OK);
    phase_release(ph);
    return r;
}

TEST(sobol_slab_validation)
{
    slab_result r = slab_sobol(0.9, 2.0, 0.75, 4000000, 0); /* van de Hulst 1980, Table 35 */
    fprintf(stderr, "Rd %.6f +- %.6f (0.09739), Tt %.6f +- %.6f (0.66096)\n", r.Rd, r.Rd_stderr, r.Tt, r.Tt_stderr);
    ASSERT_NEAR(r.Rd, 0.09739, 5.0 * r.Rd_stderr + 5e-6);
    ASSERT_NEAR(r.Tt, 0.66096, 5.0 * r.Tt_stderr + 5e-6);
    ASSERT_TRUE(5.0 * r.Rd_stderr < 0.01 * 0.09739);
    r = slab_sobol(0.9, 1.0, 0.8, 4000000, 0); /* Prahl's adding-doubling */
    ASSERT_NEAR(r.Rd, 0.04242, 5.0 * r.Rd_stderr + 5e-6);
    ASSERT_NEAR(r.Tt, 0.84561, 5.0 * r.Tt_stderr + 5e-6);
    r = slab_sobol(1.0, 3.0, 0.9, 200000, 0); /* white furnace */
    ASSERT_NEAR(r.Rd + r.Tt, 1.0, 1e-12);
    slab_result r1 = slab_sobol(0.9, 1.0, 0.5, 100000, 1), r2 = slab_sobol(0.9, 1.0, 0.5, 100000, 2);
    ASSERT_TRUE(r1.Rd == r2.Rd && r1.Tt == r2.Tt && r1.Rd_stderr == r2.Rd_stderr);
}

static const char *scene_json(const char *sampler)
{
    static char buf[1024];
    snprintf(buf, sizeof buf,
             "{\"camera\": {\"position\": [0, -3, 0], \"look_at\": [0, 0, 0], \"up\": [0, 0, 1], \"fov\": 30},"
             " \"lights\": [{\"type\": \"distant\", \"direction\": [0, 1, -1], \"irradiance\": 3}],"
             " \"media\": [{\"density\": {\"type\": \"constant\", \"value\": 1,"
             " \"bounds\": [[-0.5, -0.5, -0.5], [0.5, 0.5, 0.5]]}, \"sigma_a\": 0.5, \"sigma_s\": 3}],"
             " \"render\": {\"width\": 24, \"height\": 24, \"spp\": 16, \"threads\": 2%s%s%s}}",
             sampler ? ", \"sampler\": \"" : "", sampler ? sampler : "", sampler ? "\"" : "");
    return buf;
}

/* render.sampler: sobol is the default, independent differs, an unknown name is an error
 * naming the key; the two samplers agree on the image's mean within its standard error. */
TEST(sobol_render_option)
{
    brume_scene *s = NULL;
    const char *path = test_tmp_path("sampler.json");
    test_write_file(path, scene_json(NULL));
    ASSERT_EQ_INT(brume_scene_load(NULL, &(brume_source){.path = path}, NULL, &s), BRUME_OK);
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    ASSERT_EQ_INT(rs.sampler, BRUME_SAMPLER_SOBOL); /* the default */
    brume_scene_release(s);
    test_write_file(path, scene_json("halton"));
    brume_context *ctx = brume_context_new();
    ASSERT_TRUE(brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK);
    fprintf(stderr, "%s\n", brume_context_last_error(ctx));
    ASSERT_TRUE(strstr(brume_context_last_error(ctx), "render.sampler: unknown sampler 'halton'") != NULL);
    brume_context_release(ctx);

    struct brume_image *a = test_render_json(scene_json("sobol"), 3);
    struct brume_image *b = test_render_json(scene_json("independent"), 3);
    struct brume_image *c = test_render_json(scene_json(NULL), 3);
    const float *pa = brume_image_pixels(a), *pb = brume_image_pixels(b), *pc = brume_image_pixels(c);
    int n = 24 * 24;
    ASSERT_TRUE(memcmp(pa, pc, sizeof(float) * 4 * (size_t)n) == 0);
    ASSERT_TRUE(memcmp(pa, pb, sizeof(float) * 4 * (size_t)n) != 0);
    for (int ch = 0; ch < 3; ch++) {
        double ma, sa, mb, sb;
        test_channel_mean(pa, n, ch, &ma, &sa);
        test_channel_mean(pb, n, ch, &mb, &sb);
        ASSERT_TRUE(ma > 0.0);
        ASSERT_NEAR(ma, mb, 5.0 * sqrt(sa * sa + sb * sb));
    }
    brume_image_release(a);
    brume_image_release(b);
    brume_image_release(c);
}

/* Under sobol, a pixel's sample indices continue across passes and checkpoints: a job of
 * 3 + 5 samples, saved after the first pass and resumed, ends with the bytes of one render
 * of 8, with 1 and 2 threads; a checkpoint made under sobol is refused under independent. */
static brume_scene *sobol_scene(brume_context *ctx, brume_sampler sampler, int threads)
{
    brume_scene *s = NULL;
    ASSERT_EQ_INT(brume_scene_load(ctx, NULL, NULL, &s), BRUME_OK);
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    rs.width = 40;
    rs.height = 24;
    rs.spp = 8;
    rs.threads = threads;
    rs.sampler = sampler;
    if (brume_scene_set_settings(ctx, s, &rs) != BRUME_OK || brume_scene_commit(ctx, s) != BRUME_OK)
        TEST_FAIL("scene: %s", brume_context_last_error(ctx));
    return s;
}

TEST(sobol_passes_and_resume)
{
    brume_context *ctx = brume_context_new();
    const char *ck = test_tmp_path("sobol.ckpt");
    for (int threads = 1; threads <= 2; threads++) {
        brume_scene *s = sobol_scene(ctx, BRUME_SAMPLER_SOBOL, threads);
        brume_image *full = NULL, *img = NULL;
        ASSERT_EQ_INT(brume_render(ctx, s, &full), BRUME_OK);
        brume_render_job *job = NULL;
        ASSERT_EQ_INT(brume_render_begin(ctx, s, &job), BRUME_OK);
        ASSERT_EQ_INT(brume_render_job_add(ctx, job, 3), BRUME_OK);
        ASSERT_EQ_INT(brume_render_job_save(ctx, job, 7, ck), BRUME_OK);
        brume_render_job_release(job);
        ASSERT_EQ_INT(brume_render_job_resume(ctx, s, 7, ck, &job), BRUME_OK);
        ASSERT_EQ_INT(brume_render_job_add(ctx, job, 5), BRUME_OK);
        ASSERT_EQ_INT(brume_render_job_image(ctx, job, &img), BRUME_OK);
        size_t n = (size_t)brume_image_width(full) * (size_t)brume_image_height(full) * 4;
        ASSERT_TRUE(memcmp(brume_image_pixels(full), brume_image_pixels(img), n * sizeof(float)) == 0);
        brume_image_release(img);
        brume_image_release(full);
        brume_render_job_release(job);
        brume_scene_release(s);
    }
    brume_scene *si = sobol_scene(ctx, BRUME_SAMPLER_INDEPENDENT, 2);
    brume_render_job *job = NULL;
    ASSERT_EQ_INT(brume_render_job_resume(ctx, si, 7, ck, &job), BRUME_ERROR_STATE);
    ASSERT_TRUE(strstr(brume_context_last_error(ctx), "render.sampler") != NULL);
    ASSERT_TRUE(job == NULL);
    brume_scene_release(si);
    brume_context_release(ctx);
}

TEST_MAIN(sobol_direction_numbers, sobol_scramble_nested, sobol_pairs_are_02_nets, sobol_uniform_over_pixels,
          sobol_pairs_independent_within_pixel, sobol_smooth_integral_variance, sobol_tail_is_the_hash,
          sobol_slab_validation, sobol_render_option, sobol_passes_and_resume)
