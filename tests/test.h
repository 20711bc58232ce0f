/* test.h - the test harness: TEST(name) cases, assertions that print both sides.
 *
 * A test file defines cases with TEST(name) at the start of a line and ends with
 *   TEST_MAIN(name1, name2, ...)
 * CMake registers every TEST(name) line as its own ctest case "file.name"; the executable
 * runs one case when given its name, or all of them with no argument. A failed assertion
 * prints file:line, the expression and both values, and exits 1. */
#ifndef BRUME_TEST_H
#define BRUME_TEST_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct test_case {
    const char *name;
    void (*fn)(void);
} test_case;

int test_run(const test_case *cases, int ncases, int argc, char **argv);
/* Path of a temporary file unique to this process: "<tmpdir>/brume-test-<pid>-<name>". */
const char *test_tmp_path(const char *name);
/* Runs a shell command, returns its exit status (or -1); output goes to the log. */
int test_system(const char *cmd);
/* The whole file, NUL-terminated, in a malloc'd buffer of *n + 1 bytes (the test fails if
 * it cannot be read). */
char *test_slurp(const char *path, size_t *n);
/* Mean over n RGBA pixels of channel c, and its standard error from the spread of the
 * pixel values (pixels independent: the estimator tests' tolerance). */
void test_channel_mean(const float *rgba, int n, int c, double *mean, double *se);
/* 1 if the path names an existing file or folder. */
int test_exists(const char *path);
/* The temporary files left in dir (".NAME.tmp-" or ".brume-probe-" and six random
 * characters, as mkstemp makes them), each named on stderr. */
int test_temporaries(const char *dir);
/* True when a file whose path contains `name` is mapped into this process (/proc/self/maps):
 * whether a shared library has been loaded. */
int test_mapped(const char *name);
/* Renders the scene of a JSON text with the given seed (its other settings as written);
 * the test fails with the reader's or the renderer's message. Release with
 * brume_image_release. */
struct brume_image;
struct brume_image *test_render_json(const char *json, unsigned long long seed);
/* The scene of a JSON text named "<test>", loaded through brume_scene_load (relative file
 * names from the working folder); the test fails with the reader's message. */
struct brume_scene;
struct brume_scene *test_scene_json(const char *json);
/* Commits and renders a scene with the given seed and thread count (< 0: the scene's own);
 * the test fails with the renderer's message. */
struct brume_image *test_render_scene(struct brume_scene *s, int threads, unsigned long long seed);
/* Writes text to path (the test fails if it cannot). */
void test_write_file(const char *path, const char *text);
/* Writes n bytes to path (the test fails if it cannot). */
void test_write_bytes(const char *path, const void *data, size_t n);
/* A fresh empty folder test_tmp_path(name), emptied if it was there. */
const char *test_fresh_dir(const char *name);
/* Monotonic seconds, and a sleep of s seconds. */
double test_now(void);
void test_sleep(double s);
/* Starts exe with args split on spaces (argv[0] = exe), stdout to /dev/null, stderr to
 * err_path; returns its pid. Children still running when the test process exits (a failed
 * assertion exits) are killed then. */
int test_spawn(const char *exe, const char *args, const char *err_path);
/* The exit status of pid within timeout seconds (128 + the signal if killed), or -1 after
 * killing it when it did not end. */
int test_wait_exit(int pid, double timeout);

#define TEST(name) static void name(void)

#define TEST_FAIL(...)                                                                          \
    do {                                                                                        \
        fprintf(stderr, "%s:%d: ", __FILE__, __LINE__);                                         \
        fprintf(stderr, __VA_ARGS__);                                                           \
        fputc('\n', stderr);                                                                    \
        exit(1);                                                                                \
    } while (0)

#define ASSERT_TRUE(cond)                                                                       \
    do {                                                                                        \
        if (!(cond))                                                                            \
            TEST_FAIL("assertion failed: %s", #cond);                                          \
    } while (0)

#define ASSERT_EQ_INT(a, b)                                                                     \
    do {                                                                                        \
        long long a_ = (long long)(a), b_ = (long long)(b);                                     \
        if (a_ != b_)                                                                           \
            TEST_FAIL("%s == %s: %lld != %lld", #a, #b, a_, b_);                                \
    } while (0)

#define ASSERT_EQ_STR(a, b)                                                                     \
    do {                                                                                        \
        const char *a_ = (a), *b_ = (b);                                                        \
        if (strcmp(a_, b_) != 0)                                                                \
            TEST_FAIL("%s == %s: \"%s\" != \"%s\"", #a, #b, a_, b_);                            \
    } while (0)

#define ASSERT_CONTAINS(haystack, needle)                                                       \
    do {                                                                                        \
        const char *h_ = (haystack), *n_ = (needle);                                            \
        if (!strstr(h_, n_))                                                                    \
            TEST_FAIL("%s contains %s: \"%s\" lacks \"%s\"", #haystack, #needle, h_, n_);       \
    } while (0)

/* |a - b| <= tol */
#define ASSERT_NEAR(a, b, tol)                                                                  \
    do {                                                                                        \
        double a_ = (double)(a), b_ = (double)(b), t_ = (double)(tol);                          \
        if (!(fabs(a_ - b_) <= t_))                                                             \
            TEST_FAIL("%s ~ %s: %.9g vs %.9g, difference %.3g > tolerance %.3g", #a, #b, a_, b_, \
                      fabs(a_ - b_), t_);                                                       \
    } while (0)

#define TEST_MAIN(...)                                                                          \
    int main(int argc, char **argv)                                                             \
    {                                                                                           \
        void (*fns_[])(void) = {__VA_ARGS__};                                                   \
        static char names_[] = #__VA_ARGS__;                                                    \
        test_case cases_[sizeof fns_ / sizeof fns_[0]];                                         \
        char *save_ = NULL, *tok_ = strtok_r(names_, ", \t\n", &save_);                         \
        int n_ = 0;                                                                             \
        while (tok_ && n_ < (int)(sizeof fns_ / sizeof fns_[0])) {                              \
            cases_[n_].name = tok_;                                                             \
            cases_[n_].fn = fns_[n_];                                                           \
            n_++;                                                                               \
            tok_ = strtok_r(NULL, ", \t\n", &save_);                                            \
        }                                                                                       \
        return test_run(cases_, n_, argc, argv);                                                \
    }

#endif
