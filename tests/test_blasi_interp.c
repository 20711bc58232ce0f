/* test_blasi_interp.c - blasi.interpolate: with "trilinear" both passes see the density
 * trilinear between the voxels' centres (the transmittance against a brute-force integral
 * of that field), and the picture has no step at a voxel face where "voxel" has one. */
#include "test.h"

#include "brume.h"
#include "core/rng.h"
#include "density/density.h"
#include "render/blasi.h"
#include "scene/scene.h"

enum { NX = 6, NY = 5, NZ = 4 };

/* The test's own trilinear field of v (x fastest) at voxel-space point u: cell-centred
 * samples, clamped to the outermost ones, 0 outside the grid. */
static double tri(const double *v, const int n[3], vec3 u)
{
    const double p[3] = {u.x, u.y, u.z};
    int lo[3], hi[3];
    double a[3];
    for (int ax = 0; ax < 3; ax++) {
        if (p[ax] < 0.0 || p[ax] > n[ax])
            return 0.0;
        double x = p[ax] - 0.5, f = floor(x);
        a[ax] = x - f;
        lo[ax] = f < 0 ? 0 : (int)f;
        hi[ax] = f + 1 > n[ax] - 1 ? n[ax] - 1 : (int)f + 1;
    }
    double sum = 0.0;
    for (int q = 0; q < 8; q++) {
        int i = q & 1 ? hi[0] : lo[0], j = q & 2 ? hi[1] : lo[1], k = q & 4 ? hi[2] : lo[2];
        double w = (q & 1 ? a[0] : 1 - a[0]) * (q & 2 ? a[1] : 1 - a[1]) * (q & 4 ? a[2] : 1 - a[2]);
        sum += w * v[i + n[0] * (j + n[1] * k)];
    }
    return sum;
}

/* A scene of one medium, the grid `data` (nx ny nz values) in `bounds`, lit by a sun. */
static brume_scene *grid_scene(brume_context *ctx, const int n[3], const double *data, const char *bounds,
                               const char *sun, const char *interpolate)
{
    static char json[16384];
    int at = snprintf(json, sizeof json,
                      "{\"camera\": {\"position\": [0, 0, -4], \"look_at\": [0, 0, 0], \"up\": [0, 1, 0]},"
                      " \"background\": [0, 0, 0], \"lights\": [%s],"
                      " \"media\": [{\"sigma_a\": 0.1, \"sigma_s\": 1.0, \"density\": {\"type\": \"array\","
                      " \"dims\": [%d, %d, %d], \"bounds\": %s, \"data\": [",
                      sun, n[0], n[1], n[2], bounds);
    for (int i = 0; i < n[0] * n[1] * n[2]; i++)
        at += snprintf(json + at, sizeof json - (size_t)at, "%s%.9g", i ? ", " : "", data[i]);
    snprintf(json + at, sizeof json - (size_t)at,
             "]}}], \"blasi\": {\"interpolate\": \"%s\", \"variant\": \"physical\", \"r\": 1},"
             " \"render\": {\"width\": 8, \"height\": 8, \"spp\": 1, \"method\": \"blasi\"}}",
             interpolate);
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = json}, NULL, &s) != BRUME_OK)
        TEST_FAIL("scene: %s", brume_context_last_error(ctx));
    return s;
}

#define SUN_DOWN "{\"type\": \"distant\", \"direction\": [0, 0, 1], \"irradiance\": 3}"

/* The transmittance behind a pixel's alpha against a brute-force integral of the field: for
 * oblique rays through a grid of random values (a fifth of them 0), exp(-sigma_t times the
 * midpoint sum of 200,000 steps of the test's own trilinear field). The field's slope jumps
 * only at the planes through voxel centres (a few per ray), so the midpoint sum is off by
 * far less than 1e-7 of the optical depth: that is the tolerance. Read per voxel instead
 * ("voxel") the same rays are off by far more: the comparison can fail. */
TEST(transmittance_follows_the_trilinear_field)
{
    const int n[3] = {NX, NY, NZ};
    double v[NX * NY * NZ];
    rng g = rng_make(11, 0, 0);
    for (int i = 0; i < NX * NY * NZ; i++)
        v[i] = rng_next(&g) < 0.2 ? 0.0 : (double)(float)(2.0 * rng_next(&g));
    const char *bounds = "[[-1.2, -1.0, -0.8], [1.2, 1.0, 0.8]]";
    double worst[2] = {0.0, 0.0};
    for (int mode = 0; mode < 2; mode++) {
        brume_context *ctx = brume_context_new();
        brume_scene *s = grid_scene(ctx, n, v, bounds, SUN_DOWN, mode ? "voxel" : "trilinear");
        ASSERT_EQ_INT(brume_scene_set_option(ctx, s, "blasi.light_rays", "1000"), BRUME_OK);
        ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
        blasi_state *st = NULL;
        ASSERT_EQ_INT(blasi_prepare(s, &st), BRUME_OK);
        density_info info;
        density_get_info(s->media[0].rho, &info);
        affine3 w2v;
        ASSERT_TRUE(affine3_invert(&info.voxel_to_world, &w2v));
        rng gr = rng_make(12, 0, 0);
        int thick = 0;
        for (int it = 0; it < 30; it++) {
            vec3 target = v3(rng_next(&gr) * 2.0 - 1.0, rng_next(&gr) * 1.6 - 0.8, rng_next(&gr) * 1.2 - 0.6);
            double z = 2 * rng_next(&gr) - 1, phi = 2 * PI * rng_next(&gr), sn = sqrt(1 - z * z);
            vec3 d = v3(sn * cos(phi), sn * sin(phi), z);
            ray r = {v3_madd(target, d, -4.0), d, 0.0};
            double t0, t1;
            ASSERT_TRUE(box3_intersect(info.bounds, r, 0.0, INFINITY, &t0, &t1));
            enum { N = 200000 };
            double dt = (t1 - t0) / N, sum = 0.0;
            for (int q = 0; q < N; q++)
                sum += tri(v, n, affine3_apply(&w2v, ray_at(r, t0 + (q + 0.5) * dt))) * dt;
            double tau = 1.1 * sum, got = -log(blasi_transmittance(s, st, r).c[0]);
            if (mode == 0)
                ASSERT_NEAR(got, tau, 1e-7 * tau + 1e-12);
            worst[mode] = fmax(worst[mode], fabs(got - tau) / fmax(tau, 1e-12));
            thick += tau > 0.5;
        }
        ASSERT_TRUE(thick >= 10); /* the rays cross the field */
        blasi_finish(st);
        brume_scene_release(s);
        brume_context_release(ctx);
    }
    fprintf(stderr, "largest relative error of the optical depth: trilinear %.3g, voxel %.3g\n", worst[0], worst[1]);
    ASSERT_TRUE(worst[1] > 1e-3); /* per voxel is another field: the test tells them apart */
}

/* The radiance of view rays along z through a grid whose density doubles at x = 0 (8 x 2 x
 * 2 voxels of 0.4; rho 0.1 in columns 0-3, 0.2 in columns 4-7), lit along z: at the face
 * between columns 3 and 4 the step J = L(+e) - L(-e) against the change G = L(0.2) -
 * L(-0.2) between the columns' centres. Read per voxel a ray sees one column's voxels
 * whatever its x within it, so J = G. Trilinear, the density is continuous at the face and
 * only the stored source per unit density (the fluence, one value per voxel) may step: by
 * its noise, and by at most the difference of the columns' optical depths towards the sun,
 * sigma_t 0.1 x 0.8 = 0.088 of the source at the face, L(+-e). J must stay within 4
 * standard errors of its mean over 4 light passes (their spread) plus that; the sum is
 * under G / 2, so a stepped picture fails. */
TEST(trilinear_removes_the_steps_at_voxel_faces)
{
    const int n[3] = {8, 2, 2};
    double v[8 * 2 * 2];
    for (int i = 0; i < 32; i++)
        v[i] = i % 8 < 4 ? 0.1 : 0.2;
    const char *bounds = "[[-1.6, -0.4, -0.4], [1.6, 0.4, 0.4]]";
    enum { NB = 4 };
    double J[2][NB], G[2][NB], F[2][NB];
    for (int mode = 0; mode < 2; mode++)
        for (int b = 0; b < NB; b++) {
            brume_context *ctx = brume_context_new();
            brume_scene *s = grid_scene(ctx, n, v, bounds, SUN_DOWN, mode ? "voxel" : "trilinear");
            ASSERT_EQ_INT(brume_scene_set_option(ctx, s, "blasi.light_rays", "1000000"), BRUME_OK);
            brume_render_settings rs;
            brume_scene_settings(s, &rs);
            rs.seed = 40 + (uint64_t)b;
            ASSERT_EQ_INT(brume_scene_set_settings(ctx, s, &rs), BRUME_OK);
            ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
            blasi_state *st = NULL;
            ASSERT_EQ_INT(blasi_prepare(s, &st), BRUME_OK);
            const double xs[4] = {-0.2, -1e-4, 1e-4, 0.2};
            double L[4];
            rng g = rng_make(1, 0, 0);
            for (int q = 0; q < 4; q++) {
                bool hit = false;
                L[q] = blasi_Li(s, st, (ray){v3(xs[q], 0.2, -3.0), v3(0, 0, 1), 0.0}, &g, &hit).c[0];
            }
            J[mode][b] = L[2] - L[1];
            G[mode][b] = L[3] - L[0];
            F[mode][b] = 0.5 * (L[1] + L[2]);
            blasi_finish(st);
            brume_scene_release(s);
            brume_context_release(ctx);
        }
    for (int mode = 0; mode < 2; mode++) {
        double mj = 0.0, mg = 0.0, mf = 0.0, var = 0.0;
        for (int b = 0; b < NB; b++) {
            mj += J[mode][b] / NB;
            mg += G[mode][b] / NB;
            mf += F[mode][b] / NB;
        }
        for (int b = 0; b < NB; b++)
            var += (J[mode][b] - mj) * (J[mode][b] - mj) / (NB - 1);
        double se = sqrt(var / NB);
        fprintf(stderr, "%s: step at the face %.4g (se %.2g), change between the centres %.4g\n",
                mode ? "voxel" : "trilinear", mj, se, mg);
        ASSERT_TRUE(mg > 0.0);
        if (mode == 0) {
            ASSERT_TRUE(fabs(mj) <= 4.0 * se + 0.088 * mf);
            ASSERT_TRUE(4.0 * se + 0.088 * mf < 0.5 * mg); /* the bound tells a step from none */
        } else {
            ASSERT_NEAR(mj, mg, 1e-9 * mg); /* the whole change, at the face */
        }
    }
}

TEST_MAIN(transmittance_follows_the_trilinear_field, trilinear_removes_the_steps_at_voxel_faces)
