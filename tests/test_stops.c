/* test_stops.c - stops that keep their word: the live view's stop asked any number of times,
 * a client that never reads or a denoised view under way holding neither the stop nor the
 * exit, Ctrl-C during `render --denoise` and `brume denoise`, the first SIGTERM of a resume
 * from a forged checkpoint, Ctrl-C under mpirun, and the denoiser's buffers counted against
 * render.max_memory_mb. Every wait is bounded; the bounds leave room for a
 * loaded 2-core machine and still catch a stop that waits for the work it should cancel. */
#include "test.h"

#include <arpa/inet.h>
#include <dirent.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <stdint.h>
#include <sys/wait.h>
#include <unistd.h>

#include "brume.h"

/* A small cloud that takes minutes at 1e6 spp: a render under way when it is stopped. */
static const char cloud_json[] =
    "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 35},\n"
    " \"background\": [0.3, 0.45, 0.8],\n"
    " \"lights\": [{\"type\": \"distant\", \"direction\": [-0.5, -0.7, -0.5], \"irradiance\": 3.0}],\n"
    " \"media\": [{\"sigma_a\": 0.1, \"sigma_s\": 6,\n"
    "   \"density\": {\"type\": \"procedural_cloud\", \"resolution\": 16, \"seed\": 5}}],\n"
    " \"render\": {\"width\": 48, \"height\": 32, \"max_depth\": 16}}\n";

/* Sky only: samples cost nothing, so a large image renders in a second or two and what is
 * timed is the denoiser (its cost does not depend on the pixels' values). */
static const char sky_json[] = "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 30},"
                               " \"background\": [0.3, 0.45, 0.8]}";

/* The size whose denoising takes seconds on one thread (0.9 M pixels, 5 levels of 25 taps:
 * 4 CPU s on the project's machine, 10 s at its usual load): over the bounds below, so a
 * stop that waits for the denoiser fails them. */
#define BIG "--width 1280 --height 720"
#define BIG_W 1280
#define BIG_H 720

static const char *scene_file(const char *dir, const char *name, const char *json)
{
    static char path[2][400];
    static int k;
    k ^= 1;
    snprintf(path[k], sizeof path[k], "%s/%s", dir, name);
    test_write_file(path[k], json);
    return path[k];
}


/* The image at path is whole: it reads back at w x h. */
static void assert_image(const char *path, int w, int h)
{
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    if (brume_image_read(ctx, path, &img) != BRUME_OK)
        TEST_FAIL("%s: %s", path, brume_context_last_error(ctx));
    ASSERT_EQ_INT(brume_image_width(img), w);
    ASSERT_EQ_INT(brume_image_height(img), h);
    brume_image_release(img);
    brume_context_release(ctx);
}

static int count(const char *text, const char *needle)
{
    int n = 0;
    for (const char *at = strstr(text, needle); at; at = strstr(at + 1, needle))
        n++;
    return n;
}

/* Waits (up to 120 s) until the file at err_path contains needle; false if pid ended first. */
static bool wait_for(const char *err_path, const char *needle, pid_t pid)
{
    double t0 = test_now();
    while (test_now() - t0 < 120.0) {
        if (test_exists(err_path)) {
            size_t n;
            char *text = test_slurp(err_path, &n);
            bool found = strstr(text, needle) != NULL;
            free(text);
            if (found)
                return true;
        }
        int status;
        if (waitpid(pid, &status, WNOHANG) == pid)
            return false;
        test_sleep(0.02);
    }
    return false;
}

/* ---- HTTP to the live view ------------------------------------------------------------------- */

static int port_of(const char *err_path, pid_t pid)
{
    if (!wait_for(err_path, "live view at http://127.0.0.1:", pid))
        TEST_FAIL("no live view announced on stderr");
    size_t n;
    char *text = test_slurp(err_path, &n);
    int port = atoi(strstr(text, "live view at http://127.0.0.1:") + strlen("live view at http://127.0.0.1:"));
    free(text);
    return port;
}

/* A connected socket to the live view, 10 s timeouts; rcvbuf > 0 shrinks its receive buffer. */
static int connect_to(int port, int rcvbuf)
{
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    ASSERT_TRUE(fd >= 0);
    struct timeval tv = {10, 0};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
    if (rcvbuf > 0)
        setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof rcvbuf);
    struct sockaddr_in sa = {0};
    sa.sin_family = AF_INET;
    sa.sin_port = htons((uint16_t)port);
    sa.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ_INT(connect(fd, (struct sockaddr *)&sa, sizeof sa), 0);
    return fd;
}

static void send_text(int fd, const char *text)
{
    ASSERT_EQ_INT(write(fd, text, strlen(text)), (long long)strlen(text));
}

/* The status code of the answer on fd (read to its end), -1 when none came. */
static int answer_status(int fd)
{
    char buf[4096];
    size_t len = 0;
    ssize_t r;
    while (len + 1 < sizeof buf && (r = read(fd, buf + len, sizeof buf - len - 1)) > 0)
        len += (size_t)r;
    buf[len] = '\0';
    close(fd);
    return len > 12 && strncmp(buf, "HTTP/1.", 7) == 0 ? atoi(buf + 9) : -1;
}

/* Runs exe with args (stderr to err), sends sig after wait seconds, and waits up to 60 s for
 * the exit: its status, and in *took the seconds from the signal to the exit. */
static int signal_after(const char *exe, const char *args, const char *err, double wait, int sig, double *took)
{
    pid_t pid = test_spawn(exe, args, err);
    test_sleep(wait);
    double t0 = test_now();
    kill(pid, sig);
    int rc = test_wait_exit(pid, 60.0);
    *took = test_now() - t0;
    return rc;
}

static const char stop_request[] = "POST /stop HTTP/1.0\r\nHost: 127.0.0.1\r\nContent-Length: 0\r\n\r\n";

/* /status.json's spp_min, -1 when not answered. */
static int spp_min(int port)
{
    int fd = connect_to(port, 0);
    send_text(fd, "GET /status.json HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n");
    char buf[4096];
    size_t len = 0;
    ssize_t r;
    while (len + 1 < sizeof buf && (r = read(fd, buf + len, sizeof buf - len - 1)) > 0)
        len += (size_t)r;
    buf[len] = '\0';
    close(fd);
    const char *at = strstr(buf, "\"spp_min\": ");
    return at ? atoi(at + strlen("\"spp_min\": ")) : -1;
}

/* Five POST /stop in a row, sent before any answer is read: the render stops once, the
 * partial image is written once and whole, exit 130 as for one Ctrl-C (a second signal
 * would end at once with nothing written), and every stop that reached it is answered 202. */
TEST(serve_stops_once)
{
    const char *dir = test_fresh_dir("stops-once");
    const char *scene = scene_file(dir, "cloud.json", cloud_json);
    char out[400], err[400], args[1200];
    snprintf(out, sizeof out, "%s/out.png", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(args, sizeof args, "render %s --spp 1000000 --threads 2 --serve 127.0.0.1:0 -o %s", scene, out);
    pid_t pid = test_spawn(BRUME_EXE, args, err);
    int port = port_of(err, pid);
    double t0 = test_now();
    while (spp_min(port) < 1 && test_now() - t0 < 120.0)
        test_sleep(0.1);
    int fds[5];
    for (int k = 0; k < 5; k++) {
        fds[k] = connect_to(port, 0);
        send_text(fds[k], stop_request);
    }
    t0 = test_now();
    int answered = 0;
    for (int k = 0; k < 5; k++) {
        int status = answer_status(fds[k]);
        ASSERT_TRUE(status == 202 || status == -1); /* -1: the server had closed already */
        answered += status == 202;
    }
    int rc = test_wait_exit(pid, 60.0);
    fprintf(stderr, "5 stops: %d answered 202, exit %d after %.2f s\n", answered, rc, test_now() - t0);
    ASSERT_TRUE(answered >= 1);
    ASSERT_EQ_INT(rc, 130);
    size_t n;
    char *msg = test_slurp(err, &n);
    fprintf(stderr, "stderr: %s", msg);
    ASSERT_EQ_INT(count(msg, "wrote the partial image"), 1);
    ASSERT_TRUE(strstr(msg, "not kept") == NULL);
    free(msg);
    assert_image(out, 48, 32);
    ASSERT_EQ_INT(test_temporaries(dir), 0);
}

/* While a client holds a denoised view being computed (seconds on one thread at this size)
 * and two others never finish their request or never read, a POST /stop is answered at once
 * and brume exits within a few seconds with the partial image written (--denoise: as it is,
 * NAME-raw.png, a partial image is not denoised): neither the denoiser nor the idle clients
 * hold the stop or the exit. */
TEST(serve_stop_not_held_by_clients)
{
    const char *dir = test_fresh_dir("stops-held");
    const char *scene = scene_file(dir, "sky.json", sky_json);
    char out[400], raw[400], err[400], args[1200];
    snprintf(out, sizeof out, "%s/out.png", dir);
    snprintf(raw, sizeof raw, "%s/out-raw.png", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(args, sizeof args, "render %s " BIG " --spp 1000000 --denoise --threads 1 --serve 127.0.0.1:0 -o %s",
             scene, out);
    pid_t pid = test_spawn(BRUME_EXE, args, err);
    int port = port_of(err, pid);
    double t0 = test_now();
    while (spp_min(port) < 2 && test_now() - t0 < 120.0)
        test_sleep(0.1);
    int denoised = connect_to(port, 4096), loris = connect_to(port, 4096), reader = connect_to(port, 4096);
    send_text(denoised, "GET /image.png?view=denoised HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
    send_text(loris, "GET /status.json HTTP/1.1\r\nHost: 127.0.0.1\r\n"); /* never ends its head */
    /* up to 1000 pages asked at once (6 MB), never read: its answers fill the buffers, then its
     * own requests fill the socket's (the flood stops there: a blocking write would wait) */
    static const char page[] = "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
    int asked = 0;
    while (asked < 1000 && send(reader, page, strlen(page), MSG_DONTWAIT | MSG_NOSIGNAL) == (ssize_t)strlen(page))
        asked++;
    ASSERT_TRUE(asked > 0);
    test_sleep(1.0); /* the denoiser is under way */
    t0 = test_now();
    int stop = connect_to(port, 0);
    send_text(stop, stop_request);
    int status = answer_status(stop);
    double answered = test_now() - t0;
    int rc = test_wait_exit(pid, 60.0);
    double took = test_now() - t0;
    fprintf(stderr, "stop answered %d after %.2f s; exit %d after %.2f s\n", status, answered, rc, took);
    ASSERT_EQ_INT(status, 202);
    ASSERT_TRUE(answered < 1.0);
    ASSERT_EQ_INT(rc, 130);
    ASSERT_TRUE(took < 5.0);
    assert_image(raw, BIG_W, BIG_H); /* partial: written as it is, not denoised */
    ASSERT_TRUE(!test_exists(out));
    ASSERT_EQ_INT(test_temporaries(dir), 0);
    close(denoised);
    close(loris);
    close(reader);
}

/* Ctrl-C once `render --denoise` denoises: it stops within a row of pixels, the image before
 * denoising is kept (NAME-raw.png, written before the denoiser began) and the denoised name
 * is never written; exit 130. */
TEST(ctrl_c_during_render_denoise)
{
    const char *dir = test_fresh_dir("stops-render-denoise");
    const char *scene = scene_file(dir, "sky.json", sky_json);
    char out[400], raw[400], err[400], args[1200];
    snprintf(out, sizeof out, "%s/out.png", dir);
    snprintf(raw, sizeof raw, "%s/out-raw.png", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(args, sizeof args, "render %s " BIG " --spp 2 --threads 1 --denoise -o %s", scene, out);
    pid_t pid = test_spawn(BRUME_EXE, args, err);
    ASSERT_TRUE(wait_for(err, "the image before denoising", pid));
    test_sleep(0.3); /* into the denoiser */
    double t0 = test_now();
    kill(pid, SIGINT);
    int rc = test_wait_exit(pid, 60.0);
    double took = test_now() - t0;
    size_t n;
    char *msg = test_slurp(err, &n);
    fprintf(stderr, "exit %d after %.2f s; stderr: %s", rc, took, msg);
    ASSERT_EQ_INT(rc, 130);
    ASSERT_TRUE(took < 3.0);
    ASSERT_CONTAINS(msg, "while denoising");
    free(msg);
    assert_image(raw, BIG_W, BIG_H);
    ASSERT_TRUE(!test_exists(out));
    ASSERT_EQ_INT(test_temporaries(dir), 0);
}

/* Ctrl-C during `brume denoise`: it stops within a row of pixels, writes nothing, says so in
 * one line and exits 130. */
TEST(ctrl_c_during_denoise_command)
{
    const char *dir = test_fresh_dir("stops-denoise");
    const char *scene = scene_file(dir, "sky.json", sky_json);
    char in[400], out[400], err[400], args[1200];
    snprintf(in, sizeof in, "%s/in.exr", dir);
    snprintf(out, sizeof out, "%s/out.exr", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(args, sizeof args, "render %s " BIG " --spp 2 --aov variance -q -o %s", scene, in);
    ASSERT_EQ_INT(test_wait_exit(test_spawn(BRUME_EXE, args, err), 300.0), 0);
    snprintf(args, sizeof args, "denoise %s --threads 1 -o %s", in, out);
    double took;
    int rc = signal_after(BRUME_EXE, args, err, 2.5, SIGINT, &took); /* 2.5 s: past reading the EXR */
    size_t n;
    char *msg = test_slurp(err, &n);
    fprintf(stderr, "exit %d after %.2f s; stderr: %s", rc, took, msg);
    ASSERT_EQ_INT(rc, 130);
    ASSERT_TRUE(took < 3.0);
    ASSERT_CONTAINS(msg, "while denoising");
    ASSERT_TRUE(n > 0 && strchr(msg, '\n') == msg + n - 1);
    free(msg);
    ASSERT_TRUE(!test_exists(out));
    ASSERT_EQ_INT(test_temporaries(dir), 0);
}

/* brume_denoise_memory by hand: a 100 x 50 image with the four layers --denoise asks for
 * (10 channels) takes (4 + 10 + 3) floats of output, 12 doubles of buffers and 5 floats of
 * noise and variance ratio a pixel. */
TEST(denoise_memory_figure)
{
    ASSERT_EQ_INT(brume_denoise_memory(100, 50, 10), 5000 * (22 * 4 + 12 * 8));
    ASSERT_EQ_INT(brume_denoise_memory(0, 50, 10), 0);
}

/* render.max_memory_mb of 22 MiB holds a 400 x 300 film (177 bytes a pixel with the
 * denoiser's layers: 20.3 MiB) but not the denoiser's 184 bytes a pixel with the 56 of the
 * image it reads (27.5 MiB): refused in one line naming the limit, before rendering, nothing
 * written; with 32 MiB the same render is denoised. */
TEST(denoise_counts_against_max_memory)
{
    const char *dir = test_fresh_dir("stops-memory");
    const char *scene = scene_file(dir, "sky.json", sky_json);
    char out[400], raw[400], err[400], args[1200];
    snprintf(out, sizeof out, "%s/out.png", dir);
    snprintf(raw, sizeof raw, "%s/out-raw.png", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(args, sizeof args, "render %s --width 400 --height 300 --spp 1 --denoise -q --set render.max_memory_mb=22 -o %s",
             scene, out);
    ASSERT_EQ_INT(test_wait_exit(test_spawn(BRUME_EXE, args, err), 120.0), 1);
    size_t n;
    char *msg = test_slurp(err, &n);
    fprintf(stderr, "stderr: %s", msg);
    ASSERT_CONTAINS(msg, "render.max_memory_mb");
    ASSERT_CONTAINS(msg, "27.5 MiB");
    ASSERT_TRUE(n > 0 && strchr(msg, '\n') == msg + n - 1);
    free(msg);
    ASSERT_TRUE(!test_exists(out) && !test_exists(raw));
    snprintf(args, sizeof args, "render %s --width 400 --height 300 --spp 1 --denoise -q --set render.max_memory_mb=32 -o %s",
             scene, out);
    ASSERT_EQ_INT(test_wait_exit(test_spawn(BRUME_EXE, args, err), 120.0), 0);
    assert_image(out, 400, 300);
}

/* A checkpoint forged to resume into a pass of 2^30 samples a pixel (its header's target; the
 * checksum made again), on a sky whose samples make no collision: the first SIGTERM stops
 * the resumed render within a second or so (every tile asks between its batches of samples,
 * not only at its end), the partial image and the checkpoint written; exit 143. */
TEST(resume_of_forged_checkpoint_honours_sigterm)
{
    const char *dir = test_fresh_dir("stops-resume");
    const char *scene = scene_file(dir, "sky.json", sky_json);
    char out[400], ckpt[400], err[400], args[2400];
    snprintf(out, sizeof out, "%s/out.exr", dir);
    snprintf(ckpt, sizeof ckpt, "%s/c.ckpt", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(args, sizeof args, "render %s --width 32 --height 16 --spp 1000000 --threads 2 --checkpoint %s -o %s",
             scene, ckpt, out);
    double took;
    ASSERT_EQ_INT(signal_after(BRUME_EXE, args, err, 2.5, SIGINT, &took), 130);
    ASSERT_TRUE(test_exists(ckpt));
    /* the header ends with spp_done, target (int32), elapsed (double), pixels (uint64); then
     * per pixel 4 + 1 + 32 + 32 bytes (no AOV), then the FNV-1a 64 of every byte before */
    size_t n;
    unsigned char *data = (unsigned char *)test_slurp(ckpt, &n);
    size_t hdr = n - 8 - (size_t)32 * 16 * 69;
    uint64_t pixels;
    memcpy(&pixels, data + hdr - 8, 8);
    ASSERT_EQ_INT(pixels, 32 * 16);
    int32_t target = 1 << 30;
    memcpy(data + hdr - 20, &target, 4);
    uint64_t h = 0xcbf29ce484222325ULL;
    for (size_t i = 0; i < n - 8; i++)
        h = (h ^ data[i]) * 0x100000001b3ULL;
    memcpy(data + n - 8, &h, 8);
    test_write_bytes(ckpt, data, n);
    free(data);
    snprintf(args, sizeof args, "render %s --width 32 --height 16 --spp 1000000 --threads 2 --checkpoint %s --resume %s -o %s",
             scene, ckpt, ckpt, out);
    int rc = signal_after(BRUME_EXE, args, err, 2.0, SIGTERM, &took);
    char *msg = test_slurp(err, &n);
    fprintf(stderr, "exit %d after %.2f s; stderr: %s", rc, took, msg);
    ASSERT_EQ_INT(rc, 143);
    ASSERT_TRUE(took < 5.0);
    ASSERT_CONTAINS(msg, "wrote the partial image");
    free(msg);
    assert_image(out, 32, 16);
    ASSERT_EQ_INT(test_temporaries(dir), 0);
}

/* Under mpirun (two ranks splitting the tiles), Ctrl-C to mpirun, which passes SIGTERM to the
 * ranks: each stops its tiles, and rank 0 writes the sum of what they rendered as a partial
 * image. A signal that came before the ranks rendered (a loaded machine starts them slowly)
 * is tried again with twice the wait. (Registered only in builds with MPI.) */
TEST(mpi_ctrl_c_keeps_the_tiles)
{
    const char *dir = test_fresh_dir("stops-mpi");
    const char *scene = scene_file(dir, "cloud.json", cloud_json);
    char out[400], err[400], args[2400];
    snprintf(out, sizeof out, "%s/out.png", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    const char *mpirun = BRUME_MPIEXEC[0] ? BRUME_MPIEXEC : "/usr/bin/mpirun";
    snprintf(args, sizeof args, "--allow-run-as-root --oversubscribe -np 2 %s render %s --spp 1000000 --threads 1 -o %s",
             BRUME_EXE, scene, out);
    char *msg = NULL;
    double wait = 3.0;
    for (int attempt = 0; attempt < 3; attempt++, wait *= 2.0) {
        remove(out);
        double took;
        int rc = signal_after(mpirun, args, err, wait, SIGINT, &took);
        size_t n;
        free(msg);
        msg = test_slurp(err, &n);
        fprintf(stderr, "SIGINT after %.0f s: mpirun exit %d after %.2f s; stderr: %s", wait, rc, took, msg);
        ASSERT_TRUE(rc != 0);
        if (!strstr(msg, "not kept"))
            break;
    }
    ASSERT_CONTAINS(msg, "wrote the partial image");
    free(msg);
    assert_image(out, 48, 32);
    ASSERT_EQ_INT(test_temporaries(dir), 0);
}

/* A render with --denoise to an EXR that a signal stops: the partial image is written as it
 * is, not denoised (no "raw" layer), marked brume.partial and brume.denoise; exit 130. */
TEST(partial_exr_is_not_denoised)
{
    const char *dir = test_fresh_dir("stops-partial-exr");
    const char *scene = scene_file(dir, "cloud.json", cloud_json);
    char out[400], err[400], args[1200];
    snprintf(out, sizeof out, "%s/out.exr", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(args, sizeof args, "render %s --spp 1000000 --threads 2 --denoise -o %s", scene, out);
    int rc = -1;
    for (double wait = 1.5; wait < 13.0; wait *= 2.0) { /* a signal before the first pass: again, later */
        double took;
        rc = signal_after(BRUME_EXE, args, err, wait, SIGINT, &took);
        if (test_exists(out))
            break;
    }
    size_t n;
    char *msg = test_slurp(err, &n);
    fprintf(stderr, "exit %d; stderr: %s", rc, msg);
    ASSERT_EQ_INT(rc, 130);
    ASSERT_CONTAINS(msg, "not denoised");
    free(msg);
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    ASSERT_EQ_INT(brume_image_read(ctx, out, &img), BRUME_OK);
    ASSERT_EQ_STR(brume_image_attribute(img, "brume.partial"), "yes");
    ASSERT_EQ_STR(brume_image_attribute(img, "brume.denoise"), "no: interrupted");
    ASSERT_TRUE(brume_image_attribute(img, "brume.denoised") == NULL);
    for (int i = 0; i < brume_image_layer_count(img); i++)
        ASSERT_TRUE(strcmp(brume_image_layer_name(img, i), "raw") != 0);
    brume_image_release(img);
    brume_context_release(ctx);
    ASSERT_EQ_INT(test_temporaries(dir), 0);
}

TEST_MAIN(serve_stops_once, serve_stop_not_held_by_clients, ctrl_c_during_render_denoise, ctrl_c_during_denoise_command,
          partial_exr_is_not_denoised, denoise_memory_figure, denoise_counts_against_max_memory,
          resume_of_forged_checkpoint_honours_sigterm, mpi_ctrl_c_keeps_the_tiles)
