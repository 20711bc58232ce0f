/* gen_sparse.c - `brume gen fire` (a procedural flame: density and temperature grids,
 * sparse, and optionally its updraft as a velocity grid) and `brume gen upres` (a cloud
 * upsampled by an integer factor with fractal detail, kept sparse), written through OpenVDB as
 * .vdb or .nvdb (docs/grids.md; brume.h, "Grid files"). */
#include "brume.h"

#include <math.h>
#include <string.h>

#include "core/error.h"
#include "io/atomic.h"
#include "density/fractal.h"
#include "io/grid_io.h"
#include "io/grid_vdb.h"
#include "core/context.h"
#include "scene/scene_build.h"
#include "tool/tool_grid.h"

/* What OpenVDB's trees take per active float voxel, bytes: the value and a leaf's share of
 * its masks and node (a leaf of 8^3 voxels is about 2.2 KB), for grids whose active voxels
 * fill their leaves as the generators' solid shapes do. */
#define GEN_BYTES_PER_VOXEL 4.4

/* The status of the failure just reported (an I/O error if the callee set none). */
static brume_status failed(void) { return err_status() != BRUME_OK ? err_status() : BRUME_ERROR_IO; }

/* BRUME_OK when out names a .vdb or .nvdb file and this build has OpenVDB. */
static brume_status check_out(const char *fn, const char *out)
{
    const char *dot = strrchr(out, '.');
    if (!dot || (strcmp(dot, ".nvdb") != 0 && strcmp(dot, ".vdb") != 0))
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s: the output must be .vdb or .nvdb", fn, out);
    if (!grid_have_openvdb())
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: writing .vdb/.nvdb needs OpenVDB, and brume was built without it",
                       fn);
    return BRUME_OK;
}

/* BRUME_OK when a tree of `voxels` active float voxels in `grids` grids fits max_memory_mb
 * (0: 4096 MiB). */
static brume_status check_memory(const char *fn, const char *what, double voxels, double grids, double max_memory_mb)
{
    double mb = max_memory_mb > 0.0 ? max_memory_mb : 4096.0;
    double need = voxels * grids * GEN_BYTES_PER_VOXEL / 1048576.0;
    if (need > mb)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: %s: the grids would take up to %.0f MiB, over the budget of %g MiB",
                       fn, what, ceil(need), mb);
    return BRUME_OK;
}

/* Writes the grids through a temporary file renamed over `out` (io/atomic.h); out ends in
 * .vdb or .nvdb (the caller checked). */
static brume_status save(gridvdb_writer *w, const char *out)
{
    const char *dot = strrchr(out, '.');
    int nano = dot && strcmp(dot, ".nvdb") == 0;
    atomic_file af;
    if (atomic_open_kind(&af, out, BRUME_FILE_GRID) != BRUME_OK)
        return failed();
    /* OpenVDB writes the temporary file by name: the stream is closed first */
    fclose(af.fp);
    af.fp = NULL;
    if (gridvdb_writer_save(w, af.tmp_path, nano) != BRUME_OK) {
        err_prefix("%s", out);
        brume_status st = failed();
        atomic_abort(&af);
        return st;
    }
    return atomic_commit(&af);
}

static double smoothstep(double a, double b, double x)
{
    double t = x <= a ? 0.0 : (x >= b ? 1.0 : (x - a) / (b - a));
    return t * t * (3.0 - 2.0 * t);
}

/* In time the noise rises through the flame's fixed envelope at the updraft's speed at
 * mid-height: in flame heights, at time t (the loop of brume_grid_gen_fire reads it at h - rise). */
double brume_fire_rise(const brume_fire *fire)
{
    if (!fire || !(fire->height > 0.0))
        return NAN;
    return (fire->velocity > 0.0 ? fire->velocity : 1.0) * fire->time / fire->height;
}

void brume_fire_default(brume_fire *fire)
{
    if (fire)
        *fire = (brume_fire){.resolution = 128, .seed = 1, .height = 2.0};
}

/* The request's numbers in the ranges the generator supports. */
static brume_status fire_check(const char *fn, const brume_fire *f)
{
    brume_status st;
    if ((st = build_number(fn, "fire.resolution", f->resolution, 16, 2048)) ||
        (st = build_number(fn, "fire.height", f->height, 0x1p-1022, 1e6)) ||
        (st = build_number(fn, "fire.velocity", f->velocity, 0.0, 1e6)) ||
        (st = build_number(fn, "fire.time", f->time, -1e6, 1e6)) ||
        (st = build_number(fn, "fire.max_memory_mb", f->max_memory_mb, 0.0, 1e9)))
        return st;
    const double rise = brume_fire_rise(f);
    if (!(fabs(rise) <= 1e6)) /* the noise's lattice index is an int: keep it well inside */
        return err_set(BRUME_ERROR_RANGE, "%s: at time %g s the turbulence would rise %g flame heights, beyond 1e6",
                       fn, f->time, rise);
    double voxels = (double)f->resolution * (double)(f->resolution / 2) * (double)(f->resolution / 2);
    char what[64];
    snprintf(what, sizeof what, "fire.resolution %d", f->resolution);
    return check_memory(fn, what, voxels, f->velocity > 0.0 ? 5.0 : 2.0, f->max_memory_mb);
}

brume_status brume_grid_gen_fire(brume_context *ctx, const brume_fire *fire, const char *out,
                                 brume_grid_gen_result *res)
{
    static const char fn[] = "brume_grid_gen_fire";
    err_clear();
    brume_status st = build_need(fn, 3, "fire", fire, "out", out, "result", res);
    if (st || (st = fire_check(fn, fire)) || (st = check_out(fn, out)))
        return ctx_report(ctx, st);
    const int n = fire->resolution;
    const double height = fire->height, velocity = fire->velocity, rise = brume_fire_rise(fire);
    perlin_table pt;
    perlin_init(&pt, fire->seed);
    gridvdb_writer *w = gridvdb_writer_new();
    if (!w) {
        err_prefix("gen fire");
        return ctx_report(ctx, failed());
    }
    double vs = height / (double)n;
    int half = n / 4;
    const double origin[3] = {0.5 * vs, 0.5 * vs, 0.5 * vs}; /* index (I, J, K) centred at ((I + 1/2) vs, ...) */
    int gd = gridvdb_writer_add(w, "density", 0, vs, origin), gt = gridvdb_writer_add(w, "temperature", 0, vs, origin);
    int gv = velocity > 0.0 ? gridvdb_writer_add(w, "vel", 1, vs, origin) : -2;
    if (gd < 0 || gt < 0 || gv == -1) {
        err_prefix("gen fire");
        st = failed();
        gridvdb_writer_free(w);
        return ctx_report(ctx, st);
    }
    /* Normalized coordinates: h in [0, 1) up the flame, (x, z) across, |x|, |z| < 1/4. The
     * flame core narrows and cools with height; smoke widens above it; turbulence, growing
     * with height, displaces both and breaks them into licks and puffs. In time the noise
     * rises through the fixed envelope (hn: the height it is read at) at the updraft's speed
     * at mid-height, in heights per second. */

    for (int j = 0; j < n; j++)
        for (int k = 0; k < 2 * half; k++)
            for (int i = 0; i < 2 * half; i++) {
                double x = (i - half + 0.5) / (double)n, h = (j + 0.5) / (double)n, z = (k - half + 0.5) / (double)n;
                vec3 q = v3(x, h, z);
                double sway = 0.06 * h, hn = h - rise;
                const double nx = perlin_noise(&pt, v3(3.0 * x, 2.5 * hn, 3.0 * z)),
                             nz = perlin_noise(&pt, v3(3.0 * x + 17.0, 2.5 * hn, 3.0 * z - 5.0));
                q.x += sway * nx;
                q.z += sway * nz;
                double d = sqrt(q.x * q.x + q.z * q.z);
                double turb = perlin_turbulence(&pt, v3(9.0 * q.x, 5.0 * hn, 9.0 * q.z), 4);
                double rf = 0.11 * (1.0 - h) * (1.0 - h) + 0.015; /* flame radius */
                double core = fmax(0.0, 1.0 - d / rf) * (1.0 - smoothstep(0.35, 0.8, h));
                double T = 300.0 + 1700.0 * core * (0.55 + 0.9 * turb);
                double rs = 0.04 + 0.16 * h; /* smoke radius */
                double smoke = pow(fmax(0.0, 1.0 - d / rs), 1.5) * smoothstep(0.2, 0.6, h) * (0.2 + 1.6 * turb);
                double rho = smoke + 0.6 * core * (0.5 + turb);
                if (gv >= 0) {
                    /* the updraft, over the whole box (a lookup moves density from where
                     * there is none yet): rising faster with height, swaying with the noise
                     * that bends the flame; world units per second */
                    float v[3] = {(float)(velocity * 0.3 * nx), (float)(velocity * (0.5 + h)),
                                  (float)(velocity * 0.3 * nz)};
                    gridvdb_writer_set(w, gv, i - half, j, k - half, v);
                }
                if (rho < 2e-3)
                    continue;
                float fv = (float)rho, ft = (float)T;
                gridvdb_writer_set(w, gd, i - half, j, k - half, &fv);
                gridvdb_writer_set(w, gt, i - half, j, k - half, &ft);
            }
    st = save(w, out);
    if (st == BRUME_OK)
        *res = (brume_grid_gen_result){gridvdb_writer_active(w, gd), {2 * (long)half, n, 2 * (long)half}, vs};
    gridvdb_writer_free(w);
    return ctx_report(ctx, st);
}

/* Whether a trilinear lookup can see source voxel (i, j, k) as non-zero: it or a neighbour is. */
static bool near_nonzero(const density *src, const int n[3], int i, int j, int k)
{
    for (int q = 0; q < 27; q++) {
        int a = i + q % 3 - 1, b = j + (q / 3) % 3 - 1, c = k + q / 9 - 1;
        if (a >= 0 && b >= 0 && c >= 0 && a < n[0] && b < n[1] && c < n[2] && density_voxel(src, a, b, c) > 0.0)
            return true;
    }
    return false;
}

/* The upsampled voxels of source voxel (i, j, k): F^3 fine voxels with fractal detail. */
static void upres_voxel(gridvdb_writer *w, int g, const density *src, const affine3 *to_world, const perlin_table *pt,
                        int F, double freq, double detail, int i, int j, int k)
{
    for (int c = 0; c < F; c++)
        for (int b = 0; b < F; b++)
            for (int a = 0; a < F; a++) {
                vec3 u = v3(i + (a + 0.5) / F, j + (b + 0.5) / F, k + (c + 0.5) / F);
                vec3 p = affine3_apply(to_world, u);
                double v = density_eval(src, p);
                if (v <= 0.0)
                    continue;
                double t = perlin_turbulence(pt, v3_scale(p, freq), 3);
                v *= fmax(0.0, 1.0 + detail * (2.0 * fmin(t, 1.0) - 1.0));
                if (v < 1e-4)
                    continue;
                float fvv = (float)v;
                gridvdb_writer_set(w, g, i * F + a, j * F + b, k * F + c, &fvv);
            }
}

/* The source's placement, checked: BRUME_OK for an axis-aligned grid of cubic voxels, and
 * then near's count of the voxels a lookup sees, within the fine grid's memory budget. */
static brume_status upres_check(const char *fn, const char *in, const density *src, const density_info *info,
                                int factor, double max_memory_mb)
{
    const double *m = info->voxel_to_world.m;
    double vs = m[0];
    if (!(vs > 0.0) || m[1] != 0.0 || m[2] != 0.0 || m[4] != 0.0 || m[6] != 0.0 || m[8] != 0.0 || m[9] != 0.0 ||
        m[5] != vs || m[10] != vs)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: gen upres needs an axis-aligned grid with cubic voxels", in);
    double near = 0.0;
    for (int k = 0; k < info->n[2]; k++)
        for (int j = 0; j < info->n[1]; j++)
            for (int i = 0; i < info->n[0]; i++)
                near += near_nonzero(src, info->n, i, j, k);
    char what[64];
    snprintf(what, sizeof what, "factor %d", factor);
    return check_memory(fn, what, near * factor * factor * factor, 1.0, max_memory_mb);
}

brume_status brume_grid_gen_upres(brume_context *ctx, const char *in, const brume_grid_file_options *o, int factor,
                                  uint64_t seed, double detail, const char *out, brume_grid_gen_result *res)
{
    static const char fn[] = "brume_grid_gen_upres";
    err_clear();
    brume_status st = build_need(fn, 3, "in", in, "out", out, "result", res);
    if (st || (st = build_number(fn, "factor", factor, 1, 16)) || (st = build_number(fn, "detail", detail, 0.0, 1.0)) ||
        (st = check_out(fn, out)))
        return ctx_report(ctx, st);
    brume_density *h = NULL;
    if ((st = brume_density_load(NULL, in, o, &h)) != BRUME_OK)
        return ctx_report(ctx, st);
    const density *src = h->d;
    density_info info;
    density_get_info(src, &info);
    if ((st = upres_check(fn, in, src, &info, factor, o ? o->max_memory_mb : 0.0)) != BRUME_OK) {
        brume_density_release(h);
        return ctx_report(ctx, st);
    }
    const double *m = info.voxel_to_world.m;
    perlin_table pt;
    perlin_init(&pt, seed);
    gridvdb_writer *w = gridvdb_writer_new();
    double fv = m[0] / (double)factor;
    /* fine voxel (I, J, K) has its centre at source voxel space ((I + 1/2) / F, ...) */
    const double origin[3] = {m[3] + 0.5 * fv, m[7] + 0.5 * fv, m[11] + 0.5 * fv};
    int g = w ? gridvdb_writer_add(w, "density", 0, fv, origin) : -1;
    if (g < 0) {
        err_prefix("gen upres");
        st = failed();
        gridvdb_writer_free(w);
        brume_density_release(h);
        return ctx_report(ctx, st);
    }
    /* detail at about 4 fine voxels, whatever the factor: the same features at each F */
    double freq = 1.0 / (4.0 * fv);
    for (int k = 0; k < info.n[2]; k++)
        for (int j = 0; j < info.n[1]; j++)
            for (int i = 0; i < info.n[0]; i++)
                if (near_nonzero(src, info.n, i, j, k))
                    upres_voxel(w, g, src, &info.voxel_to_world, &pt, factor, freq, detail, i, j, k);
    brume_density_release(h);
    st = save(w, out);
    if (st == BRUME_OK)
        *res = (brume_grid_gen_result){gridvdb_writer_active(w, g),
                                       {(long)info.n[0] * factor, (long)info.n[1] * factor, (long)info.n[2] * factor},
                                       fv};
    gridvdb_writer_free(w);
    return ctx_report(ctx, st);
}
