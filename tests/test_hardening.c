/* test_hardening.c - inputs that pass validation cannot hang brume, exhaust its memory,
 * write outside the scene's folder or draw a silently wrong picture; messages stay on one
 * line; interrupted writes leave nothing behind (issue 16; the corpus of bad inputs is
 * tests/bad/). Files brume did not write, checkpoints and the live view are in
 * test_hardening_cli.c; bounded work and cancelling in test_hardening_limits.c. */
#include "test.h"

#include <dirent.h>
#include <math.h>
#include <signal.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "brume.h"
#include "core/error.h"
#include "io/atomic.h"
#include "io/grid_io.h"
#include "io/mesh.h"
#include "scene/scene.h"

/* Loads and commits a scene file; returns the status, the message in msg. */
static brume_status load_commit(const char *path, char *msg, size_t n, brume_scene **out)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    brume_status st = brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s);
    if (st == BRUME_OK)
        st = brume_scene_commit(ctx, s);
    snprintf(msg, n, "%s", brume_context_last_error(ctx));
    brume_context_release(ctx);
    if (out && st == BRUME_OK)
        *out = s;
    else
        brume_scene_release(s);
    return st;
}

static double image_mean(const char *json)
{
    brume_scene *s = NULL;
    brume_context *ctx = brume_context_new();
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = json}, NULL, &s), BRUME_OK);
    brume_image *img = NULL;
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    ASSERT_EQ_INT(brume_render(ctx, s, &img), BRUME_OK);
    int n = brume_image_width(img) * brume_image_height(img);
    double mean, se;
    test_channel_mean(brume_image_pixels(img), n, 1, &mean, &se);
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
    return mean;
}

/* A sun's angular radius tends continuously to the point sun: below 1e-5 rad it is one,
 * above it the disk is sampled; a lit plane has the same brightness on both sides and at
 * 1e-8 degrees (where 1 - cos underflowed and the sun vanished). */
TEST(sun_radius_tends_to_point_sun)
{
#define SUN_FMT \
        "{\"camera\": {\"position\": [0, 3, 0.01], \"look_at\": [0, 0, 0], \"fov\": 30}," \
        " \"lights\": [{\"type\": \"distant\", \"direction\": [0.3, -1, 0.2], \"irradiance\": 2, \"angular_radius\": %g}]," \
        " \"surfaces\": [{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 1, 0], \"size\": 100," \
        "   \"material\": {\"albedo\": 0.5}}]," \
        " \"render\": {\"width\": 16, \"height\": 16, \"spp\": 4, \"threads\": 1, \"seed\": 3}}"
    const double radii_deg[] = {0.0, 1e-8, 1e-4, 5e-4, 2e-3};
    double m[5];
    for (int i = 0; i < 5; i++) {
        char json[2048];
        snprintf(json, sizeof json, SUN_FMT, radii_deg[i]);
        m[i] = image_mean(json);
    }
    ASSERT_TRUE(m[0] > 0.05);
    /* the point sun's plane: radiance albedo / pi E cos; a disk of 2e-3 degrees changes the
     * irradiance by a relative 1e-12 and its sampling is exact on a plane */
    for (int i = 1; i < 5; i++)
        ASSERT_NEAR(m[i] / m[0], 1.0, 1e-6);
}

/* Control characters from input are escaped, long keys cut, in every message. */
TEST(messages_stay_on_one_line)
{
    char key[6000];
    memset(key, 'k', sizeof key - 1);
    key[sizeof key - 1] = '\0';
    err_set(BRUME_ERROR_PARSE, "scene.json: %s: unknown key; %s", "a\nb\x1b[31mc\r\td\x7f", key);
    const char *m = err_message();
    for (const char *c = m; *c; c++)
        ASSERT_TRUE((unsigned char)*c >= 0x20 && *c != 0x7f);
    ASSERT_CONTAINS(m, "a\\nb\\x1b[31mc\\r\\td\\x7f");
    ASSERT_CONTAINS(m, "kkk...");
    ASSERT_TRUE(strlen(m) < 400);
    /* a whole message passed on with a precision is kept whole */
    char whole[900];
    memset(whole, 'w', sizeof whole - 1);
    whole[sizeof whole - 1] = '\0';
    err_set(BRUME_ERROR_IO, "x: %.1000s", whole);
    ASSERT_TRUE(strlen(err_message()) == 3 + sizeof whole - 1);
    /* through the scene reader and the context */
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    const char *json = "{\"camera\": {\"position\": [0,0,1], \"look_at\": [0,0,0], \"f\\nov\\u001b[2J\": 1}}";
    ASSERT_TRUE(brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = json}, NULL, &s) != BRUME_OK);
    m = brume_context_last_error(ctx);
    ASSERT_TRUE(strchr(m, '\n') == NULL && strchr(m, '\x1b') == NULL);
    ASSERT_CONTAINS(m, "f\\nov\\x1b[2J");
    brume_context_release(ctx);
}

static const char *scene_with_save(const char *save)
{
    static char json[8192];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
             " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, 0], \"irradiance\": 1}],"
             " \"media\": [{\"density\": {\"type\": \"constant\", \"value\": 1}, \"sigma_a\": 0.1, \"sigma_s\": 1}],"
             " \"render\": {\"width\": 4, \"height\": 4, \"spp\": 1, \"threads\": 1, \"method\": \"blasi\"},"
             " \"blasi\": {\"light_rays\": 200, \"save_light\": \"%.4000s\"}}",
             save);
    return json;
}

/* blasi.save_light from a scene file: relative, no "..", no symbolic link out of the
 * scene's folder; nothing is written outside. Inside, the file is written. */
TEST(scene_cannot_write_outside_its_folder)
{
    const char *root = test_fresh_dir("writes");
    char dir[4200], path[4300], outside[4300], msg[1100], link[4300];
    snprintf(dir, sizeof dir, "%s/scene", root);
    ASSERT_EQ_INT(mkdir(dir, 0700), 0);
    snprintf(link, sizeof link, "%s/up", dir);
    ASSERT_EQ_INT(symlink(root, link), 0);
    snprintf(path, sizeof path, "%s/s.json", dir);
    const char *bad[] = {"../out.bl", "sub/../../out.bl", "up/out.bl", "up/../out.bl"};
    for (int i = 0; i < 4; i++) {
        test_write_file(path, scene_with_save(bad[i]));
        ASSERT_TRUE(load_commit(path, msg, sizeof msg, NULL) != BRUME_OK);
        ASSERT_CONTAINS(msg, "blasi.save_light");
        ASSERT_TRUE(strchr(msg, '\n') == NULL);
    }
    snprintf(outside, sizeof outside, "%s/abs.bl", root);
    test_write_file(path, scene_with_save(outside));
    ASSERT_TRUE(load_commit(path, msg, sizeof msg, NULL) != BRUME_OK);
    ASSERT_CONTAINS(msg, "absolute");
    snprintf(outside, sizeof outside, "%s/out.bl", root);
    ASSERT_TRUE(!test_exists(outside));
    snprintf(outside, sizeof outside, "%s/abs.bl", root);
    ASSERT_TRUE(!test_exists(outside));
    /* inside the folder: written by the render */
    test_write_file(path, scene_with_save("light.bl"));
    brume_scene *s = NULL;
    ASSERT_EQ_INT(load_commit(path, msg, sizeof msg, &s), BRUME_OK);
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    ASSERT_EQ_INT(brume_render(ctx, s, &img), BRUME_OK);
    brume_image_release(img);
    brume_context_release(ctx);
    brume_scene_release(s);
    snprintf(outside, sizeof outside, "%s/light.bl", dir);
    ASSERT_TRUE(test_exists(outside));
}

/* The hangs end: a constant density of 1e18 (near the origin and 1e6 away, where
 * t + dt == t), by every method that renders it. */
TEST(huge_density_ends)
{
#define HUGE_FMT \
        "{\"camera\": {\"position\": [%g, 0, 4], \"look_at\": [%g, 0, 0], \"fov\": 40}," \
        " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, 0], \"irradiance\": 1}]," \
        " \"media\": [{\"density\": {\"type\": \"constant\", \"value\": 1e18, \"bounds\": [[%g, -1, -1], [%g, 1, 1]]}," \
        "   \"sigma_a\": [0.1, 0.2, 0.3], \"sigma_s\": 1}]," \
        " \"render\": {\"width\": 8, \"height\": 8, \"spp\": 2, \"threads\": 1, \"method\": \"%s\", \"max_depth\": 64}," \
        " \"blasi\": {\"light_rays\": 2000, \"r\": 0, \"sources\": 1}}"
    const char *methods[] = {"path", "single", "blasi"};
    alarm(60); /* a hang fails the test instead of stalling ctest */
    for (int far = 0; far < 2; far++)
        for (int k = 0; k < 3; k++) {
            double x = far ? 1e6 : 0.0;
            char json[2048];
            snprintf(json, sizeof json, HUGE_FMT, x, x, x - 1, x + 1, methods[k]);
            double t0 = test_now(), m = image_mean(json);
            ASSERT_TRUE(isfinite(m) && m >= 0.0);
            ASSERT_TRUE(test_now() - t0 < 20.0);
        }
    alarm(0);
}

/* The 20-byte raw grid with one voxel of 3e38: `brume info` reads it, a scene
 * refuses it at commit, naming the medium and the limit. */
TEST(huge_voxel_is_refused)
{
    const char *dir = test_fresh_dir("voxel");
    char raw[4200], scene[4200], msg[1100], json[1024];
    snprintf(raw, sizeof raw, "%s/hot.raw", dir);
    float v[5] = {0, 0, 3e38f, 0, 0};
    test_write_bytes(raw, v, sizeof v);
    density_load_options o;
    density_load_options_default(&o);
    o.raw_dims[0] = 5;
    o.raw_dims[1] = o.raw_dims[2] = 1;
    density *d = density_load_file(raw, &o);
    ASSERT_TRUE(d != NULL);
    density_release(d);
    snprintf(scene, sizeof scene, "%s/s.json", dir);
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
             " \"media\": [{\"density\": {\"type\": \"grid\", \"file\": \"hot.raw\", \"dims\": [5, 1, 1]},"
             " \"sigma_a\": 0.1, \"sigma_s\": 1}]}");
    test_write_file(scene, json);
    double t0 = test_now();
    ASSERT_EQ_INT(load_commit(scene, msg, sizeof msg, NULL), BRUME_ERROR_RANGE);
    ASSERT_TRUE(test_now() - t0 < 10.0);
    ASSERT_CONTAINS(msg, "media[0]");
    ASSERT_CONTAINS(msg, "limits");
}

/* The work bomb (four million blobs from a few hundred bytes) is refused up front,
 * quickly, naming the limit; and one memory budget spans every reader and generator. */
TEST(work_bomb_and_memory_budget)
{
    const char *dir = test_fresh_dir("bomb");
    char scene[4200], msg[1100];
    snprintf(scene, sizeof scene, "%s/s.json", dir);
    test_write_file(scene, "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
                      " \"media\": [{\"density\": {\"type\": \"blobs\", \"generators\": [{\"type\": \"cloud\","
                      " \"center\": [0, 0, 0], \"radii\": 1, \"count\": 4194304}]}, \"sigma_a\": 0.1, \"sigma_s\": 1}]}");
    double t0 = test_now();
    ASSERT_EQ_INT(load_commit(scene, msg, sizeof msg, NULL), BRUME_ERROR_RANGE);
    ASSERT_TRUE(test_now() - t0 < 10.0);
    ASSERT_CONTAINS(msg, "majorant grid");
    /* two fractal grids of 1 MiB each: one fits a 1.5 MiB budget, the second does not */
#define TWO_FMT \
        "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40}," \
        " \"render\": {\"max_memory_mb\": %s}," \
        " \"media\": [{\"density\": {\"type\": \"fractal_cloud\", \"dims\": [64, 64, 64], \"method\": \"perlin\"}," \
        "  \"sigma_a\": 0.1, \"sigma_s\": 1}, {\"density\": {\"type\": \"fractal_cloud\", \"dims\": [64, 64, 64]," \
        "  \"method\": \"perlin\"}, \"sigma_a\": 0.1, \"sigma_s\": 1}]}"
    char json[2048];
    snprintf(json, sizeof json, TWO_FMT, "1.5");
    test_write_file(scene, json);
    ASSERT_EQ_INT(load_commit(scene, msg, sizeof msg, NULL), BRUME_ERROR_OUT_OF_MEMORY);
    ASSERT_CONTAINS(msg, "media[1]");
    ASSERT_CONTAINS(msg, "render.max_memory_mb");
    snprintf(json, sizeof json, TWO_FMT, "3");
    test_write_file(scene, json);
    ASSERT_EQ_INT(load_commit(scene, msg, sizeof msg, NULL), BRUME_OK);
    /* a phase table read from /dev/zero ends, within the budget */
    test_write_file(scene, "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
                      " \"media\": [{\"density\": {\"type\": \"constant\"}, \"sigma_a\": 0.1, \"sigma_s\": 1,"
                      " \"phase\": {\"type\": \"tabulated\", \"file\": \"/dev/zero\"}}]}");
    ASSERT_EQ_INT(load_commit(scene, msg, sizeof msg, NULL), BRUME_ERROR_IO);
    ASSERT_CONTAINS(msg, "/dev/zero: not a regular file");
    /* nor does a pipe without a writer block the reader: it is refused at once */
    char fifo[4300];
    snprintf(fifo, sizeof fifo, "%s/pipe", dir);
    ASSERT_EQ_INT(mkfifo(fifo, 0600), 0);
    const char *uses[] = {
        "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40}, \"media\": [{\"density\":"
        " {\"type\": \"constant\"}, \"sigma_a\": 0.1, \"sigma_s\": 1, \"phase\": {\"type\": \"tabulated\", \"file\": \"pipe\"}}]}",
        "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40}, \"media\": [{\"density\":"
        " {\"type\": \"grid\", \"file\": \"pipe\", \"format\": \"vol\"}, \"sigma_a\": 0.1, \"sigma_s\": 1}]}",
        "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40}, \"background\": {\"file\": \"pipe.png\"}}",
        "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40}, \"surfaces\": [{\"type\": \"mesh\", \"file\": \"pipe.obj\"}]}"};
    char link[4300];
    snprintf(link, sizeof link, "%s/pipe.png", dir);
    ASSERT_EQ_INT(symlink(fifo, link), 0);
    snprintf(link, sizeof link, "%s/pipe.obj", dir);
    ASSERT_EQ_INT(symlink(fifo, link), 0);
    alarm(30); /* a blocked open fails the test instead of stalling ctest */
    for (int i = 0; i < 4; i++) {
        test_write_file(scene, uses[i]);
        ASSERT_TRUE(load_commit(scene, msg, sizeof msg, NULL) != BRUME_OK);
        ASSERT_CONTAINS(msg, "not a regular file (a pipe)");
    }
    alarm(0);
}

/* raw + .hdr: the sidecar is committed before the data, so a failed data write leaves a
 * sidecar (which any stale data contradicts) and never a whole-looking raw without one;
 * the reader refuses a raw whose size contradicts its sidecar, and inverted bounds. */
TEST(raw_pairs_and_strict_readers)
{
    const char *dir = test_fresh_dir("pairs");
    char raw[4200], hdr[4300], cmd[8600];
    float v[8] = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f};
    density *d = density_new_grid(2, 2, 2, memcpy(malloc(sizeof v), v, sizeof v),
                                  (box3){v3(0, 0, 0), v3(1, 1, 1)}, GRID_NEAREST);
    ASSERT_TRUE(d != NULL);
    /* the data's destination is a folder: its rename fails after the sidecar's */
    snprintf(raw, sizeof raw, "%s/g.raw", dir);
    snprintf(hdr, sizeof hdr, "%s.hdr", raw);
    ASSERT_EQ_INT(mkdir(raw, 0700), 0);
    ASSERT_TRUE(density_write_file(d, raw, GRID_FORMAT_RAW) != BRUME_OK);
    ASSERT_TRUE(test_exists(hdr));
    rmdir(raw);
    /* a stale raw of another size beside the new sidecar is refused, not re-read */
    test_write_bytes(raw, v, 4 * sizeof(float));
    ASSERT_TRUE(density_load_file(raw, NULL) == NULL);
    ASSERT_CONTAINS(err_message(), "bytes, but");
    /* a whole pair reads back */
    ASSERT_EQ_INT(density_write_file(d, raw, GRID_FORMAT_RAW), BRUME_OK);
    density *back = density_load_file(raw, NULL);
    ASSERT_TRUE(back != NULL);
    density_release(back);
    density_release(d);
    /* inverted sidecar bounds */
    test_write_file(hdr, "dims 2 2 2\nbounds 1 0 0 0 1 1\n");
    test_write_bytes(raw, v, sizeof v);
    ASSERT_TRUE(density_load_file(raw, NULL) == NULL);
    ASSERT_CONTAINS(err_message(), "min < max");
    /* .vol with trailing bytes */
    char vol[4200];
    snprintf(vol, sizeof vol, "%s/g.vol", dir);
    unsigned char buf[48 + 32 + 1] = {'V', 'O', 'L', 3, 1, 0, 0, 0, 2, 0, 0, 0, 2, 0, 0, 0, 2, 0, 0, 0, 1, 0, 0, 0};
    float box[6] = {0, 0, 0, 1, 1, 1};
    memcpy(buf + 24, box, sizeof box);
    memcpy(buf + 48, v, sizeof v);
    test_write_bytes(vol, buf, sizeof buf - 1);
    back = density_load_file(vol, NULL);
    ASSERT_TRUE(back != NULL);
    density_release(back);
    test_write_bytes(vol, buf, sizeof buf);
    ASSERT_TRUE(density_load_file(vol, NULL) == NULL);
    ASSERT_CONTAINS(err_message(), "trailing bytes");
    /* no temporary file was left by any of it */
    snprintf(cmd, sizeof cmd, "ls -A '%s' | grep -q tmp-", dir);
    ASSERT_TRUE(test_system(cmd) != 0);
}

/* A signal in the middle of an atomic write leaves no temporary file. */
TEST(signal_during_write_leaves_no_temp_file)
{
    const char *dir = test_fresh_dir("signal");
    int sigs[] = {SIGTERM, SIGINT, SIGHUP};
    for (int k = 0; k < 3; k++) {
        grid_before_fork(); /* no idle library thread holds a lock the child needs */
        pid_t pid = fork();
        if (pid == 0) {
            char path[4200];
            snprintf(path, sizeof path, "%s/out.bin", dir);
            /* the default action, even when the test runs under nohup or in the background
             * (atomic_open leaves a signal the process ignores alone) */
            signal(sigs[k], SIG_DFL);
            atomic_file f;
            if (atomic_open(&f, path) != BRUME_OK)
                _exit(3);
            fputs("half of it", f.fp);
            fflush(f.fp);
            raise(sigs[k]);
            _exit(4); /* not reached: the default action ends the process */
        }
        int status = 0;
        ASSERT_TRUE(waitpid(pid, &status, 0) == pid);
        ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sigs[k]);
        DIR *dp = opendir(dir);
        ASSERT_TRUE(dp != NULL);
        int entries = 0;
        for (struct dirent *e; (e = readdir(dp));)
            entries += e->d_name[0] != '.' || (strcmp(e->d_name, ".") && strcmp(e->d_name, ".."));
        closedir(dp);
        ASSERT_EQ_INT(entries, 0);
    }
}

/* Defect 8: every length modifier reaches snprintf: 64-bit values were printed cut to 32
 * bits ("65536 x 65536 x 1 voxels need 0 bytes"). Expected texts written out by hand. */
TEST(messages_print_every_length_modifier)
{
    char b[256];
    err_format(b, sizeof b, "%ld", (long)-4294967297LL);
    ASSERT_EQ_STR(b, "-4294967297");
    err_format(b, sizeof b, "%lu", (unsigned long)4294967296ULL);
    ASSERT_EQ_STR(b, "4294967296");
    err_format(b, sizeof b, "%lld", -1099511627776LL);
    ASSERT_EQ_STR(b, "-1099511627776");
    err_format(b, sizeof b, "%llu x %llu", 18446744073709551615ULL, 4294967296ULL);
    ASSERT_EQ_STR(b, "18446744073709551615 x 4294967296");
    err_format(b, sizeof b, "%zu bytes", (size_t)17179869184ULL);
    ASSERT_EQ_STR(b, "17179869184 bytes");
    err_format(b, sizeof b, "%zd", (ptrdiff_t)-8589934592LL);
    ASSERT_EQ_STR(b, "-8589934592");
    err_format(b, sizeof b, "%jd %ju", (intmax_t)-5000000000LL, (uintmax_t)5000000000ULL);
    ASSERT_EQ_STR(b, "-5000000000 5000000000");
    err_format(b, sizeof b, "%td", (ptrdiff_t)6000000000LL);
    ASSERT_EQ_STR(b, "6000000000");
    err_format(b, sizeof b, "%llx %lX %016llx", 0x123456789abULL, (unsigned long)0xABCDEF012ULL, 0x1ULL);
    ASSERT_EQ_STR(b, "123456789ab ABCDEF012 0000000000000001");
    err_format(b, sizeof b, "%hd %hhu", 70000, 300); /* int promoted, printed as short and char */
    ASSERT_EQ_STR(b, "4464 44");
    err_format(b, sizeof b, "%Lg %lg %5.1f|%-4d|%*d", (long double)0.5, 0.25, 2.25, 7, 3, 9);
    ASSERT_EQ_STR(b, "0.5 0.25   2.2|7   |  9");
    err_format(b, sizeof b, "%lld x %lld x %lld voxels need %zu bytes, over the memory limit of %zu", 65536LL, 65536LL,
               1LL, (size_t)17179869184ULL, (size_t)1048576);
    ASSERT_EQ_STR(b, "65536 x 65536 x 1 voxels need 17179869184 bytes, over the memory limit of 1048576");
}

/* Defect 7: an EXR attribute key of 32 to 47 bytes (accepted by brume_image_set_attribute)
 * deadlocked the write: OpenEXR's error callback re-entered its lock. Now it is written (long
 * names) and read back; run in a child under a time limit so that a hang fails the test. */
TEST(exr_long_attribute_key_writes)
{
    const char *path = test_tmp_path("longkey.exr");
    const char *key = "brume.a_key_of_forty_bytes_long_xxxxxxxx"; /* 40 bytes */
    ASSERT_EQ_INT((int)strlen(key), 40);
    pid_t pid = fork();
    ASSERT_TRUE(pid >= 0);
    if (pid == 0) {
        alarm(30);
        brume_context *ctx = brume_context_new();
        brume_image *img = NULL;
        if (brume_image_new(ctx, 2, 2, &img) != BRUME_OK || brume_image_set_attribute(ctx, img, key, "v") != BRUME_OK)
            _exit(2);
        _exit(brume_image_write(ctx, img, path, NULL) == BRUME_OK ? 0 : 3);
    }
    int status = 0;
    ASSERT_EQ_INT(waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status)); /* not killed by the alarm */
    ASSERT_EQ_INT(WEXITSTATUS(status), 0);
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    ASSERT_EQ_INT(brume_image_read(ctx, path, &img), BRUME_OK);
    ASSERT_TRUE(brume_image_attribute(img, key) != NULL);
    ASSERT_EQ_STR(brume_image_attribute(img, key), "v");
    brume_image_release(img);
    brume_context_release(ctx);
}

/* Defect 9: an environment image is radiance: negative, NaN and infinite values are refused
 * like a grid's, naming the pixel. */
TEST(environment_image_values_checked)
{
    const float bad[3] = {-1.0f, NAN, INFINITY};
    for (int k = 0; k < 3; k++) {
        brume_scene *s = NULL;
        ASSERT_EQ_INT(brume_scene_load(NULL, NULL, NULL, &s), BRUME_OK); /* the default scene */
        brume_image *img = NULL;
        ASSERT_EQ_INT(brume_image_new(NULL, 3, 2, &img), BRUME_OK);
        float *px = brume_image_pixels(img);
        for (int i = 0; i < 3 * 2 * 4; i++)
            px[i] = 0.5f;
        px[4 * 4 + 1] = bad[k]; /* pixel (1, 1), G */
        brume_context *ctx = brume_context_new();
        ASSERT_TRUE(brume_scene_set_background_image(ctx, s, img, 1.0, NULL) != BRUME_OK);
        ASSERT_CONTAINS(brume_context_last_error(ctx), "pixel (1, 1) G");
        px[4 * 4 + 1] = 0.0f; /* zero is allowed */
        ASSERT_EQ_INT(brume_scene_set_background_image(ctx, s, img, 1.0, NULL), BRUME_OK);
        brume_context_release(ctx);
        brume_image_release(img);
        brume_scene_release(s);
    }
}

/* Defect 3: a glTF's instances are counted before assimp builds them: 3 x 3 instances of one
 * triangle read as 9 triangles (through the sandboxed reader), and 50^4 instances under
 * max_memory_mb 64 are refused at once with the figure (they built 5.8 GB). */
TEST(gltf_instances_counted)
{
    const char *dir = test_fresh_dir("gltf");
    static const char small[] =
        "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [8]}],"
        " \"nodes\": [{\"mesh\": 0}, {\"children\": [0]}, {\"children\": [0]}, {\"children\": [0]},"
        " {\"children\": [1, 2, 3]}, {\"children\": [4]}, {\"children\": [4]}, {\"children\": [4]},"
        " {\"children\": [5, 6, 7]}],"
        " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}}]}],"
        " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\","
        " \"min\": [0, 0, 0], \"max\": [1, 1, 0]}], \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 36}],"
        " \"buffers\": [{\"byteLength\": 36, \"uri\": \"data:application/octet-stream;base64,"
        "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA\"}]}";
    char path[4400];
    snprintf(path, sizeof path, "%s/small.gltf", dir);
    test_write_file(path, small);
    double *pos = NULL;
    int *idx = NULL, nv = 0, ntri = 0;
    if (mesh_load(path, &pos, &nv, &idx, &ntri) != BRUME_OK)
        TEST_FAIL("%s", err_message());
    ASSERT_EQ_INT(ntri, 9);
    free(pos);
    free(idx);
    /* the same as a .glb (binary glTF: the JSON chunk, padded with spaces, then the vertices
     * in the BIN chunk), read and counted alike */
    static const char small_bin_json[] =
        "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [8]}],"
        " \"nodes\": [{\"mesh\": 0}, {\"children\": [0]}, {\"children\": [0]}, {\"children\": [0]},"
        " {\"children\": [1, 2, 3]}, {\"children\": [4]}, {\"children\": [4]}, {\"children\": [4]},"
        " {\"children\": [5, 6, 7]}],"
        " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0}}]}],"
        " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\","
        " \"min\": [0, 0, 0], \"max\": [1, 1, 0]}], \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 36}],"
        " \"buffers\": [{\"byteLength\": 36}]}";
    const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    uint32_t jlen = (uint32_t)(strlen(small_bin_json) + 3) / 4 * 4, blen = sizeof tri;
    uint32_t head[5] = {0, 2, 12 + 8 + jlen + 8 + blen, jlen, 0}, bhead[2] = {blen, 0};
    memcpy(head, "glTF", 4);
    memcpy(head + 4, "JSON", 4);
    memcpy(bhead + 1, "BIN", 4);
    snprintf(path, sizeof path, "%s/small.glb", dir);
    FILE *fp = fopen(path, "wb");
    ASSERT_TRUE(fp != NULL);
    fwrite(head, sizeof head, 1, fp);
    fputs(small_bin_json, fp);
    for (size_t k = strlen(small_bin_json); k < jlen; k++)
        fputc(' ', fp);
    fwrite(bhead, sizeof bhead, 1, fp);
    fwrite(tri, sizeof tri, 1, fp);
    fclose(fp);
    if (mesh_load(path, &pos, &nv, &idx, &ntri) != BRUME_OK)
        TEST_FAIL("%s", err_message());
    ASSERT_EQ_INT(ntri, 9);
    free(pos);
    free(idx);
    char scene[4400], msg[1100];
    snprintf(scene, sizeof scene, "%s/s.json", dir);
    snprintf(path, sizeof path,
             "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40}, \"surfaces\": [{\"type\":"
             " \"mesh\", \"file\": \"%s/tests/bad/meshes/gltf_nested.gltf\"}], \"render\": {\"width\": 8,"
             " \"height\": 8, \"spp\": 1, \"max_memory_mb\": 64}}",
             BRUME_SOURCE_DIR);
    test_write_file(scene, path);
    double t0 = test_now();
    ASSERT_TRUE(load_commit(scene, msg, sizeof msg, NULL) != BRUME_OK);
    ASSERT_TRUE(test_now() - t0 < 2.0);
    ASSERT_CONTAINS(msg, "1.88e+07 vertices");
    ASSERT_CONTAINS(msg, "render.max_memory_mb");
    /* the same instances in a .glb: counted before assimp builds them (it ran out of its
     * address space before, seconds later) */
    snprintf(path, sizeof path,
             "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40}, \"surfaces\": [{\"type\":"
             " \"mesh\", \"file\": \"%s/tests/bad/meshes/gltf_nested.glb\"}], \"render\": {\"width\": 8,"
             " \"height\": 8, \"spp\": 1, \"max_memory_mb\": 64}}",
             BRUME_SOURCE_DIR);
    test_write_file(scene, path);
    t0 = test_now();
    ASSERT_TRUE(load_commit(scene, msg, sizeof msg, NULL) != BRUME_OK);
    ASSERT_TRUE(test_now() - t0 < 2.0);
    ASSERT_CONTAINS(msg, "gltf_nested.glb: its instances flattened make 1.88e+07 vertices");
}

/* brume_context_remove_temporaries(ctx) removes the temporary files of writes made with ctx
 * and no other's (the public writers name their context with atomic_owner). */
TEST(temporaries_removed_per_context)
{
    brume_context *a = brume_context_new(), *b = brume_context_new();
    char pa[4200], pb[4200];
    snprintf(pa, sizeof pa, "%s", test_tmp_path("temp-of-a.bin"));
    snprintf(pb, sizeof pb, "%s", test_tmp_path("temp-of-b.bin"));
    remove(pa);
    remove(pb);
    atomic_file fa, fb;
    const void *prev = atomic_owner(a);
    ASSERT_EQ_INT(atomic_open(&fa, pa), BRUME_OK);
    atomic_owner(b);
    ASSERT_EQ_INT(atomic_open(&fb, pb), BRUME_OK);
    atomic_owner(prev);
    ASSERT_TRUE(access(fa.tmp_path, F_OK) == 0 && access(fb.tmp_path, F_OK) == 0);
    brume_context_remove_temporaries(a);
    ASSERT_TRUE(access(fa.tmp_path, F_OK) != 0);
    ASSERT_TRUE(access(fb.tmp_path, F_OK) == 0);
    brume_context_remove_temporaries(b);
    ASSERT_TRUE(access(fb.tmp_path, F_OK) != 0);
    atomic_abort(&fa);
    atomic_abort(&fb);
    ASSERT_TRUE(access(pa, F_OK) != 0 && access(pb, F_OK) != 0);
    brume_context_release(a);
    brume_context_release(b);
}

TEST_MAIN(sun_radius_tends_to_point_sun, messages_stay_on_one_line, scene_cannot_write_outside_its_folder,
          huge_density_ends, huge_voxel_is_refused, work_bomb_and_memory_budget, raw_pairs_and_strict_readers,
          signal_during_write_leaves_no_temp_file, messages_print_every_length_modifier,
          exr_long_attribute_key_writes, environment_image_values_checked, gltf_instances_counted,
          temporaries_removed_per_context)
