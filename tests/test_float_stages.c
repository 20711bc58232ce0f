/* test_float_stages.c - the flight and shadow stages in float (render/track_float.h, the
 * GPU's single-precision instantiation, run here on the CPU) against the same stages in
 * double (render/flight.h, render/track.h: the CPU's, the validated reference), on the
 * same rays with the same random numbers.
 *
 * Both are unbiased estimators of the same expectations; float rounds sigma's, positions
 * and uniforms to 24 bits, so paired runs follow the same collisions most of the time and
 * part where a rounding flips a decision. The test takes the paired differences d = x_f -
 * x_d of each estimate x (per channel: the flight's transmittance Tr, its scattering
 * weight beta_s, beta_s times the distance to the collision, the emission L gathered, and
 * the shadow stage's transmittance; and whether the flight scatters, and where) and
 * requires |mean d| <= 4 standard errors of mean d (from the spread of d) plus float's
 * rounding, 1e-5 of the estimate (the pairing makes the standard error so small, about
 * 2e-8 of the estimate, that the float view's rounded sigma's, about 1e-7, would otherwise
 * stand out), and that the estimates are not all 0 (a test that could not fail). Scenes:
 * cloud64, wdas-dense (a NanoVDB grid's bricked dense copy) and a chromatic emissive grid.
 * An error shows: with the float view's majorant scaled by 0.9, cloud64's flight
 * transmittance misses by 14 standard errors. */
#include "test.h"

/* GCC cannot see that a majorant walk which failed to begin (its DDA done) reads none of
 * the DDA's other fields, once the whole float flight is inlined here */
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "brume.h"
#include "render/flight.h"
#include "render/track_float.h"
#include "scene/scene.h"

#define NQ 17 /* Tr, beta_s, beta_s t, L, shadow Tr (3 channels each); scattered, t where scattered */

static rayf rayf_of(ray r)
{
    return (rayf){v3f((float)r.o.x, (float)r.o.y, (float)r.o.z), v3f((float)r.d.x, (float)r.d.y, (float)r.d.z),
                  (float)r.time};
}

/* Ray n of a set through the box [c - h, c + h]^3: from a point on a sphere of radius 2 h
 * about c towards a point inside the box's middle half. */
static ray test_ray(uint64_t n, vec3 c, double h)
{
    rng g = rng_make(77, n, 0);
    double z = 2.0 * rng_next(&g) - 1.0, phi = 2.0 * PI * rng_next(&g), s = sqrt(fmax(0.0, 1.0 - z * z));
    vec3 o = v3_add(c, v3_scale(v3(s * cos(phi), s * sin(phi), z), 2.0 * h));
    vec3 target = v3_add(c, v3(h * (rng_next(&g) - 0.5), h * (rng_next(&g) - 0.5), h * (rng_next(&g) - 0.5)));
    return (ray){o, v3_normalize(v3_sub(target, o)), 0.0};
}

/* The paired differences of the NQ estimates over m flights and shadow rays on nrays rays,
 * each checked; *margin is the largest |mean d| / (4 standard errors + rounding) among
 * them, at most 1. */
static void compare_stages(const brume_scene *s, vec3 centre, double h, int nrays, int m, double tail_Tr,
                           double *margin)
{
    scenef v;
    const char *why = scenef_make(s, &v);
    if (why)
        TEST_FAIL("the scene has no float view: %s", why);
    double sum[NQ] = {0}, sq[NQ] = {0}, ref[NQ] = {0};
    for (int n = 0; n < m; n++) {
        const ray r = test_ray((uint64_t)(n % nrays), centre, h);
        const rayf rf = rayf_of(r);
        rng g = rng_make(5, (uint64_t)n, 1), ug = rng_make(6, (uint64_t)n, 1);
        rng gf = g, ugf = ug;
        flight f = {.s = s, .g = &g, .beta = col(1.0), .L = col(0.0), .tail_Tr = tail_Tr};
        flightf ff = {.s = &v, .g = &gf, .beta = colf(1.0f), .L = colf(0.0f), .tail_Tr = (float)tail_Tr};
        const bool sc = flight_run(&f, r, INFINITY, &ug), scf = flight_runf(&ff, rf, INFINITY, &ugf);
        rng sg = rng_make(8, (uint64_t)n, 1), sgf = sg;
        const color T = track_transmittance(s, 0, r, INFINITY, &sg);
        const colorf Tf = track_transmittancef(&v, 0, rf, INFINITY, &sgf);
        double xd[NQ], xf[NQ];
        for (int c = 0; c < 3; c++) {
            xd[c] = f.Tr.c[c];
            xf[c] = ff.Tr.c[c];
            xd[3 + c] = sc ? f.beta_s.c[c] : 0.0;
            xf[3 + c] = scf ? ff.beta_s.c[c] : 0.0;
            xd[6 + c] = sc ? f.beta_s.c[c] * f.t : 0.0;
            xf[6 + c] = scf ? ff.beta_s.c[c] * ff.t : 0.0;
            xd[9 + c] = f.L.c[c];
            xf[9 + c] = ff.L.c[c];
            xd[12 + c] = T.c[c];
            xf[12 + c] = Tf.c[c];
        }
        xd[15] = sc ? 1.0 : 0.0; /* the scattering probability */
        xf[15] = scf ? 1.0 : 0.0;
        xd[16] = sc ? f.t : 0.0; /* the collision distance, over P(scatter) */
        xf[16] = scf ? ff.t : 0.0;
        for (int q = 0; q < NQ; q++) {
            const double d = xf[q] - xd[q];
            sum[q] += d;
            sq[q] += d * d;
            ref[q] += xd[q];
        }
    }
    static const char *names[7] = {"flight Tr", "beta_s", "beta_s t", "L", "shadow Tr", "scattered", "t"};
    *margin = 0.0;
    for (int q = 0; q < NQ; q++) {
        const double mean = sum[q] / m, se = sqrt(fmax(0.0, sq[q] / m - mean * mean) / m), est = ref[q] / m;
        const double z = fabs(mean) / (se + 1e-300);
        fprintf(stderr, "%-9s channel %d: double %.6g, float - double %+.3g, standard error %.3g (|z| %.2f)\n",
                names[q < 15 ? q / 3 : q - 10], q < 15 ? q % 3 : 0, est, mean, se, se > 0.0 ? z : 0.0);
        const double tol = 4.0 * se + 1e-5 * fabs(est);
        ASSERT_TRUE(fabs(mean) <= tol);
        if (tol > 0.0)
            *margin = fmax(*margin, fabs(mean) / tol);
        if (q < 9 || q >= 12) /* every estimate but emission is positive on these rays */
            ASSERT_TRUE(est > 0.0);
    }
}

/* cloud64 (scenes/cloud64.json: gray sigma_t 20, albedo 0.9): the control density and the
 * delta tail run, in both precisions. */
TEST(cloud64)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = BRUME_SOURCE_DIR "/scenes/cloud64.json"}, NULL, &s),
                  BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    ASSERT_TRUE(s->flight_control);
    double z;
    compare_stages(s, v3(0, 0, 0), 0.5, 64, 200000, FLIGHT_TAIL_TR, &z);
    fprintf(stderr, "cloud64: largest |difference| / tolerance %.2f\n", z);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* wdas-dense (scenes/wdas-dense.json): a NanoVDB cloud held as a bricked dense copy, optical
 * depths up to 53, albedo 0.98. */
TEST(wdas_dense)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    ASSERT_EQ_INT(
        brume_scene_load(ctx, &(brume_source){.path = BRUME_SOURCE_DIR "/scenes/wdas-dense.json"}, NULL, &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    const box3 b = density_bounds(s->media[0].rho);
    const vec3 e = v3_sub(b.hi, b.lo);
    const double h = 0.5 * fmax(e.x, fmax(e.y, e.z));
    const vec3 c = v3_scale(v3_add(b.lo, b.hi), 0.5);
    ASSERT_TRUE(scenef_make(s, &(scenef){0}) == NULL); /* a NanoVDB grid's dense copy */
    double z;
    compare_stages(s, c, h, 64, 200000, FLIGHT_TAIL_TR, &z);
    fprintf(stderr, "wdas-dense: largest |difference| / tolerance %.2f\n", z);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* A small chromatic grid that emits: sigma_t differs per channel (no control density, ratio
 * tracking throughout) and the flights gather emission. */
TEST(chromatic_emissive_grid)
{
    enum { N = 12 };
    static float data[N * N * N];
    for (int k = 0; k < N; k++)
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++) {
                const double x = (i + 0.5) / N - 0.5, y = (j + 0.5) / N - 0.5, zz = (k + 0.5) / N - 0.5;
                const double r2 = x * x + y * y + zz * zz;
                data[i + N * (j + N * k)] = (float)fmax(0.0, 1.0 - 4.0 * r2) * (float)(0.5 + 0.5 * ((i + j + k) % 3));
            }
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    brume_density *d = NULL;
    const double bounds[6] = {-1, -1, -1, 1, 1, 1};
    ASSERT_EQ_INT(brume_scene_new(ctx, "chromatic", &s), BRUME_OK);
    ASSERT_EQ_INT(brume_density_new_array(ctx, data, N, N, N, bounds, BRUME_GRID_TRILINEAR, NULL, NULL, &d), BRUME_OK);
    const brume_medium m = {.sigma_a = {0.5, 1.0, 2.0}, .sigma_s = {2.0, 1.5, 1.0}, .emission = {0.5, 1.0, 2.0}};
    ASSERT_EQ_INT(brume_scene_add_medium(ctx, s, &m, d, NULL), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    ASSERT_TRUE(!s->flight_control);
    double z;
    compare_stages(s, v3(0, 0, 0), 1.0, 64, 200000, FLIGHT_TAIL_TR, &z);
    fprintf(stderr, "chromatic grid: largest |difference| / tolerance %.2f\n", z);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* Shapes the float stages do not cover are refused by name, not rendered wrongly: two media. */
TEST(refuses_other_shapes)
{
    static float data[8] = {1, 1, 1, 1, 1, 1, 1, 1};
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    const double bounds[6] = {-1, -1, -1, 1, 1, 1};
    ASSERT_EQ_INT(brume_scene_new(ctx, "two", &s), BRUME_OK);
    for (int i = 0; i < 2; i++) {
        brume_density *d = NULL;
        ASSERT_EQ_INT(brume_density_new_array(ctx, data, 2, 2, 2, bounds, BRUME_GRID_TRILINEAR, NULL, NULL, &d),
                      BRUME_OK);
        const brume_medium m = {.sigma_a = {1, 1, 1}, .sigma_s = {1, 1, 1}};
        ASSERT_EQ_INT(brume_scene_add_medium(ctx, s, &m, d, NULL), BRUME_OK);
    }
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    scenef v;
    const char *why = scenef_make(s, &v);
    ASSERT_TRUE(why != NULL);
    fprintf(stderr, "two media: %s\n", why);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* The stages' float uniforms (rng_nextf): in (0, 1), within 2^-24 of the double uniform of
 * the same dimension (the centre of its 2^-23 cell), and unbiased: over 2^20 draws the
 * mean of the difference is within 4 standard errors of 0, where truncating to 24 bits
 * would put it 2^-25 below: nearly 1,800 standard errors. */
TEST(float_uniforms)
{
    const int n = 1 << 20;
    double sum = 0.0, sq = 0.0;
    rng g = rng_make(3, 4, 5);
    for (int i = 0; i < n; i++) {
        rng h = g;
        const double u = rng_next(&g);
        const float uf = rng_nextf(&h);
        ASSERT_TRUE(uf > 0.0f && uf < 1.0f);
        ASSERT_TRUE(fabs((double)uf - u) <= 0x1.0p-24);
        ASSERT_TRUE(h.counter == g.counter);
        sum += (double)uf - u;
        sq += ((double)uf - u) * ((double)uf - u);
    }
    const double mean = sum / n, se = sqrt(fmax(0.0, sq / n - mean * mean) / n);
    fprintf(stderr, "float - double uniform: mean %.3g, standard error %.3g\n", mean, se);
    ASSERT_TRUE(fabs(mean) <= 4.0 * se);
}

TEST_MAIN(cloud64, wdas_dense, chromatic_emissive_grid, refuses_other_shapes, float_uniforms)
