/* test_blasi_brute.c - blasi's passes against brute force on the cloud of blasi_scenes.h,
 * read constant per voxel (blasi.interpolate = voxel; the trilinear field's:
 * test_blasi_interp.c): the transmittance behind a pixel's alpha and the view pass's
 * radiance against references stepped through the grid, and the printed gather two thirds
 * along an axis. */
#include "test.h"

#include "brume.h"
#include "render/blasi.h"
#include "core/error.h"
#include "scene/scene.h"

#include <unistd.h>

#include "blasi_scenes.h"
#include "core/rng.h"
#include "density/density.h"

/* Commits s, runs blasi's light pass, and describes its one medium's grid in *info. */
static blasi_state *commit_and_prepare(brume_context *ctx, brume_scene *s, density_info *info)
{
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    blasi_state *st = NULL;
    ASSERT_EQ_INT(blasi_prepare(s, &st), BRUME_OK);
    density_get_info(s->media[0].rho, info);
    return st;
}

/* A ray of random direction through a random point of the test cloud's middle
 * (|x|, |y| < 1.2, |z| < 0.3), from 5 units before it; [*t0, *t1] its stretch in `bounds`. */
static ray ray_into_cloud(rng *g, box3 bounds, double *t0, double *t1)
{
    vec3 target = v3(rng_next(g) * 2.4 - 1.2, rng_next(g) * 2.4 - 1.2, rng_next(g) * 0.6 - 0.3);
    double z = 2 * rng_next(g) - 1, phi = 2 * PI * rng_next(g), sn = sqrt(1 - z * z);
    vec3 d = v3(sn * cos(phi), sn * sin(phi), z);
    ray r = {v3_madd(target, d, -5.0), d, 0.0};
    ASSERT_TRUE(box3_intersect(bounds, r, 0.0, INFINITY, t0, t1));
    return r;
}

/* The transmittance behind a pixel's alpha (blasi_transmittance) against a brute-force
 * reference: 400,000 midpoint steps through the grid, each reading the voxel that holds
 * it. A step that straddles a voxel face charges its whole length dt to one side, so the
 * reference's optical depth is off by at most (faces crossed + 2) dt sigma_t rho_max per
 * channel: that is the tolerance (about 1e-3 here). The value blasi_Li leaves for the same
 * ray (the render asks for both) is the same bits as a fresh walk. */
static void check_transmittance(const char *json, const char *what)
{
    brume_scene *s = NULL;
    brume_context *ctx = brume_context_new();
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = json}, NULL, &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_set_option(ctx, s, "blasi.light_rays", "1000"), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_set_option(ctx, s, "blasi.interpolate", "voxel"), BRUME_OK);
    density_info info;
    blasi_state *st = commit_and_prepare(ctx, s, &info);
    const medium *md = &s->media[0];
    affine3 w2v;
    ASSERT_TRUE(affine3_invert(&info.voxel_to_world, &w2v));
    color sigma_t = col_add(md->sigma_a, md->sigma_s);
    rng g = rng_make(5, 0, 0);
    int crossed_cloud = 0;
    for (int it = 0; it < 40; it++) {
        double t0, t1;
        ray r = ray_into_cloud(&g, info.bounds, &t0, &t1);
        enum { N = 400000 };
        double dt = (t1 - t0) / N, rho_max = 0.0;
        color tau = col(0.0);
        for (int q = 0; q < N; q++) {
            vec3 u = affine3_apply(&w2v, ray_at(r, t0 + (q + 0.5) * dt));
            int i = (int)floor(u.x), j = (int)floor(u.y), k = (int)floor(u.z);
            if (i < 0 || j < 0 || k < 0 || i >= info.n[0] || j >= info.n[1] || k >= info.n[2])
                continue;
            double rho = (double)(float)density_voxel(md->rho, i, j, k);
            rho_max = fmax(rho_max, rho);
            tau = col_madd(tau, sigma_t, rho * dt);
        }
        color T = blasi_transmittance(s, st, r);
        double faces = info.n[0] + info.n[1] + info.n[2] + 2.0;
        for (int c = 0; c < 3; c++) {
            double tol = faces * dt * sigma_t.c[c] * rho_max;
            ASSERT_NEAR(-log(T.c[c]), tau.c[c], tol + 1e-12);
        }
        crossed_cloud += tau.c[0] > 0.1;
        /* the value blasi_Li leaves behind is the fresh walk's */
        bool hit = false;
        (void)blasi_Li(s, st, r, &g, &hit);
        color Tc = blasi_transmittance(s, st, r);
        for (int c = 0; c < 3; c++)
            ASSERT_TRUE(Tc.c[c] == T.c[c]);
    }
    fprintf(stderr, "%s: %d of 40 rays with optical depth > 0.1\n", what, crossed_cloud);
    ASSERT_TRUE(crossed_cloud >= 10); /* the rays do cross the cloud: the comparison can fail */
    blasi_finish(st);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* The test cloud (32 x 32 x 8: every voxel of its occupied box walked), and a grid of
 * 120 x 120 x 16 voxels (nx + ny + nz > 192: the walk over occupancy blocks, restarted
 * per run of occupied blocks) with a sparse threshold, so that both walks are checked. */
TEST(transmittance_matches_brute_force)
{
    check_transmittance(CLOUD_SCENE(SUN, ""), "32 x 32 x 8");
    check_transmittance("{\"camera\": {\"position\": [0.6, -3.5, 3.0], \"look_at\": [0, 0, 0], \"up\": [0, 0, 1]},"
                        " \"lights\": [" SUN "],"
                        " \"media\": [{\"sigma_a\": [0.2, 0.1, 0.4], \"sigma_s\": [3, 1.5, 0.75],"
                        "   \"density\": {\"type\": \"fractal_cloud\", \"dims\": [120, 120, 16], \"seed\": 4,"
                        "     \"threshold\": 0.45, \"bounds\": [[-1.6, -1.6, -0.4], [1.6, 1.6, 0.4]]}}],"
                        " \"render\": {\"width\": 8, \"height\": 8, \"spp\": 1, \"method\": \"blasi\"}}",
                        "120 x 120 x 16");
}

/* The view pass against a brute-force sum. The first pass is saved and its source S read
 * back from the file (docs/blasi.md, "Light files"); then for rays through the cloud,
 * blasi_Li is compared with a fine midpoint sum along the ray of A S dt, A the view
 * attenuation exp(-integral of kappa rho), plus A times the background at the end.
 * Tolerance: a step that straddles a voxel face takes one voxel's values for all of it, an
 * error of at most dt (S_max + (L + B) kappa rho_max) per face it crosses (counted as the
 * sum goes); the midpoint rule
 * within a voxel is exact to far less. A grey medium (the walk that keeps A as one number)
 * with the paper's absorption-only attenuation, and a chromatic one with the physical
 * variant; both absorb enough (optical depth up to about 0.5 per voxel) that the
 * integral's 1 - exp(-kappa delta) / (kappa delta) and the attenuation matter to far more
 * than the tolerance. */
static void check_view_radiance(const char *json, const char *variant, const char *what)
{
    const char *path = test_tmp_path("view.bbl");
    brume_scene *s = NULL;
    brume_context *ctx = brume_context_new();
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = json}, NULL, &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_set_option(ctx, s, "blasi.light_rays", "20000"), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_set_option(ctx, s, "blasi.interpolate", "voxel"), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_set_option(ctx, s, "blasi.variant", variant), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_set_option(ctx, s, "blasi.threshold", "1e-12"), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_set_option(ctx, s, "blasi.save_light", path), BRUME_OK);
    density_info info;
    blasi_state *st = commit_and_prepare(ctx, s, &info);
    const medium *md = &s->media[0];
    size_t nvox = (size_t)info.n[0] * (size_t)info.n[1] * (size_t)info.n[2];
    float *S = malloc(nvox * 3 * sizeof *S);
    FILE *fp = fopen(path, "rb");
    ASSERT_TRUE(fp && S);
    ASSERT_EQ_INT(fseek(fp, 8 + 4 + 4 + 8 + 16, SEEK_SET), 0); /* magic, version, media, hash, one medium's dims */
    ASSERT_TRUE(fread(S, sizeof(float) * 3, nvox, fp) == nvox);
    fclose(fp);
    unlink(path);
    affine3 w2v;
    ASSERT_TRUE(affine3_invert(&info.voxel_to_world, &w2v));
    color kappa = strcmp(variant, "paper") == 0 ? md->sigma_a : col_add(md->sigma_a, md->sigma_s);
    color S_max = col(0.0);
    double rho_max = 0.0;
    for (size_t v = 0; v < nvox; v++)
        for (int c = 0; c < 3; c++)
            S_max.c[c] = fmax(S_max.c[c], (double)S[3 * v + (size_t)c]);
    rng g = rng_make(9, 0, 0);
    int lit = 0;
    for (int it = 0; it < 20; it++) {
        double t0, t1;
        ray r = ray_into_cloud(&g, info.bounds, &t0, &t1);
        enum { N = 200000 };
        double dt = (t1 - t0) / N;
        color A = col(1.0), L = col(0.0);
        long cell = -1, faces = 0; /* the voxel of the last step, and the faces crossed */
        for (int q = 0; q < N; q++) {
            vec3 u = affine3_apply(&w2v, ray_at(r, t0 + (q + 0.5) * dt));
            int i = (int)floor(u.x), j = (int)floor(u.y), k = (int)floor(u.z);
            long here = i < 0 || j < 0 || k < 0 || i >= info.n[0] || j >= info.n[1] || k >= info.n[2]
                            ? -2
                            : i + info.n[0] * (j + (long)info.n[1] * k);
            faces += here != cell;
            cell = here;
            if (here < 0)
                continue;
            double rho = (double)(float)density_voxel(md->rho, i, j, k);
            rho_max = fmax(rho_max, rho);
            const float *sv = S + 3 * ((size_t)i + (size_t)info.n[0] * ((size_t)j + (size_t)info.n[1] * (size_t)k));
            for (int c = 0; c < 3; c++) {
                double half = exp(-0.5 * kappa.c[c] * rho * dt);
                L.c[c] += A.c[c] * half * (double)sv[c] * dt;
                A.c[c] *= half * half;
            }
        }
        color B = background_eval(&s->bg, r.d);
        bool hit = false;
        color Lb = blasi_Li(s, st, r, &g, &hit);
        ASSERT_TRUE(!hit);
        for (int c = 0; c < 3; c++) {
            double want = L.c[c] + A.c[c] * B.c[c];
            double tol = (double)faces * dt * (S_max.c[c] + (L.c[c] + B.c[c]) * kappa.c[c] * rho_max);
            ASSERT_NEAR(Lb.c[c], want, tol + 1e-12);
        }
        lit += L.c[1] > 10.0 * (double)faces * dt * S_max.c[1]; /* the source dominates the tolerance */
    }
    fprintf(stderr, "%s: %d of 20 rays gather a source well above the tolerance\n", what, lit);
    ASSERT_TRUE(lit >= 5); /* the rays do cross lit voxels: the comparison can fail */
    free(S);
    blasi_finish(st);
    brume_scene_release(s);
    brume_context_release(ctx);
}

TEST(view_radiance_matches_brute_force)
{
    check_view_radiance("{\"camera\": {\"position\": [0.6, -3.5, 3.0], \"look_at\": [0, 0, 0], \"up\": [0, 0, 1]},"
                        " \"background\": [0.2, 0.3, 0.5], \"lights\": [" SUN "],"
                        " \"media\": [{\"sigma_a\": 3.0, \"sigma_s\": 2.0,"
                        "   \"density\": {\"type\": \"fractal_cloud\", \"dims\": [32, 32, 8], \"seed\": 3,"
                        "     \"threshold\": 0.1, \"bounds\": [[-1.6, -1.6, -0.4], [1.6, 1.6, 0.4]]}}],"
                        " \"render\": {\"width\": 8, \"height\": 8, \"spp\": 1, \"method\": \"blasi\"}}",
                        "paper", "grey, paper");
    check_view_radiance("{\"camera\": {\"position\": [0.6, -3.5, 3.0], \"look_at\": [0, 0, 0], \"up\": [0, 0, 1]},"
                        " \"background\": [0.2, 0.3, 0.5], \"lights\": [" SUN "],"
                        " \"media\": [{\"sigma_a\": [1, 0.5, 2], \"sigma_s\": [3, 1.5, 0.75],"
                        "   \"density\": {\"type\": \"fractal_cloud\", \"dims\": [32, 32, 8], \"seed\": 3,"
                        "     \"threshold\": 0.1, \"bounds\": [[-1.6, -1.6, -0.4], [1.6, 1.6, 0.4]]}}],"
                        " \"render\": {\"width\": 8, \"height\": 8, \"spp\": 1, \"method\": \"blasi\"}}",
                        "physical", "chromatic, physical");
}

/* blasi.gather = printed adds A L_V once per voxel a view ray visits, L_V = S_V times the
 * voxel's mean chord 4 |V| / area (2/3 of the edge for a cube: Cauchy's formula), where
 * path_length integrates S_V over the length crossed. Along a voxel axis every visit
 * crosses one edge h, so in a nearly transparent medium (kappa rho h <= 1e-3) the printed
 * gather is 2/3 of the other, ray by ray. The same light pass (seed) feeds both. */
TEST(printed_gather_is_two_thirds_along_an_axis)
{
    const char *json = "{\"camera\": {\"position\": [0.6, -3.5, 3.0], \"look_at\": [0, 0, 0], \"up\": [0, 0, 1]},"
                       " \"background\": [0, 0, 0], \"lights\": [" SUN "],"
                       " \"media\": [{\"sigma_a\": 0.01, \"sigma_s\": 2.0,"
                       "   \"density\": {\"type\": \"fractal_cloud\", \"dims\": [32, 32, 8], \"seed\": 3,"
                       "     \"threshold\": 0.1, \"bounds\": [[-1.6, -1.6, -0.4], [1.6, 1.6, 0.4]]}}],"
                       " \"render\": {\"width\": 8, \"height\": 8, \"spp\": 1, \"method\": \"blasi\"}}";
    color L[2][12];
    for (int k = 0; k < 2; k++) {
        brume_scene *s = NULL;
        brume_context *ctx = brume_context_new();
        ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = json}, NULL, &s), BRUME_OK);
        ASSERT_EQ_INT(brume_scene_set_option(ctx, s, "blasi.light_rays", "20000"), BRUME_OK);
        ASSERT_EQ_INT(brume_scene_set_option(ctx, s, "blasi.gather", k ? "printed" : "path_length"), BRUME_OK);
        ASSERT_EQ_INT(brume_scene_set_option(ctx, s, "blasi.interpolate", "voxel"), BRUME_OK);
        density_info info;
        blasi_state *st = commit_and_prepare(ctx, s, &info);
        rng g = rng_make(3, 0, 0);
        for (int i = 0; i < 12; i++) { /* rays along x, y and z through voxel centres */
            int a = i % 3;
            double u = -1.15 + 0.1 * (i / 3) * 2.0, w = 0.05 - 0.1 * (i % 2);
            vec3 o = a == 0 ? v3(-3, u, w) : a == 1 ? v3(u, -3, w) : v3(u, w + 0.2 * (i / 3), -3);
            vec3 d = a == 0 ? v3(1, 0, 0) : a == 1 ? v3(0, 1, 0) : v3(0, 0, 1);
            bool hit = false;
            L[k][i] = blasi_Li(s, st, (ray){o, d, 0.0}, &g, &hit);
        }
        blasi_finish(st);
        brume_scene_release(s);
        brume_context_release(ctx);
    }
    int lit = 0;
    for (int i = 0; i < 12; i++)
        for (int c = 0; c < 3; c++) {
            if (L[0][i].c[c] > 0.0)
                lit++;
            ASSERT_NEAR(L[1][i].c[c], 2.0 / 3.0 * L[0][i].c[c], 2e-3 * L[0][i].c[c] + 1e-15);
        }
    fprintf(stderr, "%d of 36 ray channels gather light\n", lit);
    ASSERT_TRUE(lit >= 18);
}

TEST_MAIN(transmittance_matches_brute_force, view_radiance_matches_brute_force,
          printed_gather_is_two_thirds_along_an_axis)
