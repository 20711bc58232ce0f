/* test_hardening.c - inputs that pass validation cannot hang brume, exhaust its memory,
 * write outside the scene's folder or draw a silently wrong picture; messages stay on one
 * line; interrupted writes leave nothing behind (issue 16; the corpus of bad inputs is
 * tests/bad/). */
#include "test.h"

#include <arpa/inet.h>
#include <dirent.h>
#include <pthread.h>
#include <stdatomic.h>
#include <math.h>
#include <signal.h>
#include <stddef.h>
#include <stdint.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "brume.h"
#include "core/error.h"
#include "io/atomic.h"
#include "job/checkpoint.h"
#include "io/grid_io.h"
#include "io/mesh.h"
#include "scene/scene.h"

static double seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void write_file(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    ASSERT_TRUE(f != NULL);
    ASSERT_TRUE(fwrite(data, 1, n, f) == n);
    fclose(f);
}

static void write_text(const char *path, const char *text) { write_file(path, text, strlen(text)); }

/* A fresh empty folder under the test's temporary space. */
static const char *fresh_dir(const char *name)
{
    const char *d = test_tmp_path(name);
    char cmd[4200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s'", d, d);
    ASSERT_EQ_INT(test_system(cmd), 0);
    return d;
}

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
    ASSERT_EQ_INT(scene_parse_json(json, "<test>", &s), BRUME_OK);
    brume_context *ctx = brume_context_new();
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
    brume_scene *s = NULL;
    ASSERT_TRUE(scene_parse_json("{\"camera\": {\"position\": [0,0,1], \"look_at\": [0,0,0], \"f\\nov\\u001b[2J\": 1}}",
                                 "<test>", &s) != BRUME_OK);
    m = err_message();
    ASSERT_TRUE(strchr(m, '\n') == NULL && strchr(m, '\x1b') == NULL);
    ASSERT_CONTAINS(m, "f\\nov\\x1b[2J");
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
    const char *root = fresh_dir("writes");
    char dir[4200], path[4300], outside[4300], msg[1100], link[4300];
    snprintf(dir, sizeof dir, "%s/scene", root);
    ASSERT_EQ_INT(mkdir(dir, 0700), 0);
    snprintf(link, sizeof link, "%s/up", dir);
    ASSERT_EQ_INT(symlink(root, link), 0);
    snprintf(path, sizeof path, "%s/s.json", dir);
    const char *bad[] = {"../out.bl", "sub/../../out.bl", "up/out.bl", "up/../out.bl"};
    for (int i = 0; i < 4; i++) {
        write_text(path, scene_with_save(bad[i]));
        ASSERT_TRUE(load_commit(path, msg, sizeof msg, NULL) != BRUME_OK);
        ASSERT_CONTAINS(msg, "blasi.save_light");
        ASSERT_TRUE(strchr(msg, '\n') == NULL);
    }
    snprintf(outside, sizeof outside, "%s/abs.bl", root);
    write_text(path, scene_with_save(outside));
    ASSERT_TRUE(load_commit(path, msg, sizeof msg, NULL) != BRUME_OK);
    ASSERT_CONTAINS(msg, "absolute");
    snprintf(outside, sizeof outside, "%s/out.bl", root);
    ASSERT_TRUE(!test_exists(outside));
    snprintf(outside, sizeof outside, "%s/abs.bl", root);
    ASSERT_TRUE(!test_exists(outside));
    /* inside the folder: written by the render */
    write_text(path, scene_with_save("light.bl"));
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
            double t0 = seconds(), m = image_mean(json);
            ASSERT_TRUE(isfinite(m) && m >= 0.0);
            ASSERT_TRUE(seconds() - t0 < 20.0);
        }
    alarm(0);
}

/* The 20-byte raw grid with one voxel of 3e38: `brume info` reads it, a scene
 * refuses it at commit, naming the medium and the limit. */
TEST(huge_voxel_is_refused)
{
    const char *dir = fresh_dir("voxel");
    char raw[4200], scene[4200], msg[1100], json[1024];
    snprintf(raw, sizeof raw, "%s/hot.raw", dir);
    float v[5] = {0, 0, 3e38f, 0, 0};
    write_file(raw, v, sizeof v);
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
    write_text(scene, json);
    double t0 = seconds();
    ASSERT_EQ_INT(load_commit(scene, msg, sizeof msg, NULL), BRUME_ERROR_RANGE);
    ASSERT_TRUE(seconds() - t0 < 10.0);
    ASSERT_CONTAINS(msg, "media[0]");
    ASSERT_CONTAINS(msg, "limits");
}

/* The work bomb (four million blobs from a few hundred bytes) is refused up front,
 * quickly, naming the limit; and one memory budget spans every reader and generator. */
TEST(work_bomb_and_memory_budget)
{
    const char *dir = fresh_dir("bomb");
    char scene[4200], msg[1100];
    snprintf(scene, sizeof scene, "%s/s.json", dir);
    write_text(scene, "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
                      " \"media\": [{\"density\": {\"type\": \"blobs\", \"generators\": [{\"type\": \"cloud\","
                      " \"center\": [0, 0, 0], \"radii\": 1, \"count\": 4194304}]}, \"sigma_a\": 0.1, \"sigma_s\": 1}]}");
    double t0 = seconds();
    ASSERT_EQ_INT(load_commit(scene, msg, sizeof msg, NULL), BRUME_ERROR_RANGE);
    ASSERT_TRUE(seconds() - t0 < 10.0);
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
    write_text(scene, json);
    ASSERT_EQ_INT(load_commit(scene, msg, sizeof msg, NULL), BRUME_ERROR_OUT_OF_MEMORY);
    ASSERT_CONTAINS(msg, "media[1]");
    ASSERT_CONTAINS(msg, "render.max_memory_mb");
    snprintf(json, sizeof json, TWO_FMT, "3");
    write_text(scene, json);
    ASSERT_EQ_INT(load_commit(scene, msg, sizeof msg, NULL), BRUME_OK);
    /* a phase table read from /dev/zero ends, within the budget */
    write_text(scene, "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
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
        write_text(scene, uses[i]);
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
    const char *dir = fresh_dir("pairs");
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
    write_file(raw, v, 4 * sizeof(float));
    ASSERT_TRUE(density_load_file(raw, NULL) == NULL);
    ASSERT_CONTAINS(err_message(), "bytes, but");
    /* a whole pair reads back */
    ASSERT_EQ_INT(density_write_file(d, raw, GRID_FORMAT_RAW), BRUME_OK);
    density *back = density_load_file(raw, NULL);
    ASSERT_TRUE(back != NULL);
    density_release(back);
    density_release(d);
    /* inverted sidecar bounds */
    write_text(hdr, "dims 2 2 2\nbounds 1 0 0 0 1 1\n");
    write_file(raw, v, sizeof v);
    ASSERT_TRUE(density_load_file(raw, NULL) == NULL);
    ASSERT_CONTAINS(err_message(), "min < max");
    /* .vol with trailing bytes */
    char vol[4200];
    snprintf(vol, sizeof vol, "%s/g.vol", dir);
    unsigned char buf[48 + 32 + 1] = {'V', 'O', 'L', 3, 1, 0, 0, 0, 2, 0, 0, 0, 2, 0, 0, 0, 2, 0, 0, 0, 1, 0, 0, 0};
    float box[6] = {0, 0, 0, 1, 1, 1};
    memcpy(buf + 24, box, sizeof box);
    memcpy(buf + 48, v, sizeof v);
    write_file(vol, buf, sizeof buf - 1);
    back = density_load_file(vol, NULL);
    ASSERT_TRUE(back != NULL);
    density_release(back);
    write_file(vol, buf, sizeof buf);
    ASSERT_TRUE(density_load_file(vol, NULL) == NULL);
    ASSERT_CONTAINS(err_message(), "trailing bytes");
    /* no temporary file was left by any of it */
    snprintf(cmd, sizeof cmd, "ls -A '%s' | grep -q tmp-", dir);
    ASSERT_TRUE(test_system(cmd) != 0);
}

/* A signal in the middle of an atomic write leaves no temporary file. */
TEST(signal_during_write_leaves_no_temp_file)
{
    const char *dir = fresh_dir("signal");
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

/* ---- issue 36: files brume did not write, checkpoints, resume --------------------------- */

/* Runs `brume ARGS` in folder dir, stderr to dir/err.txt; the exit status. */
static int brume_in(const char *dir, const char *args)
{
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "cd '%s' && %s %s >/dev/null 2>err.txt", dir, BRUME_EXE, args);
    return test_system(cmd);
}

static void read_back(const char *dir, const char *name, char *out, size_t n)
{
    char path[4400];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    out[0] = '\0';
    FILE *f = fopen(path, "rb");
    if (!f)
        return;
    size_t got = fread(out, 1, n - 1, f);
    out[got] = '\0';
    fclose(f);
}

/* A one-medium scene of a 2^3 raw grid g.raw (written beside it, every voxel `rho`). */
static void write_grid_scene(const char *dir, int width, float rho, const char *extra)
{
    char path[4400], json[2048];
    float v[8];
    for (int i = 0; i < 8; i++)
        v[i] = rho;
    snprintf(path, sizeof path, "%s/g.raw", dir);
    write_file(path, v, sizeof v);
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
             " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, 0], \"irradiance\": 1}],"
             " \"media\": [{\"density\": {\"type\": \"grid\", \"file\": \"g.raw\", \"format\": \"raw\", \"dims\": [2, 2, 2]},"
             " \"sigma_a\": 0.1, \"sigma_s\": 1}],"
             " \"render\": {\"width\": %d, \"height\": %d, \"spp\": 1, \"threads\": 1}%s}",
             width, width, extra ? extra : "");
    snprintf(path, sizeof path, "%s/s.json", dir);
    write_text(path, json);
}

/* Defect 1: --checkpoint, --save-light and blasi.save_light never remove or replace a file
 * brume did not write (a note, the scene, an input, a pipe); each is refused with one line
 * before any work, and the file is left as it was. */
TEST(checkpoint_never_destroys_foreign_files)
{
    const char *dir = fresh_dir("foreign");
    char path[4400], text[256], cmd[4600];
    write_grid_scene(dir, 4, 1.0f, NULL);
    snprintf(path, sizeof path, "%s/notes.txt", dir);
    write_text(path, "keep\n");
    snprintf(path, sizeof path, "%s/fifo", dir);
    ASSERT_EQ_INT(mkfifo(path, 0600), 0);
    const char *cases[][2] = {
        {"render s.json -o out.png --quiet --checkpoint notes.txt", "notes.txt"},
        {"render s.json -o out.png --quiet --checkpoint s.json", "scene file"},
        {"render s.json -o out.png --quiet --checkpoint g.raw", "not a brume checkpoint"},
        {"render s.json -o out.png --quiet --checkpoint fifo", "not a regular file"},
        {"render s.json -o out.png --quiet --method blasi --save-light s.json", "scene file"},
        {"render s.json -o out.png --quiet --method blasi --save-light g.raw", "input of the scene"},
        {"render s.json -o out.png --quiet --method blasi --save-light fifo", "not a regular file"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        ASSERT_EQ_INT(brume_in(dir, cases[i][0]), 1);
        read_back(dir, "err.txt", text, sizeof text);
        ASSERT_CONTAINS(text, cases[i][1]);
        ASSERT_TRUE(strchr(text, '\n') == strrchr(text, '\n')); /* one line */
        read_back(dir, "notes.txt", text, sizeof text);
        ASSERT_EQ_STR(text, "keep\n");
        read_back(dir, "s.json", text, sizeof text);
        ASSERT_TRUE(strncmp(text, "{\"camera\"", 9) == 0);
        struct stat sb;
        snprintf(path, sizeof path, "%s/g.raw", dir);
        ASSERT_TRUE(stat(path, &sb) == 0 && sb.st_size == 32);
        snprintf(path, sizeof path, "%s/fifo", dir);
        ASSERT_TRUE(stat(path, &sb) == 0 && S_ISFIFO(sb.st_mode));
        snprintf(path, sizeof path, "%s/out.png", dir);
        ASSERT_TRUE(!test_exists(path)); /* refused before any work */
    }
    /* the scene file itself names its own file as the light file */
    write_grid_scene(dir, 4, 1.0f, ", \"blasi\": {\"light_rays\": 100, \"save_light\": \"s.json\"}");
    ASSERT_EQ_INT(brume_in(dir, "render s.json -o out.png --quiet --method blasi"), 1);
    read_back(dir, "err.txt", text, sizeof text);
    ASSERT_CONTAINS(text, "blasi.save_light");
    read_back(dir, "s.json", text, sizeof text);
    ASSERT_TRUE(strncmp(text, "{\"camera\"", 9) == 0);
    /* -o naming an input of the scene (its environment image) is refused once the scene is read */
    snprintf(path, sizeof path, "%s/env.pfm", dir);
    {
        const char hdr[] = "PF\n1 1\n-1\n";
        const float px[3] = {0.5f, 0.5f, 0.5f};
        FILE *f = fopen(path, "wb");
        ASSERT_TRUE(f != NULL);
        fwrite(hdr, 1, sizeof hdr - 1, f);
        fwrite(px, sizeof px, 1, f);
        fclose(f);
    }
    write_grid_scene(dir, 4, 1.0f, ", \"background\": {\"file\": \"env.pfm\"}");
    ASSERT_EQ_INT(brume_in(dir, "render s.json -o env.pfm --quiet"), 1);
    read_back(dir, "err.txt", text, sizeof text);
    ASSERT_CONTAINS(text, "an input of the scene");
    struct stat eb;
    ASSERT_TRUE(stat(path, &eb) == 0 && eb.st_size == 10 + 12); /* untouched */
    /* a device node is never replaced by an atomic write, whoever asks */
    atomic_file f;
    ASSERT_TRUE(atomic_open(&f, "/dev/null") != BRUME_OK);
    ASSERT_CONTAINS(err_message(), "not a regular file");
    /* this run's own checkpoint is removed at the end; a finished render leaves none */
    write_grid_scene(dir, 4, 1.0f, NULL);
    ASSERT_EQ_INT(brume_in(dir, "render s.json -o out.png --quiet --checkpoint c.ckpt"), 0);
    snprintf(path, sizeof path, "%s/c.ckpt", dir);
    ASSERT_TRUE(!test_exists(path));
    snprintf(cmd, sizeof cmd, "%s/out.png", dir);
    ASSERT_TRUE(test_exists(cmd));
}

/* checkpoint_remove_own reads the header: a checkpoint of another scene key, of other
 * settings, or any other file at the path stays. */
TEST(checkpoint_removed_only_when_its_header_says_so)
{
    const char *dir = fresh_dir("own");
    char path[4400], other[4400];
    write_grid_scene(dir, 4, 1.0f, NULL);
    snprintf(path, sizeof path, "%s/s.json", dir);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    brume_render_job *job = NULL;
    ASSERT_EQ_INT(brume_render_begin(ctx, s, &job), BRUME_OK);
    snprintf(path, sizeof path, "%s/c.ckpt", dir);
    ASSERT_EQ_INT(brume_render_job_save(ctx, job, 42, path), BRUME_OK);
    ASSERT_TRUE(!checkpoint_remove_own(job, 43, path)); /* another key */
    ASSERT_TRUE(test_exists(path));
    snprintf(other, sizeof other, "%s/notes.txt", dir);
    write_text(other, "BRUMECKP but not one\n");
    ASSERT_TRUE(!checkpoint_remove_own(job, 42, other));
    ASSERT_TRUE(test_exists(other));
    ASSERT_TRUE(checkpoint_remove_own(job, 42, path));
    ASSERT_TRUE(!test_exists(path));
    brume_render_job_release(job);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* Defect 2: --resume of another file: one line, no crash (the message was built from freed
 * memory: a file of 128 KiB or more, mmap'ed by malloc, crashed), and /dev/zero is refused
 * unread instead of read without bound. */
TEST(resume_of_other_files)
{
    const char *dir = fresh_dir("resume");
    char path[4400], text[512];
    write_grid_scene(dir, 256, 1.0f, NULL);
    static unsigned char junk[300000];
    memset(junk, 'x', sizeof junk);
    snprintf(path, sizeof path, "%s/junk.bin", dir);
    write_file(path, junk, sizeof junk);
    ASSERT_EQ_INT(brume_in(dir, "render s.json -o out.png --quiet --resume junk.bin"), 1);
    read_back(dir, "err.txt", text, sizeof text);
    ASSERT_CONTAINS(text, "junk.bin: not a brume checkpoint");
    double t0 = seconds();
    ASSERT_EQ_INT(brume_in(dir, "render s.json -o out.png --quiet --resume /dev/zero"), 1);
    ASSERT_TRUE(seconds() - t0 < 20.0);
    read_back(dir, "err.txt", text, sizeof text);
    ASSERT_CONTAINS(text, "/dev/zero: not a regular file");
    /* a file larger than the scene's largest checkpoint is refused unread */
    write_grid_scene(dir, 4, 1.0f, NULL);
    ASSERT_EQ_INT(brume_in(dir, "render s.json -o out.png --quiet --resume junk.bin"), 1);
    read_back(dir, "err.txt", text, sizeof text);
    ASSERT_CONTAINS(text, "larger than its largest checkpoint");
}

/* Defect 6: the checkpoint key covers the bytes of every file the scene reads: a changed
 * grid file (same size, same name) gives another key, and --resume refuses the checkpoint. */
TEST(checkpoint_key_covers_inputs)
{
    const char *dir = fresh_dir("key");
    char path[4400], text[512];
    write_grid_scene(dir, 4, 1.0f, NULL);
    snprintf(path, sizeof path, "%s/s.json", dir);
    brume_context *ctx = brume_context_new();
    brume_scene *a = NULL, *b = NULL;
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &a), BRUME_OK);
    ASSERT_EQ_INT((int)a->inputs.n, 1);
    ASSERT_CONTAINS(a->inputs.v[0].path, "g.raw");
    uint64_t ka = checkpoint_inputs_key(a, 1);
    ASSERT_TRUE(ka == checkpoint_inputs_key(a, 1));
    write_grid_scene(dir, 4, 2.0f, NULL);
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &b), BRUME_OK);
    ASSERT_TRUE(checkpoint_inputs_key(b, 1) != ka);
    brume_scene_release(a);
    brume_scene_release(b);
    brume_context_release(ctx);
    /* end to end: a checkpoint made with one grid is refused after the grid changed. The
     * checkpoint is written by an interrupted render: SIGINT before it ends */
    write_grid_scene(dir, 64, 1.0f, NULL);
    char cmd[8400];
    snprintf(cmd, sizeof cmd,
             "cd '%s' && (%s render s.json -o out.png --quiet --spp 100000 --checkpoint c.ckpt 2>err.txt & pid=$!;"
             " sleep 2; kill -INT $pid; wait $pid; exit 0)",
             dir, BRUME_EXE);
    ASSERT_EQ_INT(test_system(cmd), 0);
    snprintf(path, sizeof path, "%s/c.ckpt", dir);
    ASSERT_TRUE(test_exists(path));
    write_grid_scene(dir, 64, 2.0f, NULL);
    ASSERT_EQ_INT(brume_in(dir, "render s.json -o out.png --quiet --spp 100000 --resume c.ckpt"), 1);
    read_back(dir, "err.txt", text, sizeof text);
    ASSERT_CONTAINS(text, "another scene");
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
        ASSERT_EQ_INT(scene_parse_json(scene_default_json, "<test>", &s), BRUME_OK);
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

/* Defect 5: the film and the image count against render.max_memory_mb: 4096^2 pixels under
 * a 1 MiB limit are refused before allocating (1.41 GB were used), and 64^2 pass. */
TEST(film_counts_against_the_memory_limit)
{
#define FILM_FMT "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40}," \
                      " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, 0], \"irradiance\": 1}]," \
                      " \"media\": [{\"density\": {\"type\": \"constant\", \"value\": 1}, \"sigma_a\": 0.1, \"sigma_s\": 1}]," \
                      " \"render\": {\"width\": %d, \"height\": %d, \"spp\": 1, \"threads\": 1, \"max_memory_mb\": 1}}"
    char json[1024];
    snprintf(json, sizeof json, FILM_FMT, 4096, 4096);
    brume_scene *s = NULL;
    brume_context *ctx = brume_context_new();
    ASSERT_EQ_INT(scene_parse_json(json, "<film>", &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    brume_render_job *job = NULL;
    ASSERT_EQ_INT(brume_render_begin(ctx, s, &job), BRUME_ERROR_OUT_OF_MEMORY);
    ASSERT_TRUE(job == NULL);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "render.max_memory_mb");
    ASSERT_CONTAINS(brume_context_last_error(ctx), "4096 x 4096");
    brume_image *img = NULL;
    ASSERT_EQ_INT(brume_render(ctx, s, &img), BRUME_ERROR_OUT_OF_MEMORY);
    brume_scene_release(s);
    snprintf(json, sizeof json, FILM_FMT, 64, 64);
#undef FILM_FMT
    ASSERT_EQ_INT(scene_parse_json(json, "<film>", &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    ASSERT_EQ_INT(brume_render(ctx, s, &img), BRUME_OK);
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
}

#define BLASI_FMT \
    "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40}," \
    " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, 0], \"irradiance\": 1}]," \
    " \"media\": [{\"density\": {\"type\": \"procedural_cloud\", \"resolution\": 32}, \"sigma_a\": 0.1, \"sigma_s\": 1}]," \
    " \"render\": {\"width\": 8, \"height\": 8, \"spp\": 1, \"threads\": 2, \"method\": \"blasi\"%s}," \
    " \"blasi\": {%s}}"

/* Defect 4: Blasi's light pass estimates its work (rays x steps) and refuses a scene over
 * render.max_work with the figure; blasi.step 1e-6 at the default ray count (17 h) is one. */
TEST(blasi_work_is_bounded)
{
    char json[2048];
    snprintf(json, sizeof json, BLASI_FMT, "", "\"step\": 1e-6");
    brume_scene *s = NULL;
    brume_context *ctx = brume_context_new();
    ASSERT_EQ_INT(scene_parse_json(json, "<work>", &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    brume_image *img = NULL;
    double t0 = seconds();
    ASSERT_EQ_INT(brume_render(ctx, s, &img), BRUME_ERROR_RANGE);
    ASSERT_TRUE(seconds() - t0 < 10.0);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "render.max_work (1e+12)");
    ASSERT_CONTAINS(brume_context_last_error(ctx), "units of work");
    brume_scene_release(s);
    /* a lower limit refuses the default pass (2^21 rays x about 96 voxels) and a higher passes */
    snprintf(json, sizeof json, BLASI_FMT, ", \"max_work\": 1e6", "\"light_rays\": 100000");
    ASSERT_EQ_INT(scene_parse_json(json, "<work>", &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    ASSERT_EQ_INT(brume_render(ctx, s, &img), BRUME_ERROR_RANGE);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "render.max_work (1e+06)");
    brume_scene_release(s);
    snprintf(json, sizeof json, BLASI_FMT, ", \"max_work\": 1e9", "\"light_rays\": 100000");
    ASSERT_EQ_INT(scene_parse_json(json, "<work>", &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    ASSERT_EQ_INT(brume_render(ctx, s, &img), BRUME_OK);
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
}

#define GEN_FMT \
    "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40}," \
    " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, 0], \"irradiance\": 1}]," \
    " \"media\": [{\"density\": %s, \"sigma_a\": 0.1, \"sigma_s\": 1}]," \
    " \"render\": {\"width\": 8, \"height\": 8, \"spp\": 1, \"threads\": 2%s}%s}"

/* Loads the scene text (named gen.json), commits and renders it: BRUME_OK or the first
 * failure, with its message in ctx. */
static brume_status load_and_render(brume_context *ctx, const char *json)
{
    brume_scene *s = NULL;
    brume_status st = brume_scene_load(ctx, &(brume_source){.path = "gen.json", .text = json}, NULL, &s);
    brume_image *img = NULL;
    if (st == BRUME_OK && (st = brume_scene_commit(ctx, s)) == BRUME_OK && (st = brume_render(ctx, s, &img)) == BRUME_OK)
        brume_image_release(img);
    brume_scene_release(s);
    return st;
}

/* Defect 4: the generators estimate their work before they start (issue 36) and refuse a
 * scene over render.max_work with the figure, one line naming the file and the field: the
 * procedural cloud (voxels x 5 octaves), the fractal cloud (its base, turbulence and shape)
 * and Stam's random field (lattice points x (1 + log2 points), the FFT). The same scenes at
 * the default limit render. The figures are the formulas' for these sizes. */
TEST(generators_work_is_bounded)
{
    static const char blobs[] =
        "{\"type\": \"blobs\", \"generators\": [{\"type\": \"cloud\", \"center\": [0, 0, 0], \"radii\": [1, 0.5, 0.7],"
        " \"count\": 20, \"h\": [0.2, 0.4], \"density\": 0.15, \"falloff\": 1.0, \"seed\": 5}]}";
    struct {
        const char *density, *render, *extra, *field, *figure;
    } cases[] = {
        {"{\"type\": \"procedural_cloud\", \"resolution\": 32}", "", "", "media[0].density",
         "32^3 voxels x 5 octaves of noise are 1.64e+05 units of work"},
        {"{\"type\": \"fractal_cloud\", \"dims\": [32, 16, 8], \"method\": \"perlin\", \"octaves\": 4, \"turbulence\": 0.5}",
         "", "", "media[0].density", "are 3.69e+04 units of work"}, /* 4096 voxels x (4 + 4 + 1) */
        {"{\"type\": \"fractal_cloud\", \"dims\": [32, 16, 8], \"method\": \"midpoint\", \"turbulence\": 0}", "", "",
         "media[0].density", "are 4e+04 units of work"}, /* a 33^3 lattice + 4096 voxels */
        {blobs, ", \"method\": \"stam\"", ", \"stam\": {\"eps\": 0.4, \"lattice\": 16, \"light_grid\": 0}",
         "stam.lattice", "16 x 16 x 16 lattice points are 5.32e+04 units of work"}, /* 4096 x 13 */
    };
    brume_context *ctx = brume_context_new();
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char json[2048], render[256];
        snprintf(render, sizeof render, "%s, \"max_work\": 1e4", cases[k].render);
        snprintf(json, sizeof json, GEN_FMT, cases[k].density, render, cases[k].extra);
        ASSERT_EQ_INT(load_and_render(ctx, json), BRUME_ERROR_RANGE);
        const char *msg = brume_context_last_error(ctx);
        fprintf(stderr, "%s\n", msg);
        ASSERT_CONTAINS(msg, "gen.json");
        ASSERT_CONTAINS(msg, cases[k].field);
        ASSERT_CONTAINS(msg, cases[k].figure);
        ASSERT_CONTAINS(msg, "over render.max_work (1e+04)");
        ASSERT_TRUE(strchr(msg, '\n') == NULL);
        snprintf(json, sizeof json, GEN_FMT, cases[k].density, cases[k].render, cases[k].extra);
        if (load_and_render(ctx, json) != BRUME_OK)
            TEST_FAIL("case %zu at the default render.max_work: %s", k, brume_context_last_error(ctx));
    }
    brume_context_release(ctx);
}

static bool cancel_first(void *user, uint64_t done, uint64_t total)
{
    (void)done;
    (void)total;
    ++*(int *)user;
    return false;
}

/* Defect 4: the library's cancel (the progress callback returning false) stops Stam's random
 * field, made when a render begins, within a second: its loops asked only a load's cancel
 * (brume_context_cancel_loads), never the render's callback. A 256^3 lattice: some 6 to 13 s
 * on the 2-core test machine, uncancelled. */
TEST(stam_random_field_cancels)
{
    static const char blobs[] =
        "{\"type\": \"blobs\", \"generators\": [{\"type\": \"cloud\", \"center\": [0, 0, 0], \"radii\": [1, 0.5, 0.7],"
        " \"count\": 20, \"h\": [0.2, 0.4], \"density\": 0.15, \"falloff\": 1.0, \"seed\": 5}]}";
    char json[2048];
    snprintf(json, sizeof json, GEN_FMT, blobs, ", \"method\": \"stam\"",
             ", \"stam\": {\"eps\": 0.4, \"lattice\": 256, \"light_grid\": 0}");
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = "field.json", .text = json}, NULL, &s), BRUME_OK);
    int calls = 0;
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    rs.progress_fn = cancel_first;
    rs.progress_user = &calls;
    ASSERT_EQ_INT(brume_scene_set_settings(ctx, s, &rs), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    brume_render_job *job = NULL;
    double t0 = seconds();
    ASSERT_EQ_INT(brume_render_begin(ctx, s, &job), BRUME_ERROR_CANCELLED);
    double took = seconds() - t0;
    fprintf(stderr, "cancelled after %.2f s, %d call(s): %s\n", took, calls, brume_context_last_error(ctx));
    ASSERT_TRUE(job == NULL);
    ASSERT_TRUE(took < 1.5); /* the first call comes after 0.1 s; a plane of 256^2 modes takes ms */
    ASSERT_EQ_INT(calls, 1);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "random field: cancelled");
    brume_scene_release(s);
    brume_context_release(ctx);
}
#undef GEN_FMT

static bool cancel_at_once(void *user, uint64_t done, uint64_t total)
{
    (void)done;
    (void)total;
    ++*(int *)user;
    return false;
}

/* Defect 4: the library's cancel (the progress callback returning false) stops Blasi's light
 * pass within a second; it was asked only after the pass. A pass of some 20 s. */
TEST(blasi_light_pass_cancels)
{
    char json[2048];
    snprintf(json, sizeof json, BLASI_FMT, "", "\"light_rays\": 1e8, \"step\": 0.001");
    brume_scene *s = NULL;
    brume_context *ctx = brume_context_new();
    ASSERT_EQ_INT(scene_parse_json(json, "<cancel>", &s), BRUME_OK);
    int calls = 0;
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    rs.progress_fn = cancel_at_once;
    rs.progress_user = &calls;
    ASSERT_EQ_INT(brume_scene_set_settings(ctx, s, &rs), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    brume_render_job *job = NULL;
    double t0 = seconds();
    ASSERT_EQ_INT(brume_render_begin(ctx, s, &job), BRUME_ERROR_CANCELLED);
    double took = seconds() - t0;
    fprintf(stderr, "cancelled after %.2f s, %d call(s)\n", took, calls);
    ASSERT_TRUE(took < 1.5);
    ASSERT_EQ_INT(calls, 1);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "light pass was cancelled");
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* Defect 4: SIGINT and SIGTERM stop brume render within a second in every phase: loading
 * (procedural_cloud at 512, answered after 67 s before), Blasi's light pass (ignored) and
 * Stam's random field. */
TEST(signals_stop_every_phase)
{
    const char *dir = fresh_dir("phases");
    char path[4400], json[2048];
    snprintf(path, sizeof path, "%s/load.json", dir);
    write_text(path, "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
                     " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, 0], \"irradiance\": 1}],"
                     " \"media\": [{\"density\": {\"type\": \"procedural_cloud\", \"resolution\": 512}, \"sigma_a\": 0.1,"
                     " \"sigma_s\": 1}], \"render\": {\"width\": 8, \"height\": 8, \"spp\": 1}}");
    snprintf(path, sizeof path, "%s/light.json", dir);
    snprintf(json, sizeof json, BLASI_FMT, "", "\"light_rays\": 1e8, \"step\": 0.001");
    write_text(path, json);
    snprintf(path, sizeof path, "%s/field.json", dir); /* Stam's random field, 256^3: some 6 to 13 s */
    write_text(path, "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
                     " \"media\": [{\"density\": {\"type\": \"blobs\", \"generators\": [{\"type\": \"cloud\","
                     " \"center\": [0, 0, 0], \"radii\": [1, 0.5, 0.7], \"count\": 20, \"h\": [0.2, 0.4], \"seed\": 5}]},"
                     " \"sigma_a\": 0.1, \"sigma_s\": 1}], \"render\": {\"width\": 8, \"height\": 8, \"spp\": 1,"
                     " \"method\": \"stam\"}, \"stam\": {\"eps\": 0.4, \"lattice\": 256, \"light_grid\": 0}}");
    const char *scenes[3] = {"load.json", "light.json", "field.json"};
    const int sigs[2] = {SIGINT, SIGTERM};
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 2; j++) {
            char args[4400], err[4400];
            snprintf(args, sizeof args, "render %s/%s -o %s/out.png", dir, scenes[k], dir);
            snprintf(err, sizeof err, "%s/err.txt", dir);
            pid_t pid = test_spawn(BRUME_EXE, args, err);
            test_sleep(1.5);
            double t0 = seconds();
            kill(pid, sigs[j]);
            int rc = test_wait_exit(pid, 60.0);
            double took = seconds() - t0;
            fprintf(stderr, "%s, signal %d: exit %d after %.2f s\n", scenes[k], sigs[j], rc, took);
            ASSERT_EQ_INT(rc, 128 + sigs[j]);
            ASSERT_TRUE(took < 1.0);
            snprintf(path, sizeof path, "%s/out.png", dir);
            ASSERT_TRUE(!test_exists(path));
        }
}

/* Defect 10: the output folders are made only after the scene was read and checked: a bad
 * scene with --frames 0-200 -o out%d/f.png left 201 empty folders. */
TEST(bad_scene_makes_no_folders)
{
    const char *dir = fresh_dir("folders");
    char path[4400];
    snprintf(path, sizeof path, "%s/bad.json", dir);
    write_text(path, "{\"camera\": 5}");
    ASSERT_EQ_INT(brume_in(dir, "render bad.json --frames 0-200 -o out%d/f.png --quiet"), 1);
    ASSERT_EQ_INT(brume_in(dir, "render bad.json -o deep/er/f.png --quiet --checkpoint ck/c.ckpt"), 1);
    DIR *d = opendir(dir);
    ASSERT_TRUE(d != NULL);
    int folders = 0;
    for (struct dirent *e; (e = readdir(d));) {
        char sub[4700];
        struct stat sb;
        snprintf(sub, sizeof sub, "%s/%s", dir, e->d_name);
        folders += e->d_name[0] != '.' && stat(sub, &sb) == 0 && S_ISDIR(sb.st_mode);
    }
    closedir(d);
    ASSERT_EQ_INT(folders, 0);
    /* a good scene makes them */
    write_grid_scene(dir, 4, 1.0f, NULL);
    ASSERT_EQ_INT(brume_in(dir, "render s.json --frames 0-1 -o out%d/f.png --quiet"), 0);
    snprintf(path, sizeof path, "%s/out1/f.png", dir);
    ASSERT_TRUE(test_exists(path));
}

/* Defect 11: an interrupted sequence writes its partial frame as NAME.partial.EXT, never under
 * the name of a finished frame. */
TEST(partial_frame_says_so)
{
    const char *dir = fresh_dir("partial");
    write_grid_scene(dir, 64, 1.0f, NULL);
    char cmd[8400], path[4400];
    /* frame 0 takes long (many samples): SIGINT during it, after rendering started; retried
     * with a longer wait on a loaded machine */
    bool partial = false;
    for (int attempt = 0; attempt < 4 && !partial; attempt++) {
        snprintf(cmd, sizeof cmd,
                 "cd '%s' && (%s render s.json --frames 0-1 -o f_%%02d.pfm --spp 1000000 2>err.txt & pid=$!;"
                 " sleep %d; kill -INT $pid; wait $pid; exit 0)",
                 dir, BRUME_EXE, 2 << attempt);
        ASSERT_EQ_INT(test_system(cmd), 0);
        snprintf(path, sizeof path, "%s/f_00.partial.pfm", dir);
        partial = test_exists(path);
    }
    ASSERT_TRUE(partial);
    snprintf(path, sizeof path, "%s/f_00.pfm", dir);
    ASSERT_TRUE(!test_exists(path));
}

/* The port of the live view that `brume render --serve` announced in err (waits for it). */
static int served_port(const char *err)
{
    for (int i = 0; i < 600; i++) {
        size_t n;
        char *msg = test_exists(err) ? test_slurp(err, &n) : NULL;
        const char *at = msg ? strstr(msg, "live view at http://") : NULL;
        const char *colon = at ? strchr(at + 20, ':') : NULL;
        int port = colon ? atoi(colon + 1) : 0;
        free(msg);
        if (port > 0)
            return port;
        test_sleep(0.05);
    }
    return 0;
}

static int connect_from(const char *src, int port)
{
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    struct sockaddr_in a = {0};
    a.sin_family = AF_INET;
    inet_pton(AF_INET, src, &a.sin_addr);
    if (fd < 0 || bind(fd, (struct sockaddr *)&a, sizeof a) != 0) {
        if (fd >= 0)
            close(fd);
        return -1;
    }
    inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
    a.sin_port = htons((uint16_t)port);
    if (connect(fd, (struct sockaddr *)&a, sizeof a) != 0) {
        close(fd);
        return -1;
    }
    return fd;
}

/* Defect 11: idle connections cannot take the live view from others (32 of them blocked it:
 * now 16 per client address, dropped after 10 s idle), and binding beyond loopback warns. */
TEST(serve_idle_connections_and_exposure)
{
    const char *dir = fresh_dir("serve");
    write_grid_scene(dir, 16, 1.0f, NULL);
    char args[4400], err[4400];
    snprintf(args, sizeof args, "render %s/s.json --spp 16000000 -o %s/o.png --serve 127.0.0.1:0", dir, dir);
    snprintf(err, sizeof err, "%s/serve-err.txt", dir);
    pid_t pid = test_spawn(BRUME_EXE, args, err);
    int port = served_port(err);
    ASSERT_TRUE(port > 0);
    int idle[40];
    for (int i = 0; i < 40; i++)
        idle[i] = connect_from("127.0.0.1", port);
    test_sleep(0.3);
    int fd = connect_from("127.0.0.2", port); /* another client */
    ASSERT_TRUE(fd >= 0);
    struct timeval tv = {5, 0};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    const char req[] = "GET / HTTP/1.0\r\n\r\n";
    ASSERT_TRUE(write(fd, req, sizeof req - 1) == (ssize_t)(sizeof req - 1));
    char reply[64] = "";
    ssize_t got = read(fd, reply, sizeof reply - 1);
    reply[got > 0 ? got : 0] = '\0';
    close(fd);
    for (int i = 0; i < 40; i++)
        if (idle[i] >= 0)
            close(idle[i]);
    kill(pid, SIGTERM);
    test_wait_exit(pid, 30.0);
    ASSERT_CONTAINS(reply, "HTTP/1.1 200");
    size_t n;
    char *msg = test_slurp(err, &n);
    ASSERT_TRUE(strstr(msg, "warning") == NULL);
    free(msg);
    /* all interfaces: one warning line */
    snprintf(args, sizeof args, "render %s/s.json --spp 16000000 -o %s/o.png --serve 0.0.0.0:0", dir, dir);
    remove(err);
    pid = test_spawn(BRUME_EXE, args, err);
    ASSERT_TRUE(served_port(err) > 0);
    kill(pid, SIGTERM);
    test_wait_exit(pid, 30.0);
    msg = test_slurp(err, &n);
    ASSERT_CONTAINS(msg, "warning: --serve: the live view listens on 0.0.0.0, beyond this machine");
    free(msg);
}

/* Defect 3: a glTF's instances are counted before assimp builds them: 3 x 3 instances of one
 * triangle read as 9 triangles (through the sandboxed reader), and 50^4 instances under
 * max_memory_mb 64 are refused at once with the figure (they built 5.8 GB). */
TEST(gltf_instances_counted)
{
    const char *dir = fresh_dir("gltf");
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
    write_text(path, small);
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
    write_text(scene, path);
    double t0 = seconds();
    ASSERT_TRUE(load_commit(scene, msg, sizeof msg, NULL) != BRUME_OK);
    ASSERT_TRUE(seconds() - t0 < 2.0);
    ASSERT_CONTAINS(msg, "1.88e+07 vertices");
    ASSERT_CONTAINS(msg, "render.max_memory_mb");
    /* the same instances in a .glb: counted before assimp builds them (it ran out of its
     * address space before, seconds later) */
    snprintf(path, sizeof path,
             "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40}, \"surfaces\": [{\"type\":"
             " \"mesh\", \"file\": \"%s/tests/bad/meshes/gltf_nested.glb\"}], \"render\": {\"width\": 8,"
             " \"height\": 8, \"spp\": 1, \"max_memory_mb\": 64}}",
             BRUME_SOURCE_DIR);
    write_text(scene, path);
    t0 = seconds();
    ASSERT_TRUE(load_commit(scene, msg, sizeof msg, NULL) != BRUME_OK);
    ASSERT_TRUE(seconds() - t0 < 2.0);
    ASSERT_CONTAINS(msg, "gltf_nested.glb: its instances flattened make 1.88e+07 vertices");
}

/* Defect 5: when the film's allocation fails (within render.max_memory_mb: the machine has
 * less), the message is one line built from live memory (it read the freed job: render.c).
 * The allocation is made to fail by an address-space limit, or under ASan by its allocator
 * cap (the sanitizer suite runs this test too: a use after free there is a report). */
TEST(film_allocation_failure_is_one_line)
{
    const char *dir = fresh_dir("oom");
    char path[4400], text[1024];
    snprintf(path, sizeof path, "%s/oom.json", dir);
    write_text(path, "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
                     " \"render\": {\"width\": 8192, \"height\": 8192, \"spp\": 1, \"max_memory_mb\": 100000}}");
#if defined(__SANITIZE_ADDRESS__)
    /* the test's caps come last: ASan takes the last value of an option, and `make test` sets
     * max_allocation_size_mb=1536 in the environment */
    const char *limit = "ASAN_OPTIONS=$ASAN_OPTIONS:allocator_may_return_null=1:max_allocation_size_mb=100";
#else
    const char *limit = "ulimit -v 1500000 &&";
#endif
    char cmd[8400];
    snprintf(cmd, sizeof cmd, "cd '%s' && %s %s render oom.json -o o.png --quiet >/dev/null 2>err.txt", dir, limit,
             BRUME_EXE);
    ASSERT_EQ_INT(test_system(cmd), 1);
    read_back(dir, "err.txt", text, sizeof text);
    const char *line = strstr(text, "brume: ");
    ASSERT_TRUE(line != NULL);
    ASSERT_CONTAINS(line, "out of memory for a 8192 x 8192 render job");
    ASSERT_TRUE(strchr(line, '\n') == line + strlen(line) - 1);
}

typedef struct load_arg {
    const char *path;
    brume_status st;
    char msg[512];
    double took;
    brume_context *ctx; /* the load's context, made by the caller (who cancels it) */
    atomic_bool done;
} load_arg;

static void *load_thread(void *user)
{
    load_arg *a = user;
    brume_context *ctx = a->ctx;
    brume_scene *s = NULL;
    double t0 = seconds();
    a->st = brume_scene_load(ctx, &(brume_source){.path = a->path}, NULL, &s);
    a->took = seconds() - t0;
    snprintf(a->msg, sizeof a->msg, "%s", brume_context_last_error(ctx));
    brume_scene_release(s);
    atomic_store(&a->done, true);
    return NULL;
}

/* Defect 4: the library's cancel reaches scene loading: brume_context_cancel_loads(ctx) from
 * another thread (or a signal handler) ends a procedural_cloud at 512 (67 s) loaded with ctx,
 * and the fractal generators' midpoint and spectral syntheses, within a second; the same load
 * with another context goes on until that one is cancelled, and a load started afterwards is
 * not affected. */
TEST(scene_load_cancels)
{
    const char *dir = fresh_dir("loadcancel");
    char path[4400];
    snprintf(path, sizeof path, "%s/slow.json", dir);
    write_text(path, "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
                     " \"media\": [{\"density\": {\"type\": \"procedural_cloud\", \"resolution\": 512}, \"sigma_a\": 0.1,"
                     " \"sigma_s\": 1}], \"render\": {\"width\": 8, \"height\": 8, \"spp\": 1}}");
    load_arg a = {path, BRUME_OK, "", 0.0, brume_context_new(), false};
    load_arg other = {path, BRUME_OK, "", 0.0, brume_context_new(), false};
    pthread_t th, th_other;
    ASSERT_EQ_INT(pthread_create(&th, NULL, load_thread, &a), 0);
    ASSERT_EQ_INT(pthread_create(&th_other, NULL, load_thread, &other), 0);
    test_sleep(0.5);
    double t0 = seconds();
    brume_context_cancel_loads(a.ctx);
    pthread_join(th, NULL);
    double after = seconds() - t0;
    fprintf(stderr, "load ended %.2f s after the cancel (%.2f s in all): %s\n", after, a.took, a.msg);
    ASSERT_EQ_INT(a.st, BRUME_ERROR_CANCELLED);
    ASSERT_TRUE(after < 1.0);
    ASSERT_CONTAINS(a.msg, "loading cancelled");
    /* the load with the other context was not cancelled: it runs until its own cancel */
    test_sleep(0.3);
    ASSERT_TRUE(!atomic_load(&other.done));
    brume_context_cancel_loads(other.ctx);
    pthread_join(th_other, NULL);
    ASSERT_EQ_INT(other.st, BRUME_ERROR_CANCELLED);
    brume_context_release(a.ctx);
    brume_context_release(other.ctx);
    /* the fractal generators too: midpoint displacement on a 513^3 lattice, spectral
     * synthesis of 512^3 (about a minute each on 2 cores), cancelled inside their loops */
    static const char *const methods[] = {"midpoint", "spectral"};
    for (int m = 0; m < 2; m++) {
        snprintf(path, sizeof path, "%s/fractal-%s.json", dir, methods[m]);
        char text[600];
        snprintf(text, sizeof text,
                 "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
                 " \"media\": [{\"density\": {\"type\": \"fractal_cloud\", \"method\": \"%s\","
                 " \"dims\": [512, 512, 512]}, \"sigma_a\": 0.1, \"sigma_s\": 1}],"
                 " \"render\": {\"width\": 8, \"height\": 8, \"spp\": 1}}",
                 methods[m]);
        write_text(path, text);
        load_arg f = {path, BRUME_OK, "", 0.0, brume_context_new(), false};
        ASSERT_EQ_INT(pthread_create(&th, NULL, load_thread, &f), 0);
        test_sleep(0.5);
        t0 = seconds();
        brume_context_cancel_loads(f.ctx);
        pthread_join(th, NULL);
        after = seconds() - t0;
        fprintf(stderr, "%s: load ended %.2f s after the cancel (%.2f s in all): %s\n", methods[m], after, f.took,
                f.msg);
        ASSERT_EQ_INT(f.st, BRUME_ERROR_CANCELLED);
        /* a plane of the lattice between two checks: 0.1 s in a release build, 1.5 s seen
         * under ASan on a loaded machine; uncancelled, either load runs a minute or more */
        ASSERT_TRUE(after < 5.0);
        ASSERT_CONTAINS(f.msg, "loading cancelled");
        brume_context_release(f.ctx);
    }
    /* the next load is not cancelled */
    snprintf(path, sizeof path, "%s/small.json", dir);
    write_text(path, "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
                     " \"media\": [{\"density\": {\"type\": \"procedural_cloud\", \"resolution\": 16}, \"sigma_a\": 0.1,"
                     " \"sigma_s\": 1}], \"render\": {\"width\": 8, \"height\": 8, \"spp\": 1}}");
    load_arg b = {path, BRUME_OK, "", 0.0, brume_context_new(), false};
    brume_context_cancel_loads(b.ctx); /* before the load: not its business */
    load_thread(&b);
    ASSERT_EQ_INT(b.st, BRUME_OK);
    brume_context_release(b.ctx);
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
          signal_during_write_leaves_no_temp_file, checkpoint_never_destroys_foreign_files,
          checkpoint_removed_only_when_its_header_says_so, resume_of_other_files, checkpoint_key_covers_inputs,
          messages_print_every_length_modifier, exr_long_attribute_key_writes, environment_image_values_checked,
          film_counts_against_the_memory_limit, blasi_work_is_bounded, blasi_light_pass_cancels,
          signals_stop_every_phase, bad_scene_makes_no_folders, partial_frame_says_so,
          serve_idle_connections_and_exposure, gltf_instances_counted, film_allocation_failure_is_one_line,
          scene_load_cancels, temporaries_removed_per_context, generators_work_is_bounded,
          stam_random_field_cancels)
