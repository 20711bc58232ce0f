/* cli_gen_sparse.c - `brume gen fire` (a procedural flame: density and temperature grids,
 * sparse) and `brume gen upres` (a cloud upsampled by an integer factor with fractal
 * detail, kept sparse), written through OpenVDB as .vdb or .nvdb (docs/grids.md). */
#include "cli_gen_sparse.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli_grid.h"
#include "commands.h"
#include "tool/tool.h"
#include "density/fractal.h"
#include "io/grid_vdb.h"

static const char fire_usage[] =
    "usage: brume gen fire [flags] -o OUT(.vdb|.nvdb)\n"
    "  a procedural flame: grids \"density\" (smoke and soot) and \"temperature\" (kelvin)\n"
    "  --resolution N   voxels along the height (default 128; width and depth N/2), [16, 2048]\n"
    "  --seed N         noise seed (default 1)\n"
    "  --height H       world height of the flame (default 2; the base is centred on the origin)\n";

static const char upres_usage[] =
    "usage: brume gen upres IN(.vdb|.nvdb) --factor F -o OUT(.vdb|.nvdb) [flags]\n"
    "  IN's density grid upsampled F times per axis (trilinear) with fractal detail, kept sparse\n"
    "  --factor F       integer in [1, 16]\n"
    "  --detail A       detail amplitude in [0, 1] (default 0.5): density times 1 + A (2 n - 1), n turbulence\n"
    "  --seed N         noise seed (default 1)\n"
    "  --grid NAME      the grid of IN (default: \"density\", else the only float grid)\n"
    "  --max-memory B   for IN (default 4G)\n";

/* Writes the grids through a temporary file renamed over `out` (tool_file). */
static int save(gridvdb_writer *w, const char *out)
{
    const char *dot = strrchr(out, '.');
    int nano = dot && strcmp(dot, ".nvdb") == 0;
    if (!dot || (!nano && strcmp(dot, ".vdb") != 0)) {
        cli_error("%s: the output must be .vdb or .nvdb", out);
        return 2;
    }
    tool_file *af = tool_file_open(out);
    if (!af) {
        cli_error("%.1000s", tool_last_error());
        return 1;
    }
    /* OpenVDB writes the temporary file by name */
    if (gridvdb_writer_save(w, tool_file_by_name(af), nano) != BRUME_OK) {
        cli_error("%s: %.1000s", out, tool_last_error());
        tool_file_abort(af);
        return 1;
    }
    if (tool_file_commit(af) != BRUME_OK) {
        cli_error("%.1000s", tool_last_error());
        return 1;
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

static double smoothstep(double a, double b, double x)
{
    double t = x <= a ? 0.0 : (x >= b ? 1.0 : (x - a) / (b - a));
    return t * t * (3.0 - 2.0 * t);
}

int gen_fire(int argc, char **argv)
{
    long n = 128, seed = 1;
    double height = 2.0;
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
        else {
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
    if (!grid_have_openvdb()) {
        cli_error("gen fire: writing .vdb/.nvdb needs OpenVDB, and brume was built without OpenVDB");
        return 1;
    }
    perlin_table pt;
    perlin_init(&pt, (uint64_t)seed);
    gridvdb_writer *w = gridvdb_writer_new();
    if (!w) {
        cli_error("gen fire: %.1000s", tool_last_error());
        return 1;
    }
    double vs = height / (double)n;
    int half = (int)(n / 4);
    const double origin[3] = {0.5 * vs, 0.5 * vs, 0.5 * vs}; /* index (I, J, K) centred at ((I + 1/2) vs, ...) */
    int gd = gridvdb_writer_add(w, "density", 0, vs, origin), gt = gridvdb_writer_add(w, "temperature", 0, vs, origin);
    if (gd < 0 || gt < 0) {
        cli_error("gen fire: %.1000s", tool_last_error());
        gridvdb_writer_free(w);
        return 1;
    }
    /* Normalized coordinates: h in [0, 1) up the flame, (x, z) across, |x|, |z| < 1/4. The
     * flame core narrows and cools with height; smoke widens above it; turbulence, growing
     * with height, displaces both and breaks them into licks and puffs. */
    for (int j = 0; j < n; j++)
        for (int k = 0; k < 2 * half; k++)
            for (int i = 0; i < 2 * half; i++) {
                double x = (i - half + 0.5) / (double)n, h = (j + 0.5) / (double)n, z = (k - half + 0.5) / (double)n;
                vec3 q = v3(x, h, z);
                double sway = 0.06 * h;
                q.x += sway * perlin_noise(&pt, v3(3.0 * x, 2.5 * h - 0.0, 3.0 * z));
                q.z += sway * perlin_noise(&pt, v3(3.0 * x + 17.0, 2.5 * h, 3.0 * z - 5.0));
                double d = sqrt(q.x * q.x + q.z * q.z);
                double turb = perlin_turbulence(&pt, v3(9.0 * q.x, 5.0 * h, 9.0 * q.z), 4);
                double rf = 0.11 * (1.0 - h) * (1.0 - h) + 0.015; /* flame radius */
                double core = fmax(0.0, 1.0 - d / rf) * (1.0 - smoothstep(0.35, 0.8, h));
                double T = 300.0 + 1700.0 * core * (0.55 + 0.9 * turb);
                double rs = 0.04 + 0.16 * h; /* smoke radius */
                double smoke = pow(fmax(0.0, 1.0 - d / rs), 1.5) * smoothstep(0.2, 0.6, h) * (0.2 + 1.6 * turb);
                double rho = smoke + 0.6 * core * (0.5 + turb);
                if (rho < 2e-3)
                    continue;
                float fv = (float)rho, ft = (float)T;
                gridvdb_writer_set(w, gd, i - half, j, k - half, &fv);
                gridvdb_writer_set(w, gt, i - half, j, k - half, &ft);
            }
    int rc = save(w, out);
    if (rc == 0)
        printf("%s: %llu active voxels, index box %ld x %ld x %ld, voxel %g\n", out, gridvdb_writer_active(w, gd),
               2 * (long)half, n, 2 * (long)half, vs);
    gridvdb_writer_free(w);
    return rc;
}

int gen_upres(int argc, char **argv)
{
    long factor = 0, seed = 1;
    double detail = 0.5;
    const char *in = NULL, *out = NULL;
    density_load_options o;
    density_load_options_default(&o);
    o.filter = GRID_TRILINEAR;
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
    if (!grid_have_openvdb()) {
        cli_error("gen upres: writing .vdb/.nvdb needs OpenVDB, and brume was built without OpenVDB");
        return 1;
    }
    density *src = density_load_file(in, &o);
    if (!src) {
        cli_error("%.1000s", tool_last_error());
        return 1;
    }
    density_info info;
    density_get_info(src, &info);
    const double *m = info.voxel_to_world.m;
    double vs = m[0];
    if (!(vs > 0.0) || m[1] != 0.0 || m[2] != 0.0 || m[4] != 0.0 || m[6] != 0.0 || m[8] != 0.0 || m[9] != 0.0 ||
        m[5] != vs || m[10] != vs) {
        cli_error("%s: gen upres needs an axis-aligned grid with cubic voxels", in);
        density_release(src);
        return 1;
    }
    perlin_table pt;
    perlin_init(&pt, (uint64_t)seed);
    gridvdb_writer *w = gridvdb_writer_new();
    double fv = vs / (double)factor;
    /* fine voxel (I, J, K) has its centre at source voxel space ((I + 1/2) / F, ...) */
    const double origin[3] = {m[3] + 0.5 * fv, m[7] + 0.5 * fv, m[11] + 0.5 * fv};
    int g = w ? gridvdb_writer_add(w, "density", 0, fv, origin) : -1;
    if (g < 0) {
        cli_error("gen upres: %.1000s", tool_last_error());
        gridvdb_writer_free(w);
        density_release(src);
        return 1;
    }
    int F = (int)factor;
    /* detail at about 4 fine voxels, whatever the factor: the same features at each F */
    double freq = 1.0 / (4.0 * fv);
    for (int k = 0; k < info.n[2]; k++)
        for (int j = 0; j < info.n[1]; j++)
            for (int i = 0; i < info.n[0]; i++) {
                /* only source voxels that a trilinear lookup can see as non-zero */
                double near = 0.0;
                for (int q = 0; q < 27 && near <= 0.0; q++) {
                    int a = i + q % 3 - 1, b = j + (q / 3) % 3 - 1, c = k + q / 9 - 1;
                    if (a >= 0 && b >= 0 && c >= 0 && a < info.n[0] && b < info.n[1] && c < info.n[2])
                        near = density_voxel(src, a, b, c);
                }
                if (near <= 0.0)
                    continue;
                for (int c = 0; c < F; c++)
                    for (int b = 0; b < F; b++)
                        for (int a = 0; a < F; a++) {
                            vec3 u = v3(i + (a + 0.5) / F, j + (b + 0.5) / F, k + (c + 0.5) / F);
                            vec3 p = affine3_apply(&info.voxel_to_world, u);
                            double v = density_eval(src, p);
                            if (v <= 0.0)
                                continue;
                            double t = perlin_turbulence(&pt, v3_scale(p, freq), 3);
                            v *= fmax(0.0, 1.0 + detail * (2.0 * fmin(t, 1.0) - 1.0));
                            if (v < 1e-4)
                                continue;
                            float fvv = (float)v;
                            gridvdb_writer_set(w, g, i * F + a, j * F + b, k * F + c, &fvv);
                        }
            }
    density_release(src);
    int rc = save(w, out);
    if (rc == 0)
        printf("%s: %llu active voxels, index box %d x %d x %d, voxel %g\n", out, gridvdb_writer_active(w, g),
               info.n[0] * F, info.n[1] * F, info.n[2] * F, fv);
    gridvdb_writer_free(w);
    return rc;
}
