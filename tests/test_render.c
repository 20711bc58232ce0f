/* test_render.c - the renderer end to end: determinism across threads, and estimators
 * checked against closed forms with tolerances from their own variance. */
#include "test.h"

#include <unistd.h>

#include "brume.h"
#include "core/error.h"
#include "render/integrator.h"
#include "scene/scene.h"
#include "render/track.h"

/* Built-in default scene at a small size, 1 vs 2 threads: bit-identical pixels. */
TEST(threads_do_not_change_the_image)
{
    brume_image *img[3];
    for (int k = 0; k < 3; k++) {
        brume_context *ctx = brume_context_new();
        brume_scene *s = NULL;
        ASSERT_EQ_INT(brume_scene_load(ctx, NULL, NULL, &s), BRUME_OK);
        brume_render_settings rs;
        brume_scene_settings(s, &rs);
        rs.width = 48;
        rs.height = 32;
        rs.spp = 2;
        ASSERT_EQ_INT(brume_scene_set_settings(ctx, s, &rs), BRUME_OK);
        img[k] = test_render_scene(s, k == 0 ? 1 : 2, k == 2 ? 99 : 1);
        brume_scene_release(s);
        brume_context_release(ctx);
    }
    size_t n = 48 * 32 * 4;
    ASSERT_TRUE(memcmp(brume_image_pixels(img[0]), brume_image_pixels(img[1]), n * sizeof(float)) == 0);
    /* a different seed gives a different image: the comparison above can fail */
    ASSERT_TRUE(memcmp(brume_image_pixels(img[0]), brume_image_pixels(img[2]), n * sizeof(float)) != 0);
    for (int k = 0; k < 3; k++)
        brume_image_release(img[k]);
}

/* A purely absorbing box of fog (sigma_a = 1.5, length 2 along the view) in front of a
 * constant background B: every covered pixel has expectation B exp(-3) per channel and
 * alpha 1 - exp(-3). Each sample is B or 0 (absorbed), a Bernoulli with p = exp(-3);
 * the tolerance is 5 standard errors of the image mean. */
TEST(absorbing_fog_closed_form)
{
    const char *json = "{\"camera\": {\"position\": [0, 0, 10], \"look_at\": [0, 0, 0], \"fov\": 5},"
                       " \"background\": [2.0, 1.0, 0.5],"
                       " \"media\": [{\"sigma_a\": 1.5, \"sigma_s\": 0,"
                       "   \"density\": {\"type\": \"constant\", \"bounds\": [[-5, -5, -1], [5, 5, 1]]}}],"
                       " \"render\": {\"width\": 32, \"height\": 32, \"spp\": 64}}";
    brume_image *img = test_render_json(json, 5);
    const float *px = brume_image_pixels(img);
    int n = 32 * 32;
    double T = exp(-3.0), bg[3] = {2.0, 1.0, 0.5};
    for (int c = 0; c < 3; c++) {
        double mean = 0.0;
        for (int i = 0; i < n; i++)
            mean += px[4 * i + c];
        mean /= n;
        double se = bg[c] * sqrt(T * (1.0 - T) / (n * 64.0));
        ASSERT_NEAR(mean, bg[c] * T, 5.0 * se);
    }
    /* alpha = 1 - ratio-tracked transmittance: with a majorant equal to sigma_t each
     * estimate is 0 or 1, a Bernoulli with mean T */
    double alpha = 0.0;
    for (int i = 0; i < n; i++)
        alpha += px[4 * i + 3];
    ASSERT_NEAR(alpha / n, 1.0 - T, 5.0 * sqrt(T * (1.0 - T) / (n * 8.0))); /* 8 alpha samples a pixel */
    brume_image_release(img);
}

/* A furnace: renders json with `seed` and asserts, for channels c0 .. c1 - 1, that the
 * image mean is expect[c] within 5 standard errors (plus 1e-6) and that 5 standard errors
 * are below rel_tol expect[c], so an energy error of rel_tol cannot pass. */
static void check_furnace(const char *json, uint64_t seed, const double expect[3], int c0, int c1, double rel_tol)
{
    brume_image *img = test_render_json(json, seed);
    const float *px = brume_image_pixels(img);
    for (int c = c0; c < c1; c++) {
        double mean, se;
        test_channel_mean(px, 32 * 32, c, &mean, &se);
        fprintf(stderr, "channel %d: mean %.5f, standard error %.5f, expected %.3f\n", c, mean, se, expect[c]);
        ASSERT_NEAR(mean, expect[c], 5.0 * se + 1e-6);
        ASSERT_TRUE(5.0 * se < rel_tol * expect[c]);
    }
    brume_image_release(img);
}

/* White furnace: a heterogeneous medium with albedo 1 in every channel (but a different
 * extinction per channel, so spectral tracking is exercised), lit only by a constant
 * background of radiance 1: every pixel's expectation is exactly 1. */
static const char white_furnace_json[] = /* %s: more settings; %d: spp */
    "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 30},"
    " \"background\": 1.0,%s"
    " \"media\": [{\"sigma_a\": 0, \"sigma_s\": [8, 4, 2],"
    "   \"density\": {\"type\": \"procedural_cloud\", \"resolution\": 24, \"seed\": 3},"
    "   \"phase\": {\"type\": \"hg\", \"g\": 0.5}}],"
    " \"render\": {\"width\": 32, \"height\": 32, \"spp\": %d, \"max_depth\": 100000}}";

TEST(white_furnace)
{
    char json[1024];
    snprintf(json, sizeof json, white_furnace_json, "", 96);
    const double one[3] = {1.0, 1.0, 1.0};
    check_furnace(json, 11, one, 0, 3, 0.01); /* a 1 % energy error fails */
}

/* An emitting furnace: a heterogeneous, chromatic, absorbing and scattering cloud whose
 * emission Le equals the background B. The uniform field L = B solves the equation (what
 * sigma_a removes, sigma_a Le puts back; scattering moves uniform radiance around), so
 * every pixel's expectation is B per channel. Exercises the emission term at every
 * tentative collision, weighted by the flight's ratio-tracked transmittance. */
TEST(emitting_furnace)
{
    const char *json = "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 30},"
                       " \"background\": [0.5, 0.8, 0.3],"
                       " \"media\": [{\"sigma_a\": [3, 1, 2], \"sigma_s\": [2, 6, 1], \"emission\": [0.5, 0.8, 0.3],"
                       "   \"density\": {\"type\": \"procedural_cloud\", \"resolution\": 24, \"seed\": 8},"
                       "   \"phase\": {\"type\": \"hg\", \"g\": 0.3}}],"
                       " \"render\": {\"width\": 32, \"height\": 32, \"spp\": 64, \"max_depth\": 100000}}";
    const double B[3] = {0.5, 0.8, 0.3};
    check_furnace(json, 12, B, 0, 3, 0.01);
}

/* Gray white furnace with an isotropic medium, dense enough that most paths scatter many
 * times: every pixel's expectation is the background, 0.75. Next-event estimation of the
 * background and phase sampling share the work through MIS, so a sample is not exactly
 * 0.75; the image mean must be within 5 standard errors, and those below 0.5 %. */
TEST(white_furnace_gray)
{
    const char *json = "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 30},"
                       " \"background\": 0.75,"
                       " \"media\": [{\"sigma_a\": 0, \"sigma_s\": 30,"
                       "   \"density\": {\"type\": \"procedural_cloud\", \"resolution\": 24, \"seed\": 4}}],"
                       " \"render\": {\"width\": 32, \"height\": 32, \"spp\": 128, \"max_depth\": 100000}}";
    const double bg[3] = {0.75, 0.75, 0.75};
    check_furnace(json, 2, bg, 1, 2, 0.005);
}

/* Single scattering in a thin homogeneous slab seen head-on, lit by a distant light from
 * behind the camera at angle: for optical depth tau along the view and the light path the
 * single-scattered radiance has a closed form (see the derivation in the comment below). */
TEST(single_scattering_closed_form)
{
    /* Slab z in [-d, 0] with sigma_s = s, sigma_a = 0; camera looks along -z; the light
     * travels along -z too (straight behind the camera), so light and view paths inside the
     * slab have equal length to depth z. Radiance scattered back toward the camera
     * (cos = -1 between propagation directions) from depth x: E p(-1) s exp(-2 s x), so
     *   L = E p(-1) s int_0^d exp(-2 s x) dx = E p(-1) (1 - exp(-2 s d)) / 2. */
    const char *json = "{\"camera\": {\"position\": [0, 0, 20], \"look_at\": [0, 0, 0], \"fov\": 2},"
                       " \"lights\": [{\"type\": \"distant\", \"direction\": [0, 0, -1], \"irradiance\": 3.0}],"
                       " \"media\": [{\"sigma_a\": 0, \"sigma_s\": 0.8,"
                       "   \"density\": {\"type\": \"constant\", \"bounds\": [[-50, -50, -1], [50, 50, 0]]},"
                       "   \"phase\": {\"type\": \"hg\", \"g\": -0.3}}],"
                       " \"render\": {\"width\": 16, \"height\": 16, \"spp\": 2560, \"method\": \"single\"}}";
    brume_image *img = test_render_json(json, 3);
    const float *px = brume_image_pixels(img);
    double g = -0.3, cos_t = -1.0;
    double p = (1 - g * g) / (4 * 3.14159265358979323846 * pow(1 + g * g - 2 * g * cos_t, 1.5));
    double expect = 3.0 * p * (1 - exp(-2 * 0.8 * 1.0)) / 2;
    int n = 16 * 16;
    double mean, se;
    test_channel_mean(px, n, 0, &mean, &se);
    fprintf(stderr, "single scattering: mean %.6f, expected %.6f, standard error %.6f\n", mean, expect, se);
    ASSERT_NEAR(mean, expect, 5.0 * se + 1e-9);
    ASSERT_TRUE(5.0 * se < 0.01 * expect);
    brume_image_release(img);
}

/* The same slab with a forward phase function (HG g = 0.6): p(-1) = 0.0124 is a sixth of
 * an isotropic phase function's 1 / (4 pi), so next-event estimation traces the shadow ray
 * with probability q = 4 pi p(-1) = 0.156 and divides by it (path.c, nee_roulette).
 * The tolerance is 5 standard errors of the image mean, which include the roulette's
 * variance; an estimate not divided by q would be 0.156 times the expectation. */
TEST(single_scattering_forward_hg_shadow_roulette)
{
    const char *json = "{\"camera\": {\"position\": [0, 0, 20], \"look_at\": [0, 0, 0], \"fov\": 2},"
                       " \"lights\": [{\"type\": \"distant\", \"direction\": [0, 0, -1], \"irradiance\": 3.0}],"
                       " \"media\": [{\"sigma_a\": 0, \"sigma_s\": 0.8,"
                       "   \"density\": {\"type\": \"constant\", \"bounds\": [[-50, -50, -1], [50, 50, 0]]},"
                       "   \"phase\": {\"type\": \"hg\", \"g\": 0.6}}],"
                       " \"render\": {\"width\": 16, \"height\": 16, \"spp\": 2560, \"method\": \"single\"}}";
    brume_image *img = test_render_json(json, 5);
    const float *px = brume_image_pixels(img);
    double g = 0.6, cos_t = -1.0;
    double p = (1 - g * g) / (4 * 3.14159265358979323846 * pow(1 + g * g - 2 * g * cos_t, 1.5));
    double expect = 3.0 * p * (1 - exp(-2 * 0.8 * 1.0)) / 2;
    double mean, se;
    test_channel_mean(px, 16 * 16, 0, &mean, &se);
    fprintf(stderr, "single scattering, g 0.6: mean %.6f, expected %.6f, standard error %.6f\n", mean, expect, se);
    ASSERT_NEAR(mean, expect, 5.0 * se + 1e-9);
    ASSERT_TRUE(5.0 * se < 0.03 * expect);
    brume_image_release(img);
}

/* The 12^3 grid of rho in [0.3, 1] over [-1, 1]^3 that the tests below share; skewed,
 * rho' = 1 - 0.7 x^4 with x = (rho - 0.3) / 0.7, also in [0.3, 1] but mostly near 1, with
 * narrow dips. */
enum { POSITIVE_N = 12 };
static void positive_grid_data(float *data, bool skewed)
{
    enum { N = POSITIVE_N };
    for (int k = 0; k < N; k++)
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++) {
                double rho = 0.65 + 0.35 * sin(1.7 * i + 0.9 * j) * cos(1.3 * k - 0.4 * i);
                const double x = (rho - 0.3) / 0.7;
                data[i + N * (j + N * k)] = (float)(skewed ? 1.0 - 0.7 * x * x * x * x : rho);
            }
}

/* A committed scene of one medium m in that grid (trilinear). */
static brume_scene *positive_grid_scene_of(brume_context *ctx, const char *name, brume_medium m, bool skewed)
{
    enum { N = POSITIVE_N };
    static float data[N * N * N];
    positive_grid_data(data, skewed);
    brume_scene *s = NULL;
    brume_density *d = NULL;
    const double bounds[6] = {-1, -1, -1, 1, 1, 1};
    ASSERT_EQ_INT(brume_scene_new(ctx, name, &s), BRUME_OK);
    ASSERT_EQ_INT(brume_density_new_array(ctx, data, N, N, N, bounds, BRUME_GRID_TRILINEAR, NULL, NULL, &d), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_add_medium(ctx, s, &m, d, NULL), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    return s;
}

static brume_scene *positive_grid_scene(brume_context *ctx, const char *name, brume_medium m)
{
    return positive_grid_scene_of(ctx, name, m, false);
}

/* Residual ratio tracking against the closed form: a grid with rho in [0.3, 1] everywhere
 * (so its cells have a positive minorant and the control optical depth carries most of the
 * estimate), chromatic sigma_t = (1, 1.5, 2) so the control takes the smallest channel and
 * the others keep a residual. T = exp(-sigma_t int rho) per channel, the integral by a
 * 200,000-point midpoint rule; the mean of 50,000 estimates (800,000 for the skewed grid,
 * where the wrong rate is off by 3 %) must be within 5 standard
 * errors (plus 1e-6) of it, and those below 5 % of T. Then the same with gray sigma_t = 1.5,
 * in the grid and in its skewed version: the cells' means lie nearer their minima in one and
 * nearer their maxima in the other, so the rate max(sigma_maj - sigma_c', sigma_c' -
 * sigma_c) takes either side, and no estimate may be negative (each factor lies in [0, 2]).
 * Dropping the control's exp(-tau_c) makes the mean miss by far more; taking the rate
 * sigma_maj - sigma_c' misses by 8 standard errors on the skewed grid. */
TEST(residual_ratio_tracking_transmittance)
{
    for (int v = 0; v < 3; v++) {
    const int skewed = v == 2;
    const brume_medium m = v == 0 ? (brume_medium){.sigma_a = {0.5, 0.75, 1}, .sigma_s = {0.5, 0.75, 1}}
                                  : (brume_medium){.sigma_a = {0.75, 0.75, 0.75}, .sigma_s = {0.75, 0.75, 0.75}};
    brume_context *ctx = brume_context_new();
    brume_scene *s = positive_grid_scene_of(ctx, "rrt", m, skewed);
    ray r = {v3(-1.5, -0.3, -0.9), v3_normalize(v3(1.0, 0.2, 0.55)), 0.0};
    double t0, t1;
    ASSERT_TRUE(box3_intersect((box3){v3(-1, -1, -1), v3(1, 1, 1)}, r, 0.0, INFINITY, &t0, &t1));
    const int Q = 200000;
    double tau_rho = 0.0;
    for (int q = 0; q < Q; q++)
        tau_rho += density_eval(s->media[0].rho, ray_at(r, t0 + (t1 - t0) * (q + 0.5) / Q));
    tau_rho *= (t1 - t0) / Q;
    const int M = skewed ? 800000 : 50000;
    double sum[3] = {0}, sq[3] = {0}, lowest = INFINITY;
    for (int n = 0; n < M; n++) {
        rng g = rng_make(17, (uint64_t)n, 0);
        color T = track_transmittance(s, 0, r, INFINITY, &g);
        for (int c = 0; c < 3; c++) {
            sum[c] += T.c[c];
            sq[c] += T.c[c] * T.c[c];
            lowest = fmin(lowest, T.c[c]);
        }
    }
    ASSERT_TRUE(lowest >= 0.0); /* every factor in [0, 2] */
    const double sigma_t[3] = {v ? 1.5 : 1, 1.5, v ? 1.5 : 2};
    for (int c = 0; c < 3; c++) {
        double mean = sum[c] / M, se = sqrt(fmax(0.0, sq[c] / M - mean * mean) / M);
        double T = exp(-sigma_t[c] * tau_rho);
        fprintf(stderr, "case %d, channel %d: mean %.6g, standard error %.3g, closed form %.6g\n", v, c, mean, se, T);
        ASSERT_NEAR(mean, T, 5.0 * se + 1e-6);
        ASSERT_TRUE(5.0 * se < 0.05 * T);
    }
    brume_scene_release(s);
    brume_context_release(ctx);
    }
}

/* The flight's delta tail (flight.c; docs/path-tracer.md, "The flight's delta tail")
 * changes how a flight's weights are drawn, not their expectations. One ray through the
 * heterogeneous grid above, in a medium of gray extinction sigma_t = 1.5 and chromatic
 * albedo; with T(t) the transmittance to t, the expectations are closed forms up to
 * quadrature: the escaping weight E[Tr] = T(end), the scattering weight
 * E[beta_s] = (sigma_s / sigma_t) (1 - T(end)), and where the flight scatters,
 * E[beta_s (t - t0)] = (sigma_s / sigma_t) int (t - t0) sigma_t rho T dt. Each must hold
 * within 5 standard errors (those under 3 % of the value) for pure ratio tracking (no
 * tail), the path tracer's tail and a tail from the first collision. The last is delta
 * tracking, whose scattering weight is exactly the albedo: that it is shows the tail runs. */
TEST(flight_delta_tail_unbiased)
{
    const double sigma_t = 1.5, sigma_s[3] = {0.6, 0.9, 1.2};
    brume_context *ctx = brume_context_new();
    brume_scene *s =
        positive_grid_scene(ctx, "tail", (brume_medium){.sigma_a = {0.9, 0.6, 0.3}, .sigma_s = {0.6, 0.9, 1.2}});
    ASSERT_TRUE(s->flight_control);
    ray r = {v3(-1.5, -0.3, -0.9), v3_normalize(v3(1.0, 0.2, 0.55)), 0.0};
    double t0, t1;
    ASSERT_TRUE(box3_intersect((box3){v3(-1, -1, -1), v3(1, 1, 1)}, r, 0.0, INFINITY, &t0, &t1));
    const int Q = 200000;
    const double dt = (t1 - t0) / Q;
    double tau = 0.0, S = 0.0, M1 = 0.0; /* optical depth; int sigma_t rho T; int (t - t0) sigma_t rho T */
    for (int q = 0; q < Q; q++) {
        double t = t0 + (q + 0.5) * dt, k = sigma_t * density_eval(s->media[0].rho, ray_at(r, t));
        double T = exp(-(tau + 0.5 * k * dt)); /* at the step's midpoint */
        S += k * T * dt;
        M1 += (t - t0) * k * T * dt;
        tau += k * dt;
    }
    const double T_end = exp(-tau);
    fprintf(stderr, "optical depth %.4f: T(end) %.5f, 1 - T(end) %.5f (quadrature %.5f), moment %.5f\n", tau, T_end,
            1.0 - T_end, S, M1);
    ASSERT_NEAR(S, 1.0 - T_end, 1e-6);
    const double tails[3] = {0.0, FLIGHT_TAIL_TR, 2.0};
    const int M = 400000;
    for (int v = 0; v < 3; v++) {
        double sum[7] = {0}, sq[7] = {0};
        double worst = 0.0; /* delta tracking: largest |beta_s - albedo| */
        for (int n = 0; n < M; n++) {
            rng g = rng_make(23, (uint64_t)n, (uint64_t)v), ug = rng_make(29, (uint64_t)n, (uint64_t)v);
            flight f = {.s = s, .g = &g, .beta = col(1.0), .L = col(0.0), .tail_Tr = tails[v]};
            bool scattered = flight_run(&f, r, INFINITY, &ug);
            double x[7] = {f.Tr.c[0]};
            for (int c = 0; c < 3; c++) {
                x[1 + c] = scattered ? f.beta_s.c[c] : 0.0;
                x[4 + c] = scattered ? f.beta_s.c[c] * (f.t - t0) : 0.0;
                if (scattered)
                    worst = fmax(worst, fabs(f.beta_s.c[c] - sigma_s[c] / sigma_t));
            }
            for (int i = 0; i < 7; i++) {
                sum[i] += x[i];
                sq[i] += x[i] * x[i];
            }
        }
        double expect[7] = {T_end};
        for (int c = 0; c < 3; c++) {
            expect[1 + c] = sigma_s[c] / sigma_t * S;
            expect[4 + c] = sigma_s[c] / sigma_t * M1;
        }
        for (int i = 0; i < 7; i++) {
            double mean = sum[i] / M, se = sqrt(fmax(0.0, sq[i] / M - mean * mean) / M);
            fprintf(stderr, "tail %.1f, estimate %d: mean %.6g, standard error %.3g, closed form %.6g\n", tails[v], i,
                    mean, se, expect[i]);
            ASSERT_NEAR(mean, expect[i], 5.0 * se + 1e-6);
            ASSERT_TRUE(5.0 * se < 0.03 * expect[i]);
        }
        if (v == 2)
            ASSERT_TRUE(worst < 1e-12);
        else if (v == 0)
            ASSERT_TRUE(worst > 0.01); /* ratio tracking's weights vary */
    }
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* The grid of rho in [0.3, 1] above, written as a raw file for scene text; returns its path. */
static const char *write_positive_grid(void)
{
    static float data[POSITIVE_N * POSITIVE_N * POSITIVE_N];
    positive_grid_data(data, false);
    const char *path = test_tmp_path("positive.raw");
    FILE *f = fopen(path, "wb");
    ASSERT_TRUE(f && fwrite(data, sizeof data, 1, f) == 1);
    fclose(f);
    return path;
}

/* Furnaces whose extinction is gray but whose albedo and emission are not, in the grid
 * above (every cell has a positive minorant, so most collisions are the control medium's,
 * which need no lookup and weigh sigma_s / sigma_t and sigma_a Le / sigma_t): with albedo 1
 * and a background of 1 every pixel's expectation is 1; with Le = B it is B per channel, as
 * in emitting_furnace. A 5 % error in the control collisions' weights fails both. */
TEST(furnaces_gray_extinction)
{
    const char *path = write_positive_grid();
    char json[2048];
    const char *media[2] = {"\"sigma_a\": 0, \"sigma_s\": 6",
                            "\"sigma_a\": [3, 1, 2], \"sigma_s\": [2, 4, 3], \"emission\": [0.5, 0.8, 0.3]"};
    const char *bg[2] = {"1", "[0.5, 0.8, 0.3]"};
    const double expect[2][3] = {{1, 1, 1}, {0.5, 0.8, 0.3}};
    for (int v = 0; v < 2; v++) {
        snprintf(json, sizeof json,
                 "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 30},"
                 " \"background\": %s,"
                 " \"media\": [{%s,"
                 "   \"density\": {\"type\": \"grid\", \"file\": \"%s\", \"format\": \"raw\", \"dims\": [12, 12, 12],"
                 "                \"bounds\": [[-1, -1, -1], [1, 1, 1]]},"
                 "   \"phase\": {\"type\": \"hg\", \"g\": 0.3}}],"
                 " \"render\": {\"width\": 32, \"height\": 32, \"spp\": 64, \"max_depth\": 100000}}",
                 bg[v], media[v], path);
        check_furnace(json, 13 + (uint64_t)v, expect[v], 0, 3, 0.01);
    }
    unlink(path);
}

/* Renders head VALUE tail (npix pixels, seed) for each of n values, with the mean of channel
 * 1 and its standard error over the pixels into mean[] and se[], and checks that every mean
 * agrees with the first within 5 standard errors of their difference, those under rel of
 * the first mean (tight enough to matter). */
static void option_means_agree(const char *key, const char *head, const char *const *values, int n,
                               const char *tail, int npix, uint64_t seed, double rel, double *mean, double *se)
{
    char json[1024];
    for (int k = 0; k < n; k++) {
        snprintf(json, sizeof json, "%s%s%s", head, values[k], tail);
        brume_image *img = test_render_json(json, seed);
        test_channel_mean(brume_image_pixels(img), npix, 1, &mean[k], &se[k]);
        fprintf(stderr, "%s %s: mean %.6f, standard error %.6f\n", key, values[k], mean[k], se[k]);
        brume_image_release(img);
    }
    for (int k = 1; k < n; k++) {
        double tol = 5.0 * sqrt(se[0] * se[0] + se[k] * se[k]);
        ASSERT_NEAR(mean[k], mean[0], tol);
        ASSERT_TRUE(tol < rel * mean[0]);
    }
}

/* json at 4 spp with 1 and 2 threads: the same npix pixels, bit for bit. */
static void same_image_for_threads(const char *json, int npix)
{
    brume_scene *s[2];
    brume_image *img[2];
    for (int k = 0; k < 2; k++) {
        ASSERT_EQ_INT(brume_scene_load(NULL, &(brume_source){.path = "<test>", .text = json}, NULL, &s[k]), BRUME_OK);
        brume_render_settings rs;
        brume_scene_settings(s[k], &rs);
        rs.spp = 4;
        ASSERT_EQ_INT(brume_scene_set_settings(NULL, s[k], &rs), BRUME_OK);
        img[k] = test_render_scene(s[k], k + 1, 7);
    }
    ASSERT_TRUE(memcmp(brume_image_pixels(img[0]), brume_image_pixels(img[1]), (size_t)npix * 4 * sizeof(float)) == 0);
    for (int k = 0; k < 2; k++) {
        brume_image_release(img[k]);
        brume_scene_release(s[k]);
    }
}

/* Sun-lobe sampling (path.c; docs/path-tracer.md, "Sun-lobe sampling") changes the
 * estimator, not its expectation. A homogeneous slab (thickness 1, sigma_s 2, sigma_a 0.1,
 * HG g = 0.9) lit by a delta sun 60 degrees off the vertical, seen head-on through a narrow
 * camera: every pixel has the same expectation, so the pixels' spread gives the image
 * mean's standard error. The camera looks against the forward lobe and sees mostly light
 * scattered several times, much of it carried by the lobe samples (a next-event estimate
 * not weighed against them by MIS counts that light twice, and the means part by far more
 * than the tolerance). With path.sun_lobe 0 (no lobe samples), the default 2 and 0.25
 * (lobe samples drawn with probabilities P well under 1, which the MIS weights must carry),
 * the means must agree within 5 standard errors of their difference, those under 3 % of
 * the mean, and the default's pixel variance must be under half that without lobe samples
 * (they are drawn and pay). The image stays the same for 1 and 2 threads. */
TEST(sun_lobe_sampling_unbiased)
{
    const char *head = "{\"camera\": {\"position\": [0, 0, 20], \"look_at\": [0, 0, 0], \"fov\": 2},"
                       " \"lights\": [{\"type\": \"distant\", \"direction\": [0.5, 0, 0.8660254], \"irradiance\": 3.0}],"
                       " \"media\": [{\"sigma_a\": 0.1, \"sigma_s\": 2,"
                       "   \"density\": {\"type\": \"constant\", \"bounds\": [[-50, -50, -1], [50, 50, 0]]},"
                       "   \"phase\": {\"type\": \"hg\", \"g\": 0.8}}],"
                       " \"path\": {\"sun_lobe\": ";
    const char *tail = "}, \"render\": {\"width\": 32, \"height\": 32, \"spp\": 128, \"max_depth\": 64}}";
    const char *const kappa[3] = {"0", "2", "0.25"};
    double mean[3], se[3];
    option_means_agree("sun_lobe", head, kappa, 3, tail, 32 * 32, 21, 0.03, mean, se);
    ASSERT_TRUE(se[1] * se[1] < 0.5 * se[0] * se[0]);
    char json[1024];
    snprintf(json, sizeof json, "%s2%s", head, tail);
    same_image_for_threads(json, 32 * 32);
}

/* The mean of channel 1 over a render of json at two seeds, and its standard error from the
 * pixels' differences between the two (valid when pixels have different expectations:
 * half the squared difference of a pixel estimates its variance). */
static void two_seed_mean(const char *json, uint64_t seed, int n, double *mean, double *se)
{
    brume_image *img[2];
    for (int k = 0; k < 2; k++)
        img[k] = test_render_json(json, seed + (uint64_t)k);
    const float *a = brume_image_pixels(img[0]), *b = brume_image_pixels(img[1]);
    double m = 0.0, v = 0.0;
    for (int i = 0; i < n; i++) {
        m += 0.5 * (a[4 * i + 1] + b[4 * i + 1]);
        v += 0.5 * (a[4 * i + 1] - b[4 * i + 1]) * (a[4 * i + 1] - b[4 * i + 1]);
    }
    *mean = m / n;
    *se = sqrt(v / 2.0) / n; /* the mean of two renders: half the variance of one */
    for (int k = 0; k < 2; k++)
        brume_image_release(img[k]);
}

/* Sun-lobe sampling with a surface inside the medium: the slab of
 * sun_lobe_sampling_unbiased lit from above, with an opaque diffuse plate across half of
 * it, 0.4 below its top, seen from below. Light reaches the slab under the plate round its
 * edge, and the lobe samples of vertices there (drawn towards the sun, so up into the
 * plate) must stop at it as the path's own flights do (lobe samples that went through it
 * to the sunlit medium above raised the mean by 24 %), and next-event estimates at
 * vertices on the plate must not be weighed against lobe samples. The camera sees both
 * halves, so the pixels differ: the standard error comes from two seeds per
 * configuration. Means with path.sun_lobe 0 and 2 must agree within 5 standard errors of
 * their difference, and those be under 4 % of the mean. */
TEST(sun_lobe_sampling_stops_at_surfaces)
{
    const char *head = "{\"camera\": {\"position\": [0, 0, -20], \"look_at\": [0, 0, 0], \"fov\": 4},"
                       " \"lights\": [{\"type\": \"distant\", \"direction\": [0.5, 0, -0.8660254], \"irradiance\": 3.0}],"
                       " \"media\": [{\"sigma_a\": 0.1, \"sigma_s\": 2,"
                       "   \"density\": {\"type\": \"constant\", \"bounds\": [[-50, -50, -1], [50, 50, 0]]},"
                       "   \"phase\": {\"type\": \"hg\", \"g\": 0.8}}],"
                       " \"surfaces\": [{\"type\": \"quad\", \"corner\": [-50, -50, -0.4], \"edge_u\": [50, 0, 0],"
                       "   \"edge_v\": [0, 100, 0], \"material\": {\"albedo\": 0.5}}],"
                       " \"path\": {\"sun_lobe\": ";
    const char *tail = "}, \"render\": {\"width\": 32, \"height\": 32, \"spp\": 128, \"max_depth\": 64}}";
    char json[1400];
    double mean[2], se[2];
    for (int k = 0; k < 2; k++) {
        snprintf(json, sizeof json, "%s%s%s", head, k == 0 ? "0" : "2", tail);
        two_seed_mean(json, 31 + 2 * (uint64_t)k, 32 * 32, &mean[k], &se[k]);
        fprintf(stderr, "sun_lobe %s: mean %.6f, standard error %.6f\n", k == 0 ? "0" : "2", mean[k], se[k]);
    }
    double tol = 5.0 * sqrt(se[0] * se[0] + se[1] * se[1]);
    ASSERT_NEAR(mean[1], mean[0], tol);
    ASSERT_TRUE(tol < 0.04 * mean[0]);
}

/* Camera rays that miss the world box of every medium's walks skip the path at once
 * (path_Li_alpha's cull), which must give what the whole path comes to, bit for bit. The
 * same scene with the medium keyframed by one identity key is not culled (moving media
 * are not) and moves nothing, so its image is the reference: cloud64.raw fills part of the
 * view and the sky the rest. Axis-aligned, so that the box is tight around the cloud's
 * cells and a box too small cuts the cloud (test_grid's check_majorants holds every walk
 * of rotated and re-placed grids inside the box). */
static brume_image *cull_scene_image(bool keyed)
{
    char json[2048];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0.2, -2.2, 0.3], \"look_at\": [0.05, 0, 0], \"up\": [0, 0, 1], \"fov\": 26},"
             " \"background\": [0.1, 0.2, 0.4],"
             " \"lights\": [{\"type\": \"distant\", \"direction\": [-0.5, 0.6, -0.62], \"irradiance\": 3}],"
             " \"media\": [{\"density\": {\"type\": \"grid\", \"file\": \"%s\", \"format\": \"raw\","
             "   \"dims\": [64, 64, 64], \"bounds\": [[-0.5, -0.5, -0.5], [0.5, 0.5, 0.5]]},"
             "   \"sigma_a\": 1, \"sigma_s\": 12, \"phase\": {\"type\": \"hg\", \"g\": 0.6}%s}],"
             " \"render\": {\"width\": 64, \"height\": 48, \"spp\": 2, \"max_depth\": 8}}",
             BRUME_DATA_DIR "/cloud64.raw",
             keyed ? ", \"keyframes\": [{\"time\": 0, \"transform\": {\"translate\": [0, 0, 0]}}]" : "");
    return test_render_json(json, 7);
}

TEST(camera_cull_changes_no_pixel)
{
    brume_image *culled = cull_scene_image(false), *full = cull_scene_image(true);
    const size_t n = (size_t)64 * 48 * 4;
    const float *a = brume_image_pixels(culled), *b = brume_image_pixels(full);
    size_t differ = 0, sky = 0;
    for (size_t i = 0; i < n; i += 4) {
        differ += memcmp(a + i, b + i, 4 * sizeof(float)) != 0;
        sky += a[i] == 0.1f && a[i + 1] == 0.2f && a[i + 2] == 0.4f && a[i + 3] == 0.0f;
    }
    if (differ)
        TEST_FAIL("%zu of %zu pixels differ from the unculled render", differ, n / 4);
    /* the view holds both: pixels that only see the sky, and pixels that see the cloud */
    ASSERT_TRUE(sky > n / 4 / 10 && sky < n / 4 * 9 / 10);
    brume_image_release(culled);
    brume_image_release(full);
}

/* The sun roulette's prediction (path_state.c, sun_tau_build; docs/path-tracer.md, "Sun rays
 * deep in a cloud") in a homogeneous box ([-1, 1]^3, sigma_t 3) under an oblique sun: the
 * exact transmittance from p is exp(-3 d(p)), d the distance to the box's face along the
 * direction to the sun. The prediction takes the least optical depth of the 8 grid nodes
 * around p, so it must lie between T(p) (the sweep may not overestimate the depth) and
 * T(p) exp(3 sum_a h_a / |w_a|), what d can change by within one cell of sides h_a. A box
 * thin to the sun (sigma_t 0.3, the roulette would act nowhere) and sun_roulette 0 get no
 * prediction (1), and points outside the box none either. */
static void *sun_state(brume_context *ctx, const char *sigma_s, const char *roulette, brume_scene **out)
{
    char json[1024];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},"
             " \"lights\": [{\"type\": \"distant\", \"direction\": [0.3, 0.4, -0.8660254], \"irradiance\": 1}],"
             " \"media\": [{\"sigma_a\": 0, \"sigma_s\": %s,"
             "   \"density\": {\"type\": \"constant\", \"bounds\": [[-1, -1, -1], [1, 1, 1]]}}],"
             " \"path\": {\"sun_roulette\": %s}}",
             sigma_s, roulette);
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = json}, NULL, &s) != BRUME_OK ||
        brume_scene_commit(ctx, s) != BRUME_OK)
        TEST_FAIL("scene: %s", brume_context_last_error(ctx));
    void *state = NULL;
    if (integrator_prepare(INTEGRATOR_PATH, s, &state) != BRUME_OK)
        TEST_FAIL("prepare: %s", err_message());
    *out = s;
    return state;
}

TEST(sun_roulette_prediction)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s;
    void *st = sun_state(ctx, "3", "0.03", &s);
    const vec3 w = v3_normalize(v3(-0.3, -0.4, 0.8660254)); /* towards the sun */
    const double wa[3] = {w.x, w.y, w.z};
    double slack = 0.0;
    for (int a = 0; a < 3; a++)
        slack += 3.0 * (2.0 / 31.0) / fabs(wa[a]); /* 32 nodes along each side of 2 */
    int below = 0, above = 0, deep = 0, n = 0;
    for (int i = 0; i < 11; i++)
        for (int j = 0; j < 11; j++)
            for (int k = 0; k < 11; k++) {
                const double x[3] = {-0.99 + 0.198 * i, -0.99 + 0.198 * j, -0.99 + 0.198 * k};
                double d = INFINITY;
                for (int a = 0; a < 3; a++)
                    d = fmin(d, ((wa[a] > 0.0 ? 1.0 : -1.0) - x[a]) / wa[a]);
                const double T = exp(-3.0 * d), That = path_sun_transmittance_hat(st, 0, v3(x[0], x[1], x[2]));
                below += That < T * (1.0 - 1e-5);
                above += That > T * exp(slack) * (1.0 + 1e-5);
                deep += That < 0.03;
                n++;
            }
    if (below || above)
        TEST_FAIL("%d of %d predictions under the exact transmittance, %d over it by more than exp(%.3f)", below, n,
                  above, slack);
    ASSERT_TRUE(deep > n / 10); /* the roulette acts in a good part of the box */
    ASSERT_TRUE(path_sun_transmittance_hat(st, 0, v3(0, 0, -1.5)) == 1.0); /* outside */
    integrator_finish(INTEGRATOR_PATH, st);
    brume_scene_release(s);
    const char *none[2][2] = {{"0.3", "0.03"}, {"3", "0"}};
    for (int c = 0; c < 2; c++) {
        st = sun_state(ctx, none[c][0], none[c][1], &s);
        ASSERT_TRUE(path_sun_transmittance_hat(st, 0, v3(0, 0, -0.99)) == 1.0);
        integrator_finish(INTEGRATOR_PATH, st);
        brume_scene_release(s);
    }
    brume_context_release(ctx);
}

/* The sun roulette changes the estimator, not its expectation: a slab of optical depth 6
 * (sigma_s 5.94, sigma_a 0.06, HG 0.8, 4 x 4 wide) lit from below by a delta sun 30 degrees
 * off the vertical and seen from above through a narrow camera, so that most scattering
 * events lie where the sun's predicted transmittance is under T0 (checked) and their shadow
 * rays and lobe samples are rouletted. With path.sun_roulette 0 (off), the default 0.03 and
 * 0.5 (most sun rays rouletted), the means must agree within 5 standard errors of their
 * difference, those under 4 % of the mean. The image stays the same for 1 and 2 threads.
 * A roulette that did not divide by its probability would lose a third of the light at 0.5. */
TEST(sun_roulette_unbiased)
{
    const char *head = "{\"camera\": {\"position\": [0, 0, 20], \"look_at\": [0, 0, 0], \"fov\": 2},"
                       " \"lights\": [{\"type\": \"distant\", \"direction\": [0.5, 0, 0.8660254], \"irradiance\": 3.0}],"
                       " \"media\": [{\"sigma_a\": 0.06, \"sigma_s\": 5.94,"
                       "   \"density\": {\"type\": \"constant\", \"bounds\": [[-2, -2, -1], [2, 2, 0]]},"
                       "   \"phase\": {\"type\": \"hg\", \"g\": 0.8}}],"
                       " \"path\": {\"sun_roulette\": ";
    const char *tail = "}, \"render\": {\"width\": 24, \"height\": 24, \"spp\": 384, \"max_depth\": 256}}";
    const char *const T0[3] = {"0", "0.03", "0.5"};
    double mean[3], se[3];
    option_means_agree("sun_roulette", head, T0, 3, tail, 24 * 24, 5, 0.04, mean, se);
    /* the camera's side of the slab is where the roulette acts */
    brume_context *ctx = brume_context_new();
    brume_scene *s;
    char json[1024];
    snprintf(json, sizeof json, "%s0.03%s", head, tail);
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = json}, NULL, &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    void *st = NULL;
    ASSERT_EQ_INT(integrator_prepare(INTEGRATOR_PATH, s, &st), BRUME_OK);
    ASSERT_TRUE(path_sun_transmittance_hat(st, 0, v3(0, 0, -0.2)) < 0.03);
    integrator_finish(INTEGRATOR_PATH, st);
    brume_scene_release(s);
    brume_context_release(ctx);
    same_image_for_threads(json, 24 * 24);
}

/* Splitting at the camera vertex (path.split; docs/path-tracer.md, "Splitting at the camera
 * vertex"). A white furnace rendered with 3 continuations per camera path must still be 1 in
 * every channel (continuations weighed 1 instead of 1 / 3 give 1.52). In a slab like
 * sun_roulette_unbiased's but of albedo 0.9 (optical depth 6, HG 0.8), means with 1 and 3
 * continuations must agree within 5 standard errors of their difference, those under 4 %
 * of the mean; the pixels' variance at 3 must be under 0.7 of that at 1 (it is 0.38: the
 * light seen comes from paths that scatter many times, which the continuations repeat; a
 * roulette that compared a continuation's throughput with 1 rather than with its share of
 * 1 / 3 ends most of them, and gives 1.24); and 1 and 2 threads give the same bits. */
TEST(split_camera_vertex)
{
    char json[1024];
    snprintf(json, sizeof json, white_furnace_json, " \"path\": {\"split\": 3},", 48);
    const double one[3] = {1.0, 1.0, 1.0};
    check_furnace(json, 21, one, 0, 3, 0.01);
    const char *head = "{\"camera\": {\"position\": [0, 0, 20], \"look_at\": [0, 0, 0], \"fov\": 2},"
                       " \"lights\": [{\"type\": \"distant\", \"direction\": [0.5, 0, 0.8660254], \"irradiance\": 3.0}],"
                       " \"media\": [{\"sigma_a\": 0.6, \"sigma_s\": 5.4,"
                       "   \"density\": {\"type\": \"constant\", \"bounds\": [[-2, -2, -1], [2, 2, 0]]},"
                       "   \"phase\": {\"type\": \"hg\", \"g\": 0.8}}],"
                       " \"path\": {\"split\": ";
    const char *tail = "}, \"render\": {\"width\": 24, \"height\": 24, \"spp\": 256, \"max_depth\": 256}}";
    const char *const k[2] = {"1", "3"};
    double mean[2], se[2];
    option_means_agree("split", head, k, 2, tail, 24 * 24, 9, 0.04, mean, se);
    ASSERT_TRUE(se[1] * se[1] < 0.7 * se[0] * se[0]);
    snprintf(json, sizeof json, "%s3%s", head, tail);
    same_image_for_threads(json, 24 * 24);
}

TEST_MAIN(threads_do_not_change_the_image, absorbing_fog_closed_form, white_furnace, emitting_furnace,
          white_furnace_gray, single_scattering_closed_form,
          single_scattering_forward_hg_shadow_roulette, residual_ratio_tracking_transmittance, flight_delta_tail_unbiased,
          furnaces_gray_extinction, sun_lobe_sampling_unbiased, sun_lobe_sampling_stops_at_surfaces,
          camera_cull_changes_no_pixel, sun_roulette_prediction, sun_roulette_unbiased, split_camera_vertex)
