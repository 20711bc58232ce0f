/* cmd_slab.c - `brume slab`: Rd and Tt of a plane-parallel slab under a normal beam. */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "cli_flags.h"
#include "commands.h"
#include "tool/tool.h"

/* The command line: the slab, the phase function and the walk. */
typedef struct slab_opts {
    tool_slab_params p;
    const char *phase_name;
    double g, k;
    bool have_g, have_k;
    int max_depth;
} slab_opts;

static bool flag_gk(void *opts, const cli_flag *f, const char *v)
{
    const char *a = f->name;
    slab_opts *o = opts;
    bool g = a[2] == 'g';
    if (!arg_double(a, v, -0.999999, 0.999999, g ? &o->g : &o->k))
        return false;
    *(g ? &o->have_g : &o->have_k) = true;
    return true;
}

#define OFF(field) offsetof(slab_opts, field)

static const cli_flag slab_flags[] = {
    {"--albedo", NULL, "A", "single-scattering albedo in [0, 1]", NULL, CLI_FLAG_DOUBLE, OFF(p.albedo), 0.0, 1.0,
     NULL},
    {"--tau", NULL, "T", "optical thickness in [0, 1e5] (0 = semi-infinite)", NULL, CLI_FLAG_DOUBLE, OFF(p.tau), 0.0,
     1e5, NULL},
    {"--phase", NULL, "NAME", "isotropic, rayleigh, hazy, murky, hg (with --g), schlick (with --k,\n"
     "or --g converted by k = 1.55 g - 0.55 g^3), or a tabulated file", NULL, CLI_FLAG_STRING, OFF(phase_name), 0, 0,
     NULL},
    {"--g", NULL, "G", "hg's asymmetry, or schlick's through k(g)", NULL, CLI_FLAG_CALL, 0, 0, 0, flag_gk},
    {"--k", NULL, "K", "schlick's parameter", NULL, CLI_FLAG_CALL, 0, 0, 0, flag_gk},
    {"--samples", NULL, "N", "photons (default 1000000)", NULL, CLI_FLAG_U64, OFF(p.samples), 0, 0, NULL},
    {"--seed", NULL, "S", "random seed (default 1)", NULL, CLI_FLAG_U64, OFF(p.seed), 0, 0, NULL},
    {"--threads", NULL, "N", "worker threads (default: one per core)", NULL, CLI_FLAG_INT, OFF(p.threads), 0, 1024,
     NULL},
    {"--max-depth", NULL, "N", "count at most N scattering events (1 = single scattering)", NULL, CLI_FLAG_INT,
     OFF(max_depth), 1, 1 << 30, NULL},
};

const cli_command cli_slab_command = {
    "slab", "reflectance and transmittance of a plane-parallel slab (the renderer's own random walk)",
    "--albedo A --tau T --phase NAME [--g G | --k K] [options]",
    "Total diffuse reflectance Rd and total transmittance Tt (with the unscattered part) of\n"
    "a plane-parallel slab of optical thickness T (0 = semi-infinite) and albedo A under a\n"
    "normally incident collimated beam, refractive index 1 on both sides, computed by the\n"
    "renderer's own random walk. Prints `Rd VALUE STDERR` and `Tt VALUE STDERR`.\n",
    slab_flags, CLI_NFLAGS(slab_flags), NULL, NULL};

/* The phase function the flags name: its own, or NULL with a message (*rc the exit status). */
static phase *slab_phase(const slab_opts *o, int *rc)
{
    *rc = 2;
    phase *ph = NULL;
    if (strcmp(o->phase_name, "hg") == 0) {
        if (!o->have_g) {
            cli_error("slab: --phase hg needs --g");
            return NULL;
        }
        ph = tool_phase_hg(o->g);
    } else if (strcmp(o->phase_name, "schlick") == 0) {
        if (!o->have_g && !o->have_k) {
            cli_error("slab: --phase schlick needs --k (or --g)");
            return NULL;
        }
        ph = tool_phase_schlick(o->have_k ? o->k : tool_schlick_k_from_g(o->g));
    } else {
        if (o->have_g || o->have_k) {
            cli_error("slab: --g and --k apply to hg and schlick only, not '%s'", o->phase_name);
            return NULL;
        }
        ph = tool_phase_named(o->phase_name);
    }
    if (!ph) {
        cli_error("slab: --phase: %.1000s", tool_last_error());
        *rc = 1;
    }
    return ph;
}

int cmd_slab(int argc, char **argv)
{
    slab_opts o = {.p = {.albedo = -1.0, .tau = -1.0, .samples = 1000000, .seed = 1, .threads = 0,
                         .max_depth = 1 << 30}};
    int n = 0, rc = cli_flags_parse(&cli_slab_command, &o, argc, argv, NULL, 0, &n);
    if (rc >= 0)
        return rc;
    tool_slab_params p = o.p;
    if (o.max_depth)
        p.max_depth = o.max_depth;
    if (p.albedo < 0.0 || p.tau < 0.0 || !o.phase_name) {
        cli_error("slab: --albedo, --tau and --phase are required (try `brume help slab`)");
        return 2;
    }
    if (o.have_g && o.have_k) {
        cli_error("slab: give --g or --k, not both");
        return 2;
    }
    phase *ph = slab_phase(&o, &rc);
    if (!ph)
        return rc;
    p.ph = ph;
    tool_slab_result r;
    brume_status st = tool_slab_run(&p, &r);
    tool_phase_release(ph);
    if (st != BRUME_OK) {
        cli_error("%.1000s", tool_last_error());
        return 1;
    }
    printf("Rd %.6f %.6f\n", r.Rd, r.Rd_stderr);
    printf("Tt %.6f %.6f\n", r.Tt, r.Tt_stderr);
    return 0;
}
