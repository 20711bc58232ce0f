/* cmd_slab.c - `brume slab`: Rd and Tt of a plane-parallel slab under a normal beam. */
#include <stdio.h>
#include <string.h>

#include "args.h"
#include "commands.h"
#include "tool/tool.h"

static void slab_usage(FILE *out)
{
    fprintf(out,
            "usage: brume slab --albedo A --tau T --phase NAME [--g G | --k K] [--samples N] [--seed S]\n"
            "                  [--threads N] [--max-depth N]\n"
            "Total diffuse reflectance Rd and total transmittance Tt (with the unscattered part) of\n"
            "a plane-parallel slab of optical thickness T (0 = semi-infinite) and albedo A under a\n"
            "normally incident collimated beam, refractive index 1 on both sides, computed by the\n"
            "renderer's own random walk. Prints `Rd VALUE STDERR` and `Tt VALUE STDERR`.\n\n"
            "  --phase NAME   isotropic, rayleigh, hazy, murky, hg (with --g), schlick (with --k,\n"
            "                 or --g converted by k = 1.55 g - 0.55 g^3), or a tabulated file\n"
            "  --samples N    photons (default 1000000)\n"
            "  --max-depth N  count at most N scattering events (1 = single scattering)\n");
}

int cmd_slab(int argc, char **argv)
{
    tool_slab_params p = {.albedo = -1.0, .tau = -1.0, .samples = 1000000, .seed = 1, .threads = 0, .max_depth = 1 << 30};
    const char *phase_name = NULL;
    double g = 0.0, k = 0.0;
    bool have_g = false, have_k = false;
    int max_depth = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v;
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            slab_usage(stdout);
            return 0;
        } else if (strcmp(a, "--albedo") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_double(a, v, 0.0, 1.0, &p.albedo)) return 2;
        } else if (strcmp(a, "--tau") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_double(a, v, 0.0, 1e5, &p.tau)) return 2;
        } else if (strcmp(a, "--phase") == 0) {
            if (!(phase_name = arg_value(argc, argv, &i))) return 2;
        } else if (strcmp(a, "--g") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_double(a, v, -0.999999, 0.999999, &g)) return 2;
            have_g = true;
        } else if (strcmp(a, "--k") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_double(a, v, -0.999999, 0.999999, &k)) return 2;
            have_k = true;
        } else if (strcmp(a, "--samples") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_u64(a, v, &p.samples)) return 2;
        } else if (strcmp(a, "--seed") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_u64(a, v, &p.seed)) return 2;
        } else if (strcmp(a, "--threads") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_int(a, v, 0, 1024, &p.threads)) return 2;
        } else if (strcmp(a, "--max-depth") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_int(a, v, 1, 1 << 30, &max_depth)) return 2;
        } else {
            cli_error("slab: unknown argument '%s' (try `brume help slab`)", a);
            return 2;
        }
    }
    if (max_depth)
        p.max_depth = max_depth;
    if (p.albedo < 0.0 || p.tau < 0.0 || !phase_name) {
        cli_error("slab: --albedo, --tau and --phase are required (try `brume help slab`)");
        return 2;
    }
    if (have_g && have_k) {
        cli_error("slab: give --g or --k, not both");
        return 2;
    }
    phase *ph = NULL;
    if (strcmp(phase_name, "hg") == 0) {
        if (!have_g) {
            cli_error("slab: --phase hg needs --g");
            return 2;
        }
        ph = tool_phase_hg(g);
    } else if (strcmp(phase_name, "schlick") == 0) {
        if (!have_g && !have_k) {
            cli_error("slab: --phase schlick needs --k (or --g)");
            return 2;
        }
        ph = tool_phase_schlick(have_k ? k : tool_schlick_k_from_g(g));
    } else {
        if (have_g || have_k) {
            cli_error("slab: --g and --k apply to hg and schlick only, not '%s'", phase_name);
            return 2;
        }
        ph = tool_phase_named(phase_name);
    }
    if (!ph) {
        cli_error("slab: --phase: %.1000s", tool_last_error());
        return 1;
    }
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
