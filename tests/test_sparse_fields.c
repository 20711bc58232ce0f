/* test_sparse_fields.c - the fields a .vdb carries beside density: blackbody colours
 * against published chromaticities, albedo, temperature and emission grids through the
 * scene file's keys, blackbody emission against its closed form; and brume gen upres and
 * gen fire, which write sparse grids (the fire's frames through the readers' patterns). */
#include "test.h"

#include <stdint.h>
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
#include "vdb_puffs.h"

#define DATA(f) BRUME_DATA_DIR "/" f

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
 * 0.3516), 10000 K (0.2807, 0.2884). Tolerance 0.0015: the published points carry four
 * digits, and the colour matching functions are the CIE's table every 5 nm. */
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
    brume_context *ctx = brume_context_new();
    if (brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = json}, NULL, &s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    ASSERT_TRUE(brume_scene_commit(ctx, s) == BRUME_OK);
    ASSERT_TRUE(s->has_emission);
    rng g = rng_make(3, 0, 0);
    for (int n = 0; n < 200; n++) {
        int p = n & 1;
        int i = puff_c[p][0] + (int)(rng_next(&g) * 9) - 4, j = puff_c[p][1] + (int)(rng_next(&g) * 9) - 4,
            k = puff_c[p][2] + (int)(rng_next(&g) * 9) - 4;
        medium_sample ms;
        media_at(s, 0, centre(i, j, k), 0.0, &ms);
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
        ASSERT_TRUE(brume_scene_load(ctx, &(brume_source){.path = "bad.json", .text = json}, NULL, &s) != BRUME_OK);
        const char *msg = brume_context_last_error(ctx);
        fprintf(stderr, "%s\n", msg);
        ASSERT_CONTAINS(msg, "bad.json");
        ASSERT_CONTAINS(msg, bad[b].needle);
        ASSERT_TRUE(!strchr(msg, '\n'));
    }
    brume_context_release(ctx);
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
    brume_context *ctx = brume_context_new();
    ASSERT_TRUE(brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = json2}, NULL, &s) == BRUME_OK);
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

TEST_MAIN(blackbody_chromaticity, medium_fields_from_scene_keys, blackbody_emission_closed_form, gen_upres_and_fire,
          gen_fire_frames)
