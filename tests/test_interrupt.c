/* test_interrupt.c - `brume render` as a user drives it: signals that keep the work,
 * checkpoints and resume (byte-identical to an uninterrupted render), budgets, and output
 * paths checked before any rendering. Every wait is bounded. */
/* posix_openpt and the pseudo-terminal calls of ctrl_c_on_a_terminal */
#define _XOPEN_SOURCE 700
#include "test.h"

#include <dirent.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "brume.h"

/* A small cloud that renders in a few seconds on one core at a 1.2 % noise target. */
static const char scene_json[] =
    "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 35},\n"
    " \"background\": [0.3, 0.45, 0.8],\n"
    " \"lights\": [{\"type\": \"distant\", \"direction\": [-0.5, -0.7, -0.5], \"irradiance\": 3.0}],\n"
    " \"media\": [{\"sigma_a\": 0.1, \"sigma_s\": 6,\n"
    "   \"density\": {\"type\": \"procedural_cloud\", \"resolution\": 16, \"seed\": 5},\n"
    "   \"phase\": {\"type\": \"hg\", \"g\": 0.5}}],\n"
    " \"render\": {\"width\": 48, \"height\": 32, \"spp\": 256, \"max_depth\": 16}}\n";

/* A fresh folder for one test. */
static const char *fresh_dir(const char *name)
{
    static char dir[300];
    snprintf(dir, sizeof dir, "%s", test_tmp_path(name));
    char cmd[2200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s'", dir, dir);
    ASSERT_EQ_INT(test_system(cmd), 0);
    return dir;
}

static int run(const char *args, const char *err_path)
{
    return test_wait_exit(test_spawn(BRUME_EXE, args, err_path), 300.0);
}


static bool same_file(const char *a, const char *b)
{
    size_t na, nb;
    char *da = test_slurp(a, &na), *db = test_slurp(b, &nb);
    bool same = na == nb && memcmp(da, db, na) == 0;
    free(da);
    free(db);
    return same;
}

/* One line, containing `needle`. */
static void assert_one_line(const char *err_path, const char *needle)
{
    size_t n;
    char *msg = test_slurp(err_path, &n);
    fprintf(stderr, "stderr: %s", msg);
    ASSERT_CONTAINS(msg, needle);
    ASSERT_TRUE(n > 0 && strchr(msg, '\n') == msg + n - 1);
    free(msg);
}

/* SIGINT, SIGTERM, SIGHUP: the render stops within about a second (5 s allowed on a loaded
 * machine), the partial image is written whole, stderr says so with the samples, no
 * temporary file is left, the exit status is 128 + the signal. */
TEST(signal_writes_partial_image)
{
    const int sigs[3] = {SIGINT, SIGTERM, SIGHUP};
    for (int k = 0; k < 3; k++) {
        const char *dir = fresh_dir("sig");
        char scene[400], out[400], err[400], args[8192];
        snprintf(scene, sizeof scene, "%s/scene.json", dir);
        snprintf(out, sizeof out, "%s/out.exr", dir);
        snprintf(err, sizeof err, "%s/err.txt", dir);
        test_write_file(scene, scene_json);
        snprintf(args, sizeof args, "render %s --spp 1000000 --threads 2 --aov samples -o %s", scene, out);
        /* a loaded machine may take longer than the wait to start rendering: a signal that
         * came before the first pass finished (nothing written, or "(0 to" samples) is tried
         * again with twice the wait, up to 4 times; a brume that never writes the partial
         * image still fails below */
        int rc = -1;
        double took = 0.0, wait = 1.5;
        char *msg = NULL;
        for (int attempt = 0; attempt < 4; attempt++, wait *= 2.0) {
            pid_t pid = test_spawn(BRUME_EXE, args, err);
            test_sleep(wait);
            double t0 = test_now();
            kill(pid, sigs[k]);
            rc = test_wait_exit(pid, 60.0);
            took = test_now() - t0;
            fprintf(stderr, "signal %d after %.1f s: exit %d after %.2f s\n", sigs[k], wait, rc, took);
            size_t n;
            free(msg);
            msg = test_slurp(err, &n);
            if (strstr(msg, "partial image") && !strstr(msg, "(0 to"))
                break;
        }
        ASSERT_EQ_INT(rc, 128 + sigs[k]);
        /* within a tile, not a pass; the bound leaves room for the EXR write and a loaded
         * machine, and still catches a signal that is ignored until the end */
        ASSERT_TRUE(took < 20.0);
        ASSERT_CONTAINS(msg, "partial image");
        ASSERT_CONTAINS(msg, "samples per pixel");
        free(msg);
        brume_context *ctx = brume_context_new();
        brume_image *img = NULL;
        ASSERT_EQ_INT(brume_image_read(ctx, out, &img), BRUME_OK);
        ASSERT_EQ_INT(brume_image_width(img), 48);
        ASSERT_EQ_STR(brume_image_attribute(img, "brume.partial"), "yes");
        /* every pixel has samples: the first pass is one sample */
        const float *cnt = brume_image_layer_pixels(img, 0);
        for (int i = 0; i < 48 * 32; i++)
            ASSERT_TRUE(cnt[i] >= 1.0f);
        brume_image_release(img);
        brume_context_release(ctx);
        ASSERT_EQ_INT(test_temporaries(dir), 0);
    }
}

/* A second SIGINT ends the process at once, and still leaves no temporary file; whatever
 * output exists is whole. */
TEST(second_sigint_ends_at_once)
{
    const char *dir = fresh_dir("sig2");
    char scene[400], out[400], err[400], args[8192];
    snprintf(scene, sizeof scene, "%s/scene.json", dir);
    snprintf(out, sizeof out, "%s/out.png", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    test_write_file(scene, scene_json);
    for (int k = 0; k < 3; k++) {
        snprintf(args, sizeof args, "render %s --spp 1000000 -o %s --checkpoint %s/ck", scene, out, dir);
        pid_t pid = test_spawn(BRUME_EXE, args, err);
        test_sleep(0.8 + 0.3 * k);
        kill(pid, SIGINT);
        test_sleep(0.002 * k);
        kill(pid, SIGINT);
        int rc = test_wait_exit(pid, 10.0);
        ASSERT_EQ_INT(rc, 130);
        ASSERT_EQ_INT(test_temporaries(dir), 0);
        if (test_exists(out)) {
            brume_context *ctx = brume_context_new();
            brume_image *img = NULL;
            ASSERT_EQ_INT(brume_image_read(ctx, out, &img), BRUME_OK);
            brume_image_release(img);
            brume_context_release(ctx);
        }
    }
}

/* A sequence interrupted after some frames keeps them: each is a whole image. */
TEST(sequence_keeps_finished_frames)
{
    const char *dir = fresh_dir("seq");
    char scene[400], err[400], args[8192], frame[600];
    snprintf(scene, sizeof scene, "%s/scene.json", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    test_write_file(scene, scene_json);
    snprintf(args, sizeof args, "render %s --spp 64 --frames 0-99 -o %s/frames/f_%%02d.pfm", scene, dir);
    pid_t pid = test_spawn(BRUME_EXE, args, err);
    snprintf(frame, sizeof frame, "%s/frames/f_02.pfm", dir);
    double t0 = test_now();
    while (!test_exists(frame) && test_now() - t0 < 60.0)
        test_sleep(0.02);
    ASSERT_TRUE(test_exists(frame));
    kill(pid, SIGINT);
    ASSERT_EQ_INT(test_wait_exit(pid, 30.0), 130);
    int whole = 0;
    for (int f = 0; f < 100; f++) {
        snprintf(frame, sizeof frame, "%s/frames/f_%02d.pfm", dir, f);
        if (!test_exists(frame))
            break;
        brume_context *ctx = brume_context_new();
        brume_image *img = NULL;
        ASSERT_EQ_INT(brume_image_read(ctx, frame, &img), BRUME_OK);
        brume_image_release(img);
        brume_context_release(ctx);
        whole++;
    }
    ASSERT_TRUE(whole >= 3);
    char frames[600];
    snprintf(frames, sizeof frames, "%s/frames", dir);
    ASSERT_EQ_INT(test_temporaries(frames), 0);
}

/* Interrupted at several points (inside passes and between), with 1 and 2 threads, then
 * resumed from the checkpoint (and once interrupted again and resumed again): the final
 * EXR is byte-identical to the uninterrupted render's, which is the same with 1 and 2
 * threads. */
TEST(resume_is_byte_identical)
{
    const char *dir = fresh_dir("resume");
    char scene[400], err[400], ref[400], out[400], ck[400], args[8192];
    snprintf(scene, sizeof scene, "%s/scene.json", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(ck, sizeof ck, "%s/render.ckpt", dir);
    test_write_file(scene, scene_json);
    const char *common = "--noise 0.012 --min-spp 8 --spp 65536 --aov samples,variance";
    char ref1[400];
    snprintf(ref1, sizeof ref1, "%s/ref1.exr", dir);
    for (int threads = 1; threads <= 2; threads++) {
        snprintf(ref, sizeof ref, "%s/ref%d.exr", dir, threads);
        snprintf(args, sizeof args, "render %s %s --threads %d -o %s", scene, common, threads, ref);
        double t0 = test_now();
        ASSERT_EQ_INT(run(args, err), 0);
        double D = test_now() - t0;
        fprintf(stderr, "%d thread(s): uninterrupted render %.2f s\n", threads, D);
        if (threads == 2)
            ASSERT_TRUE(same_file(ref, ref1));
        const double cuts[3] = {0.15, 0.4, 0.7};
        int interrupted = 0;
        for (int c = 0; c < 3; c++) {
            snprintf(out, sizeof out, "%s/out-%d-%d.exr", dir, threads, c);
            remove(ck);
            snprintf(args, sizeof args, "render %s %s --threads %d -o %s --checkpoint %s", scene, common, threads, out,
                     ck);
            /* the machine's load changes between runs: a run that ended before the signal is
             * tried again with an earlier one, a run stopped before it had started rendering
             * (no checkpoint: the signal came during start-up) with a later one */
            double cut = cuts[c];
            int rc = -1;
            for (int attempt = 0; attempt < 4; attempt++) {
                remove(ck);
                pid_t pid = test_spawn(BRUME_EXE, args, err);
                test_sleep(cut * D);
                kill(pid, SIGINT);
                rc = test_wait_exit(pid, 60.0);
                if (rc == 0) { /* finished before the signal: nothing to resume */
                    ASSERT_TRUE(same_file(ref, out));
                    cut *= 0.5;
                } else if (rc == 130 && !test_exists(ck)) {
                    cut = cut * 1.5 + 0.05;
                } else {
                    break;
                }
            }
            if (rc == 0 || (rc == 130 && !test_exists(ck)))
                continue; /* never cut mid-render in 4 tries: counted as not interrupted */
            ASSERT_EQ_INT(rc, 130);
            interrupted++;
            if (c == 1) { /* interrupted twice */
                snprintf(args, sizeof args, "render %s %s --threads %d -o %s --resume %s --checkpoint %s", scene, common,
                         3 - threads, out, ck, ck);
                pid_t pid = test_spawn(BRUME_EXE, args, err);
                test_sleep(0.2 * D);
                kill(pid, SIGINT);
                rc = test_wait_exit(pid, 60.0);
                ASSERT_TRUE(rc == 130 || rc == 0);
            }
            if (test_exists(ck)) {
                snprintf(args, sizeof args, "render %s %s --threads %d -o %s --resume %s --checkpoint %s", scene,
                         common, threads, out, ck, ck);
                ASSERT_EQ_INT(run(args, err), 0);
            }
            if (!same_file(ref, out))
                TEST_FAIL("%d thread(s), cut at %.0f %%: the resumed render differs from the uninterrupted one",
                          threads, 100 * cuts[c]);
            ASSERT_TRUE(!test_exists(ck)); /* a finished render removes its checkpoint */
            ASSERT_EQ_INT(test_temporaries(dir), 0);
        }
        fprintf(stderr, "%d thread(s): %d of 3 runs interrupted and resumed\n", threads, interrupted);
        ASSERT_TRUE(interrupted >= 2);
    }
}

/* Bad checkpoints: truncated, corrupt, another brume version, another scene, other
 * settings: one line naming the file, exit 1, the existing output untouched. */
TEST(bad_checkpoints_refused)
{
    const char *dir = fresh_dir("badck");
    char scene[400], scene2[400], err[400], out[400], ck[400], bad[400], args[8192];
    snprintf(scene, sizeof scene, "%s/scene.json", dir);
    snprintf(scene2, sizeof scene2, "%s/other.json", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(out, sizeof out, "%s/out.pfm", dir);
    snprintf(ck, sizeof ck, "%s/render.ckpt", dir);
    snprintf(bad, sizeof bad, "%s/bad.ckpt", dir);
    test_write_file(scene, scene_json);
    test_write_file(scene2, scene_json);
    FILE *fp = fopen(scene2, "a");
    fputs(" ", fp); /* another file's bytes */
    fclose(fp);
    snprintf(args, sizeof args, "render %s --spp 1000000 -o %s --checkpoint %s", scene, out, ck);
    /* a signal during start-up leaves no checkpoint: try again with twice the wait */
    for (int attempt = 0; attempt < 4 && !test_exists(ck); attempt++) {
        pid_t pid = test_spawn(BRUME_EXE, args, err);
        test_sleep(1.0 * (1 << attempt));
        kill(pid, SIGINT);
        ASSERT_EQ_INT(test_wait_exit(pid, 60.0), 130);
    }
    ASSERT_TRUE(test_exists(ck));
    test_write_file(out, "PF\nprevious output"); /* an image's first bytes: -o may replace it */
    size_t n;
    char *bytes = test_slurp(ck, &n);
    struct {
        const char *what, *needle;
        size_t len;
        int flip;
        const char *version;
    } cases[3] = {{"truncated", "truncated", n - 100, -1, NULL},
                  {"corrupt", "corrupt", n, (int)(n / 2), NULL},
                  {"other version", "0.0.0-other", n, -1, "0.0.0-other"}};
    for (int k = 0; k < 3; k++) {
        char *copy = malloc(n);
        memcpy(copy, bytes, n);
        if (cases[k].flip >= 0)
            copy[cases[k].flip] ^= 0x40;
        if (cases[k].version)
            memcpy(copy + 16, cases[k].version, strlen(cases[k].version) + 1);
        fp = fopen(bad, "wb");
        fwrite(copy, 1, cases[k].len, fp);
        fclose(fp);
        free(copy);
        snprintf(args, sizeof args, "render %s --spp 1000000 -o %s --resume %s", scene, out, bad);
        ASSERT_EQ_INT(run(args, err), 1);
        assert_one_line(err, cases[k].needle);
        assert_one_line(err, bad);
    }
    free(bytes);
    /* another scene file, other settings */
    snprintf(args, sizeof args, "render %s --spp 1000000 -o %s --resume %s", scene2, out, ck);
    ASSERT_EQ_INT(run(args, err), 1);
    assert_one_line(err, "another scene");
    snprintf(args, sizeof args, "render %s --spp 1000000 --width 40 -o %s --resume %s", scene, out, ck);
    ASSERT_EQ_INT(run(args, err), 1);
    assert_one_line(err, "render.width");
    snprintf(args, sizeof args, "render %s --spp 1000000 -o %s --resume %s/missing.ckpt", scene, out, dir);
    ASSERT_EQ_INT(run(args, err), 1);
    size_t m;
    char *kept = test_slurp(out, &m);
    ASSERT_EQ_STR(kept, "PF\nprevious output");
    free(kept);
}

/* A resumed render may take another budget (docs/render-jobs.md): a render interrupted
 * with a checkpoint, resumed with --time, continues from the samples it saved and spends
 * the new budget. Before, --time was part of the scene key and the resume was refused as
 * "made from another scene"; and the library charged the saved seconds to the new budget. */
TEST(resume_takes_another_budget)
{
    const char *dir = fresh_dir("rebudget");
    char scene[400], err[400], out[400], ck[400], args[8192];
    snprintf(scene, sizeof scene, "%s/scene.json", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(out, sizeof out, "%s/out.exr", dir);
    snprintf(ck, sizeof ck, "%s/render.ckpt", dir);
    test_write_file(scene, scene_json);
    /* interrupted once it has samples (a signal during start-up leaves no checkpoint: wait
     * twice as long) */
    snprintf(args, sizeof args, "render %s --spp 1000000 --threads 2 --aov samples -o %s --checkpoint %s", scene, out,
             ck);
    for (int attempt = 0; attempt < 4 && !test_exists(ck); attempt++) {
        pid_t pid = test_spawn(BRUME_EXE, args, err);
        test_sleep(1.5 * (1 << attempt));
        kill(pid, SIGINT);
        ASSERT_EQ_INT(test_wait_exit(pid, 60.0), 130);
    }
    ASSERT_TRUE(test_exists(ck));
    size_t n;
    char *msg = test_slurp(err, &n);
    const char *counts = strstr(msg, "partial image");
    int saved_min = -1, saved_max = -1;
    ASSERT_TRUE(counts && (counts = strchr(counts, '(')) != NULL);
    ASSERT_EQ_INT(sscanf(counts, "(%d to %d samples", &saved_min, &saved_max), 2);
    free(msg);
    ASSERT_TRUE(saved_min >= 1);
    /* another budget, shorter than the seconds the checkpoint had spent, another thread
     * count: the resumed job goes on from there */
    snprintf(args, sizeof args, "render %s --spp 1000000 --threads 1 --time 0.5 --aov samples -o %s --resume %s",
             scene, out, ck);
    ASSERT_EQ_INT(run(args, err), 0);
    msg = test_slurp(err, &n);
    fprintf(stderr, "saved %d to %d spp; resumed with --time 0.5: %s", saved_min, saved_max, msg);
    ASSERT_CONTAINS(msg, "of a 0.5 s budget");
    free(msg);
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    ASSERT_EQ_INT(brume_image_read(ctx, out, &img), BRUME_OK);
    const float *cnt = brume_image_layer_pixels(img, 0);
    for (int i = 0; i < 48 * 32; i++)
        if (cnt[i] <= (float)saved_max) /* each pixel past the most any had: the cut pass completed, then more */
            TEST_FAIL("pixel %d: %.0f samples after the resume, the checkpoint had %d to %d", i, cnt[i], saved_min,
                      saved_max);
    ASSERT_TRUE(atoi(brume_image_attribute(img, "brume.spp_min")) > saved_max);
    brume_image_release(img);
    brume_context_release(ctx);
    ASSERT_EQ_INT(test_temporaries(dir), 0);
}

/* A render its time budget ends before its samples keeps its checkpoint: a second run
 * with --resume and another --time goes on from it (the state was removed as if the render
 * had finished, and the second run started over). A render that finishes removes it. */
TEST(budget_keeps_the_checkpoint)
{
    const char *dir = fresh_dir("budgetkeeps");
    char scene[400], err[400], out[400], ck[400], args[8192];
    snprintf(scene, sizeof scene, "%s/scene.json", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(out, sizeof out, "%s/out.exr", dir);
    snprintf(ck, sizeof ck, "%s/render.ckpt", dir);
    test_write_file(scene, scene_json);
    snprintf(args, sizeof args, "render %s --spp 1000000 --time 0.3 -o %s --checkpoint %s", scene, out, ck);
    ASSERT_EQ_INT(run(args, err), 0);
    ASSERT_TRUE(test_exists(ck));
    size_t n;
    char *msg = test_slurp(err, &n);
    ASSERT_CONTAINS(msg, "its state is kept in");
    free(msg);
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    ASSERT_EQ_INT(brume_image_read(ctx, out, &img), BRUME_OK);
    int first_max = atoi(brume_image_attribute(img, "brume.spp_max"));
    brume_image_release(img);
    ASSERT_TRUE(first_max >= 1);
    snprintf(args, sizeof args, "render %s --spp 1000000 --time 0.3 -o %s --checkpoint %s --resume %s", scene, out,
             ck, ck);
    ASSERT_EQ_INT(run(args, err), 0);
    ASSERT_TRUE(test_exists(ck));
    img = NULL;
    ASSERT_EQ_INT(brume_image_read(ctx, out, &img), BRUME_OK);
    int second_min = atoi(brume_image_attribute(img, "brume.spp_min"));
    brume_image_release(img);
    if (second_min <= first_max)
        TEST_FAIL("resumed: %d samples per pixel at least, the first run had at most %d", second_min, first_max);
    /* a render that reaches its samples within its budget is finished: its checkpoint goes
     * (one made by a render of those settings first, so that the file is its own; a budget
     * that ends before the first sample is an error, so it takes the one above) */
    snprintf(args, sizeof args, "render %s --spp 256 --time 0.3 -o %s --checkpoint %s", scene, out, ck);
    ASSERT_EQ_INT(run(args, err), 0);
    ASSERT_TRUE(test_exists(ck));
    snprintf(args, sizeof args, "render %s --spp 256 --time 60 -o %s --checkpoint %s --resume %s", scene, out, ck, ck);
    ASSERT_EQ_INT(run(args, err), 0);
    ASSERT_TRUE(!test_exists(ck));
    brume_context_release(ctx);
    ASSERT_EQ_INT(test_temporaries(dir), 0);
}

/* Outputs are checked before any rendering: a render that would take days fails at once
 * on a bad extension, a --aov layer with PNG, a folder that cannot be made; missing folders
 * of a good output are made. */
TEST(outputs_checked_before_rendering)
{
    const char *dir = fresh_dir("outputs");
    char err[400], args[8192], path[400];
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(path, sizeof path, "%s/file", dir);
    test_write_file(path, "a file, not a folder");
    struct {
        const char *o, *extra, *needle;
        int rc;
    } cases[5] = {{"x.jpg", "", "unknown image format", 1},
                  {"x.png", "--aov depth", "--aov", 2},
                  {"file/x.png", "", "not a folder", 1},
                  {"f_%04d.png", "", "frame pattern", 2},
                  {"x.exr", "--checkpoint file/ck", "not a folder", 1}};
    for (int k = 0; k < 5; k++) {
        char extra[700] = "";
        if (strstr(cases[k].extra, "file/"))
            snprintf(extra, sizeof extra, "--checkpoint %s/file/ck", dir);
        else
            snprintf(extra, sizeof extra, "%s", cases[k].extra);
        snprintf(args, sizeof args, "render --spp 16777216 --width 4000 --height 4000 %s -o %s/%s", extra, dir,
                 cases[k].o);
        double t0 = test_now();
        ASSERT_EQ_INT(test_wait_exit(test_spawn(BRUME_EXE, args, err), 20.0), cases[k].rc);
        fprintf(stderr, "%s: refused in %.2f s\n", cases[k].o, test_now() - t0);
        assert_one_line(err, cases[k].needle);
    }
    snprintf(args, sizeof args, "render --spp 1 --width 8 --height 8 --quiet -o %s/a/b/c.png", dir);
    ASSERT_EQ_INT(run(args, err), 0);
    snprintf(path, sizeof path, "%s/a/b/c.png", dir);
    ASSERT_TRUE(test_exists(path));
    ASSERT_EQ_INT(test_temporaries(dir), 0);
}

/* Budgets on the command line: bad values are usage errors (exit 2, one line); --noise
 * stops with the target met (stderr and the EXR header say so); --time stops. */
TEST(budgets_on_the_command_line)
{
    const char *dir = fresh_dir("budgets");
    char err[400], args[8192], out[400], scene[400];
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(out, sizeof out, "%s/out.exr", dir);
    snprintf(scene, sizeof scene, "%s/scene.json", dir);
    const char *bad[8] = {"--time 0", "--time -1", "--time nan", "--noise 0", "--noise -0.1", "--noise nan",
                          "--noise 2", "--min-spp 0"};
    for (int k = 0; k < 8; k++) {
        snprintf(args, sizeof args, "render %s -o %s", bad[k], out);
        ASSERT_EQ_INT(run(args, err), 2);
        char flag[32];
        snprintf(flag, sizeof flag, "%.*s", (int)strcspn(bad[k], " "), bad[k]);
        assert_one_line(err, flag); /* names the flag */
    }
    ASSERT_TRUE(!test_exists(out));
    /* constant absorbing fog: Bernoulli samples, relative error sqrt((1 - T) / (T n)) */
    test_write_file(scene, "{\"camera\": {\"position\": [0, 0, 10], \"look_at\": [0, 0, 0], \"fov\": 5},"
                      " \"background\": [2.0, 1.0, 0.5],"
                      " \"media\": [{\"sigma_a\": 0.5, \"sigma_s\": 0,"
                      "   \"density\": {\"type\": \"constant\", \"bounds\": [[-5, -5, -1], [5, 5, 1]]}}],"
                      " \"render\": {\"width\": 16, \"height\": 16}}");
    snprintf(args, sizeof args, "render %s --noise 0.05 -o %s", scene, out);
    ASSERT_EQ_INT(run(args, err), 0);
    assert_one_line(err, "target 5%");
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    ASSERT_EQ_INT(brume_image_read(ctx, out, &img), BRUME_OK);
    double noise = atof(brume_image_attribute(img, "brume.noise"));
    double T = exp(-1.0), n_need = (1.0 - T) / (T * 0.05 * 0.05);
    double mean = atof(brume_image_attribute(img, "brume.spp_mean"));
    fprintf(stderr, "noise %.4f, %.0f samples on average (closed form %.0f)\n", noise, mean, n_need);
    ASSERT_TRUE(noise > 0.0 && noise <= 0.05);
    ASSERT_TRUE(mean >= 0.85 * n_need && mean <= 1.35 * n_need);
    brume_image_release(img);
    snprintf(args, sizeof args, "render %s --time 0.5 -o %s", scene, out);
    double t0 = test_now();
    ASSERT_EQ_INT(run(args, err), 0);
    fprintf(stderr, "--time 0.5: %.2f s\n", test_now() - t0);
    ASSERT_EQ_INT(brume_image_read(ctx, out, &img), BRUME_OK);
    ASSERT_TRUE(atoi(brume_image_attribute(img, "brume.spp_min")) >= 1);
    brume_image_release(img);
    brume_context_release(ctx);
}

/* Ctrl-C on a terminal, as a person presses it: brume runs on a pseudo-terminal (its
 * controlling terminal, so the progress bar is drawn), ^C is typed into it once the bar
 * shows, and the render ends with status 130 and its one-line message, the bar's last
 * drawing showing how far it got: a stopped render must not end on 100 %. */
TEST(ctrl_c_on_a_terminal)
{
    const char *dir = fresh_dir("tty");
    char scene[400], out[400];
    snprintf(scene, sizeof scene, "%s/scene.json", dir);
    snprintf(out, sizeof out, "%s/out.exr", dir);
    test_write_file(scene, scene_json);
    int master = posix_openpt(O_RDWR | O_NOCTTY);
    ASSERT_TRUE(master >= 0);
    ASSERT_TRUE(grantpt(master) == 0 && unlockpt(master) == 0);
    const char *slave = ptsname(master);
    ASSERT_TRUE(slave != NULL);
    pid_t pid = fork();
    ASSERT_TRUE(pid >= 0);
    if (pid == 0) { /* a new session whose controlling terminal is the slave, opened first */
        setsid();
        int fd = open(slave, O_RDWR);
        if (fd < 0)
            _exit(127);
        dup2(fd, 0), dup2(fd, 1), dup2(fd, 2);
        if (fd > 2)
            close(fd);
        close(master);
        execl(BRUME_EXE, "brume", "render", scene, "--spp", "1000000", "--threads", "2", "-o", out, (char *)NULL);
        _exit(127);
    }
    size_t cap = 1 << 16, n = 0;
    char *text = calloc(cap + 1, 1);
    ASSERT_TRUE(text != NULL);
    double t0 = test_now(), t_bar = -1.0;
    bool typed = false;
    while (test_now() - t0 < 120.0) { /* every wait bounded */
        struct pollfd p = {master, POLLIN, 0};
        if (poll(&p, 1, 100) > 0) {
            char buf[4096];
            ssize_t k = read(master, buf, sizeof buf);
            if (k <= 0) /* EIO: the process closed the terminal */
                break;
            if (n + (size_t)k > cap) { /* keep the end, where the last bar is */
                memmove(text, text + n + (size_t)k - cap, cap - (size_t)k);
                n = cap - (size_t)k;
            }
            memcpy(text + n, buf, (size_t)k);
            n += (size_t)k;
            text[n] = '\0';
        }
        if (t_bar < 0.0 && strstr(text, "render ["))
            t_bar = test_now();
        if (!typed && t_bar >= 0.0 && test_now() - t_bar > 1.0) { /* the first pass is done by then */
            ASSERT_EQ_INT((int)write(master, "\x03", 1), 1);
            typed = true;
        }
    }
    int rc = test_wait_exit(pid, 60.0);
    close(master);
    fprintf(stderr, "terminal output (end): %s\n", n > 600 ? text + n - 600 : text);
    ASSERT_TRUE(typed);
    ASSERT_EQ_INT(rc, 130);
    ASSERT_CONTAINS(text, "interrupted by SIGINT");
    /* the last bar drawn: "render [####....]  17% ..." */
    char *bar = NULL;
    for (char *q = strstr(text, "render ["); q; q = strstr(q + 1, "render ["))
        bar = q;
    ASSERT_TRUE(bar != NULL);
    char *close_bracket = strchr(bar, ']');
    ASSERT_TRUE(close_bracket != NULL);
    int pct = atoi(close_bracket + 1);
    fprintf(stderr, "last bar: %d %%\n", pct);
    ASSERT_TRUE(pct < 100);
    free(text);
}

TEST_MAIN(signal_writes_partial_image, second_sigint_ends_at_once, sequence_keeps_finished_frames,
          resume_is_byte_identical, bad_checkpoints_refused, outputs_checked_before_rendering,
          budgets_on_the_command_line, ctrl_c_on_a_terminal, resume_takes_another_budget,
          budget_keeps_the_checkpoint)
