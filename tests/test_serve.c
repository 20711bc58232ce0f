/* test_serve.c - `brume render --serve`: the live view's endpoints with a plain HTTP client,
 * the page in headless Chromium (its screenshot must show the image), and bad input (a port
 * in use, a bad host). Loopback addresses only; every wait is bounded. */
#include "test.h"

#include <arpa/inet.h>
#include <math.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "brume.h"

/* Pure red background, nothing else: the image is red everywhere, so a screenshot shows
 * whether it is on the page. */
static const char red_json[] = "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 30},"
                               " \"background\": [1, 0, 0], \"render\": {\"width\": 96, \"height\": 64}}";

/* The port from "live view at http://127.0.0.1:PORT/" in err_path, waiting up to 60 s. */
static int wait_port(const char *err_path, pid_t pid)
{
    double t0 = test_now();
    while (test_now() - t0 < 60.0) {
        size_t n;
        if (!test_exists(err_path)) { /* the child has not opened it yet */
            test_sleep(0.01);
            continue;
        }
        char *text = test_slurp(err_path, &n);
        const char *at = strstr(text, "live view at http://127.0.0.1:");
        int port = at ? atoi(at + strlen("live view at http://127.0.0.1:")) : 0;
        free(text);
        if (port > 0)
            return port;
        int status;
        if (waitpid(pid, &status, WNOHANG) == pid)
            TEST_FAIL("brume ended before serving");
        test_sleep(0.05);
    }
    TEST_FAIL("no live view announced on stderr");
}

typedef struct response {
    int status;
    char *head, *body; /* malloc'd; body NUL-terminated */
    size_t body_len;
} response;

/* A plain HTTP/1.0 request to 127.0.0.1:port, 10 s timeouts. */
static response http(int port, const char *method, const char *path)
{
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    ASSERT_TRUE(fd >= 0);
    struct timeval tv = {10, 0};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
    struct sockaddr_in sa = {0};
    sa.sin_family = AF_INET;
    sa.sin_port = htons((uint16_t)port);
    sa.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ_INT(connect(fd, (struct sockaddr *)&sa, sizeof sa), 0);
    char req[512];
    int n = snprintf(req, sizeof req, "%s %s HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n", method, path);
    ASSERT_EQ_INT(write(fd, req, (size_t)n), n);
    size_t cap = 1 << 16, len = 0;
    char *buf = malloc(cap);
    for (;;) {
        if (len + 1 >= cap)
            buf = realloc(buf, cap *= 2);
        ssize_t r = read(fd, buf + len, cap - len - 1);
        if (r <= 0)
            break;
        len += (size_t)r;
    }
    close(fd);
    buf[len] = '\0';
    response res = {0, NULL, NULL, 0};
    char *sep = strstr(buf, "\r\n\r\n");
    ASSERT_TRUE(sep != NULL && strncmp(buf, "HTTP/1.", 7) == 0);
    res.status = atoi(buf + 9);
    size_t hl = (size_t)(sep - buf);
    res.head = malloc(hl + 1);
    memcpy(res.head, buf, hl);
    res.head[hl] = '\0';
    res.body_len = len - hl - 4;
    res.body = malloc(res.body_len + 1);
    memcpy(res.body, sep + 4, res.body_len);
    res.body[res.body_len] = '\0';
    free(buf);
    return res;
}

static void response_free(response *r)
{
    free(r->head);
    free(r->body);
}

/* A number of /status.json's body by its key; NAN when absent. */
static double status_field(const char *body, const char *key)
{
    char pat[64];
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    const char *at = strstr(body, pat);
    return at ? strtod(at + strlen(pat), NULL) : NAN;
}

/* The three endpoints and nothing else; the server keeps serving the final image after the
 * render until SIGINT (exit 0: the image was written), or exits with --serve-exit. */
TEST(endpoints)
{
    char scene[512], err[512];
    snprintf(scene, sizeof scene, "%s", test_tmp_path("serve.json"));
    snprintf(err, sizeof err, "%s", test_tmp_path("serve-err.txt"));
    remove(err);
    char out[512], args[2048];
    snprintf(out, sizeof out, "%s", test_tmp_path("serve-out.png"));
    remove(out);
    test_write_file(scene, "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 30},"
                      " \"background\": [0.3, 0.45, 0.8],"
                      " \"lights\": [{\"type\": \"distant\", \"direction\": [-0.5, -0.7, -0.5], \"irradiance\": 3.0}],"
                      " \"media\": [{\"sigma_a\": 0.1, \"sigma_s\": 6,"
                      "   \"density\": {\"type\": \"procedural_cloud\", \"resolution\": 16, \"seed\": 5}}],"
                      " \"render\": {\"width\": 48, \"height\": 32, \"max_depth\": 16}}");
    snprintf(args, sizeof args, "render %s --noise 0.03 --serve 127.0.0.1:0 -o %s", scene, out);
    pid_t pid = test_spawn(BRUME_EXE, args, err);
    int port = wait_port(err, pid);
    response r = http(port, "GET", "/");
    ASSERT_EQ_INT(r.status, 200);
    ASSERT_CONTAINS(r.head, "text/html");
    ASSERT_CONTAINS(r.body, "<img id=\"img\" src=\"/image.png\"");
    ASSERT_CONTAINS(r.body, "exposure");
    ASSERT_CONTAINS(r.body, "/status.json");
    response_free(&r);
    /* status until finished: the progress line's figures, sane: elapsed never
     * falls, done never exceeds total, and the end says so */
    double t0 = test_now(), elapsed0 = -1.0, elapsed = -1.0;
    bool finished = false;
    while (!finished && test_now() - t0 < 120.0) {
        r = http(port, "GET", "/status.json");
        ASSERT_EQ_INT(r.status, 200);
        ASSERT_CONTAINS(r.head, "application/json");
        ASSERT_CONTAINS(r.body, "\"spp_mean\":");
        ASSERT_CONTAINS(r.body, "\"eta\":");
        ASSERT_CONTAINS(r.body, "\"noise\":");
        double e = status_field(r.body, "elapsed");
        ASSERT_TRUE(e >= elapsed);
        elapsed = e;
        elapsed0 = elapsed0 < 0.0 ? e : elapsed0;
        ASSERT_TRUE(status_field(r.body, "done") <= status_field(r.body, "total"));
        ASSERT_TRUE(status_field(r.body, "spp_min") <= status_field(r.body, "spp_mean") + 1e-3);
        ASSERT_TRUE(status_field(r.body, "spp_mean") <= status_field(r.body, "spp_max") + 1e-3);
        finished = strstr(r.body, "\"finished\": true") != NULL;
        if (finished) {
            fprintf(stderr, "status: %s", r.body);
            ASSERT_TRUE(status_field(r.body, "eta") == 0.0 && status_field(r.body, "fraction") == 1.0);
            ASSERT_TRUE(status_field(r.body, "done") == status_field(r.body, "total"));
            ASSERT_TRUE(elapsed > 0.0 && elapsed >= elapsed0);
        }
        response_free(&r);
        if (!finished)
            test_sleep(0.1);
    }
    ASSERT_TRUE(finished);
    /* the final image is written, and served as the same PNG */
    t0 = test_now();
    while (!test_exists(out) && test_now() - t0 < 30.0)
        test_sleep(0.05);
    r = http(port, "GET", "/image.png");
    ASSERT_EQ_INT(r.status, 200);
    ASSERT_CONTAINS(r.head, "image/png");
    size_t n;
    char *file = test_slurp(out, &n);
    ASSERT_TRUE(r.body_len == n && memcmp(r.body, file, n) == 0);
    free(file);
    response_free(&r);
    r = http(port, "GET", "/image.png?exposure=2");
    ASSERT_EQ_INT(r.status, 200);
    ASSERT_TRUE(r.body_len > 8 && memcmp(r.body, "\x89PNG", 4) == 0);
    response_free(&r);
    const char *refused[4] = {"/image.png?exposure=abc", "/etc/passwd", "/../README.md", "/index.html"};
    const int codes[4] = {400, 404, 404, 404};
    for (int k = 0; k < 4; k++) {
        r = http(port, "GET", refused[k]);
        ASSERT_EQ_INT(r.status, codes[k]);
        response_free(&r);
    }
    r = http(port, "POST", "/");
    ASSERT_EQ_INT(r.status, 405);
    response_free(&r);
    /* still serving; Ctrl-C ends it, with success: the render was complete */
    ASSERT_TRUE(waitpid(pid, NULL, WNOHANG) == 0);
    kill(pid, SIGINT);
    ASSERT_EQ_INT(test_wait_exit(pid, 10.0), 0);
    /* --serve-exit: ends by itself once the image is written */
    snprintf(args, sizeof args, "render %s --spp 4 --serve 127.0.0.1:0 --serve-exit -o %s", scene, out);
    ASSERT_EQ_INT(test_wait_exit(test_spawn(BRUME_EXE, args, err), 60.0), 0);
    remove(out);
    remove(scene);
    remove(err);
}

/* One line on stderr containing needle, exit 1, and no output file. */
static void refused(const char *serve, const char *needle)
{
    const char *err = test_tmp_path("serve-err.txt");
    char out[512], args[2048];
    snprintf(out, sizeof out, "%s", test_tmp_path("never.png"));
    remove(out);
    snprintf(args, sizeof args, "render --spp 16777216 --serve %s -o %s", serve, out);
    ASSERT_EQ_INT(test_wait_exit(test_spawn(BRUME_EXE, args, err), 30.0), 1);
    size_t n;
    char *msg = test_slurp(err, &n);
    fprintf(stderr, "--serve %s: %s", serve, msg);
    ASSERT_CONTAINS(msg, needle);
    ASSERT_TRUE(n > 0 && strchr(msg, '\n') == msg + n - 1);
    free(msg);
    ASSERT_TRUE(!test_exists(out));
}

/* A port in use, a host that does not resolve, a port out of range: exit 1 before any work. */
TEST(bad_port_and_host)
{
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    struct sockaddr_in sa = {0};
    sa.sin_family = AF_INET;
    sa.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ_INT(bind(fd, (struct sockaddr *)&sa, sizeof sa), 0);
    ASSERT_EQ_INT(listen(fd, 1), 0);
    socklen_t len = sizeof sa;
    getsockname(fd, (struct sockaddr *)&sa, &len);
    char spec[64];
    snprintf(spec, sizeof spec, "127.0.0.1:%d", ntohs(sa.sin_port));
    refused(spec, "in use");
    close(fd);
    /* a machine whose DNS servers do not answer would wait 5 s per server and attempt: one
     * second, once, is enough to learn that the name does not resolve */
    setenv("RES_OPTIONS", "timeout:1 attempts:1", 1);
    refused("no-such-host.invalid:8080", "no-such-host.invalid");
    unsetenv("RES_OPTIONS");
    refused("127.0.0.1:70000", "port");
}

/* The page in a real browser: headless Chromium loads it and takes a screenshot, which
 * must show the (pure red) image. Skipped (77) only when chromium is not installed. */
typedef struct shot_figures {
    int red, x0, y0, x1, y1; /* pure red pixels and their bounding box */
    int w, h;
} shot_figures;

/* A headless Chromium screenshot of the page at `fragment` (window 640 x 480). */
static shot_figures screenshot(const char *chromium, int port, const char *fragment)
{
    char shot[512], profile[512], args[4096];
    snprintf(shot, sizeof shot, "%s", test_tmp_path("screenshot.png"));
    snprintf(profile, sizeof profile, "%s", test_tmp_path("chromium-profile"));
    remove(shot);
    snprintf(args, sizeof args,
             "--headless --no-sandbox --disable-gpu --disable-dev-shm-usage --no-first-run --user-data-dir=%s "
             "--window-size=640,480 --virtual-time-budget=5000 --screenshot=%s http://127.0.0.1:%d/%s",
             profile, shot, port, fragment);
    const char *cerr = test_tmp_path("chromium-err.txt");
    int rc = test_wait_exit(test_spawn(chromium, args, cerr), 180.0);
    if (rc != 0) {
        size_t n;
        char *msg = test_slurp(cerr, &n);
        TEST_FAIL("chromium exit %d: %s", rc, msg);
    }
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    if (brume_image_read(ctx, shot, &img) != BRUME_OK)
        TEST_FAIL("screenshot: %s", brume_context_last_error(ctx));
    shot_figures f = {0, 1 << 30, 1 << 30, -1, -1, brume_image_width(img), brume_image_height(img)};
    const float *px = brume_image_pixels(img);
    for (int y = 0; y < f.h; y++)
        for (int x = 0; x < f.w; x++) {
            const float *p = px + 4 * (y * f.w + x);
            if (!(p[0] > 0.9f && p[1] < 0.05f && p[2] < 0.05f))
                continue;
            f.red++;
            f.x0 = x < f.x0 ? x : f.x0;
            f.y0 = y < f.y0 ? y : f.y0;
            f.x1 = x > f.x1 ? x : f.x1;
            f.y1 = y > f.y1 ? y : f.y1;
        }
    fprintf(stderr, "screenshot #%s: %d x %d, %d pure red pixels in [%d, %d] x [%d, %d]\n", fragment, f.w, f.h, f.red,
            f.x0, f.x1, f.y0, f.y1);
    brume_image_release(img);
    brume_context_release(ctx);
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", profile);
    test_system(cmd);
    remove(shot);
    return f;
}

/* The page in a browser: a red 96 x 64 image (the page itself has no red) is fitted to the
 * window, a solid red rectangle of the image's 3 : 2 shape far larger than the image; at
 * #zoom=1 (the 1:1 button's state) it is the image's own 96 x 64 pixels; at #view=noise (the
 * view menu's state) the noise heat map of a noiseless image shows no red. The stop button's
 * request ends the process as Ctrl-C does. */
TEST(browser_shows_the_image)
{
    const char *chromium = NULL;
    const char *candidates[3] = {"/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome"};
    for (int k = 0; k < 3 && !chromium; k++)
        if (access(candidates[k], X_OK) == 0)
            chromium = candidates[k];
    if (!chromium) {
        fprintf(stderr, "chromium is not installed: skipped\n");
        exit(77);
    }
    char scene[512], err[512], out[512], args[4096];
    snprintf(scene, sizeof scene, "%s", test_tmp_path("red.json"));
    snprintf(err, sizeof err, "%s", test_tmp_path("red-err.txt"));
    snprintf(out, sizeof out, "%s", test_tmp_path("red.exr"));
    remove(err);
    test_write_file(scene, red_json);
    snprintf(args, sizeof args, "render %s --spp 2 --aov variance --serve 127.0.0.1:0 -o %s", scene, out);
    pid_t pid = test_spawn(BRUME_EXE, args, err);
    int port = wait_port(err, pid);
    /* the render finished first, so that the page shows the whole image however slowly
     * this machine runs (Chromium's virtual time budget is not wall-clock time) */
    double t0 = test_now();
    bool finished = false;
    while (!finished && test_now() - t0 < 120.0) {
        response r = http(port, "GET", "/status.json");
        finished = r.status == 200 && strstr(r.body, "\"finished\": true") != NULL;
        response_free(&r);
        if (!finished)
            test_sleep(0.1);
    }
    ASSERT_TRUE(finished);
    shot_figures fit = screenshot(chromium, port, "");
    int bw = fit.x1 - fit.x0 + 1, bh = fit.y1 - fit.y0 + 1;
    ASSERT_TRUE(fit.red >= 20 * 96 * 64);                  /* scaled up to the window */
    ASSERT_TRUE(fit.red >= bw * bh * 98 / 100);            /* one solid rectangle */
    ASSERT_TRUE(fabs((double)bw / bh - 1.5) < 0.03);       /* the image's shape */
    ASSERT_TRUE(bw >= fit.w * 9 / 10 || bh >= fit.h / 2);  /* as wide as the window, or limited by its height */
    shot_figures one = screenshot(chromium, port, "#zoom=1");
    ASSERT_TRUE(one.red >= 96 * 64 * 9 / 10 && one.red <= 96 * 64 * 11 / 10);
    ASSERT_EQ_INT(one.x1 - one.x0 + 1, 96);
    ASSERT_EQ_INT(one.y1 - one.y0 + 1, 64);
    shot_figures noise = screenshot(chromium, port, "#view=noise");
    ASSERT_EQ_INT(noise.red, 0);
    response r = http(port, "POST", "/stop");
    ASSERT_EQ_INT(r.status, 202);
    response_free(&r);
    ASSERT_EQ_INT(test_wait_exit(pid, 10.0), 0); /* after the render: the serving ends as by Ctrl-C */
    remove(out);
    remove(scene);
}

TEST_MAIN(endpoints, bad_port_and_host, browser_shows_the_image)
