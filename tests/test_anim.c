/* test_anim.c - time in the renderer: motion blur of a moving sphere and a moving medium
 * against the box-convolved shape, thin-lens focus against the circle of confusion,
 * keyframed cameras, sequences, shards, and MPI ranks against one process. */
#include "test.h"

#include <sys/stat.h>

#include "brume.h"
#include "scene/scene.h"

static brume_scene *scene_at(const char *json, double time, long frame_no)
{
    brume_scene *s = NULL;
    brume_context *ctx = brume_context_new();
    brume_load_options o = {.time = time, .frame = frame_no > 0 ? frame_no : 0};
    if (brume_scene_load(ctx, &(brume_source){.path = "<anim test>", .text = json}, &o, &s) != BRUME_OK)
        TEST_FAIL("scene: %s", brume_context_last_error(ctx));
    brume_context_release(ctx);
    return s;
}

static brume_image *render(brume_scene *s)
{
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    if (brume_scene_commit(ctx, s) != BRUME_OK || brume_render(ctx, s, &img) != BRUME_OK)
        TEST_FAIL("render: %s", brume_context_last_error(ctx));
    brume_context_release(ctx);
    return img;
}

static double red(const brume_image *img, int x, int y)
{
    return brume_image_pixels(img)[4 * ((size_t)y * (size_t)brume_image_width(img) + (size_t)x)];
}

/* Expected coverage of pixel [x, x+1] x [y, y+1] by a shape whose horizontal half-extent at
 * height v is h(v) (h < 0: not covered), centred at cx moving uniformly from cx - D/2 to
 * cx + D/2 over the shutter: the shape convolved with a box of width D, integrated over the
 * pixel. The time integral is exact (the overlap of two intervals), the pixel one by a
 * 64 x 64 midpoint rule. */
typedef double (*half_width_fn)(double dv, double size);
static double disc_half_width(double dv, double r) { return r * r - dv * dv > 0 ? sqrt(r * r - dv * dv) : -1.0; }
static double square_half_width(double dv, double a) { return fabs(dv) < a ? a : -1.0; }

static double blurred_coverage(half_width_fn h, double size, double cx, double cy, double D, int x, int y)
{
    const int n = 64;
    double sum = 0.0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            double u = x + (i + 0.5) / n, v = y + (j + 0.5) / n;
            double hw = h(v - cy, size);
            if (hw < 0.0)
                continue;
            /* the centre c covers u while |u - c| < hw, c in [cx - D/2, cx + D/2] */
            double lo = fmax(u - hw, cx - 0.5 * D), hi = fmin(u + hw, cx + 0.5 * D);
            sum += hi > lo ? (hi - lo) / D : 0.0;
        }
    return sum / (n * n);
}

/* Checks the centre row of img against the blurred shape and reports the ramp's extent. */
static void check_blur_profile(const brume_image *img, half_width_fn h, double size_px, double D_px, int spp)
{
    int W = brume_image_width(img), H = brume_image_height(img), y = H / 2;
    double cx = 0.5 * W, cy = 0.5 * H;
    int first_m = -1, last_m = -1, first_e = -1, last_e = -1;
    double worst = 0.0;
    for (int x = 0; x < W; x++) {
        double e = blurred_coverage(h, size_px, cx, cy, D_px, x, y), m = red(img, x, y);
        /* binomial noise of spp samples of a 0/1 estimator, and 0.01 for the perspective
         * and quadrature approximations of the expectation */
        double tol = 4.0 * sqrt(fmax(e * (1.0 - e), 0.02) / spp) + 0.01;
        if (fabs(m - e) > tol)
            TEST_FAIL("pixel %d of the centre row: measured %.4f, expected %.4f (tolerance %.4f)", x, m, e, tol);
        worst = fmax(worst, fabs(m - e) / tol);
        if (m > 0.05) {
            if (first_m < 0) first_m = x;
            last_m = x;
        }
        if (e > 0.05) {
            if (first_e < 0) first_e = x;
            last_e = x;
        }
    }
    ASSERT_TRUE(first_m >= 0 && first_e >= 0);
    fprintf(stderr, "blur: ramp extent measured %d px, expected %d px (shape %.2f px + motion %.2f px); worst "
                    "pixel at %.2f of its tolerance\n",
            last_m - first_m + 1, last_e - first_e + 1, 2 * size_px, D_px, worst);
    ASSERT_NEAR(last_m - first_m, last_e - first_e, 1.0);
}

/* Pixels per world unit at distance z on the axis for a camera of vertical fov (degrees)
 * and image height H. */
static double px_per_unit(double fov, int H, double z) { return 0.5 * H / (z * tan(0.5 * fov * PI / 180.0)); }

/* An emissive sphere of radius 0.3 at distance 10 moving by 1 unit along x while the
 * shutter is open [0, 1] s: Embree motion blur through the path integrator. */
TEST(moving_sphere_blurs_by_its_motion)
{
    const char *json =
        "{\"camera\": {\"position\": [0, 0, 10], \"look_at\": [0, 0, 0], \"fov\": 8, \"shutter\": [0, 1]},"
        " \"surfaces\": [{\"type\": \"sphere\", \"radius\": 0.3, \"material\": {\"albedo\": 0, \"emission\": 1},"
        "   \"keyframes\": [{\"time\": 0, \"transform\": {\"translate\": [-0.5, 0, 0]}},"
        "                   {\"time\": 1, \"transform\": {\"translate\": [0.5, 0, 0]}}]}],"
        " \"render\": {\"width\": 63, \"height\": 15, \"spp\": 256, \"max_depth\": 1,"
        "             \"filter\": {\"type\": \"box\", \"width\": 1}}}";
    brume_scene *s = scene_at(json, 0.0, -1);
    ASSERT_TRUE(!brume_scene_world_is_static(s));
    brume_image *img = render(s);
    double k = px_per_unit(8.0, 15, 10.0);
    double r_px = 0.3 / sqrt(100.0 - 0.09) * 10.0 * k; /* tangent of the angular radius */
    check_blur_profile(img, disc_half_width, r_px, 1.0 * k, 256);
    brume_image_release(img);
    brume_scene_release(s);
}

/* A thin emissive, optically thick slab (a square seen face on) moving the same way: media
 * move through the shared tracking code. */
TEST(moving_medium_blurs_by_its_motion)
{
    const char *json =
        "{\"camera\": {\"position\": [0, 0, 10], \"look_at\": [0, 0, 0], \"fov\": 8, \"shutter\": [0, 1]},"
        " \"media\": [{\"density\": {\"type\": \"constant\", \"value\": 1,"
        "                           \"bounds\": [[-0.25, -0.25, -0.025], [0.25, 0.25, 0.025]]},"
        "   \"sigma_a\": 4000, \"sigma_s\": 0, \"emission\": 1,"
        "   \"keyframes\": [{\"time\": 0, \"transform\": {\"translate\": [-0.5, 0, 0]}},"
        "                   {\"time\": 1, \"transform\": {\"translate\": [0.5, 0, 0]}}]}],"
        " \"render\": {\"width\": 63, \"height\": 15, \"spp\": 256, \"max_depth\": 1,"
        "             \"filter\": {\"type\": \"box\", \"width\": 1}}}";
    brume_scene *s = scene_at(json, 0.0, -1);
    brume_image *img = render(s);
    double k = px_per_unit(8.0, 15, 10.0);
    /* the silhouette is the front face, at distance 9.975 */
    check_blur_profile(img, square_half_width, 0.25 * 10.0 / 9.975 * k, 1.0 * k, 256);
    brume_image_release(img);
    brume_scene_release(s);
}

/* Intensity-weighted mean and variance along x of img's columns [x0, x1). */
static void moments_x(const brume_image *img, int x0, int x1, double *mean, double *var)
{
    double s0 = 0.0, s1 = 0.0, s2 = 0.0;
    for (int y = 0; y < brume_image_height(img); y++)
        for (int x = x0; x < x1; x++) {
            double w = red(img, x, y), px = x + 0.5;
            s0 += w;
            s1 += w * px;
            s2 += w * px * px;
        }
    ASSERT_TRUE(s0 > 0.0);
    *mean = s1 / s0;
    *var = s2 / s0 - *mean * *mean;
}

/* Thin lens focused at 10 with aperture radius 0.2: a small emissive sphere at distance 10
 * stays sharp; one at distance 6 spreads over the circle of confusion, whose radius on the
 * focus plane is a |z - f| / z. A uniform disc of radius c has variance c^2 / 4 per axis;
 * the sphere's own image adds rho^2 / 4, and the unit box filter (each pixel integrates
 * its cell) adds 1/12. */
TEST(thin_lens_focuses_at_the_focus_distance)
{
    const char *json =
        "{\"camera\": {\"position\": [0, 0, 10], \"look_at\": [0, 0, 0], \"fov\": 20,"
        "             \"aperture_radius\": 0.2, \"focus_distance\": 10},"
        " \"surfaces\": [{\"type\": \"sphere\", \"center\": [-1, 0, 0], \"radius\": 0.05,"
        "                 \"material\": {\"albedo\": 0, \"emission\": 1}},"
        "                {\"type\": \"sphere\", \"center\": [0.6, 0, 4], \"radius\": 0.05,"
        "                 \"material\": {\"albedo\": 0, \"emission\": 1}}],"
        " \"render\": {\"width\": 96, \"height\": 64, \"spp\": 256, \"max_depth\": 1,"
        "             \"filter\": {\"type\": \"box\", \"width\": 1}}}";
    brume_scene *s = scene_at(json, 0.0, -1);
    brume_image *img = render(s);
    const double a = 0.2, f = 10.0, rho = 0.05, zb = 6.0;
    double k = px_per_unit(20.0, 64, f); /* on the focus plane */
    double rho_a = rho / 10.0 * f * k, rho_b = rho / zb * f * k;
    double c = a * fabs(zb - f) / zb * k;
    double mean_a, var_a, mean_b, var_b;
    moments_x(img, 0, 48, &mean_a, &var_a);
    moments_x(img, 48, 96, &mean_b, &var_b);
    double want_a = rho_a * rho_a / 4.0 + 1.0 / 12.0; /* about one pixel: a sharp image */
    double want_b = c * c / 4.0 + rho_b * rho_b / 4.0 + 1.0 / 12.0;
    double coc_measured = 4.0 * sqrt(fmax(0.0, var_b - 1.0 / 12.0 - rho_b * rho_b / 4.0)); /* diameter */
    fprintf(stderr, "lens: in focus spread %.3f px (want <= %.3f); off focus spread %.3f px (want %.3f): circle of "
                    "confusion %.3f px across vs %.3f expected\n",
            sqrt(var_a), sqrt(want_a) + 0.1, sqrt(var_b), sqrt(want_b), coc_measured, 2.0 * c);
    ASSERT_TRUE(sqrt(var_a) <= sqrt(want_a) + 0.1);
    ASSERT_NEAR(sqrt(var_b), sqrt(want_b), 0.04 * sqrt(want_b));
    ASSERT_NEAR(coc_measured, 2.0 * c, 0.1 * 2.0 * c);
    brume_image_release(img);
    brume_scene_release(s);
}

static const char *keyed_camera_json =
    "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 30,"
    "   \"keyframes\": [{\"time\": 0, \"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 30},"
    "                   {\"time\": 2, \"position\": [2, 1, 4], \"look_at\": [1, 0, 0], \"fov\": 50}]},"
    " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, -1], \"irradiance\": 3}],"
    " \"background\": 0.2,"
    " \"media\": [{\"density\": {\"type\": \"constant\", \"value\": 1, \"bounds\": [[-1, -1, -1], [1, 1, 1]]},"
    "             \"sigma_a\": 0.1, \"sigma_s\": 1.5}],"
    " \"render\": {\"width\": 32, \"height\": 24, \"spp\": 2, \"fps\": 2}}";

/* Frame 2 at 2 fps is t = 1, halfway between the keys: the same bytes as a fixed camera at
 * the interpolated pose. */
TEST(keyed_camera_matches_fixed_camera_at_the_frame_time)
{
    const char *fixed =
        "{\"camera\": {\"position\": [1, 0.5, 4], \"look_at\": [0.5, 0, 0], \"fov\": 40},"
        " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, -1], \"irradiance\": 3}],"
        " \"background\": 0.2,"
        " \"media\": [{\"density\": {\"type\": \"constant\", \"value\": 1, \"bounds\": [[-1, -1, -1], [1, 1, 1]]},"
        "             \"sigma_a\": 0.1, \"sigma_s\": 1.5}],"
        " \"render\": {\"width\": 32, \"height\": 24, \"spp\": 2}}";
    brume_scene *a = scene_at(keyed_camera_json, 0.0, 2);
    ASSERT_NEAR(brume_scene_time(a), 1.0, 0.0);
    ASSERT_TRUE(brume_scene_world_is_static(a));
    brume_scene *b = scene_at(fixed, 0.0, -1);
    brume_image *ia = render(a), *ib = render(b);
    ASSERT_TRUE(memcmp(brume_image_pixels(ia), brume_image_pixels(ib), 32 * 24 * 4 * sizeof(float)) == 0);

    /* the same scene moved to frame 2 after commit (what sequences do when only the camera
     * moves, keeping the integrator's prepared state) gives the same bytes again */
    brume_scene *c = scene_at(keyed_camera_json, 0.0, 0);
    brume_context *ctx = brume_context_new();
    brume_image *i0 = render(c), *ic = NULL;
    ASSERT_EQ_INT(brume_scene_set_camera_time(ctx, c, 1.0), BRUME_OK);
    ASSERT_EQ_INT(brume_render(ctx, c, &ic), BRUME_OK);
    ASSERT_TRUE(memcmp(brume_image_pixels(ia), brume_image_pixels(ic), 32 * 24 * 4 * sizeof(float)) == 0);
    ASSERT_TRUE(memcmp(brume_image_pixels(ia), brume_image_pixels(i0), 32 * 24 * 4 * sizeof(float)) != 0);
    brume_context_release(ctx);
    brume_image_release(i0);
    brume_image_release(ic);
    brume_image_release(ia);
    brume_image_release(ib);
    brume_scene_release(a);
    brume_scene_release(b);
    brume_scene_release(c);
}

/* Keyframe errors name the key; a scene where more than the camera moves refuses to be
 * moved after commit. */
TEST(keyframe_errors_and_moving_worlds)
{
    brume_scene *s = NULL;
    const char *bad = "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0],"
                      " \"keyframes\": [{\"time\": 1, \"fov\": 30}, {\"time\": 1, \"fov\": 40}]}}";
    brume_context *ctx = brume_context_new();
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = "<bad>", .text = bad}, NULL, &s), BRUME_ERROR_RANGE);
    const char *lit = "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0]},"
                      " \"lights\": [{\"type\": \"point\", \"position\": [0, 0, 0], \"intensity\": 1,"
                      "   \"keyframes\": [{\"time\": 0, \"intensity\": 1}, {\"time\": 2, \"intensity\": 3}]}]}";
    s = scene_at(lit, 1.0, -1);
    ASSERT_NEAR(s->lights[0].L.c[0], 2.0, 1e-12);
    ASSERT_TRUE(!brume_scene_world_is_static(s));
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_set_camera_time(ctx, s, 2.0), BRUME_ERROR_STATE);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* ---- the tool: sequences, video, shards, MPI ------------------------------------------ */

static int same_file(const char *a, const char *b)
{
    size_t na, nb;
    char *da = test_slurp(a, &na), *db = test_slurp(b, &nb);
    int same = na == nb && memcmp(da, db, na) == 0;
    free(da);
    free(db);
    return same;
}

/* A small scene file where a sphere moves past a cloud of fog: every frame differs. */
static const char *write_scene(void)
{
    const char *path = test_tmp_path("anim.json");
    FILE *fp = fopen(path, "w");
    ASSERT_TRUE(fp != NULL);
    fputs("{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0], \"fov\": 40, \"shutter\": [0, 0.02]},"
          " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, -1], \"irradiance\": 3}],"
          " \"background\": 0.2,"
          " \"media\": [{\"density\": {\"type\": \"constant\", \"value\": 1,"
          "                           \"bounds\": [[-1, -1, -1], [1, 1, 1]]}, \"sigma_a\": 0.1, \"sigma_s\": 1}],"
          " \"surfaces\": [{\"type\": \"sphere\", \"radius\": 0.4, \"material\": {\"albedo\": 0.7},"
          "   \"keyframes\": [{\"time\": 0, \"transform\": {\"translate\": [-1.5, 0, 1.2]}},"
          "                   {\"time\": 1, \"transform\": {\"translate\": [1.5, 0, 1.2]}}]}],"
          " \"render\": {\"width\": 24, \"height\": 16, \"spp\": 2, \"fps\": 8}}",
          fp);
    fclose(fp);
    return path;
}

static int run(const char *args, const char *err_path)
{
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "%s %s >/dev/null 2>%s", BRUME_EXE, args, err_path);
    return test_system(cmd);
}

TEST(sequence_writes_one_file_per_frame)
{
    char scene[512], dir[512], args[4096], p[700];
    snprintf(scene, sizeof scene, "%s", write_scene());
    snprintf(dir, sizeof dir, "%s", test_tmp_path("seq"));
    mkdir(dir, 0755);
    const char *err = test_tmp_path("seq-err.txt");
    snprintf(args, sizeof args, "render %s --frames 2-4 --threads 1 --quiet -o %s/f_%%03d.pfm", scene, dir);
    ASSERT_EQ_INT(run(args, err), 0);
    for (int f = 1; f <= 5; f++) {
        snprintf(p, sizeof p, "%s/f_%03d.pfm", dir, f);
        ASSERT_EQ_INT(test_exists(p), f >= 2 && f <= 4);
    }
    char a[700], b[700];
    snprintf(a, sizeof a, "%s/f_002.pfm", dir);
    snprintf(b, sizeof b, "%s/f_004.pfm", dir);
    ASSERT_TRUE(!same_file(a, b)); /* the sphere moved */
    /* --frame F alone writes that frame: the same bytes as within the sequence */
    snprintf(args, sizeof args, "render %s --frame 4 --threads 2 --quiet -o %s/one.pfm", scene, dir);
    ASSERT_EQ_INT(run(args, err), 0);
    snprintf(a, sizeof a, "%s/one.pfm", dir);
    ASSERT_TRUE(same_file(a, b));
    /* several frames into one file name: refused before any work */
    snprintf(args, sizeof args, "render %s --frames 0-1 --quiet -o %s/nopattern.pfm", scene, dir);
    ASSERT_EQ_INT(run(args, err), 2);
    size_t n;
    char *msg = test_slurp(err, &n);
    ASSERT_CONTAINS(msg, "%d");
    free(msg);
    snprintf(p, sizeof p, "%s/nopattern.pfm", dir);
    ASSERT_TRUE(!test_exists(p));
    snprintf(args, sizeof args, "rm -rf %s %s", dir, err);
    test_system(args);
}

TEST(video_with_and_without_ffmpeg)
{
    char scene[512], dir[512], args[4096], p[700];
    snprintf(scene, sizeof scene, "%s", write_scene());
    snprintf(dir, sizeof dir, "%s", test_tmp_path("vid"));
    mkdir(dir, 0755);
    const char *err = test_tmp_path("vid-err.txt");
    snprintf(args, sizeof args, "render %s --frames 0-3 --quiet -o %s/v_%%02d.png --video %s/v.mp4", scene, dir, dir);
    ASSERT_EQ_INT(run(args, err), 0);
    snprintf(p, sizeof p, "%s/v.mp4", dir);
    struct stat st;
    ASSERT_TRUE(stat(p, &st) == 0 && st.st_size > 100);
    /* no ffmpeg in PATH: checked before any work: one clear line, exit status 1,
     * nothing rendered */
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "env PATH=/nonexistent %s render %s --frames 0-1 --quiet -o %s/w_%%02d.png --video "
             "%s/w.mp4 >/dev/null 2>%s", BRUME_EXE, scene, dir, dir, err);
    ASSERT_EQ_INT(test_system(cmd), 1);
    size_t n;
    char *msg = test_slurp(err, &n);
    ASSERT_CONTAINS(msg, "ffmpeg not found");
    free(msg);
    snprintf(p, sizeof p, "%s/w_01.png", dir);
    ASSERT_TRUE(!test_exists(p));
    snprintf(p, sizeof p, "%s/w.mp4", dir);
    ASSERT_TRUE(!test_exists(p));
    /* a video name that ffmpeg would read as an option ("--video -y") is refused */
    snprintf(args, sizeof args, "render %s --frames 0-1 --quiet -o %s/y_%%02d.png --video -y", scene, dir);
    ASSERT_EQ_INT(run(args, err), 2);
    msg = test_slurp(err, &n);
    ASSERT_CONTAINS(msg, "'-y' is not a file name");
    free(msg);
    snprintf(p, sizeof p, "%s/y_00.png", dir);
    ASSERT_TRUE(!test_exists(p));
    /* ffmpeg's own complaint comes back inside brume's one line, not as its own stderr: an
     * output ffmpeg cannot encode (an unknown container) */
    snprintf(args, sizeof args, "render %s --frames 0-1 --quiet -o %s/z_%%02d.png --video %s/z.nosuchformat", scene,
             dir, dir);
    ASSERT_EQ_INT(run(args, err), 1);
    msg = test_slurp(err, &n);
    ASSERT_CONTAINS(msg, "ffmpeg failed making");
    ASSERT_TRUE(strchr(msg, '\n') == msg + n - 1); /* one line */
    free(msg);
    snprintf(args, sizeof args, "rm -rf %s %s", dir, err);
    test_system(args);
}

/* Shards 0/3, 1/3 and 2/3 of frames 0-6 render each frame exactly once, frame f in shard
 * f % 3, with the same bytes as an unsharded run. */
TEST(shards_cover_every_frame_once)
{
    char scene[512], base[512], args[4096], p[800], q[800];
    snprintf(scene, sizeof scene, "%s", write_scene());
    snprintf(base, sizeof base, "%s", test_tmp_path("shard"));
    mkdir(base, 0755);
    const char *err = test_tmp_path("shard-err.txt");
    for (int i = 0; i < 3; i++) {
        snprintf(p, sizeof p, "%s/s%d", base, i);
        mkdir(p, 0755);
        snprintf(args, sizeof args, "render %s --frames 0-6 --shard %d/3 --threads 1 --quiet -o %s/f_%%d.pfm", scene,
                 i, p);
        ASSERT_EQ_INT(run(args, err), 0);
    }
    snprintf(args, sizeof args, "render %s --frames 0-6 --threads 2 --quiet -o %s/all_%%d.pfm", scene, base);
    ASSERT_EQ_INT(run(args, err), 0);
    for (int f = 0; f < 7; f++) {
        int count = 0;
        for (int i = 0; i < 3; i++) {
            snprintf(p, sizeof p, "%s/s%d/f_%d.pfm", base, i, f);
            if (test_exists(p)) {
                count++;
                ASSERT_EQ_INT(i, f % 3);
                snprintf(q, sizeof q, "%s/all_%d.pfm", base, f);
                ASSERT_TRUE(same_file(p, q));
            }
        }
        ASSERT_EQ_INT(count, 1);
    }
    /* one frame cannot be sharded: a clear refusal */
    snprintf(args, sizeof args, "render %s --shard 0/2 --quiet -o %s/x.pfm", scene, base);
    ASSERT_EQ_INT(run(args, err), 2);
    snprintf(args, sizeof args, "rm -rf %s %s", base, err);
    test_system(args);
}

/* Two MPI ranks on this machine: a frame split by tiles, and a sequence split by frames,
 * give the same EXR bytes as one process. (Registered only in builds with MPI.) */
TEST(mpi_matches_one_process)
{
    char scene[512], dir[512], args[4096], cmd[8192], a[700], b[700];
    snprintf(scene, sizeof scene, "%s", write_scene());
    snprintf(dir, sizeof dir, "%s", test_tmp_path("mpi"));
    mkdir(dir, 0755);
    const char *err = test_tmp_path("mpi-err.txt");
    const char *mpirun = BRUME_MPIEXEC[0] ? BRUME_MPIEXEC : "mpirun";
    /* a frame: 40 x 30 has 6 tiles of 16 x 16, interleaved over the ranks */
    snprintf(args, sizeof args, "render %s --width 40 --height 30 --threads 1 --quiet -o %s/one.exr", scene, dir);
    ASSERT_EQ_INT(run(args, err), 0);
    snprintf(cmd, sizeof cmd, "ASAN_OPTIONS=detect_leaks=0 %s --allow-run-as-root --oversubscribe -np 2 %s render %s "
             "--width 40 --height 30 --threads 1 --quiet -o %s/two.exr >/dev/null 2>%s", mpirun, BRUME_EXE, scene,
             dir, err);
    ASSERT_EQ_INT(test_system(cmd), 0);
    snprintf(a, sizeof a, "%s/one.exr", dir);
    snprintf(b, sizeof b, "%s/two.exr", dir);
    ASSERT_TRUE(same_file(a, b));
    /* a sequence: frames 0-3, two per rank, all written by rank 0 */
    snprintf(args, sizeof args, "render %s --frames 0-3 --threads 1 --quiet -o %s/one_%%d.exr", scene, dir);
    ASSERT_EQ_INT(run(args, err), 0);
    snprintf(cmd, sizeof cmd, "ASAN_OPTIONS=detect_leaks=0 %s --allow-run-as-root --oversubscribe -np 2 %s render %s "
             "--frames 0-3 --threads 1 --quiet -o %s/two_%%d.exr >/dev/null 2>%s", mpirun, BRUME_EXE, scene, dir,
             err);
    ASSERT_EQ_INT(test_system(cmd), 0);
    for (int f = 0; f < 4; f++) {
        snprintf(a, sizeof a, "%s/one_%d.exr", dir, f);
        snprintf(b, sizeof b, "%s/two_%d.exr", dir, f);
        ASSERT_TRUE(same_file(a, b));
    }
    snprintf(args, sizeof args, "rm -rf %s %s", dir, err);
    test_system(args);
}

TEST_MAIN(moving_sphere_blurs_by_its_motion, moving_medium_blurs_by_its_motion,
          thin_lens_focuses_at_the_focus_distance, keyed_camera_matches_fixed_camera_at_the_frame_time,
          keyframe_errors_and_moving_worlds, sequence_writes_one_file_per_frame, video_with_and_without_ffmpeg,
          shards_cover_every_frame_once, mpi_matches_one_process)
