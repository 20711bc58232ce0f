/* cmd_phase.c - `brume phase`: fit Blasi's two-lobe Schlick mixture, plot phase functions. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "commands.h"
#include "tool/tool.h"

static const char phase_usage[] =
    "usage: brume phase fit NAME [--norm angle|cos|log] [--given r,k,kprime]\n"
    "       brume phase plot NAME... -o FILE.png [--log] [--norm angle|cos|log] [--given r,k,kprime]\n"
    "       brume phase plot NAME... -o FILE.png --overlay [--log]\n"
    "       brume phase help\n"
    "\n"
    "NAME is isotropic, rayleigh, hazy, murky, hg:G, schlick:K, or a file of lines\n"
    "\"angle_in_degrees value\" ('#' starts a comment).\n"
    "\n"
    "fit   fits r phi_k + (1 - r) phi_k' (Blasi Eq. 22, k <= k') to NAME and prints\n"
    "      the lines: r VALUE, k VALUE, kprime VALUE, error VALUE. The error is the\n"
    "      relative L2 norm of the difference (default over the angle; see\n"
    "      docs/phase-functions.md). With --given r,k,kprime nothing is fitted: the\n"
    "      error of that mixture (e.g. a table's published fit) in the same norm.\n"
    "plot  draws, for each NAME, a polar and a cartesian plot of the function (solid)\n"
    "      and of its fitted mixture (dashed) into one PNG; --log plots log10 phi;\n"
    "      --given draws that mixture instead of the fit (Blasi's Figures 2-4 with Figure 7's\n"
    "      values); --overlay draws every NAME on one pair of axes, no fit (Figures 5 and 6).\n";

static int phase_usage_error(const char *what)
{
    cli_error("phase: %s (try: brume phase help)", what);
    return 2;
}

/* "r,k,kprime" of Blasi Eq. 22, each in its domain. */
static bool parse_given(const char *text, phase_fit_result *fit)
{
    char tail;
    return sscanf(text, "%lf,%lf,%lf%c", &fit->r, &fit->k, &fit->kprime, &tail) == 3 && fit->r >= 0.0 &&
           fit->r <= 1.0 && fabs(fit->k) < 1.0 && fabs(fit->kprime) < 1.0;
}

static int phase_fit_cmd(int argc, char **argv)
{
    const char *name = NULL;
    phase_fit_norm norm = PHASE_FIT_NORM_ANGLE;
    const char *given = NULL;
    for (int i = 2; i < argc; i++) {
        if (strcmp(argv[i], "--norm") == 0) {
            if (i + 1 >= argc || !phase_fit_norm_from_name(argv[i + 1], &norm))
                return phase_usage_error("--norm needs angle, cos or log");
            i++;
        } else if (strcmp(argv[i], "--given") == 0) {
            if (i + 1 >= argc)
                return phase_usage_error("--given needs r,k,kprime");
            given = argv[++i];
        } else if (argv[i][0] == '-' && argv[i][1] == '-') {
            cli_error("phase fit: unknown option %s", argv[i]);
            return 2;
        } else if (name) {
            return phase_usage_error("fit takes one NAME");
        } else {
            name = argv[i];
        }
    }
    if (!name)
        return phase_usage_error("fit needs a NAME");
    phase *p = tool_phase_named(name);
    if (!p) {
        cli_error("%.1000s", tool_last_error());
        return 1;
    }
    phase_fit_result fit;
    brume_status st = BRUME_OK;
    if (given) {
        /* Blasi Eq. 22's parameters as given (e.g. Figure 7's table), scored, not fitted */
        if (!parse_given(given, &fit)) {
            tool_phase_release(p);
            cli_error("phase fit: --given: expected r,k,kprime with r in [0, 1] and |k|, |kprime| < 1, got '%s'", given);
            return 2;
        }
        fit.error = phase_fit_error(p, norm, fit.r, fit.k, fit.kprime);
    } else {
        st = phase_fit_schlick_mix(p, norm, &fit);
    }
    tool_phase_release(p);
    if (st != BRUME_OK) {
        cli_error("%.1000s", tool_last_error());
        return 1;
    }
    printf("r %.4f\nk %.4f\nkprime %.4f\nerror %.6g\n", fit.r, fit.k, fit.kprime, fit.error);
    return 0;
}

typedef struct plot_opts {
    const char *out;
    bool log_scale, overlay, have_given;
    phase_fit_result given;
    phase_fit_norm norm;
    int n; /* NAMEs */
} plot_opts;

/* The options of `phase plot` into *o. -1: go on; otherwise the exit status (2 with a
 * message). */
static int parse_plot(int argc, char **argv, plot_opts *o)
{
    for (int i = 2; i < argc; i++) {
        if (strcmp(argv[i], "-o") == 0) {
            if (i + 1 >= argc)
                return phase_usage_error("-o needs a file name");
            o->out = argv[++i];
        } else if (strcmp(argv[i], "--log") == 0) {
            o->log_scale = true;
        } else if (strcmp(argv[i], "--overlay") == 0) {
            o->overlay = true;
        } else if (strcmp(argv[i], "--given") == 0) {
            if (i + 1 >= argc || !parse_given(argv[i + 1], &o->given))
                return phase_usage_error("--given needs r,k,kprime with r in [0, 1] and |k|, |kprime| < 1");
            o->have_given = true;
            i++;
        } else if (strcmp(argv[i], "--norm") == 0) {
            if (i + 1 >= argc || !phase_fit_norm_from_name(argv[i + 1], &o->norm))
                return phase_usage_error("--norm needs angle, cos or log");
            i++;
        } else if (argv[i][0] == '-' && argv[i][1] != '\0') {
            cli_error("phase plot: unknown option %s", argv[i]);
            return 2;
        } else {
            o->n++;
        }
    }
    if (o->n == 0)
        return phase_usage_error("plot needs at least one NAME");
    if (!o->out)
        return phase_usage_error("plot needs -o FILE.png");
    return -1;
}

static int phase_plot_cmd(int argc, char **argv)
{
    plot_opts o = {.norm = PHASE_FIT_NORM_ANGLE};
    int rc = parse_plot(argc, argv, &o);
    if (rc >= 0)
        return rc;
    const char *out = o.out;
    bool log_scale = o.log_scale, overlay = o.overlay, have_given = o.have_given;
    phase_fit_result given = o.given;
    phase_fit_norm norm = o.norm;
    int n = o.n;

    /* rows borrow the phases that truth[] and approx[] own. */
    phase_plot_row *rows = calloc((size_t)n, sizeof *rows);
    phase **truth = calloc((size_t)n, sizeof *truth), **approx = calloc((size_t)n, sizeof *approx);
    char(*titles)[256] = calloc((size_t)n, sizeof *titles);
    const char **labels = calloc((size_t)n, sizeof *labels);
    int status = 1, m = 0;
    if (!rows || !truth || !approx || !titles || !labels) {
        cli_error("phase plot: out of memory");
        goto done;
    }
    for (int i = 2; i < argc; i++) {
        if (strcmp(argv[i], "-o") == 0 || strcmp(argv[i], "--norm") == 0 || strcmp(argv[i], "--given") == 0) {
            i++;
            continue;
        }
        if (strcmp(argv[i], "--log") == 0 || strcmp(argv[i], "--overlay") == 0)
            continue;
        phase_fit_result fit = given;
        truth[m] = tool_phase_named(argv[i]);
        labels[m] = argv[i];
        if (overlay) {
            if (!truth[m]) {
                cli_error("%.1000s", tool_last_error());
                m++;
                goto done;
            }
            m++;
            continue;
        }
        if (!truth[m] || (have_given ? (fit.error = phase_fit_error(truth[m], norm, fit.r, fit.k, fit.kprime), 0)
                                     : phase_fit_schlick_mix(truth[m], norm, &fit) != BRUME_OK) ||
            !(approx[m] = tool_phase_schlick_mix(fit.r, fit.k, fit.kprime))) {
            cli_error("%.1000s", tool_last_error());
            m++;
            goto done;
        }
        rows[m].truth = truth[m];
        rows[m].approx = approx[m];
        snprintf(titles[m], sizeof titles[m],
                 "%s: true (solid), Schlick mixture r %.2f, k %.2f, k' %.2f (dashed, %s), error %.3g",
                 argv[i], fit.r, fit.k, fit.kprime, have_given ? "given" : "fitted", fit.error);
        rows[m].title = titles[m];
        m++;
    }
    if (overlay) {
        /* one row: every function on the same axes */
        snprintf(titles[0], sizeof titles[0], "%d phase functions, phi(theta) (the integral of phi over cos is 2)", m);
        rows[0] = (phase_plot_row){titles[0], NULL, NULL, m, (const phase *const *)truth, labels, NULL};
    }
    if (phase_plot_png(out, overlay ? 1 : m, rows, log_scale) != BRUME_OK) {
        cli_error("%.1000s", tool_last_error());
        goto done;
    }
    status = 0;
done:
    for (int i = 0; i < m; i++) {
        tool_phase_release(truth[i]);
        tool_phase_release(approx[i]);
    }
    free(labels);
    free(rows);
    free(truth);
    free(approx);
    free(titles);
    return status;
}

int cmd_phase(int argc, char **argv)
{
    if (argc < 2)
        return phase_usage_error("missing subcommand fit, plot or help");
    if (strcmp(argv[1], "help") == 0 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        fputs(phase_usage, stdout);
        return 0;
    }
    if (strcmp(argv[1], "fit") == 0)
        return phase_fit_cmd(argc, argv);
    if (strcmp(argv[1], "plot") == 0)
        return phase_plot_cmd(argc, argv);
    cli_error("phase: unknown subcommand %s (try: brume phase help)", argv[1]);
    return 2;
}
