/* test_sequence.c - `brume render` over a sequence of grid files (docs/production.md,
 * "Sequences"): the next frame's grids read on a thread while a frame renders.
 *   - the frames are the same bytes with and without it (--no-read-ahead), and the same as
 *     each frame rendered alone; --stats says which frames were read ahead;
 *   - where render.max_memory_mb cannot hold two frames it is not done, and a load beside
 *     another scene's bytes (brume_load_options.memory_held) is refused past the limit or
 *     is the same scene;
 *   - a bad next file is reported in the one line a render without read-ahead gives.
 * The frames are .vdb files written by `brume gen` (read through the sandboxed OpenVDB
 * reader; skipped without OpenVDB). */
#include <signal.h>
#include <string.h>

#include "brume.h"
#include "io/grid_io.h"
#include "scene/scene.h"
#include "test.h"

/* The frames' format: .vdb, read through the sandboxed OpenVDB reader (the read-ahead's
 * cancel kills that child), under the sanitizers too. */
#define EXT ".vdb"

/* Frames 1..n of a cloud moving along x (file k spans x in [k, k + 1]) in a fresh folder,
 * with the scene s.json reading smoke_####.vdb (frame f reads file f + 1); the folder. */
static const char *make_frames(const char *name, int n, const char *dims)
{
    if (!grid_have_openvdb()) {
        printf("skipped: no OpenVDB (writing .vdb)\n");
        exit(77);
    }
    const char *dir = test_tmp_path(name);
    char cmd[4096], path[2048];
    snprintf(cmd, sizeof cmd, "rm -rf %s && mkdir -p %s", dir, dir);
    ASSERT_EQ_INT(test_system(cmd), 0);
    for (int k = 1; k <= n; k++) {
        snprintf(cmd, sizeof cmd,
                 "%s gen cloud --dims %s --shape ellipsoid --bounds %d,0,0,%d,1,1 -o %s/smoke_%04d" EXT, BRUME_EXE,
                 dims, k, k + 1, dir, k);
        ASSERT_EQ_INT(test_system(cmd), 0);
    }
    snprintf(path, sizeof path, "%s/s.json", dir);
    test_write_file(path, "{\"camera\": {\"position\": [3, 2, 6], \"look_at\": [3, 0.5, 0.5], \"fov\": 40},"
                          " \"lights\": [{\"type\": \"distant\", \"direction\": [0.3, -1, -0.4], \"irradiance\": 3}],"
                          " \"media\": [{\"density\": {\"type\": \"grid\", \"file\": \"smoke_####" EXT "\","
                          " \"frame_offset\": 1}, \"sigma_a\": 0.5, \"sigma_s\": 8}],"
                          " \"render\": {\"width\": 24, \"height\": 16, \"spp\": 4, \"threads\": 2}}");
    return dir;
}

/* `brume render DIR/s.json ARGS` with stderr to DIR/err.txt: the exit status; the text of
 * stderr in *err (the caller frees it). */
static int render(const char *dir, const char *args, char **err)
{
    char cmd[4096], path[2048];
    snprintf(path, sizeof path, "%s/err.txt", dir);
    snprintf(cmd, sizeof cmd, "cd %s && %s render s.json %s 2> err.txt", dir, BRUME_EXE, args);
    int rc = test_system(cmd);
    size_t n = 0;
    *err = test_slurp(path, &n);
    return rc;
}

/* 1 when DIR/a and DIR/b hold the same bytes. */
static int same_file(const char *dir, const char *a, const char *b)
{
    char pa[2048], pb[2048];
    snprintf(pa, sizeof pa, "%s/%s", dir, a);
    snprintf(pb, sizeof pb, "%s/%s", dir, b);
    size_t na = 0, nb = 0;
    char *x = test_slurp(pa, &na), *y = test_slurp(pb, &nb);
    int same = na == nb && na > 0 && memcmp(x, y, na) == 0;
    free(x);
    free(y);
    return same;
}

/* Frames 1 and 2 are read while the frame before renders (--stats says so); every frame is
 * the same bytes as without read-ahead and as the frame rendered alone, and the frames
 * differ (a frame read for another would show). */
TEST(read_ahead_gives_the_same_bytes)
{
    const char *dir = make_frames("seq-ahead", 3, "16x16x16");
    char *err = NULL;
    ASSERT_EQ_INT(render(dir, "--frames 0-2 --stats -q -o a_%d.png", &err), 0);
    printf("%s", err);
    ASSERT_CONTAINS(err, "stats: frame 0 grids read ahead: no (the first frame)");
    ASSERT_CONTAINS(err, "stats: frame 1 grids read ahead: yes");
    ASSERT_CONTAINS(err, "stats: frame 2 grids read ahead: yes");
    free(err);
    ASSERT_EQ_INT(render(dir, "--frames 0-2 --stats -q --no-read-ahead -o b_%d.png", &err), 0);
    ASSERT_CONTAINS(err, "stats: frame 1 grids read ahead: no (--no-read-ahead)");
    ASSERT_CONTAINS(err, "stats: frame 2 grids read ahead: no (--no-read-ahead)");
    free(err);
    ASSERT_EQ_INT(render(dir, "--frame 2 -q -o c_%d.png", &err), 0);
    free(err);
    ASSERT_TRUE(same_file(dir, "a_0.png", "b_0.png"));
    ASSERT_TRUE(same_file(dir, "a_1.png", "b_1.png"));
    ASSERT_TRUE(same_file(dir, "a_2.png", "b_2.png"));
    ASSERT_TRUE(same_file(dir, "a_2.png", "c_2.png"));
    ASSERT_TRUE(!same_file(dir, "a_1.png", "a_2.png"));
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    test_system(cmd);
}

/* Frame f of DIR/s.json loaded and committed beside `held` bytes under the scene's limit
 * (render.max_memory_mb = mb, 0: the default): the status, its bytes in *bytes. */
static brume_status load_frame(const char *dir, long f, double mb, size_t held, size_t *bytes, size_t *limit,
                               char *msg, size_t n)
{
    char path[2048], set[64];
    snprintf(path, sizeof path, "%s/s.json", dir);
    snprintf(set, sizeof set, "render.max_memory_mb=%.6f", mb);
    const char *sets[1] = {set};
    brume_load_options lo = {0.0, f, sets, mb > 0.0 ? 1 : 0, NULL, held, false};
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    brume_status st = brume_scene_load(ctx, &(brume_source){.path = path}, &lo, &s);
    if (st == BRUME_OK)
        st = brume_scene_commit(ctx, s);
    *bytes = brume_scene_memory(s, limit);
    snprintf(msg, n, "%s", brume_context_last_error(ctx));
    brume_scene_release(s);
    brume_context_release(ctx);
    return st;
}

/* A limit that holds one frame but not two: nothing is read ahead, the images are the same.
 * And the load itself: beside more bytes than the limit leaves it is refused in one line;
 * beside fewer it is the scene a load alone makes (the same bytes taken). */
TEST(read_ahead_held_back_by_memory_limit)
{
    const char *dir = make_frames("seq-memory", 2, "64x64x64");
    size_t one = 0, limit = 0, again = 0;
    char msg[1024];
    ASSERT_EQ_INT(load_frame(dir, 1, 0.0, 0, &one, &limit, msg, sizeof msg), BRUME_OK);
    double mb = 1.5 * (double)one / 1048576.0;
    printf("a frame takes %zu bytes; limit %.3f MiB\n", one, mb);
    ASSERT_TRUE(mb >= 1.0);
    char args[512], *err = NULL;
    snprintf(args, sizeof args, "--frames 0-1 --stats -q --set render.max_memory_mb=%.6f -o m_%%d.png", mb);
    ASSERT_EQ_INT(render(dir, args, &err), 0);
    ASSERT_CONTAINS(err, "stats: frame 1 grids read ahead: no (two frames' grids would pass render.max_memory_mb)");
    free(err);
    ASSERT_EQ_INT(render(dir, "--frames 0-1 --stats -q -o a_%d.png", &err), 0);
    ASSERT_CONTAINS(err, "stats: frame 1 grids read ahead: yes");
    free(err);
    ASSERT_TRUE(same_file(dir, "m_1.png", "a_1.png"));
    /* beside a frame of `one` bytes under 1.5 x one: refused, naming the limit and the hold */
    ASSERT_EQ_INT(load_frame(dir, 1, mb, one, &again, &limit, msg, sizeof msg), BRUME_ERROR_OUT_OF_MEMORY);
    printf("%s\n", msg);
    ASSERT_TRUE(strchr(msg, '\n') == NULL);
    ASSERT_CONTAINS(msg, "render.max_memory_mb");
    ASSERT_CONTAINS(msg, "while another scene holds");
    /* beside a third of a frame: the same scene as alone */
    ASSERT_EQ_INT(load_frame(dir, 1, mb, one / 3, &again, &limit, msg, sizeof msg), BRUME_OK);
    ASSERT_EQ_INT((long long)again, (long long)one);
    ASSERT_NEAR((double)limit, mb * 1048576.0, 2.0); /* the limit given, to the rounding of %.6f */
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    test_system(cmd);
}

/* The next frame's file is there but bad: its read ahead fails, the frame is read again
 * after the one before is written, and the error is the one line a render without
 * read-ahead gives. */
TEST(bad_next_file_reported_in_one_line)
{
    const char *dir = make_frames("seq-bad", 3, "16x16x16");
    char path[2048];
    snprintf(path, sizeof path, "%s/smoke_0002" EXT, dir);
    test_write_file(path, "not a vdb file\n");
    char *with = NULL, *without = NULL;
    ASSERT_EQ_INT(render(dir, "--frames 0-2 -q -o a_%d.png", &with), 1);
    ASSERT_EQ_INT(render(dir, "--frames 0-2 -q --no-read-ahead -o b_%d.png", &without), 1);
    printf("%s", with);
    ASSERT_CONTAINS(with, "smoke_0002" EXT);
    ASSERT_TRUE(strchr(with, '\n') == with + strlen(with) - 1); /* one line */
    ASSERT_EQ_STR(with, without);
    free(with);
    free(without);
    ASSERT_TRUE(same_file(dir, "a_0.png", "b_0.png")); /* frame 0 written */
    snprintf(path, sizeof path, "%s/a_1.png", dir);
    ASSERT_TRUE(!test_exists(path));
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    test_system(cmd);
}

/* The camera of frame f of the studio scene of `pattern` (committed): position, look_at. */
static void studio_camera(const char *pattern, long f, double pos[3], double at[3])
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    brume_load_options lo = {0.0, f, NULL, 0, NULL, 0, false};
    if (brume_scene_load(ctx, &(brume_source){.path = pattern}, &lo, &s) != BRUME_OK ||
        brume_scene_commit(ctx, s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    v3_to_array(s->cam.position, pos);
    v3_to_array(s->cam.look_at, at);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* `brume render smoke_####.vdb --frames 1-3`: each frame its file, in the studio scene framed
 * on the box over all the files (the camera does not jump); a "frame" box that is not two
 * corners is refused in one line. */
TEST(studio_scene_of_a_pattern)
{
    const char *dir = make_frames("seq-studio", 3, "16x16x16");
    char pattern[2048], cmd[4096];
    snprintf(pattern, sizeof pattern, "%s/smoke_####" EXT, dir);
    double p1[3], a1[3], p3[3], a3[3];
    studio_camera(pattern, 1, p1, a1);
    studio_camera(pattern, 3, p3, a3);
    for (int i = 0; i < 3; i++) {
        ASSERT_NEAR(p1[i], p3[i], 0.0);
        ASSERT_NEAR(a1[i], a3[i], 0.0);
    }
    /* files 1 to 3 span x in [1, 4]: the box over them is centred on x = 2.5 (each file's own
     * box on k + 0.5) */
    ASSERT_NEAR(a1[0], 2.5, 0.01);
    ASSERT_NEAR(a1[1], 0.5, 0.01);
    snprintf(cmd, sizeof cmd, "cd %s && %s render 'smoke_####" EXT "' --frames 1-3 --spp 2 --width 24 --height 16 -q -o o_%%d.png",
             dir, BRUME_EXE);
    ASSERT_EQ_INT(test_system(cmd), 0);
    ASSERT_TRUE(!same_file(dir, "o_1.png", "o_3.png"));
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    const char *bad = "{\"camera\": {\"frame\": [[0, 0, 0]]}, \"media\": [{\"density\": {\"type\": \"constant\"}, "
                      "\"sigma_a\": 0, \"sigma_s\": 1}]}";
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = "box.json", .text = bad}, NULL, &s), BRUME_ERROR_PARSE);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "box.json: camera.frame: a box is [[x0, y0, z0], [x1, y1, z1]]");
    brume_context_release(ctx);
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    test_system(cmd);
}

/* Ctrl-C while frame 0 renders and frame 1 (a larger file, read through the sandboxed
 * reader) is read ahead: the partial frame 0 is written, the read is cancelled and its
 * thread joined, brume exits 130 at once (5 s allowed on a loaded machine), frame 1 is not
 * written. */
TEST(ctrl_c_while_reading_ahead)
{
    const char *dir = make_frames("seq-sigint", 1, "16x16x16");
    char cmd[4096], err[2048], args[4096], path[2048];
    snprintf(cmd, sizeof cmd, "%s gen cloud --dims 96x96x96 --shape ellipsoid --bounds 2,0,0,3,1,1 -o %s/smoke_0002" EXT,
             BRUME_EXE, dir);
    ASSERT_EQ_INT(test_system(cmd), 0);
    snprintf(path, sizeof path, "%s/s.json", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(args, sizeof args, "render %s --frames 0-1 --spp 1000000 --progress-every 0.1 --stats -o %s/f_%%d.exr",
             path, dir);
    int pid = test_spawn(BRUME_EXE, args, err);
    double t0 = test_now();
    char *text = NULL;
    size_t n = 0;
    for (;;) { /* frame 0 renders once its first progress line is out; frame 1 is read by then */
        free(text);
        text = test_exists(err) ? test_slurp(err, &n) : NULL;
        if ((text && strstr(text, " spp")) || test_now() - t0 > 60.0)
            break;
        test_sleep(0.02);
    }
    ASSERT_CONTAINS(text, " spp");
    free(text);
    kill(pid, SIGINT);
    double t1 = test_now();
    ASSERT_EQ_INT(test_wait_exit(pid, 30.0), 130);
    printf("exited %.2f s after SIGINT\n", test_now() - t1);
    ASSERT_TRUE(test_now() - t1 < 5.0);
    text = test_slurp(err, &n);
    printf("%s", text);
    ASSERT_CONTAINS(text, "interrupted by SIGINT: wrote the partial image");
    free(text);
    snprintf(path, sizeof path, "%s/f_0.partial.exr", dir);
    ASSERT_TRUE(test_exists(path));
    snprintf(path, sizeof path, "%s/f_1.exr", dir);
    ASSERT_TRUE(!test_exists(path));
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    test_system(cmd);
}

TEST_MAIN(read_ahead_gives_the_same_bytes, read_ahead_held_back_by_memory_limit, bad_next_file_reported_in_one_line,
          studio_scene_of_a_pattern, ctrl_c_while_reading_ahead)
