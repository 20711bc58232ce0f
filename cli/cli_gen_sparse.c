/* cli_gen_sparse.c - the command lines of `brume gen fire` (a procedural flame: density and
 * temperature grids, sparse, and its velocity) and `brume gen upres` (a cloud upsampled by an integer factor
 * with fractal detail, kept sparse); the grids are made and written through OpenVDB by
 * brume_grid_gen_fire and brume_grid_gen_upres (docs/grids.md). */
#include "cli_gen_sparse.h"

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli_flags.h"
#include "cli_grid.h"
#include "commands.h"
#include "cli_job.h"

/* OUT must be .vdb or .nvdb: 0, or 2 with a message. */
static int check_output(const char *out)
{
    const char *dot = strrchr(out, '.');
    if (!dot || (strcmp(dot, ".nvdb") != 0 && strcmp(dot, ".vdb") != 0)) {
        cli_error("%s: the output must be .vdb or .nvdb", out);
        return 2;
    }
    return 0;
}

/* 1 when name holds a frame pattern, 0 when none, -1 with a message when a malformed one. */
static int pattern_kind(const char *name)
{
    bool pattern = false;
    brume_context *ctx = brume_context_new();
    brume_status st = ctx ? brume_sequence_pattern(ctx, name, &pattern) : BRUME_ERROR_OUT_OF_MEMORY;
    if (st != BRUME_OK)
        cli_error("%.1000s", ctx ? brume_context_last_error(ctx) : "out of memory");
    brume_context_release(ctx);
    return st != BRUME_OK ? -1 : pattern ? 1 : 0;
}

static bool parse_int(const char *s, long lo, long hi, long *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (!*s || *end || v < lo || v > hi)
        return false;
    *out = v;
    return true;
}

/* The command line of `gen fire`. */
typedef struct fire_opts {
    const char *out;
    int n, seed;
    double height, velocity, time, fps;
    double max_memory_mb; /* 0: the library's default */
    long first, last;
    bool frames, timed;
} fire_opts;

static bool bad_value(const char *cmd, const cli_flag *f, const char *v)
{
    cli_error("%s: bad value for %s: %s", cmd, f->name, v);
    return false;
}

/* A number in the flag's [lo, hi] (an open bound is the double next to it) into the double
 * at its offset. */
static bool fire_num(void *opts, const cli_flag *f, const char *v)
{
    fire_opts *o = opts;
    double x = 0.0;
    if (!cli_parse_doubles(v, &x, 1) || !(x >= f->lo && x <= f->hi))
        return bad_value("gen fire", f, v);
    *(double *)(void *)((char *)opts + f->off) = x;
    o->timed |= f->off == offsetof(fire_opts, time);
    return true;
}

/* An integer in the flag's [lo, hi] into the int at its offset. */
static bool sparse_int(void *opts, const cli_flag *f, const char *v, const char *cmd)
{
    long x = 0;
    if (!parse_int(v, (long)f->lo, (long)f->hi, &x))
        return bad_value(cmd, f, v);
    *(int *)(void *)((char *)opts + f->off) = (int)x;
    return true;
}

static bool fire_int(void *opts, const cli_flag *f, const char *v) { return sparse_int(opts, f, v, "gen fire"); }

static bool fire_memory(void *opts, const cli_flag *f, const char *v)
{
    size_t bytes = 0;
    if (!cli_parse_bytes(v, &bytes) || bytes == 0)
        return bad_value("gen fire", f, v);
    ((fire_opts *)opts)->max_memory_mb = (double)bytes / 1048576.0; /* exact below 2^53 bytes */
    return true;
}

static bool fire_frames(void *opts, const cli_flag *f, const char *v)
{
    fire_opts *o = opts;
    char *end;
    o->first = strtol(v, &end, 10);
    o->frames = end != v && *end == '-' && parse_int(end + 1, 0, 100000, &o->last) && o->first >= 0 &&
                o->first <= o->last;
    return o->frames || bad_value("gen fire", f, v);
}

#define FOFF(field) offsetof(fire_opts, field)
#define BELOW_1E6 0x1.e847fffffffffp+19 /* the double below 1e6: the bound is open */

static const cli_flag fire_flags[] = {
    {"--output", "-o", "OUT", "the grids: .vdb or .nvdb (required); with --frames a frame pattern", NULL,
     CLI_FLAG_STRING, FOFF(out), 0, 0, NULL},
    {"--resolution", NULL, "N", "voxels along the height (default 128; width and depth N/2), [16, 2048]", NULL,
     CLI_FLAG_CALL, FOFF(n), 16, 2048, fire_int},
    {"--seed", NULL, "N", "noise seed (default 1)", NULL, CLI_FLAG_CALL, FOFF(seed), 0, 2147483647.0, fire_int},
    {"--height", NULL, "H", "world height of the flame (default 2; the base is centred on the origin)", NULL,
     CLI_FLAG_CALL, FOFF(height), DBL_TRUE_MIN, BELOW_1E6, fire_num},
    {"--velocity", NULL, "S", "also a vec3 grid \"vel\": the updraft, S (0.5 + h) world units per second up at\n"
     "height fraction h with a sway of 0.3 S, over the whole box (default 0: none)", NULL, CLI_FLAG_CALL,
     FOFF(velocity), 0.0, BELOW_1E6, fire_num},
    {"--time", NULL, "T", "seconds: the turbulence has risen by S T (by T without --velocity) (default 0)", NULL,
     CLI_FLAG_CALL, FOFF(time), -1e6, 1e6, fire_num},
    {"--frames", NULL, "A-B", "frames A to B at times f / F, each to OUT with f in the frame pattern\n"
     "(%04d, ####, $F4: docs/grids.md, \"Sequences\"), in [0, 100000]", NULL, CLI_FLAG_CALL, 0, 0, 0, fire_frames},
    {"--fps", NULL, "F", "frames per second, (0, 1000] (default 24, as render.fps)", NULL, CLI_FLAG_CALL, FOFF(fps),
     DBL_TRUE_MIN, 1000.0, fire_num},
    {"--max-memory", NULL, "BYTES", "refuse grids that could take more (K/M/G suffixes; default 4G)", NULL,
     CLI_FLAG_CALL, 0, 0, 0, fire_memory},
};

const cli_command cli_gen_fire_command = {
    "gen fire", "a procedural flame: sparse density and temperature grids, and its velocity",
    "[options] -o OUT(.vdb|.nvdb)\n[options] --frames A-B [--fps F] -o OUT_%04d.nvdb",
    "A procedural flame: grids \"density\" (smoke and soot) and \"temperature\" (kelvin), a file\n"
    "per frame with --frames.\n",
    fire_flags, CLI_NFLAGS(fire_flags), NULL, NULL};

/* The request checked before the first file is written: 0, or the exit status after the
 * message. */
static int fire_check(fire_opts *o)
{
    if (!o->out) {
        cli_error("gen fire: no output file (-o OUT.vdb)");
        return 2;
    }
    if (!brume_grid_have_openvdb()) {
        cli_error("gen fire: writing .vdb/.nvdb needs OpenVDB, and brume was built without OpenVDB");
        return 1;
    }
    if (check_output(o->out))
        return 2;
    int kind = pattern_kind(o->out);
    if (kind < 0 || (kind == 1) != o->frames) {
        if (kind < 0)
            return 2;
        else
            cli_error(o->frames ? "-o %s: --frames needs a frame pattern in the name (fire_%%04d.nvdb, fire_####.nvdb)"
                                : "-o %s: a frame pattern needs --frames A-B",
                      o->out);
        return 2;
    }
    if (o->frames && o->timed) {
        cli_error("gen fire: --time and --frames: a frame's time is f / --fps");
        return 2;
    }
    if (!o->frames)
        o->first = o->last = 0;
    /* every frame's request, checked at the last frame's time (the rise grows with time) */
    brume_fire fire = {.resolution = o->n, .seed = (uint64_t)o->seed, .height = o->height, .velocity = o->velocity,
                       .time = o->frames ? (double)o->last / o->fps : o->time, .max_memory_mb = o->max_memory_mb};
    if (!(fabs(brume_fire_rise(&fire)) <= 1e6)) {
        cli_error("gen fire: %s %g s: the turbulence would rise %g flame heights, beyond 1e6",
                  o->frames ? "the last frame at" : "--time", fire.time, brume_fire_rise(&fire));
        return 2;
    }
    return 0;
}

/* Operands are refused by every `gen` subcommand but upres's IN: -1 to go on, or the exit
 * status. */
static int parse_sparse(const cli_command *c, void *opts, int argc, char **argv, int max_operands,
                        const char **operand)
{
    const char *ops[1] = {NULL};
    int n = 0, rc = cli_flags_parse(c, opts, argc, argv, ops, max_operands, &n);
    if (operand)
        *operand = ops[0];
    return rc;
}

int gen_fire(int argc, char **argv)
{
    fire_opts o = {.n = 128, .seed = 1, .height = 2.0, .fps = 24.0, .first = 0, .last = -1};
    int rc = parse_sparse(&cli_gen_fire_command, &o, argc, argv, 0, NULL);
    if (rc >= 0 || (rc = fire_check(&o)) != 0)
        return rc;
    for (long f = o.first; f <= o.last; f++) {
        char name[4096];
        if (o.frames)
            (void)brume_sequence_name(NULL, o.out, f, name, sizeof name); /* a pattern, checked above */
        else
            snprintf(name, sizeof name, "%s", o.out);
        brume_fire fire = {.resolution = o.n, .seed = (uint64_t)o.seed, .height = o.height, .velocity = o.velocity,
                           .time = o.frames ? (double)f / o.fps : o.time, .max_memory_mb = o.max_memory_mb};
        brume_grid_gen_result res;
        brume_context *ctx = brume_context_new();
        brume_status st = ctx ? brume_grid_gen_fire(ctx, &fire, name, &res) : BRUME_ERROR_OUT_OF_MEMORY;
        if (st != BRUME_OK)
            cli_error("%.1000s", ctx ? brume_context_last_error(ctx) : "gen fire: out of memory");
        brume_context_release(ctx);
        if (st != BRUME_OK)
            return 1;
        printf("%s: %llu active voxels, index box %ld x %ld x %ld, voxel %g\n", name, res.active_voxels, res.box[0],
               res.box[1], res.box[2], res.voxel);
    }
    return 0;
}

/* The command line of `gen upres`. */
typedef struct upres_opts {
    brume_grid_file_options grid; /* first: the loading flags' (--grid, --max-memory) */
    const char *out;
    int factor, seed;
    double detail;
} upres_opts;

static bool upres_int(void *opts, const cli_flag *f, const char *v) { return sparse_int(opts, f, v, "gen upres"); }

static bool upres_detail(void *opts, const cli_flag *f, const char *v)
{
    double *d = &((upres_opts *)opts)->detail;
    return (cli_parse_doubles(v, d, 1) && *d >= 0.0 && *d <= 1.0) || bad_value("gen upres", f, v);
}

#define UOFF(field) offsetof(upres_opts, field)

static const cli_flag upres_flags[] = {
    {"--output", "-o", "OUT", "the grid: .vdb or .nvdb (required)", NULL, CLI_FLAG_STRING, UOFF(out), 0, 0, NULL},
    {"--factor", NULL, "F", "integer in [1, 16] (required)", NULL, CLI_FLAG_CALL, UOFF(factor), 1, 16, upres_int},
    {"--detail", NULL, "A", "detail amplitude in [0, 1] (default 0.5): density times 1 + A (2 n - 1), n turbulence",
     NULL, CLI_FLAG_CALL, 0, 0, 0, upres_detail},
    {"--seed", NULL, "N", "noise seed (default 1)", NULL, CLI_FLAG_CALL, UOFF(seed), 0, 2147483647.0, upres_int},
    CLI_LOAD_FLAG("--grid", "NAME", "the grid of IN (default: \"density\", else the only float grid)", "grid",
                  cli_grid_name),
    CLI_LOAD_FLAG("--max-memory", "B", "for IN (default 4G)", "max_memory_mb", cli_grid_max_memory),
};

const cli_command cli_gen_upres_command = {
    "gen upres", "a cloud upsampled by an integer factor with fractal detail, kept sparse",
    "IN(.vdb|.nvdb) --factor F -o OUT(.vdb|.nvdb) [options]",
    "IN's density grid upsampled F times per axis (trilinear) with fractal detail, kept sparse.\n",
    upres_flags, CLI_NFLAGS(upres_flags), NULL, NULL};

int gen_upres(int argc, char **argv)
{
    upres_opts o = {.out = NULL, .factor = 0, .seed = 1, .detail = 0.5};
    brume_grid_file_options_default(&o.grid); /* trilinear */
    const char *in = NULL;
    int rc = parse_sparse(&cli_gen_upres_command, &o, argc, argv, 1, &in);
    if (rc >= 0)
        return rc;
    if (!in || !o.out || !o.factor) {
        cli_error("gen upres: need IN, --factor F and -o OUT (see brume gen upres --help)");
        return 2;
    }
    if (!brume_grid_have_openvdb()) {
        cli_error("gen upres: writing .vdb/.nvdb needs OpenVDB, and brume was built without OpenVDB");
        return 1;
    }
    if (check_output(o.out))
        return 2;
    if (cli_check_output("-o", o.out, BRUME_FILE_GRID, NULL, NULL, &in, 1) != 0)
        return 1;
    brume_grid_gen_result res;
    brume_context *ctx = brume_context_new();
    brume_status st = ctx ? brume_grid_gen_upres(ctx, in, &o.grid, o.factor, (uint64_t)o.seed, o.detail, o.out, &res)
                          : BRUME_ERROR_OUT_OF_MEMORY;
    if (st != BRUME_OK)
        cli_error("%.1000s", ctx ? brume_context_last_error(ctx) : "gen upres: out of memory");
    brume_context_release(ctx);
    if (st != BRUME_OK)
        return 1;
    printf("%s: %llu active voxels, index box %ld x %ld x %ld, voxel %g\n", o.out, res.active_voxels, res.box[0],
           res.box[1], res.box[2], res.voxel);
    return 0;
}
