/* test_cli.c - the brume tool as a user runs it: exit codes, messages, output files. */
#include "test.h"

#include <sys/stat.h>

/* Runs `brume ARGS`, stderr captured to a file; returns the exit status. */
static int run(const char *args, const char *err_path)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "%s %s >/dev/null 2>%s", BRUME_EXE, args, err_path);
    return test_system(cmd);
}

TEST(version_and_help)
{
    const char *err = test_tmp_path("err.txt");
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "%s --version | grep -q '^brume [0-9]'", BRUME_EXE);
    ASSERT_EQ_INT(test_system(cmd), 0);
    snprintf(cmd, sizeof cmd, "%s help | grep -q render", BRUME_EXE);
    ASSERT_EQ_INT(test_system(cmd), 0);
    snprintf(cmd, sizeof cmd, "%s help render | grep -q -- --spp", BRUME_EXE);
    ASSERT_EQ_INT(test_system(cmd), 0);
    ASSERT_EQ_INT(run("frobnicate", err), 2);
    ASSERT_EQ_INT(run("render --no-such-flag", err), 2);
    ASSERT_EQ_INT(run("render --spp zero", err), 2);
    remove(err);
}

/* The done-when criterion of the foundation: --threads 1 and --threads 2 write
 * byte-identical PFM and EXR files. */
TEST(threads_give_identical_files)
{
    const char *ext[2] = {"pfm", "exr"};
    for (int e = 0; e < 2; e++) {
        char a[512], b[512], args[2048];
        snprintf(a, sizeof a, "%s", test_tmp_path(e ? "t1.exr" : "t1.pfm"));
        snprintf(b, sizeof b, "%s", test_tmp_path(e ? "t2.exr" : "t2.pfm"));
        const char *err = test_tmp_path("err.txt");
        snprintf(args, sizeof args, "render --width 40 --height 30 --spp 2 --threads 1 --quiet -o %s", a);
        ASSERT_EQ_INT(run(args, err), 0);
        snprintf(args, sizeof args, "render --width 40 --height 30 --spp 2 --threads 2 --quiet -o %s", b);
        ASSERT_EQ_INT(run(args, err), 0);
        size_t na, nb;
        char *da = test_slurp(a, &na), *db = test_slurp(b, &nb);
        if (na != nb || memcmp(da, db, na) != 0)
            TEST_FAIL("%s files differ between 1 and 2 threads", ext[e]);
        ASSERT_TRUE(na > 1000); /* a real image, not an empty file */
        free(da);
        free(db);
        remove(a);
        remove(b);
        remove(err);
    }
}

/* A malformed scene: exit 1, one line on stderr naming the file and the key, no output. */
TEST(malformed_scene_leaves_no_output)
{
    const char *scene = test_tmp_path("bad-scene.json");
    const char *out = test_tmp_path("bad-out.png");
    const char *err = test_tmp_path("err.txt");
    FILE *fp = fopen(scene, "w");
    fputs("{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0], \"zoom\": 2}}\n", fp);
    fclose(fp);
    remove(out);
    char args[2048];
    snprintf(args, sizeof args, "render %s -o %s --quiet", scene, out);
    ASSERT_EQ_INT(run(args, err), 1);
    ASSERT_TRUE(!test_exists(out));
    size_t n;
    char *msg = test_slurp(err, &n);
    ASSERT_CONTAINS(msg, scene);
    ASSERT_CONTAINS(msg, "camera.zoom");
    ASSERT_TRUE(n > 0 && strchr(msg, '\n') == msg + n - 1); /* exactly one line */
    free(msg);
    /* an unwritable destination (its folder would be a file): exit 1 and nothing left behind */
    snprintf(args, sizeof args, "render --width 8 --height 8 --spp 1 --quiet -o %s/x.png", scene);
    ASSERT_EQ_INT(run(args, err), 1);
    remove(scene);
    remove(err);
}

/* The default scene renders to a PNG with the documented command. */
TEST(default_render_writes_png)
{
    const char *out = test_tmp_path("default.png");
    const char *err = test_tmp_path("err.txt");
    char args[1024];
    snprintf(args, sizeof args, "render --width 64 --height 40 --spp 2 --quiet -o %s", out);
    ASSERT_EQ_INT(run(args, err), 0);
    size_t n;
    char *png = test_slurp(out, &n);
    ASSERT_TRUE(n > 8 && memcmp(png, "\x89PNG\r\n\x1a\n", 8) == 0);
    free(png);
    remove(out);
    remove(err);
}

TEST_MAIN(version_and_help, threads_give_identical_files, malformed_scene_leaves_no_output, default_render_writes_png)
