/* harness.c - runs the cases of one test executable (see test.h). */
#include "test.h"

#include <sys/stat.h>
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
