/* test_hardening_cli.c - brume render and the files it did not write: --checkpoint,
 * --save-light and -o never replace a file of someone else's, a checkpoint is removed only
 * when its header says it is this render's, --resume refuses other files and a changed
 * input; a bad scene makes no folders, an interrupted sequence names its partial frame;
 * idle connections cannot take the live view; a failed film allocation is one line. */
#include "test.h"

#include <arpa/inet.h>
#include <dirent.h>
#include <netinet/in.h>
#include <signal.h>
#include <stdint.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <unistd.h>

#include "brume.h"
#include "core/error.h"
#include "io/atomic.h"
#include "job/checkpoint.h"
#include "scene/scene.h"

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
    test_write_bytes(path, v, sizeof v);
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
             " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, 0], \"irradiance\": 1}],"
             " \"media\": [{\"density\": {\"type\": \"grid\", \"file\": \"g.raw\", \"format\": \"raw\", \"dims\": [2, 2, 2]},"
             " \"sigma_a\": 0.1, \"sigma_s\": 1}],"
             " \"render\": {\"width\": %d, \"height\": %d, \"spp\": 1, \"threads\": 1}%s}",
             width, width, extra ? extra : "");
    snprintf(path, sizeof path, "%s/s.json", dir);
    test_write_file(path, json);
}

/* Defect 1: --checkpoint, --save-light and blasi.save_light never remove or replace a file
 * brume did not write (a note, the scene, an input, a pipe); each is refused with one line
 * before any work, and the file is left as it was. */
TEST(checkpoint_never_destroys_foreign_files)
{
    const char *dir = test_fresh_dir("foreign");
    char path[4400], text[256], cmd[4600];
    write_grid_scene(dir, 4, 1.0f, NULL);
    snprintf(path, sizeof path, "%s/notes.txt", dir);
    test_write_file(path, "keep\n");
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
    const char *dir = test_fresh_dir("own");
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
    test_write_file(other, "BRUMECKP but not one\n");
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
    const char *dir = test_fresh_dir("resume");
    char path[4400], text[512];
    write_grid_scene(dir, 256, 1.0f, NULL);
    static unsigned char junk[300000];
    memset(junk, 'x', sizeof junk);
    snprintf(path, sizeof path, "%s/junk.bin", dir);
    test_write_bytes(path, junk, sizeof junk);
    ASSERT_EQ_INT(brume_in(dir, "render s.json -o out.png --quiet --resume junk.bin"), 1);
    read_back(dir, "err.txt", text, sizeof text);
    ASSERT_CONTAINS(text, "junk.bin: not a brume checkpoint");
    double t0 = test_now();
    ASSERT_EQ_INT(brume_in(dir, "render s.json -o out.png --quiet --resume /dev/zero"), 1);
    ASSERT_TRUE(test_now() - t0 < 20.0);
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
    const char *dir = test_fresh_dir("key");
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

/* Defect 10: the output folders are made only after the scene was read and checked: a bad
 * scene with --frames 0-200 -o out%d/f.png left 201 empty folders. */
TEST(bad_scene_makes_no_folders)
{
    const char *dir = test_fresh_dir("folders");
    char path[4400];
    snprintf(path, sizeof path, "%s/bad.json", dir);
    test_write_file(path, "{\"camera\": 5}");
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
    const char *dir = test_fresh_dir("partial");
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
    const char *dir = test_fresh_dir("serve");
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

/* Defect 5: when the film's allocation fails (within render.max_memory_mb: the machine has
 * less), the message is one line built from live memory (it read the freed job: render.c).
 * The allocation is made to fail by an address-space limit, or under ASan by its allocator
 * cap (the sanitizer suite runs this test too: a use after free there is a report). */
TEST(film_allocation_failure_is_one_line)
{
    const char *dir = test_fresh_dir("oom");
    char path[4400], text[1024];
    snprintf(path, sizeof path, "%s/oom.json", dir);
    test_write_file(path, "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
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

TEST_MAIN(checkpoint_never_destroys_foreign_files, checkpoint_removed_only_when_its_header_says_so,
          resume_of_other_files, checkpoint_key_covers_inputs, bad_scene_makes_no_folders, partial_frame_says_so,
          serve_idle_connections_and_exposure, film_allocation_failure_is_one_line)
