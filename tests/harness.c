/* harness.c - runs the cases of one test executable (see test.h). */
#include "test.h"

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
