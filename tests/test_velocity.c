/* test_velocity.c - velocity motion blur (docs/animation.md, "Velocity motion blur"):
 *   - a puff moved by a constant velocity grid renders, within the estimators' noise, as the
 *     same puff moved by keyframes over the same shutter (per channel, per block), while the
 *     unmoved puff does not (the comparison can fail);
 *   - a sequence of files, each with its own velocity, blurs each frame by its own file's;
 *   - the moved majorants bound the advected density at random points and times of the
 *     shutter, for a rotating velocity (three float grids vel.x/.y/.z), with the cell grid's
 *     majorants and with the tree's, and the undilated majorants do not;
 *   - bad velocity inputs are refused with one line naming the file and the field.
 * The grids are written here with OpenVDB's writer as .nvdb (skipped without OpenVDB). */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "brume.h"
#include "core/error.h"
#include "core/rng.h"
#include "density/density.h"
#include "io/grid_io.h"
#include "io/grid_vdb.h"
#include "scene/scene.h"
#include "test.h"

static void need_openvdb(void)
{
    if (!grid_have_openvdb()) {
        printf("skipped: no OpenVDB (writing .nvdb)\n");
        exit(77);
    }
}

/* A gaussian puff "density" (16^3 voxels of 0.1, centred on `centre`, peak 4; for kind 1 a
 * block of 8^3 voxels of density 4 in the middle) and a velocity:
 * kind 0 a vec3 grid "vel" = (1, 0, 0) everywhere it is active (a box well around the puff),
 * kind 1 three float grids vel.x/.y/.z of the rotation v = omega (-y, x, 0) about the z axis,
 * kind 2 a vec3 grid "vel" (1 + 0.01 i, 0, 0) with one NaN voxel, kind 3 a vec3 grid "vel" =
 * (0, 1, 0). Written to path as .nvdb. */
static void write_puff(const char *path, const double centre[3], int kind)
{
    gridvdb_writer *w = gridvdb_writer_new();
    ASSERT_TRUE(w != NULL);
    const double h = 0.1, omega = 2.0;
    const double origin[3] = {centre[0] - 0.75, centre[1] - 0.75, centre[2] - 0.75};
    int gd = gridvdb_writer_add(w, "density", 0, h, origin);
    ASSERT_TRUE(gd >= 0);
    for (int k = 0; k < 16; k++)
        for (int j = 0; j < 16; j++)
            for (int i = 0; i < 16; i++) {
                double x = h * (i - 7.5), y = h * (j - 7.5), z = h * (k - 7.5);
                float v = (float)(4.0 * exp(-(x * x + y * y + z * z) / (2 * 0.25 * 0.25)));
                if (kind == 1) /* a sharp-edged block: a bound too short by a voxel shows */
                    v = i >= 4 && i < 12 && j >= 4 && j < 12 && k >= 4 && k < 12 ? 4.0f : 0.0f;
                if (v > 1e-3f)
                    gridvdb_writer_set(w, gd, i, j, k, &v);
            }
    if (kind == 1) {
        int g[3] = {gridvdb_writer_add(w, "vel.x", 0, h, origin), gridvdb_writer_add(w, "vel.y", 0, h, origin),
                    gridvdb_writer_add(w, "vel.z", 0, h, origin)};
        ASSERT_TRUE(g[0] >= 0 && g[1] >= 0 && g[2] >= 0);
        for (int k = -8; k < 24; k++)
            for (int j = -8; j < 24; j++)
                for (int i = -8; i < 24; i++) {
                    double x = origin[0] + h * i, y = origin[1] + h * j;
                    float v[3] = {(float)(-omega * y), (float)(omega * x), 0.0f};
                    for (int c = 0; c < 3; c++)
                        gridvdb_writer_set(w, g[c], i, j, k, &v[c]);
                }
    } else {
        int gv = gridvdb_writer_add(w, "vel", 1, h, origin);
        ASSERT_TRUE(gv >= 0);
        /* the box well around the puff and where the velocity carries it (along x, or y) */
        const int jlo = kind == 3 ? -12 : -4, jhi = kind == 3 ? 28 : 20, ilo = kind == 3 ? -4 : -12,
                  ihi = kind == 3 ? 20 : 28;
        for (int k = -4; k < 20; k++)
            for (int j = jlo; j < jhi; j++)
                for (int i = ilo; i < ihi; i++) {
                    float v[3] = {kind == 3 ? 0.0f : 1.0f, kind == 3 ? 1.0f : 0.0f, 0.0f};
                    if (kind == 2) { /* varying, so that pruning keeps the NaN's leaf */
                        v[0] += 0.01f * (float)i;
                        v[1] = i == 3 && j == 4 && k == 5 ? NAN : 0.0f;
                    }
                    gridvdb_writer_set(w, gv, i, j, k, v);
                }
    }
    ASSERT_EQ_INT(gridvdb_writer_save(w, path, 1), BRUME_OK);
    gridvdb_writer_free(w);
}

/* The puff scene: `density_extra` adds keys to the grid (a placement), `medium_extra` to the
 * medium (a velocity or keyframes). */
static brume_image *render_puff(const char *path, const char *density_extra, const char *medium_extra,
                                unsigned long long seed)
{
    char json[4096];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0.4, 0, 5], \"look_at\": [0.4, 0, 0], \"fov\": 30, \"shutter\": [0, 0.8]},"
             " \"lights\": [{\"type\": \"distant\", \"direction\": [0.3, -1, -0.4], \"irradiance\": 3.0}],"
             " \"background\": [0.1, 0.15, 0.25],"
             " \"media\": [{\"density\": {\"type\": \"grid\", \"file\": \"%s\"%s},"
             "   \"sigma_a\": [1, 1.5, 2], \"sigma_s\": [3, 2.5, 2], \"emission\": [0.6, 0.3, 0.1]%s}],"
             " \"render\": {\"width\": 32, \"height\": 24, \"spp\": 64, \"max_depth\": 4}}",
             path, density_extra, medium_extra);
    return test_render_json(json, seed);
}

/* Blocks (of a 4 x 4 split) and channels where a and b differ by more than z standard
 * errors; the largest ratio in *worst. Per block, the mean of the pixel differences
 * d = a - b, whose standard error is the spread of d over the block's pixels / sqrt(n): the
 * renders are independent (other seeds) and pixels independent, and under the hypothesis
 * that both estimate the same image every d has mean 0, so the image's own variation across
 * the block cancels and the spread is the estimators' noise alone. */
static int blocks_differ(const brume_image *a, const brume_image *b, double z, double *worst)
{
    const int W = brume_image_width(a), H = brume_image_height(a), bw = W / 4, bh = H / 4;
    ASSERT_TRUE(brume_image_width(b) == W && brume_image_height(b) == H);
    const float *pa = brume_image_pixels(a), *pb = brume_image_pixels(b);
    int bad = 0;
    *worst = 0.0;
    for (int by = 0; by < 4; by++)
        for (int bx = 0; bx < 4; bx++)
            for (int c = 0; c < 3; c++) {
                double s1 = 0.0, s2 = 0.0, scale = 0.0;
                int n = 0;
                for (int y = by * bh; y < (by + 1) * bh; y++)
                    for (int x = bx * bw; x < (bx + 1) * bw; x++, n++) {
                        size_t i = 4 * ((size_t)y * (size_t)W + (size_t)x) + (size_t)c;
                        double d = (double)pa[i] - (double)pb[i];
                        s1 += d;
                        s2 += d * d;
                        scale = fmax(scale, fabs((double)pa[i]));
                    }
                double mean = s1 / n, var = fmax(0.0, (s2 - s1 * s1 / n) / (n - 1));
                /* a block the medium never reaches has no noise: equal up to rounding there */
                double se = sqrt(var / n) + 1e-6 * scale;
                double r = se > 0.0 ? fabs(mean) / se : 0.0;
                *worst = fmax(*worst, r);
                bad += r > z;
            }
    return bad;
}

/* A constant velocity u over the shutter [0, 0.8] from frame time 0 moves the puff as the
 * keyframed translation by u t does: back-advection x - u t is exact for a constant field.
 * 48 block-channel comparisons at z = 4.5 standard errors: a false failure has probability
 * below 48 x 6.8e-6 = 3.3e-4 for gaussian block means (48 pixels each; seeds fixed; the
 * t distribution's heavier tail at 47 degrees of freedom makes it about 2e-3). */
TEST(constant_velocity_matches_keyframed_translation)
{
    need_openvdb();
    const char *path = test_tmp_path("velocity-puff.nvdb");
    write_puff(path, (const double[3]){0, 0, 0}, 0);
    brume_image *vel = render_puff(path, "", ", \"velocity\": {\"grid\": \"vel\", \"scale\": 1.0}", 11);
    brume_image *key = render_puff(path, "",
                                   ", \"keyframes\": [{\"time\": 0, \"transform\": {\"translate\": [0, 0, 0]}},"
                                   " {\"time\": 0.8, \"transform\": {\"translate\": [0.8, 0, 0]}}]",
                                   12);
    brume_image *still = render_puff(path, "", "", 13);
    double worst, worst_still;
    int bad = blocks_differ(vel, key, 4.5, &worst);
    int bad_still = blocks_differ(still, key, 4.5, &worst_still);
    printf("velocity vs keyframes: %d of 48 beyond 4.5 se (worst %.2f); unmoved vs keyframes: %d (worst %.1f)\n", bad,
           worst, bad_still, worst_still);
    ASSERT_EQ_INT(bad, 0);
    /* the comparison has the power to see the motion: the unmoved puff fails it */
    ASSERT_TRUE(bad_still >= 6);
    /* the velocity's scale is its units: twice the scale moves twice as far (differs too) */
    brume_image *fast = render_puff(path, "", ", \"velocity\": {\"grid\": \"vel\", \"scale\": 2.0}", 14);
    double worst_fast;
    ASSERT_TRUE(blocks_differ(fast, key, 4.5, &worst_fast) >= 6);
    brume_image_release(fast);
    brume_image_release(vel);
    brume_image_release(key);
    brume_image_release(still);
}

/* A sequence of files, each with its own velocity, as a simulation writes it: frame f reads
 * file f's density and velocity. Files velseq_0001 (velocity +x) and velseq_0002 (+y),
 * frames at f seconds (render.fps 1), the shutter [0, 0.8] from the frame's time: frame 2
 * renders as the puff moved along +y by keyframes over [2, 2.8], and not as the one moved
 * along +x (frame 1's velocity, or one velocity for the whole sequence). Tolerance as
 * above. */
TEST(sequence_frames_blur_by_their_own_velocity)
{
    need_openvdb();
    char p1[512], p2[512], pattern[512];
    snprintf(p1, sizeof p1, "%s", test_tmp_path("velseq_0001.nvdb"));
    snprintf(p2, sizeof p2, "%s", test_tmp_path("velseq_0002.nvdb"));
    snprintf(pattern, sizeof pattern, "%s", test_tmp_path("velseq_%04d.nvdb"));
    write_puff(p1, (const double[3]){0, 0, 0}, 0);
    write_puff(p2, (const double[3]){0, 0, 0}, 3);
    brume_image *img[3];
    const char *extra[3] = {", \"velocity\": {\"grid\": \"vel\"}",
                             ", \"keyframes\": [{\"time\": 2, \"transform\": {\"translate\": [0, 0, 0]}},"
                             " {\"time\": 2.8, \"transform\": {\"translate\": [0, 0.8, 0]}}]",
                             ", \"keyframes\": [{\"time\": 2, \"transform\": {\"translate\": [0, 0, 0]}},"
                             " {\"time\": 2.8, \"transform\": {\"translate\": [0.8, 0, 0]}}]"};
    for (int m = 0; m < 3; m++) {
        char json[4096];
        snprintf(json, sizeof json,
                 "{\"camera\": {\"position\": [0.4, 0.4, 5], \"look_at\": [0.4, 0.4, 0], \"fov\": 34,"
                 " \"shutter\": [0, 0.8]},"
                 " \"lights\": [{\"type\": \"distant\", \"direction\": [0.3, -1, -0.4], \"irradiance\": 3.0}],"
                 " \"background\": [0.1, 0.15, 0.25],"
                 " \"media\": [{\"density\": {\"type\": \"grid\", \"file\": \"%s\"},"
                 "   \"sigma_a\": [1, 1.5, 2], \"sigma_s\": [3, 2.5, 2], \"emission\": [0.6, 0.3, 0.1]%s}],"
                 " \"render\": {\"width\": 32, \"height\": 24, \"spp\": 64, \"max_depth\": 4, \"fps\": 1}}",
                 m == 0 ? pattern : p2, extra[m]);
        brume_context *ctx = brume_context_new();
        brume_scene *s = NULL;
        brume_load_options lo = {.frame = 2};
        if (brume_scene_load(ctx, &(brume_source){.path = "velseq.json", .text = json}, &lo, &s) != BRUME_OK)
            TEST_FAIL("%s", brume_context_last_error(ctx));
        img[m] = test_render_scene(s, -1, 31 + (unsigned long long)m);
        brume_scene_release(s);
        brume_context_release(ctx);
    }
    double worst_y, worst_x;
    int bad_y = blocks_differ(img[0], img[1], 4.5, &worst_y), bad_x = blocks_differ(img[0], img[2], 4.5, &worst_x);
    printf("frame 2 by its file's velocity vs keyframes along +y: %d of 48 beyond 4.5 se (worst %.2f); vs +x: %d "
           "(worst %.1f)\n", bad_y, worst_y, bad_x, worst_x);
    ASSERT_EQ_INT(bad_y, 0);
    ASSERT_TRUE(bad_x >= 6);
    for (int m = 0; m < 3; m++)
        brume_image_release(img[m]);
}

/* The grid's placement transform turns the vectors with the grid: the file's velocity
 * (1, 0, 0) on a grid turned 90 degrees about z moves the puff (round, centred on the axis:
 * turned into itself) along +y, as keyframes along +y do, and not as the unturned vectors
 * would (along +x). Tolerance as above. */
TEST(grid_transform_turns_the_velocity)
{
    need_openvdb();
    const char *path = test_tmp_path("velocity-turned.nvdb");
    write_puff(path, (const double[3]){0, 0, 0}, 0);
    const char *turn = ", \"transform\": {\"rotate\": {\"axis\": [0, 0, 1], \"angle\": 90}}";
    brume_image *vel = render_puff(path, turn, ", \"velocity\": {\"grid\": \"vel\"}", 21);
    brume_image *key = render_puff(path, "",
                                   ", \"keyframes\": [{\"time\": 0, \"transform\": {\"translate\": [0, 0, 0]}},"
                                   " {\"time\": 0.8, \"transform\": {\"translate\": [0, 0.8, 0]}}]",
                                   22);
    brume_image *along_x = render_puff(path, "", ", \"velocity\": {\"grid\": \"vel\"}", 23);
    double worst, worst_x;
    int bad = blocks_differ(vel, key, 4.5, &worst), bad_x = blocks_differ(along_x, key, 4.5, &worst_x);
    printf("turned velocity vs keyframes along y: %d of 48 (worst %.2f); unturned: %d (worst %.1f)\n", bad, worst,
           bad_x, worst_x);
    ASSERT_EQ_INT(bad, 0);
    ASSERT_TRUE(bad_x >= 6);
    brume_image_release(vel);
    brume_image_release(key);
    brume_image_release(along_x);
}

/* The majorant at world point x of field d's walk: the segment of a short ray through x. */
static double majorant_at(const density *d, vec3 x)
{
    const double eps = 1e-7;
    const ray r = {v3_sub(x, v3(eps, 0, 0)), v3(1, 0, 0), 0.0};
    majorant_iter it;
    majorant_seg seg;
    density_majorant_begin(d, r, 0.0, 2 * eps, &it);
    while (majorant_next(&it, &seg))
        if (seg.t0 <= eps && eps < seg.t1)
            return seg.rho_maj;
    return 0.0;
}

/* rho(x - v(x) dt) <= the moved majorant at x, at 200000 random points of the moved field's
 * box and times dt of the shutter [-0.1, 0.3], for the rotation omega = 2 about the z axis
 * (|v| up to 7.3 over the velocity grid, 3.2 at the block: points move up to 22 voxels, 10
 * at the block) and a sharp-edged block; rho's own, undilated majorants fail (so the check can fail), and the majorants from
 * each cell's own radius are below those of the global radius somewhere (the local bound
 * does something) and nowhere above. Run with the cell grid's majorants and with the tree's
 * (a large box's: the coarse uniform bound, one radius). */
static void check_moved_majorant(bool tree)
{
    need_openvdb();
    const char *path = test_tmp_path("velocity-swirl.nvdb");
    write_puff(path, (const double[3]){1.5, 0.5, 0}, 1);
    uint64_t old = nanovdb_set_cell_grid_limit(tree ? 0 : (uint64_t)1 << 23);
    char json[2048];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0], \"fov\": 40, \"shutter\": [-0.1, 0.3]},"
             " \"media\": [{\"density\": {\"type\": \"grid\", \"file\": \"%s\"}, \"sigma_a\": 1, \"sigma_s\": 1,"
             "   \"velocity\": {\"grid\": \"vel\"}}]}",
             path);
    brume_scene *s = NULL;
    brume_context *ctx = brume_context_new();
    if (brume_scene_load(ctx, &(brume_source){.path = "<velocity test>", .text = json}, NULL, &s) != BRUME_OK ||
        brume_scene_commit(ctx, s) != BRUME_OK)
        TEST_FAIL("scene: %s", brume_context_last_error(ctx));
    nanovdb_set_cell_grid_limit(old);
    const medium *md = &s->media[0];
    ASSERT_TRUE(md->moved != NULL && md->velocity[2] != NULL);
    /* the bound from the components' ranges over the voxel centres written: |v_x| = omega |y|
     * <= 2 x 2.05, |v_y| = omega |x| <= 2 x 3.05 (x in [-0.05, 3.05], y in [-1.05, 2.05]) */
    printf("max |v| bound %.4f\n", md->velocity_max);
    ASSERT_NEAR(md->velocity_max, sqrt(4.1 * 4.1 + 6.1 * 6.1), 1e-5);
    /* points within 1 world unit of the block (|v dt| <= 0.96 there), where the bound is tight */
    const box3 rb = density_bounds(md->rho), b = {v3_sub(rb.lo, v3(1, 1, 1)), v3_add(rb.hi, v3(1, 1, 1))};
    /* the same majorants with the global radius max |v| max |dt|, not each cell's own */
    density *global = density_new_moved_majorant(md->rho, md->velocity_max * 0.3, NULL, NULL);
    ASSERT_TRUE(global != NULL);
    rng g = rng_make(5, 0, 0);
    int above_own = 0, n = 200000, nonzero = 0, tighter = 0;
    for (int i = 0; i < n; i++) {
        vec3 x = v3(b.lo.x + rng_next(&g) * (b.hi.x - b.lo.x), b.lo.y + rng_next(&g) * (b.hi.y - b.lo.y),
                    b.lo.z + rng_next(&g) * (b.hi.z - b.lo.z));
        double dt = -0.1 + 0.4 * rng_next(&g);
        vec3 v = v3(density_eval(md->velocity[0], x), density_eval(md->velocity[1], x),
                    density_eval(md->velocity[2], x));
        double rho = density_eval(md->rho, v3_sub(x, v3_scale(v, dt)));
        double maj = majorant_at(md->moved, x);
        if (!(rho <= maj))
            TEST_FAIL("rho(x - v dt) = %g above the moved majorant %g at (%g, %g, %g), dt %g", rho, maj, x.x, x.y, x.z,
                      dt);
        nonzero += rho > 0.0;
        above_own += rho > majorant_at(md->rho, x);
        double maj_global = majorant_at(global, x);
        ASSERT_TRUE(maj <= maj_global);
        tighter += maj < maj_global;
    }
    printf("%d of %d points with density; %d above rho's own (undilated) majorant; %d where the cells' own "
           "radii give less than the global one\n", nonzero, n, above_own, tighter);
    ASSERT_TRUE(nonzero > n / 500);
    ASSERT_TRUE(above_own > 0);
    ASSERT_TRUE(tree || tighter > 0); /* a large box's velocity has no cells: one radius */
    density_release(global);
    brume_scene_release(s);
    brume_context_release(ctx);
}

TEST(moved_majorant_bounds_advected_density) { check_moved_majorant(false); }
TEST(moved_majorant_bounds_advected_density_tree) { check_moved_majorant(true); }

/* Each bad velocity input: one line naming the scene file, the field and the grid file. */
static void refused(const char *grid_path, const char *velocity, const char *method, const char *want)
{
    const char *scene = test_tmp_path("velocity-bad.json");
    char json[2048];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0], \"shutter\": [0, 0.5]},"
             " \"media\": [{\"density\": {\"type\": \"grid\", \"file\": \"%s\"}, \"sigma_a\": 1, \"sigma_s\": 1,"
             "   \"velocity\": %s}],"
             " \"render\": {\"width\": 8, \"height\": 8, \"spp\": 1, \"method\": \"%s\"}}",
             grid_path, velocity, method);
    test_write_file(scene, json);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    brume_image *img = NULL;
    brume_status st = brume_scene_load(ctx, &(brume_source){.path = scene}, NULL, &s);
    if (st == BRUME_OK) {
        st = brume_scene_commit(ctx, s);
        if (st == BRUME_OK)
            st = brume_render(ctx, s, &img);
    }
    const char *msg = brume_context_last_error(ctx);
    printf("%s\n", msg);
    ASSERT_TRUE(st != BRUME_OK && img == NULL);
    ASSERT_TRUE(strchr(msg, '\n') == NULL);
    ASSERT_CONTAINS(msg, scene);
    ASSERT_CONTAINS(msg, "velocity");
    ASSERT_CONTAINS(msg, want);
    brume_scene_release(s);
    brume_context_release(ctx);
}

TEST(bad_velocity_inputs_refused)
{
    need_openvdb();
    const char *good = test_tmp_path("velocity-good.nvdb"), *nan = test_tmp_path("velocity-nan.nvdb");
    write_puff(good, (const double[3]){0, 0, 0}, 0);
    write_puff(nan, (const double[3]){0, 0, 0}, 2);
    char want[1024];
    snprintf(want, sizeof want, "%s: no velocity grid \"v\"", good);
    refused(good, "{\"grid\": \"v\"}", "path", want);
    snprintf(want, sizeof want, "%s: grid \"density\" is a float grid", good);
    refused(good, "{\"grid\": \"density\"}", "path", want);
    snprintf(want, sizeof want, "%s: voxel (3, 4, 5) has value nan: need finite", nan);
    refused(nan, "{\"grid\": \"vel\"}", "path", want);
    refused(good, "{\"grid\": \"vel\", \"scale\": -1}", "path", "velocity.scale");
    refused(good, "{\"grid\": \"vel\", \"speed\": 1}", "path", "speed");
    refused(good, "{\"grid\": \"vel\"}", "blasi", "method blasi does not blur by velocity");
}

/* The puff with a fast velocity (`scale` world units per second, shutter [0, shutter])
 * loaded and committed under render.max_memory_mb = mb (0: the default); the status, the
 * scene's bytes (brume_scene_memory) and its moved majorant's in *bytes and *moved. */
static brume_status load_fast_puff(const char *grid, double scale, double shutter, double mb, size_t *bytes,
                                   size_t *moved, char *msg, size_t n)
{
    const char *scene = test_tmp_path("velocity-budget.json");
    char json[2048], render[64] = "";
    if (mb > 0.0)
        snprintf(render, sizeof render, ", \"render\": {\"max_memory_mb\": %.6f}", mb);
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0], \"shutter\": [0, %g]},"
             " \"media\": [{\"density\": {\"type\": \"grid\", \"file\": \"%s\"}, \"sigma_a\": 1, \"sigma_s\": 1,"
             "   \"velocity\": {\"grid\": \"vel\", \"scale\": %g}}]%s}",
             shutter, grid, scale, render);
    test_write_file(scene, json);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    brume_status st = brume_scene_load(ctx, &(brume_source){.path = scene}, NULL, &s);
    if (st == BRUME_OK)
        st = brume_scene_commit(ctx, s);
    *bytes = brume_scene_memory(s, NULL);
    *moved = 0;
    if (st == BRUME_OK && s->media[0].moved) {
        density_info info;
        density_get_info(s->media[0].moved, &info);
        *moved = info.memory_bytes;
    }
    snprintf(msg, n, "%s", brume_context_last_error(ctx));
    brume_scene_release(s);
    brume_context_release(ctx);
    return st;
}

/* The moved majorant grid (up to 16 MiB) counts against render.max_memory_mb like every
 * grid: the scene's bytes grow by it, and a limit that holds the grids but not it refuses
 * the scene in one line naming it and the key. */
TEST(moved_majorant_counts_against_memory_limit)
{
    need_openvdb();
    const char *grid = test_tmp_path("velocity-budget.nvdb");
    write_puff(grid, (const double[3]){0, 0, 0}, 0);
    size_t still = 0, blur = 0, moved = 0, none = 0;
    char msg[1024];
    /* scale 100: the puff moves 80 units (800 voxels) within the shutter: a large dilation */
    ASSERT_EQ_INT(load_fast_puff(grid, 100.0, 0.0, 0.0, &still, &none, msg, sizeof msg), BRUME_OK);
    ASSERT_EQ_INT((int)none, 0); /* a closed shutter moves nothing: no moved majorant */
    ASSERT_EQ_INT(load_fast_puff(grid, 100.0, 0.8, 0.0, &blur, &moved, msg, sizeof msg), BRUME_OK);
    printf("grids %zu bytes; with the moved majorant %zu (it alone %zu)\n", still, blur, moved);
    ASSERT_TRUE(moved > ((size_t)1 << 20));
    ASSERT_EQ_INT((long long)(blur - still), (long long)moved);
    double mb = ((double)still + 0.5 * (double)moved) / 1048576.0; /* the grids fit, the moved majorant not */
    ASSERT_TRUE(mb >= 1.0);
    ASSERT_EQ_INT(load_fast_puff(grid, 100.0, 0.8, mb, &blur, &moved, msg, sizeof msg), BRUME_ERROR_OUT_OF_MEMORY);
    printf("%s\n", msg);
    ASSERT_TRUE(strchr(msg, '\n') == NULL);
    ASSERT_CONTAINS(msg, "media[0].velocity");
    ASSERT_CONTAINS(msg, "moved majorant grid");
    ASSERT_CONTAINS(msg, "render.max_memory_mb");
    remove(grid);
}

TEST_MAIN(constant_velocity_matches_keyframed_translation, grid_transform_turns_the_velocity,
          sequence_frames_blur_by_their_own_velocity,
          moved_majorant_bounds_advected_density,
          moved_majorant_bounds_advected_density_tree, bad_velocity_inputs_refused,
          moved_majorant_counts_against_memory_limit)
