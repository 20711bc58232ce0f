/* cmd_phase.c - `brume phase`: fit Blasi's two-lobe Schlick mixture, plot phase functions. */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brume.h"
#include "cli_flags.h"
#include "cli_job.h"
#include "commands.h"

/* The context of the command's calls (cmd_phase makes it). */
static brume_context *g_ctx;

static int phase_usage_error(const char *what)
{
    cli_error("phase: %s (try: brume phase help)", what);
    return 2;
}

/* "r,k,kprime" of Blasi Eq. 22, each in its domain. */
static bool parse_given(const char *text, brume_phase_fit *fit)
{
    char tail;
    return sscanf(text, "%lf,%lf,%lf%c", &fit->r, &fit->k, &fit->kprime, &tail) == 3 && fit->r >= 0.0 &&
           fit->r <= 1.0 && fabs(fit->k) < 1.0 && fabs(fit->kprime) < 1.0;
}

/* The options of `phase fit` and `phase plot`. */
typedef struct phase_opts {
    const char *out;
    bool log_scale, overlay;
    const char *given; /* r,k,kprime, or NULL */
    brume_phase_fit_norm norm;
} phase_opts;

static bool flag_norm(void *opts, const cli_flag *f, const char *v)
{
    (void)f;
    if (brume_phase_fit_norm_from_name(g_ctx, v, &((phase_opts *)opts)->norm) != BRUME_OK) {
        phase_usage_error("--norm needs angle, cos or log");
        return false;
    }
    return true;
}

#define OFF(field) offsetof(phase_opts, field)
#define NORM_FLAG {"--norm", NULL, "angle|cos|log", "the norm of the error (default angle;\n" \
                   "docs/phase-functions.md)", NULL, CLI_FLAG_CALL, 0, 0, 0, flag_norm}
#define GIVEN_FLAG(what) {"--given", NULL, "r,k,kprime", "Blasi Eq. 22's parameters as given: " what, NULL, \
                          CLI_FLAG_STRING, OFF(given), 0, 0, NULL}

static const cli_flag fit_flags[] = {
    NORM_FLAG,
    GIVEN_FLAG("nothing is fitted, the error of\nthat mixture (e.g. a table's published fit) in the same norm"),
};

static const char names_help[] = "NAME is isotropic, rayleigh, hazy, murky, hg:G, schlick:K, or a file of lines\n"
                                 "\"angle_in_degrees value\" ('#' starts a comment).\n";

const cli_command cli_phase_fit_command = {
    "phase fit", "fit Blasi's two-lobe Schlick mixture (Eq. 22) to a phase function, or score a given one",
    "NAME [options]",
    "Fits r phi_k + (1 - r) phi_k' (Blasi Eq. 22, k <= k') to NAME and prints the lines:\n"
    "r VALUE, k VALUE, kprime VALUE, error VALUE. The error is the relative L2 norm of the\n"
    "difference (default over the angle; see docs/phase-functions.md).\n",
    fit_flags, CLI_NFLAGS(fit_flags), names_help, NULL};

static const cli_flag plot_flags[] = {
    {"--output", "-o", "FILE.png", "the plots (required)", NULL, CLI_FLAG_STRING, OFF(out), 0, 0, NULL},
    {"--log", NULL, NULL, "plot log10 phi", NULL, CLI_FLAG_TRUE, OFF(log_scale), 0, 0, NULL},
    {"--overlay", NULL, NULL, "every NAME on one pair of axes, no fit (Figures 5 and 6)", NULL, CLI_FLAG_TRUE,
     OFF(overlay), 0, 0, NULL},
    NORM_FLAG,
    GIVEN_FLAG("draw that mixture instead of the fit\n(Blasi's Figures 2-4 with Figure 7's values)"),
};

const cli_command cli_phase_plot_command = {
    "phase plot", "polar and cartesian plots of phase functions and their fits, as Figures 2-6",
    "NAME... -o FILE.png [options]",
    "Draws, for each NAME, a polar and a cartesian plot of the function (solid) and of its\n"
    "fitted mixture (dashed) into one PNG.\n",
    plot_flags, CLI_NFLAGS(plot_flags), names_help, NULL};

/* `phase fit` or `phase plot` (argv[0]) into *o and names (room for argc): -1 to go on, or
 * the exit status. */
static int parse_phase(const cli_command *c, phase_opts *o, int argc, char **argv, const char **names, int max,
                       int *n)
{
    int rc = cli_flags_parse(c, o, argc, argv, names, max, n);
    if (rc < 0 && o->given) {
        brume_phase_fit fit;
        if (!parse_given(o->given, &fit)) {
            cli_error("%s: --given: expected r,k,kprime with r in [0, 1] and |k|, |kprime| < 1, got '%s'", c->name,
                      o->given);
            return 2;
        }
    }
    return rc;
}

static int phase_fit_cmd(int argc, char **argv)
{
    phase_opts o = {.norm = BRUME_PHASE_FIT_ANGLE};
    const char **names = malloc((size_t)argc * sizeof *names);
    int n = 0, rc = names ? parse_phase(&cli_phase_fit_command, &o, argc, argv, names, argc, &n) : 2;
    const char *name = n > 0 ? names[0] : NULL;
    free(names);
    if (rc >= 0)
        return rc;
    if (n > 1)
        return phase_usage_error("fit takes one NAME");
    if (!name)
        return phase_usage_error("fit needs a NAME");
    brume_phase_fit_norm norm = o.norm;
    const char *given = o.given;
    brume_phase *p = NULL;
    if (brume_phase_new_named(g_ctx, name, &p) != BRUME_OK) {
        cli_error("%.1000s", brume_context_last_error(g_ctx));
        return 1;
    }
    brume_phase_fit fit;
    brume_status st = BRUME_OK;
    if (given) {
        /* Blasi Eq. 22's parameters as given (e.g. Figure 7's table), scored, not fitted */
        if (!parse_given(given, &fit)) {
            brume_phase_release(p);
            cli_error("phase fit: --given: expected r,k,kprime with r in [0, 1] and |k|, |kprime| < 1, got '%s'", given);
            return 2;
        }
        fit.error = brume_phase_fit_error(p, norm, fit.r, fit.k, fit.kprime);
    } else {
        st = brume_phase_fit_schlick_mix(g_ctx, p, norm, &fit);
    }
    brume_phase_release(p);
    if (st != BRUME_OK) {
        cli_error("%.1000s", brume_context_last_error(g_ctx));
        return 1;
    }
    printf("r %.4f\nk %.4f\nkprime %.4f\nerror %.6g\n", fit.r, fit.k, fit.kprime, fit.error);
    return 0;
}

/* The plots of names[0..n) that o asks for. The exit status. */
static int plot_names(const phase_opts *o, const char *const *names, int n)
{
    const char *out = o->out;
    bool log_scale = o->log_scale, overlay = o->overlay, have_given = o->given != NULL;
    brume_phase_fit given = {0};
    if (have_given)
        parse_given(o->given, &given);
    brume_phase_fit_norm norm = o->norm;

    /* rows borrow the phases that truth[] and approx[] own. */
    brume_phase_plot_row *rows = calloc((size_t)n, sizeof *rows);
    brume_phase **truth = calloc((size_t)n, sizeof *truth), **approx = calloc((size_t)n, sizeof *approx);
    char(*titles)[256] = calloc((size_t)n, sizeof *titles);
    const char **labels = calloc((size_t)n, sizeof *labels);
    int status = 1, m = 0;
    if (!rows || !truth || !approx || !titles || !labels) {
        cli_error("phase plot: out of memory");
        goto done;
    }
    for (int i = 0; i < n; i++) {
        brume_phase_fit fit = given;
        bool made = brume_phase_new_named(g_ctx, names[i], &truth[m]) == BRUME_OK;
        labels[m] = names[i];
        if (overlay) {
            if (!made) {
                cli_error("%.1000s", brume_context_last_error(g_ctx));
                m++;
                goto done;
            }
            m++;
            continue;
        }
        if (!made ||
            (have_given ? (fit.error = brume_phase_fit_error(truth[m], norm, fit.r, fit.k, fit.kprime), 0)
                        : brume_phase_fit_schlick_mix(g_ctx, truth[m], norm, &fit) != BRUME_OK) ||
            brume_phase_new_schlick_mix(g_ctx, fit.r, fit.k, fit.kprime, &approx[m]) != BRUME_OK) {
            cli_error("%.1000s", brume_context_last_error(g_ctx));
            m++;
            goto done;
        }
        rows[m].truth = truth[m];
        rows[m].approx = approx[m];
        snprintf(titles[m], sizeof titles[m],
                 "%s: true (solid), Schlick mixture r %.2f, k %.2f, k' %.2f (dashed, %s), error %.3g",
                 names[i], fit.r, fit.k, fit.kprime, have_given ? "given" : "fitted", fit.error);
        rows[m].title = titles[m];
        m++;
    }
    if (overlay) {
        /* one row: every function on the same axes */
        snprintf(titles[0], sizeof titles[0], "%d phase functions, phi(theta) (the integral of phi over cos is 2)", m);
        rows[0] = (brume_phase_plot_row){titles[0], NULL, NULL, m, (const brume_phase *const *)truth, labels, NULL};
    }
    if (brume_phase_plot_png(g_ctx, out, overlay ? 1 : m, rows, log_scale) != BRUME_OK) {
        cli_error("%.1000s", brume_context_last_error(g_ctx));
        goto done;
    }
    status = 0;
done:
    for (int i = 0; i < m; i++) {
        brume_phase_release(truth[i]);
        brume_phase_release(approx[i]);
    }
    free(labels);
    free(rows);
    free(truth);
    free(approx);
    free(titles);
    return status;
}

static int phase_plot_cmd(int argc, char **argv)
{
    phase_opts o = {.norm = BRUME_PHASE_FIT_ANGLE};
    const char **names = malloc((size_t)argc * sizeof *names);
    int n = 0, rc = names ? parse_phase(&cli_phase_plot_command, &o, argc, argv, names, argc, &n) : 2;
    if (rc < 0 && n == 0)
        rc = phase_usage_error("plot needs at least one NAME");
    if (rc < 0 && !o.out)
        rc = phase_usage_error("plot needs -o FILE.png");
    if (rc < 0 && cli_check_output("-o", o.out, BRUME_FILE_IMAGE, NULL, NULL, names, n) != 0)
        rc = 1; /* never over a table it reads */
    if (rc < 0)
        rc = plot_names(&o, names, n);
    free(names);
    return rc;
}

int cmd_phase(int argc, char **argv)
{
    if (argc < 2)
        return phase_usage_error("missing subcommand fit, plot or help");
    if (strcmp(argv[1], "help") == 0 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        char *help[] = {"help", "phase", NULL};
        return cli_help(2, help);
    }
    bool fit = strcmp(argv[1], "fit") == 0, plot = strcmp(argv[1], "plot") == 0;
    if (fit || plot) {
        if (!(g_ctx = brume_context_new())) {
            cli_error("out of memory");
            return 1;
        }
        int rc = fit ? phase_fit_cmd(argc - 1, argv + 1) : phase_plot_cmd(argc - 1, argv + 1);
        brume_context_release(g_ctx);
        g_ctx = NULL;
        return rc;
    }
    cli_error("phase: unknown subcommand %s (try: brume phase help)", argv[1]);
    return 2;
}
