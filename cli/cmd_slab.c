/* cmd_slab.c - `brume slab`: Rd and Tt of a plane-parallel slab under a normal beam. */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "brume.h"
#include "cli_flags.h"
#include "commands.h"

/* The command line: the slab, the phase function and the walk. */
typedef struct slab_opts {
    brume_slab_params p;
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

/* The phase function the flags name, then the slab: 0 with *r, else the exit status with a
 * message. */
static int run_slab(const slab_opts *o, brume_slab_params *p, brume_slab_result *r)
{
    const char *phase_name = o->phase_name;
    bool hg = strcmp(phase_name, "hg") == 0, schlick = strcmp(phase_name, "schlick") == 0;
    if ((hg && !o->have_g) || (schlick && !o->have_g && !o->have_k)) {
        cli_error(hg ? "slab: --phase hg needs --g" : "slab: --phase schlick needs --k (or --g)");
        return 2;
    }
    if (!hg && !schlick && (o->have_g || o->have_k)) {
        cli_error("slab: --g and --k apply to hg and schlick only, not '%s'", phase_name);
        return 2;
    }
    brume_context *ctx = brume_context_new();
    if (!ctx) {
        cli_error("out of memory");
        return 1;
    }
    brume_phase *ph = NULL;
    brume_status st = hg        ? brume_phase_new_hg(ctx, o->g, &ph)
                      : schlick ? brume_phase_new_schlick(ctx, o->have_k ? o->k : brume_schlick_k_from_g(o->g), &ph)
                                : brume_phase_new_named(ctx, phase_name, &ph);
    if (st != BRUME_OK)
        cli_error("slab: --phase: %.1000s", brume_context_last_error(ctx));
    p->phase = ph;
    if (st == BRUME_OK && (st = brume_slab_run(ctx, p, r)) != BRUME_OK)
        cli_error("%.1000s", brume_context_last_error(ctx));
    brume_phase_release(ph);
    brume_context_release(ctx);
    return st == BRUME_OK ? 0 : 1;
}

int cmd_slab(int argc, char **argv)
{
    slab_opts o = {.p = {.albedo = -1.0, .tau = -1.0, .samples = 1000000, .seed = 1, .threads = 0,
                         .max_depth = 1 << 30}};
    int n = 0, rc = cli_flags_parse(&cli_slab_command, &o, argc, argv, NULL, 0, &n);
    if (rc >= 0)
        return rc;
    brume_slab_params p = o.p;
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
    brume_slab_result r;
    if ((rc = run_slab(&o, &p, &r)) != 0)
        return rc;
    printf("Rd %.6f %.6f\n", r.Rd, r.Rd_stderr);
    printf("Tt %.6f %.6f\n", r.Tt, r.Tt_stderr);
    return 0;
}
