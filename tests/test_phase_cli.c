/* test_phase_cli.c - `brume phase`: the fit output format, plots, and exit statuses.
 * The command is called directly from the commands' library (brume_cmds). */
#include "test.h"

#include <fcntl.h>
#include <unistd.h>

#include "commands.h"
#include "core/error.h"
#include "phase/phase.h"
#include "brume.h"

/* fontconfig (under cairo's text) keeps process-lifetime caches that LeakSanitizer reports
 * at exit; they are not ours. The hook is read only by sanitizer builds. */
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void) { return "leak:libfontconfig\n"; }

/* Runs cmd_phase with stdout captured into out (NUL-terminated); returns its status. */
static int run_phase(char *out, size_t cap, int argc, char **argv)
{
    const char *path = test_tmp_path("stdout.txt");
    fflush(stdout);
    int saved = dup(STDOUT_FILENO);
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    ASSERT_TRUE(saved >= 0 && fd >= 0);
    dup2(fd, STDOUT_FILENO);
    close(fd);
    int status = cmd_phase(argc, argv);
    fflush(stdout);
    dup2(saved, STDOUT_FILENO);
    close(saved);
    FILE *f = fopen(path, "r");
    ASSERT_TRUE(f != NULL);
    size_t n = fread(out, 1, cap - 1, f);
    out[n] = '\0';
    fclose(f);
    remove(path);
    return status;
}

/* Four lines: r, k, kprime, error; the values are those of the library's fit, and the
 * murky fit is at least as close as Figure 7's parameters. */
TEST(fit_output)
{
    char out[4096], *argv[] = {"phase", "fit", "murky"};
    ASSERT_EQ_INT(run_phase(out, sizeof out, 3, argv), 0);
    double r, k, kp, e;
    char extra[8];
    int got = sscanf(out, "r %lf\nk %lf\nkprime %lf\nerror %lf\n%7s", &r, &k, &kp, &e, extra);
    if (got != 4)
        TEST_FAIL("unexpected output (%d fields): \"%s\"", got, out);
    brume_phase *p = NULL;
    ASSERT_EQ_INT(brume_phase_new_preset(NULL, BRUME_PHASE_MURKY, &p), BRUME_OK);
    double e_paper = brume_phase_fit_error(p, BRUME_PHASE_FIT_ANGLE, 0.19, -0.65, 0.91);
    ASSERT_TRUE(e <= e_paper);
    ASSERT_NEAR(brume_phase_fit_error(p, BRUME_PHASE_FIT_ANGLE, r, k, kp), e, 1e-4);
    ASSERT_TRUE(k < 0.0 && kp > 0.9);
    brume_phase_release(p);
}

TEST(plot_png)
{
    const char *png = test_tmp_path("plot.png");
    char out[256], *argv[] = {"phase", "plot", "rayleigh", "murky", "-o", (char *)png, "--log"};
    ASSERT_EQ_INT(run_phase(out, sizeof out, 7, argv), 0);
    FILE *f = fopen(png, "rb");
    ASSERT_TRUE(f != NULL);
    unsigned char sig[8];
    ASSERT_EQ_INT(fread(sig, 1, 8, f), 8);
    ASSERT_TRUE(memcmp(sig, "\x89PNG\r\n\x1a\n", 8) == 0);
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fclose(f);
    ASSERT_TRUE(size > 1000 && size < 300 * 1024);
    remove(png);
}

TEST(exit_status)
{
    char out[4096];
    char *usage1[] = {"phase"}, *usage2[] = {"phase", "fit"}, *usage3[] = {"phase", "plot", "hazy"},
         *usage4[] = {"phase", "frobnicate"}, *bad1[] = {"phase", "fit", "schlick:1.5"},
         *bad2[] = {"phase", "fit", "/nonexistent/table.txt"}, *help[] = {"phase", "help"};
    ASSERT_EQ_INT(run_phase(out, sizeof out, 1, usage1), 2);
    ASSERT_EQ_INT(run_phase(out, sizeof out, 2, usage2), 2);
    ASSERT_EQ_INT(run_phase(out, sizeof out, 3, usage3), 2);
    ASSERT_EQ_INT(run_phase(out, sizeof out, 2, usage4), 2);
    ASSERT_EQ_INT(run_phase(out, sizeof out, 3, bad1), 1);
    ASSERT_EQ_INT(run_phase(out, sizeof out, 3, bad2), 1);
    ASSERT_EQ_INT(run_phase(out, sizeof out, 2, help), 0);
    ASSERT_CONTAINS(out, "brume phase fit NAME");
}

TEST_MAIN(fit_output, plot_png, exit_status)
