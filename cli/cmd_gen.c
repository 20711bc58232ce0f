/* cmd_gen.c - `brume gen cloud`, and `gen fire|upres` (cli_gen_sparse.c): a fractal cloud grid (Blasi et al. 1993, sec. 4.1; the
 * generator is src/density/fractal.c, called through brume_density_new_fractal). `brume gen cloud --dims 65x65x10 --seed 1 -o
 * cloud.vol` makes the paper's grid. */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "cli_flags.h"
#include "cli_gen_sparse.h"
#include "cli_grid.h"
#include "commands.h"
#include "cli_job.h"

/* The command line of `gen cloud`: the generator's parameters, the output. */
typedef struct cloud_opts {
    brume_fractal p;
    const char *out;
    bool has_bounds;
} cloud_opts;

static bool parse_num(const char *s, double *v) { return cli_parse_doubles(s, v, 1); }

static bool bad_value(const cli_flag *f, const char *v)
{
    cli_error("gen: bad value for %s: %s", f->name, v);
    return false;
}

/* A number into the double at the flag's offset. */
static bool flag_num(void *opts, const cli_flag *f, const char *v)
{
    return parse_num(v, (double *)(void *)((char *)opts + f->off)) || bad_value(f, v);
}

static bool flag_dims(void *opts, const cli_flag *f, const char *v)
{
    return cli_parse_dims(v, ((cloud_opts *)opts)->p.dims) || bad_value(f, v);
}

/* The index of v in names (NULL-terminated), or -1 after the message. */
static int pick(const cli_flag *f, const char *v, const char *const *names)
{
    for (int k = 0; names[k]; k++)
        if (strcmp(v, names[k]) == 0)
            return k;
    bad_value(f, v);
    return -1;
}

static bool flag_method(void *opts, const cli_flag *f, const char *v)
{
    static const char *const names[] = {"midpoint", "spectral", "perlin", NULL};
    static const brume_fractal_method values[] = {BRUME_FRACTAL_MIDPOINT, BRUME_FRACTAL_SPECTRAL, BRUME_FRACTAL_PERLIN};
    int k = pick(f, v, names);
    if (k >= 0)
        ((cloud_opts *)opts)->p.method = values[k];
    return k >= 0;
}

static bool flag_shape(void *opts, const cli_flag *f, const char *v)
{
    static const char *const names[] = {"ellipsoid", "slab", "none", NULL};
    static const brume_fractal_shape values[] = {BRUME_FRACTAL_SHAPE_ELLIPSOID, BRUME_FRACTAL_SHAPE_SLAB,
                                                 BRUME_FRACTAL_SHAPE_NONE};
    int k = pick(f, v, names);
    if (k >= 0)
        ((cloud_opts *)opts)->p.shape = values[k];
    return k >= 0;
}

static bool flag_octaves(void *opts, const cli_flag *f, const char *v)
{
    double x = 0.0;
    if (!parse_num(v, &x) || !(x >= 1 && x <= 16 && x == (int)x))
        return bad_value(f, v);
    ((cloud_opts *)opts)->p.octaves = (int)x;
    return true;
}

static bool flag_wind(void *opts, const cli_flag *f, const char *v)
{
    return cli_parse_doubles(v, ((cloud_opts *)opts)->p.wind, 3) || bad_value(f, v);
}

static bool flag_bounds(void *opts, const cli_flag *f, const char *v)
{
    cloud_opts *o = opts;
    double *b = o->p.bounds;
    o->has_bounds = cli_parse_doubles(v, b, 6) && b[3] > b[0] && b[4] > b[1] && b[5] > b[2];
    return o->has_bounds || bad_value(f, v);
}

#define OFF(field) offsetof(cloud_opts, field)
#define NUM(name, arg, help, field) {name, NULL, arg, help, NULL, CLI_FLAG_CALL, OFF(p.field), 0, 0, flag_num}

static const cli_flag cloud_flags[] = {
    {"--output", "-o", "OUT", "the grid: .vol, .raw, .df3, .nvdb or .vdb (required)", NULL, CLI_FLAG_STRING, OFF(out),
     0, 0, NULL},
    {"--dims", NULL, "NXxNYxNZ", "voxels (default 65x65x10, the paper's grid)", NULL, CLI_FLAG_CALL, 0, 0, 0,
     flag_dims},
    {"--seed", NULL, "N", "random seed (default 1)", NULL, CLI_FLAG_U64, OFF(p.seed), 0, 0, NULL},
    {"--method", NULL, "midpoint|spectral|perlin", "fBm base (default midpoint)", NULL, CLI_FLAG_CALL, 0, 0, 0,
     flag_method},
    NUM("--hurst", "H", "Hurst exponent in (0, 1) (default 0.5)", hurst),
    {"--octaves", NULL, "N", "Perlin octaves, base and turbulence (default 6)", NULL, CLI_FLAG_CALL, 0, 0, 0,
     flag_octaves},
    NUM("--frequency", "F", "Perlin base cycles across the grid (default 2)", frequency),
    {"--shape", NULL, "ellipsoid|slab|none", "solid texture (default slab)", NULL, CLI_FLAG_CALL, 0, 0, 0,
     flag_shape},
    NUM("--falloff", "F", "soft edge of the shape, in (0, 1] (default 0.6)", falloff),
    NUM("--threshold", "T", "density threshold at time 0, in [0, 1) (default 0.4)", threshold),
    NUM("--threshold-rate", "R", "threshold change per unit time (default 0)", threshold_rate),
    NUM("--turbulence", "A", "turbulence amplitude (default 0)", turbulence),
    NUM("--turbulence-frequency", "F", "turbulence cycles across the grid (default 4)", turbulence_frequency),
    {"--wind", NULL, "X,Y,Z", "turbulence drift per unit time (default 0,0,0)", NULL, CLI_FLAG_CALL, 0, 0, 0,
     flag_wind},
    NUM("--time", "T", "time (default 0)", time),
    NUM("--density", "D", "largest density (default 1)", density),
    {"--bounds", NULL, "X0,Y0,Z0,X1,Y1,Z1", "world box (default: centred, cubic voxels, longest axis 1)", NULL,
     CLI_FLAG_CALL, 0, 0, 0, flag_bounds},
};

const cli_command cli_gen_cloud_command = {
    "gen cloud", "a fractal cloud grid (Blasi et al. 1993, sec. 4.1)",
    "[options] -o OUT(.vol|.raw|.df3|.nvdb|.vdb)",
    "A fractal cloud grid (Blasi et al. 1993, sec. 4.1; src/density/fractal.c): `brume gen cloud\n"
    "--dims 65x65x10 --seed 1 -o cloud.vol` makes the paper's grid.\n",
    cloud_flags, CLI_NFLAGS(cloud_flags), NULL, NULL};

static int gen_cloud(int argc, char **argv)
{
    cloud_opts o = {.out = NULL, .has_bounds = false};
    brume_fractal_default(&o.p);
    int n = 0, rc = cli_flags_parse(&cli_gen_cloud_command, &o, argc, argv, NULL, 0, &n);
    if (rc >= 0)
        return rc;
    brume_fractal p = o.p;
    const char *out = o.out;
    bool has_bounds = o.has_bounds;
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
    if (cli_check_output("-o", out, BRUME_FILE_GRID, NULL, NULL, NULL, 0) != 0)
        return 1;
    brume_context *ctx = brume_context_new();
    brume_density *d = NULL;
    brume_status st = ctx ? brume_density_new_fractal(ctx, &p, &d) : BRUME_ERROR_OUT_OF_MEMORY;
    int rc2 = 0;
    if (st != BRUME_OK) { /* the request refused */
        cli_error("gen: %.1000s", ctx ? brume_context_last_error(ctx) : "out of memory");
        rc2 = 2;
    } else if (brume_density_write(ctx, d, out, BRUME_GRID_FORMAT_AUTO) != BRUME_OK) {
        cli_error("%.1000s", brume_context_last_error(ctx));
        rc2 = 1;
    }
    brume_density_release(d);
    brume_context_release(ctx);
    return rc2;
}

int cmd_gen(int argc, char **argv)
{
    if (argc >= 2 && (strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "--help") == 0)) {
        char *help[] = {"help", "gen", NULL};
        return cli_help(2, help);
    }
    if (argc >= 2 && strcmp(argv[1], "cloud") == 0)
        return gen_cloud(argc - 1, argv + 1);
    if (argc >= 2 && strcmp(argv[1], "fire") == 0)
        return gen_fire(argc - 1, argv + 1);
    if (argc >= 2 && strcmp(argv[1], "upres") == 0)
        return gen_upres(argc - 1, argv + 1);
    cli_error("gen: expected `brume gen cloud|fire|upres` (see brume gen --help)");
    return 2;
}
