/* cli_gen_sparse.c - the command lines of `brume gen fire` (a procedural flame: density and
 * temperature grids, sparse, and its velocity) and `brume gen upres` (a cloud upsampled by an integer factor
 * with fractal detail, kept sparse); the grids are made and written through OpenVDB by
 * src/tool/gen_sparse.c (docs/grids.md). */
#include "cli_gen_sparse.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli_grid.h"
#include "commands.h"
#include "tool/tool.h"

static const char fire_usage[] =
    "usage: brume gen fire [flags] -o OUT(.vdb|.nvdb)\n"
    "       brume gen fire [flags] --frames A-B [--fps F] -o OUT_%04d.nvdb   (a file per frame)\n"
    "  a procedural flame: grids \"density\" (smoke and soot) and \"temperature\" (kelvin)\n"
    "  --resolution N   voxels along the height (default 128; width and depth N/2), [16, 2048]\n"
    "  --seed N         noise seed (default 1)\n"
    "  --height H       world height of the flame (default 2; the base is centred on the origin)\n"
    "  --velocity S     also a vec3 grid \"vel\": the updraft, S (0.5 + h) world units per second up at\n"
    "                   height fraction h with a sway of 0.3 S, over the whole box (default 0: none)\n"
    "  --time T         seconds: the turbulence has risen by S T (by T without --velocity) (default 0)\n"
    "  --frames A-B     frames A to B at times f / F, each to OUT with f in the frame pattern\n"
    "                   (%04d, ####, $F4: docs/grids.md, \"Sequences\"), in [0, 100000]\n"
    "  --fps F          frames per second, (0, 1000] (default 24, as render.fps)\n";

static const char upres_usage[] =
    "usage: brume gen upres IN(.vdb|.nvdb) --factor F -o OUT(.vdb|.nvdb) [flags]\n"
    "  IN's density grid upsampled F times per axis (trilinear) with fractal detail, kept sparse\n"
    "  --factor F       integer in [1, 16]\n"
    "  --detail A       detail amplitude in [0, 1] (default 0.5): density times 1 + A (2 n - 1), n turbulence\n"
    "  --seed N         noise seed (default 1)\n"
    "  --grid NAME      the grid of IN (default: \"density\", else the only float grid)\n"
    "  --max-memory B   for IN (default 4G)\n";

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

static bool parse_int(const char *s, long lo, long hi, long *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (!*s || *end || v < lo || v > hi)
        return false;
    *out = v;
    return true;
}

int gen_fire(int argc, char **argv)
{
    long n = 128, seed = 1, first = 0, last = -1;
    double height = 2.0, velocity = 0.0, time = 0.0, fps = 24.0;
    bool frames = false, timed = false;
    const char *out = NULL;
    for (int i = 1; i < argc; i++) {
        const char *f = argv[i];
        if (strcmp(f, "-h") == 0 || strcmp(f, "--help") == 0) {
            fputs(fire_usage, stdout);
            return 0;
        }
        if (i + 1 >= argc) {
            cli_error("gen fire: %s needs a value (see brume gen fire --help)", f);
            return 2;
        }
        const char *v = argv[++i];
        bool ok = true;
        if (strcmp(f, "-o") == 0 || strcmp(f, "--output") == 0)
            out = v;
        else if (strcmp(f, "--resolution") == 0)
            ok = parse_int(v, 16, 2048, &n);
        else if (strcmp(f, "--seed") == 0)
            ok = parse_int(v, 0, 2147483647L, &seed);
        else if (strcmp(f, "--height") == 0)
            ok = cli_parse_doubles(v, &height, 1) && height > 0.0 && height < 1e6;
        else if (strcmp(f, "--velocity") == 0)
            ok = cli_parse_doubles(v, &velocity, 1) && velocity >= 0.0 && velocity < 1e6;
        else if (strcmp(f, "--time") == 0)
            ok = (timed = cli_parse_doubles(v, &time, 1) && time >= -1e6 && time <= 1e6);
        else if (strcmp(f, "--fps") == 0)
            ok = cli_parse_doubles(v, &fps, 1) && fps > 0.0 && fps <= 1000.0;
        else if (strcmp(f, "--frames") == 0) {
            char *end;
            first = strtol(v, &end, 10);
            ok = end != v && *end == '-' && parse_int(end + 1, 0, 100000, &last) && first >= 0 && first <= last;
            frames = ok;
        } else {
            cli_error("gen fire: unknown flag %s (see brume gen fire --help)", f);
            return 2;
        }
        if (!ok) {
            cli_error("gen fire: bad value for %s: %s", f, v);
            return 2;
        }
    }
    if (!out) {
        cli_error("gen fire: no output file (-o OUT.vdb)");
        return 2;
    }
    if (!tool_grid_have_openvdb()) {
        cli_error("gen fire: writing .vdb/.nvdb needs OpenVDB, and brume was built without OpenVDB");
        return 1;
    }
    if (check_output(out))
        return 2;
    int kind = tool_seq_is_pattern(out);
    if (kind < 0 || (kind == 1) != frames) {
        if (kind < 0)
            cli_error("%.1000s", tool_last_error());
        else
            cli_error(frames ? "-o %s: --frames needs a frame pattern in the name (fire_%%04d.nvdb, fire_####.nvdb)"
                             : "-o %s: a frame pattern needs --frames A-B",
                      out);
        return 2;
    }
    if (frames && timed) {
        cli_error("gen fire: --time and --frames: a frame's time is f / --fps");
        return 2;
    }
    if (!frames)
        first = last = 0;
    /* every frame's time checked before the first file is written */
    double t_max = frames ? (double)last / fps : time;
    if (!(fabs(tool_gen_fire_rise(height, velocity, t_max)) <= 1e6)) {
        cli_error("gen fire: %s %g s: the turbulence would rise %g flame heights, beyond 1e6", frames ? "the last frame at"
                                                                                                          : "--time",
                  t_max, tool_gen_fire_rise(height, velocity, t_max));
        return 2;
    }
    for (long f = first; f <= last; f++) {
        char name[4096];
        if (frames)
            tool_seq_name(out, f, name, sizeof name);
        else
            snprintf(name, sizeof name, "%s", out);
        tool_gen_result res;
        if (tool_gen_fire(name, (int)n, (uint64_t)seed, height, velocity, frames ? (double)f / fps : time, &res) !=
            BRUME_OK) {
            cli_error("%.1000s", tool_last_error());
            return 1;
        }
        printf("%s: %llu active voxels, index box %ld x %ld x %ld, voxel %g\n", name, res.active, res.box[0],
               res.box[1], res.box[2], res.voxel);
    }
    return 0;
}

int gen_upres(int argc, char **argv)
{
    long factor = 0, seed = 1;
    double detail = 0.5;
    const char *in = NULL, *out = NULL;
    brume_grid_file_options o;
    brume_grid_file_options_default(&o); /* trilinear */
    for (int i = 1; i < argc; i++) {
        const char *f = argv[i];
        if (strcmp(f, "-h") == 0 || strcmp(f, "--help") == 0) {
            fputs(upres_usage, stdout);
            return 0;
        }
        if (f[0] != '-') {
            if (in) {
                cli_error("gen upres: unexpected argument %s", f);
                return 2;
            }
            in = f;
            continue;
        }
        if (strcmp(f, "--grid") == 0 || strcmp(f, "--max-memory") == 0) {
            int r = cli_load_flag("gen upres", argc, argv, &i, &o);
            if (r < 0)
                return 2;
            continue;
        }
        if (i + 1 >= argc) {
            cli_error("gen upres: %s needs a value (see brume gen upres --help)", f);
            return 2;
        }
        const char *v = argv[++i];
        bool ok = true;
        if (strcmp(f, "-o") == 0 || strcmp(f, "--output") == 0)
            out = v;
        else if (strcmp(f, "--factor") == 0)
            ok = parse_int(v, 1, 16, &factor);
        else if (strcmp(f, "--seed") == 0)
            ok = parse_int(v, 0, 2147483647L, &seed);
        else if (strcmp(f, "--detail") == 0)
            ok = cli_parse_doubles(v, &detail, 1) && detail >= 0.0 && detail <= 1.0;
        else {
            cli_error("gen upres: unknown flag %s (see brume gen upres --help)", f);
            return 2;
        }
        if (!ok) {
            cli_error("gen upres: bad value for %s: %s", f, v);
            return 2;
        }
    }
    if (!in || !out || !factor) {
        cli_error("gen upres: need IN, --factor F and -o OUT (see brume gen upres --help)");
        return 2;
    }
    if (!tool_grid_have_openvdb()) {
        cli_error("gen upres: writing .vdb/.nvdb needs OpenVDB, and brume was built without OpenVDB");
        return 1;
    }
    if (check_output(out))
        return 2;
    tool_gen_result res;
    if (tool_gen_upres(in, &o, (int)factor, (uint64_t)seed, detail, out, &res) != BRUME_OK) {
        cli_error("%.1000s", tool_last_error());
        return 1;
    }
    printf("%s: %llu active voxels, index box %ld x %ld x %ld, voxel %g\n", out, res.active, res.box[0], res.box[1],
           res.box[2], res.voxel);
    return 0;
}
