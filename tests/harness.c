/* harness.c - runs the cases of one test executable (see test.h). */
#include "test.h"

#include <dirent.h>

#include "brume.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

int test_run(const test_case *cases, int ncases, int argc, char **argv)
{
    if (argc > 1) {
        for (int i = 0; i < ncases; i++)
            if (strcmp(cases[i].name, argv[1]) == 0) {
                cases[i].fn();
                printf("ok %s\n", cases[i].name);
                return 0;
            }
        fprintf(stderr, "no test case named %s\n", argv[1]);
        return 2;
    }
    for (int i = 0; i < ncases; i++) {
        cases[i].fn();
        printf("ok %s\n", cases[i].name);
    }
    return 0;
}

const char *test_tmp_path(const char *name)
{
    static char buf[8][512];
    static int slot;
    const char *dir = getenv("TMPDIR");
    char *p = buf[slot++ % 8];
    snprintf(p, 512, "%s/brume-test-%ld-%s", dir && *dir ? dir : "/tmp", (long)getpid(), name);
    return p;
}

int test_system(const char *cmd)
{
    int rc = system(cmd);
    if (rc == -1)
        return -1;
    return (rc >> 8) & 0xff;
}

char *test_slurp(const char *path, size_t *n)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        TEST_FAIL("cannot open %s", path);
    fseek(fp, 0, SEEK_END);
    long len = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    if (len < 0)
        TEST_FAIL("cannot size %s", path);
    char *buf = malloc((size_t)len + 1);
    if (!buf)
        TEST_FAIL("out of memory reading %s", path);
    *n = fread(buf, 1, (size_t)len, fp);
    fclose(fp);
    if (*n != (size_t)len)
        TEST_FAIL("short read of %s", path);
    buf[*n] = '\0';
    return buf;
}

int test_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

int test_temporaries(const char *dir)
{
    DIR *d = opendir(dir);
    ASSERT_TRUE(d != NULL);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strstr(e->d_name, ".tmp-") || strstr(e->d_name, ".brume-probe-")) {
            fprintf(stderr, "temporary file left: %s/%s\n", dir, e->d_name);
            n++;
        }
    closedir(d);
    return n;
}

void test_channel_mean(const float *rgba, int n, int c, double *mean, double *se)
{
    double s = 0.0, s2 = 0.0;
    for (int i = 0; i < n; i++) {
        double v = (double)rgba[4 * i + c];
        s += v;
        s2 += v * v;
    }
    *mean = s / n;
    *se = sqrt(fmax(s2 / n - *mean * *mean, 1e-12) / n);
}

void test_write_file(const char *path, const char *text)
{
    FILE *fp = fopen(path, "w");
    if (!fp)
        TEST_FAIL("cannot write %s", path);
    fputs(text, fp);
    fclose(fp);
}

void test_write_bytes(const char *path, const void *data, size_t n)
{
    FILE *fp = fopen(path, "wb");
    if (!fp)
        TEST_FAIL("cannot write %s", path);
    size_t put = fwrite(data, 1, n, fp);
    if (fclose(fp) != 0 || put != n)
        TEST_FAIL("short write of %s", path);
}

const char *test_fresh_dir(const char *name)
{
    const char *d = test_tmp_path(name);
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s'", d, d);
    if (test_system(cmd) != 0)
        TEST_FAIL("cannot make the folder %s", d);
    return d;
}

double test_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void test_sleep(double s)
{
    struct timespec ts = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
    nanosleep(&ts, NULL);
}

/* Children still running when a test fails (TEST_FAIL exits) are killed at exit. */
static pid_t children[64];
static int nchildren;

static void kill_children(void)
{
    for (int i = 0; i < nchildren; i++)
        if (children[i] > 0 && waitpid(children[i], NULL, WNOHANG) == 0) {
            kill(children[i], SIGKILL);
            waitpid(children[i], NULL, 0);
        }
}

int test_spawn(const char *exe, const char *args, const char *err_path)
{
    static char buf[4096];
    snprintf(buf, sizeof buf, "%s", args);
    char *argv[64];
    int n = 0;
    argv[n++] = (char *)exe;
    for (char *tok = strtok(buf, " "); tok && n < 63; tok = strtok(NULL, " "))
        argv[n++] = tok;
    argv[n] = NULL;
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0)
        TEST_FAIL("fork failed");
    if (pid == 0) {
        int out = open("/dev/null", O_WRONLY), err = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(out, 1);
        dup2(err, 2);
        execv(exe, argv);
        _exit(127);
    }
    if (nchildren == 0)
        atexit(kill_children);
    if (nchildren < 64)
        children[nchildren++] = pid;
    return (int)pid;
}

int test_wait_exit(int pid, double timeout)
{
    double t0 = test_now();
    for (;;) {
        int status = 0;
        if (waitpid(pid, &status, WNOHANG) == pid)
            return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        if (test_now() - t0 > timeout) {
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            return -1;
        }
        test_sleep(0.01);
    }
}

brume_image *test_render_scene(brume_scene *s, int threads, unsigned long long seed)
{
    brume_context *ctx = brume_context_new();
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    if (threads >= 0)
        rs.threads = threads;
    rs.seed = seed;
    brume_image *img = NULL;
    if (brume_scene_set_settings(ctx, s, &rs) != BRUME_OK || brume_scene_commit(ctx, s) != BRUME_OK ||
        brume_render(ctx, s, &img) != BRUME_OK)
        TEST_FAIL("render: %s", brume_context_last_error(ctx));
    brume_context_release(ctx);
    return img;
}

brume_scene *test_scene_json(const char *json)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = json}, NULL, &s) != BRUME_OK)
        TEST_FAIL("scene: %s", brume_context_last_error(ctx));
    brume_context_release(ctx);
    return s;
}

brume_image *test_render_json(const char *json, unsigned long long seed)
{
    brume_scene *s = test_scene_json(json);
    brume_image *img = test_render_scene(s, -1, seed);
    brume_scene_release(s);
    return img;
}

int test_mapped(const char *name)
{
    FILE *f = fopen("/proc/self/maps", "r");
    if (!f)
        return 0;
    char line[4096];
    int found = 0;
    while (!found && fgets(line, sizeof line, f))
        found = strstr(line, name) != NULL;
    fclose(f);
    return found;
}
