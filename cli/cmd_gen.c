/* cmd_gen.c - `brume gen cloud`, and `gen fire|upres` (cli_gen_sparse.c): a fractal cloud grid (Blasi et al. 1993, sec. 4.1; the
 * generator is src/density/fractal.c, called through src/tool/grids.c). `brume gen cloud --dims 65x65x10 --seed 1 -o
 * cloud.vol` makes the paper's grid. */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "cli_gen_sparse.h"
#include "cli_grid.h"
#include "commands.h"
#include "tool/tool.h"

static const char usage[] =
    "usage: brume gen cloud [flags] -o OUT(.vol|.raw|.df3|.nvdb|.vdb)\n"
    "       brume gen fire|upres ... (see brume gen fire --help, brume gen upres --help)\n"
    "  --dims NXxNYxNZ          voxels (default 65x65x10, the paper's grid)\n"
    "  --seed N                 random seed (default 1)\n"
    "  --method midpoint|spectral|perlin   fBm base (default midpoint)\n"
    "  --hurst H                Hurst exponent in (0, 1) (default 0.5)\n"
    "  --octaves N              Perlin octaves, base and turbulence (default 6)\n"
    "  --frequency F            Perlin base cycles across the grid (default 2)\n"
    "  --shape ellipsoid|slab|none   solid texture (default slab)\n"
    "  --falloff F              soft edge of the shape, in (0, 1] (default 0.6)\n"
    "  --threshold T            density threshold at time 0, in [0, 1) (default 0.4)\n"
    "  --threshold-rate R       threshold change per unit time (default 0)\n"
    "  --turbulence A           turbulence amplitude (default 0)\n"
    "  --turbulence-frequency F turbulence cycles across the grid (default 4)\n"
    "  --wind X,Y,Z             turbulence drift per unit time (default 0,0,0)\n"
    "  --time T                 time (default 0)\n"
    "  --density D              largest density (default 1)\n"
    "  --bounds X0,Y0,Z0,X1,Y1,Z1   world box (default: centred, cubic voxels, longest axis 1)\n";

static bool parse_num(const char *s, double *v) { return cli_parse_doubles(s, v, 1); }

/* One flag of `gen cloud` with its value v into *p (or *out, *has_bounds). 1: taken; 0: a
 * bad value; -1: the message printed. */
static int parse_cloud_flag(const char *f, const char *v, brume_fractal *p, const char **out, bool *has_bounds)
{
    double x = 0.0;
    bool ok = true;
    if (strcmp(f, "-o") == 0 || strcmp(f, "--output") == 0)
        *out = v;
    else if (strcmp(f, "--dims") == 0)
        ok = cli_parse_dims(v, p->dims);
    else if (strcmp(f, "--seed") == 0) {
        if (!arg_u64(f, v, &p->seed)) /* digits only: "-1" is refused, not wrapped */
            return -1;
    } else if (strcmp(f, "--method") == 0) {
        ok = true;
        if (strcmp(v, "midpoint") == 0)
            p->method = BRUME_FRACTAL_MIDPOINT;
        else if (strcmp(v, "spectral") == 0)
            p->method = BRUME_FRACTAL_SPECTRAL;
        else if (strcmp(v, "perlin") == 0)
            p->method = BRUME_FRACTAL_PERLIN;
        else
            ok = false;
    } else if (strcmp(f, "--shape") == 0) {
        if (strcmp(v, "ellipsoid") == 0)
            p->shape = BRUME_FRACTAL_SHAPE_ELLIPSOID;
        else if (strcmp(v, "slab") == 0)
            p->shape = BRUME_FRACTAL_SHAPE_SLAB;
        else if (strcmp(v, "none") == 0)
            p->shape = BRUME_FRACTAL_SHAPE_NONE;
        else
            ok = false;
    } else if (strcmp(f, "--octaves") == 0) {
        ok = parse_num(v, &x) && x >= 1 && x <= 16 && x == (int)x;
        p->octaves = (int)x;
    } else if (strcmp(f, "--wind") == 0) {
        ok = cli_parse_doubles(v, p->wind, 3);
    } else if (strcmp(f, "--bounds") == 0) {
        double *b = p->bounds;
        ok = *has_bounds = cli_parse_doubles(v, b, 6) && b[3] > b[0] && b[4] > b[1] && b[5] > b[2];
    } else {
        static const struct {
            const char *flag;
            size_t off;
        } nums[] = {{"--hurst", offsetof(brume_fractal, hurst)},
                    {"--frequency", offsetof(brume_fractal, frequency)},
                    {"--falloff", offsetof(brume_fractal, falloff)},
                    {"--threshold", offsetof(brume_fractal, threshold)},
                    {"--threshold-rate", offsetof(brume_fractal, threshold_rate)},
                    {"--turbulence", offsetof(brume_fractal, turbulence)},
                    {"--turbulence-frequency", offsetof(brume_fractal, turbulence_frequency)},
                    {"--time", offsetof(brume_fractal, time)},
                    {"--density", offsetof(brume_fractal, density)}};
        size_t k = 0;
        while (k < sizeof nums / sizeof *nums && strcmp(f, nums[k].flag) != 0)
            k++;
        if (k == sizeof nums / sizeof *nums) {
            cli_error("gen: unknown flag %s (see brume gen --help)", f);
            return -1;
        }
        ok = parse_num(v, (double *)((char *)p + nums[k].off));
    }
    return ok ? 1 : 0;
}

int cmd_gen(int argc, char **argv)
{
    if (argc >= 2 && (strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "--help") == 0)) {
        fputs(usage, stdout);
        return 0;
    }
    if (argc >= 2 && strcmp(argv[1], "fire") == 0)
        return gen_fire(argc - 1, argv + 1);
    if (argc >= 2 && strcmp(argv[1], "upres") == 0)
        return gen_upres(argc - 1, argv + 1);
    if (argc < 2 || strcmp(argv[1], "cloud") != 0) {
        cli_error("gen: expected `brume gen cloud|fire|upres` (see brume gen --help)");
        return 2;
    }
    brume_fractal p;
    brume_fractal_default(&p);
    const char *out = NULL;
    bool has_bounds = false;

    for (int i = 2; i < argc; i++) {
        const char *f = argv[i];
        if (strcmp(f, "-h") == 0 || strcmp(f, "--help") == 0) {
            fputs(usage, stdout);
            return 0;
        }
        if (i + 1 >= argc) {
            cli_error("gen: %s needs a value (see brume gen --help)", f);
            return 2;
        }
        const char *v = argv[++i];
        int ok = parse_cloud_flag(f, v, &p, &out, &has_bounds);
        if (ok < 0)
            return 2;
        if (!ok) {
            cli_error("gen: bad value for %s: %s", f, v);
            return 2;
        }
    }
    if (!out) {
        cli_error("gen: no output file (-o OUT)");
        return 2;
    }
    if (!has_bounds) { /* the largest axis spans 1, centred on the origin */
        int m = p.dims[0] > p.dims[1] ? p.dims[0] : p.dims[1];
        m = p.dims[2] > m ? p.dims[2] : m;
        for (int a = 0; a < 3; a++) {
            p.bounds[a + 3] = 0.5 * p.dims[a] / m;
            p.bounds[a] = -p.bounds[a + 3];
        }
    }
    p.filter = BRUME_GRID_NEAREST;
    density *d = tool_gen_cloud(&p);
    if (!d) {
        cli_error("gen: %.1000s", tool_last_error());
        return 2;
    }
    brume_status s = tool_grid_write(d, out, NULL);
    tool_grid_release(d);
    if (s != BRUME_OK) {
        cli_error("%.1000s", tool_last_error());
        return 1;
    }
    return 0;
}
