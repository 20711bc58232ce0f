/* scene_media.c - the public density and phase-function builders (brume.h): dense arrays
 * from memory (copied or borrowed), constants, the procedural and fractal generators, NanoVDB
 * buffers, grid files, Stam's blobs; the phase functions of phase/phase.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/budget.h"
#include "core/context.h"
#include "core/error.h"
#include "density/blobs.h"
#include "density/fractal.h"
#include "io/grid_io.h"
#include "scene/scene_build.h"

/* Majorant cells along the longest axis of a blob field, for path and single. */
#define BLOB_MAJORANT_CELLS 32

static const double BIG = 1e30;

/* Wraps d (NULL: the failure err_set() describes, prefixed by fn) into a new handle. */
static brume_status wrap(const char *fn, density *d, bool evolves, brume_density **out)
{
    if (!d)
        return err_prefix("%s", fn);
    brume_density *h = malloc(sizeof *h);
    if (!h) {
        density_release(d);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn);
    }
    h->d = d;
    h->evolves = evolves;
    *out = h;
    return BRUME_OK;
}

static brume_status check_filter(const char *fn, brume_grid_filter f)
{
    if (f != BRUME_GRID_NEAREST && f != BRUME_GRID_TRILINEAR)
        return err_set(BRUME_ERROR_RANGE, "%s: filter: unknown filter %d", fn, (int)f);
    return BRUME_OK;
}

static grid_filter to_filter(brume_grid_filter f) { return f == BRUME_GRID_NEAREST ? GRID_NEAREST : GRID_TRILINEAR; }

brume_status brume_density_new_array(brume_context *ctx, const float *data, int nx, int ny, int nz,
                                     const double bounds[6], brume_grid_filter filter, brume_release_fn release,
                                     void *user, brume_density **out)
{
    static const char fn[] = "brume_density_new_array";
    err_clear();
    if (!out)
        return ctx_report(ctx, build_null(fn, "out"));
    *out = NULL;
    if (!data || !bounds)
        return ctx_report(ctx, build_null(fn, !data ? "data" : "bounds"));
    int n[3] = {nx, ny, nz};
    for (int a = 0; a < 3; a++)
        if (n[a] < 1 || n[a] > 65536)
            return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: n%c: %d outside [1, 65536]", fn, "xyz"[a], n[a]));
    size_t count = (size_t)nx * (size_t)ny * (size_t)nz;
    if (count > DENSITY_DEFAULT_MAX_MEMORY / sizeof(float))
        return ctx_report(ctx, err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: %d x %d x %d values exceed %zu GiB", fn, nx,
                                       ny, nz, DENSITY_DEFAULT_MAX_MEMORY >> 30));
    box3 b;
    brume_status st;
    if ((st = build_box(fn, "bounds", bounds, &b)) || (st = check_filter(fn, filter)))
        return ctx_report(ctx, st);
    float *values;
    if (release) {
        values = (float *)(uintptr_t)data; /* borrowed: density/ only reads a grid's values */
    } else {
        values = malloc(count * sizeof *values);
        if (!values)
            return ctx_report(ctx, err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu values", fn, count));
        memcpy(values, data, count * sizeof *values);
    }
    density *d = density_new_grid(nx, ny, nz, values, b, to_filter(filter));
    if (!d) {
        if (!release)
            free(values);
        return ctx_report(ctx, err_prefix("%s: data", fn));
    }
    if (release)
        density_grid_borrow(d, release, user);
    return ctx_report(ctx, wrap(fn, d, false, out));
}

brume_status brume_density_new_constant(brume_context *ctx, double value, const double bounds[6],
                                        brume_density **out)
{
    static const char fn[] = "brume_density_new_constant";
    err_clear();
    if (!out)
        return ctx_report(ctx, build_null(fn, "out"));
    *out = NULL;
    box3 b;
    brume_status st;
    if ((st = build_need(fn, 1, "bounds", (const void *)bounds)) || (st = build_number(fn, "value", value, 0.0, BIG)) ||
        (st = build_box(fn, "bounds", bounds, &b)))
        return ctx_report(ctx, st);
    float *data = malloc(sizeof *data);
    if (!data)
        return ctx_report(ctx, err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn));
    data[0] = (float)value;
    density *d = density_new_grid(1, 1, 1, data, b, GRID_NEAREST);
    if (!d)
        free(data);
    return ctx_report(ctx, wrap(fn, d, false, out));
}

brume_status brume_density_new_procedural_cloud(brume_context *ctx, int resolution, uint64_t seed,
                                                const double bounds[6], brume_density **out)
{
    static const char fn[] = "brume_density_new_procedural_cloud";
    err_clear();
    if (!out)
        return ctx_report(ctx, build_null(fn, "out"));
    *out = NULL;
    box3 b;
    brume_status st;
    if ((st = build_need(fn, 1, "bounds", (const void *)bounds)) ||
        (st = build_number(fn, "resolution", resolution, 2, 512)) || (st = build_box(fn, "bounds", bounds, &b)))
        return ctx_report(ctx, st);
    return ctx_report(ctx, wrap(fn, density_new_procedural_cloud(resolution, seed, b), false, out));
}

brume_status brume_density_new_pbrt_cloud(brume_context *ctx, double dens, double wispiness, double frequency,
                                          const double bounds[6], brume_density **out)
{
    static const char fn[] = "brume_density_new_pbrt_cloud";
    err_clear();
    if (!out)
        return ctx_report(ctx, build_null(fn, "out"));
    *out = NULL;
    box3 b;
    brume_status st;
    if ((st = build_need(fn, 1, "bounds", (const void *)bounds)) || (st = build_number(fn, "density", dens, 0.0, BIG)) ||
        (st = build_number(fn, "wispiness", wispiness, 0.0, BIG)) ||
        (st = build_number(fn, "frequency", frequency, 0.0, BIG)) || (st = build_box(fn, "bounds", bounds, &b)))
        return ctx_report(ctx, st);
    pbrt_cloud c = {dens, wispiness, frequency, {b.lo.x, b.lo.y, b.lo.z}, {b.hi.x, b.hi.y, b.hi.z}};
    return ctx_report(ctx, wrap(fn, density_new_pbrt_cloud(&c), false, out));
}

brume_status brume_density_new_nanovdb(brume_context *ctx, const void *buffer, size_t size,
                                       brume_grid_filter filter, double scale, brume_density **out)
{
    static const char fn[] = "brume_density_new_nanovdb";
    err_clear();
    if (!out)
        return ctx_report(ctx, build_null(fn, "out"));
    *out = NULL;
    if (!buffer)
        return ctx_report(ctx, build_null(fn, "buffer"));
    brume_status st;
    if ((st = check_filter(fn, filter)) || (st = build_number(fn, "scale", scale, 1e-30, BIG)))
        return ctx_report(ctx, st);
    if (size == 0 || size > DENSITY_DEFAULT_MAX_MEMORY)
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: size: %zu bytes outside [1, %zu]", fn, size,
                                       DENSITY_DEFAULT_MAX_MEMORY));
    void *copy = malloc(size); /* malloc's alignment is at least the 8 bytes NanoVDB needs */
    if (!copy)
        return ctx_report(ctx, err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu bytes", fn, size));
    memcpy(copy, buffer, size);
    density *d = density_new_nanovdb(copy, size, to_filter(filter), NULL, scale, 0, "buffer");
    if (!d)
        free(copy);
    return ctx_report(ctx, wrap(fn, d, false, out));
}

void brume_grid_file_options_default(brume_grid_file_options *o)
{
    if (!o)
        return;
    memset(o, 0, sizeof *o);
    o->filter = BRUME_GRID_TRILINEAR;
    o->scale = 1.0;
    o->transform[0] = o->transform[5] = o->transform[10] = 1.0;
}

/* The public grid file options as the loader's (err_set naming fn and the field). */
_Static_assert((int)BRUME_GRID_FORMAT_AUTO == (int)GRID_FORMAT_AUTO && (int)BRUME_GRID_FORMAT_RAW == (int)GRID_FORMAT_RAW &&
                   (int)BRUME_GRID_FORMAT_DF3 == (int)GRID_FORMAT_DF3 && (int)BRUME_GRID_FORMAT_VOL == (int)GRID_FORMAT_VOL &&
                   (int)BRUME_GRID_FORMAT_NVDB == (int)GRID_FORMAT_NVDB && (int)BRUME_GRID_FORMAT_VDB == (int)GRID_FORMAT_VDB,
               "brume_grid_format and grid_format are one enum");

static brume_status file_options(const char *fn, const brume_grid_file_options *opts, density_load_options *out);

/* The count (1 or 3) fields of a grid file as public densities, within what the memory
 * budget of a scene being read has left (core/budget.h). */
static brume_status load_fields(brume_context *ctx, const char *fn, const char *path,
                                const brume_grid_file_options *opts, int count, bool any_sign, brume_density **out)
{
    err_clear();
    if (!out)
        return ctx_report(ctx, build_null(fn, "out"));
    for (int c = 0; c < count; c++)
        out[c] = NULL;
    if (!path)
        return ctx_report(ctx, build_null(fn, "path"));
    density_load_options o;
    brume_status st = file_options(fn, opts, &o);
    if (st)
        return ctx_report(ctx, st);
    o.any_sign = any_sign;
    size_t left = budget_left();
    if (left < o.max_memory)
        o.max_memory = left > 0 ? left : 1;
    density *d[3];
    if (!density_load_file_fields(path, &o, count, d))
        return ctx_report(ctx, err_status()); /* "PATH: reason" names the file */
    size_t bytes = 0; /* a vec3 grid's components share one buffer: count it once, and each one's majorants */
    for (int c = 0; c < count; c++) {
        density_info info;
        density_get_info(d[c], &info);
        bytes = c == 0 ? info.memory_bytes : bytes + info.memory_bytes - density_shared_bytes(d[c]);
    }
    if ((st = budget_take(bytes, path)) != BRUME_OK) {
        for (int c = 0; c < count; c++)
            density_release(d[c]);
        return ctx_report(ctx, st);
    }
    for (int c = 0; c < count; c++)
        if ((st = wrap(fn, d[c], false, &out[c])) != BRUME_OK) {
            for (int k = 0; k < c; k++) {
                brume_density_release(out[k]);
                out[k] = NULL;
            }
            for (int k = c + 1; k < count; k++)
                density_release(d[k]);
            return ctx_report(ctx, st);
        }
    return ctx_report(ctx, BRUME_OK);
}

brume_status brume_density_load(brume_context *ctx, const char *path, const brume_grid_file_options *opts,
                                brume_density **out)
{
    return load_fields(ctx, "brume_density_load", path, opts, 1, false, out);
}

brume_status brume_density_load_rgb(brume_context *ctx, const char *path, const brume_grid_file_options *opts,
                                    brume_density **out)
{
    return load_fields(ctx, "brume_density_load_rgb", path, opts, 3, false, out);
}

/* The grid named name in list[0..n), or NULL. */
static const gridvdb_info *find_grid(const gridvdb_info *list, int n, const char *name)
{
    for (int i = 0; i < n; i++)
        if (strcmp(list[i].name, name) == 0)
            return &list[i];
    return NULL;
}

brume_status brume_density_load_velocity(brume_context *ctx, const char *path, const brume_grid_file_options *opts,
                                         brume_density **out)
{
    static const char fn[] = "brume_density_load_velocity";
    err_clear();
    if (!out)
        return ctx_report(ctx, build_null(fn, "out"));
    for (int c = 0; c < 3; c++)
        out[c] = NULL;
    if (!path)
        return ctx_report(ctx, build_null(fn, "path"));
    brume_grid_file_options o;
    brume_grid_file_options_default(&o);
    if (opts)
        o = *opts;
    if (!memchr(o.grid, '\0', sizeof o.grid))
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: opts.grid: not NUL-terminated within 128 bytes", fn));
    char name[128];
    snprintf(name, sizeof name, "%s", o.grid[0] ? o.grid : "vel");
    /* the grids' types: a vec3 grid, or three float grids, never a float grid thrice */
    gridvdb_info *list = NULL;
    int n = 0;
    brume_status st = grid_list_file(path, DENSITY_DEFAULT_MAX_MEMORY, &list, &n);
    if (st)
        return ctx_report(ctx, st); /* "PATH: reason" */
    const gridvdb_info *g = find_grid(list, n, name);
    char comp[3][128];
    const gridvdb_info *gc[3];
    for (int c = 0; c < 3; c++) {
        snprintf(comp[c], sizeof comp[c], "%.125s.%c", name, "xyz"[c]);
        gc[c] = find_grid(list, n, comp[c]);
    }
    if (g && strncmp(g->type, "vec3", 4) != 0)
        st = err_set(BRUME_ERROR_UNSUPPORTED, "%s: grid \"%s\" is a %s grid: a velocity needs a vec3 grid (or three float "
                     "grids %s.x, %s.y, %s.z)", path, name, g->type, name, name, name);
    else if (!g && !(gc[0] && gc[1] && gc[2]))
        st = err_set(BRUME_ERROR_PARSE, "%s: no velocity grid \"%s\" (a vec3 grid, or float grids %s.x, %s.y, %s.z) "
                     "among its %d grids", path, name, name, name, name, n);
    for (int c = 0; !st && !g && c < 3; c++)
        if (strcmp(gc[c]->type, "float") != 0)
            st = err_set(BRUME_ERROR_UNSUPPORTED, "%s: grid \"%s\" is a %s grid: a velocity component needs a float grid",
                         path, comp[c], gc[c]->type);
    free(list);
    if (st)
        return ctx_report(ctx, st);
    if (g)
        return load_fields(ctx, fn, path, &o, 3, true, out);
    for (int c = 0; c < 3; c++) {
        memcpy(o.grid, comp[c], sizeof o.grid);
        if ((st = load_fields(ctx, fn, path, &o, 1, true, &out[c])) != BRUME_OK) {
            for (int k = 0; k < c; k++) {
                brume_density_release(out[k]);
                out[k] = NULL;
            }
            return st;
        }
    }
    return ctx_report(ctx, BRUME_OK);
}

static brume_status file_options(const char *fn, const brume_grid_file_options *opts, density_load_options *out)
{
    brume_grid_file_options def;
    if (!opts) {
        brume_grid_file_options_default(&def);
        opts = &def;
    }
    density_load_options o;
    density_load_options_default(&o);
    brume_status st;
    if ((unsigned)opts->format > (unsigned)BRUME_GRID_FORMAT_VDB)
        return err_set(BRUME_ERROR_RANGE, "%s: opts.format: %d is not a brume_grid_format", fn, (int)opts->format);
    o.format = (grid_format)opts->format;
    bool any_dims = opts->dims[0] || opts->dims[1] || opts->dims[2];
    for (int k = 0; k < 3 && any_dims; k++) {
        if (opts->dims[k] < 1 || opts->dims[k] > 65536)
            return err_set(BRUME_ERROR_RANGE, "%s: opts.dims[%d]: %d outside [1, 65536]", fn, k,
                                           opts->dims[k]);
        o.raw_dims[k] = opts->dims[k];
    }
    if (opts->has_bounds) {
        if ((st = build_box(fn, "opts.bounds", opts->bounds, &o.bounds)))
            return st;
        o.has_bounds = true;
    }
    if (opts->has_transform) {
        affine3 inv;
        memcpy(o.transform.m, opts->transform, sizeof o.transform.m);
        if (!affine3_invert(&o.transform, &inv))
            return err_set(BRUME_ERROR_RANGE, "%s: opts.transform: not finite and invertible", fn);
        o.has_transform = true;
    }
    if ((st = check_filter(fn, opts->filter)) || (st = build_number(fn, "opts.scale", opts->scale, 1e-30, BIG)))
        return st;
    o.filter = to_filter(opts->filter);
    o.scale = opts->scale;
    if (opts->max_memory_mb != 0.0) {
        if ((st = build_number(fn, "opts.max_memory_mb", opts->max_memory_mb, 1.0, 1e9)))
            return st;
        o.max_memory = (size_t)(opts->max_memory_mb * 1048576.0);
    }
    if (!memchr(opts->grid, '\0', sizeof opts->grid))
        return err_set(BRUME_ERROR_RANGE, "%s: opts.grid: not NUL-terminated within 128 bytes", fn);
    snprintf(o.grid, sizeof o.grid, "%s", opts->grid);
    o.edge_zero = opts->edge_zero;
    *out = o;
    return BRUME_OK;
}

void brume_fractal_default(brume_fractal *f)
{
    if (!f)
        return;
    fractal_params p;
    fractal_params_default(&p);
    memset(f, 0, sizeof *f);
    for (int a = 0; a < 3; a++)
        f->dims[a] = p.n[a];
    f->seed = p.seed;
    f->method = (brume_fractal_method)p.method;
    f->hurst = p.hurst;
    f->octaves = p.octaves;
    f->frequency = p.frequency;
    f->shape = (brume_fractal_shape)p.shape;
    f->falloff = p.falloff;
    f->threshold = p.threshold;
    f->threshold_rate = p.threshold_rate;
    f->turbulence = p.turbulence;
    f->turbulence_frequency = p.turbulence_frequency;
    f->wind[0] = p.wind.x;
    f->wind[1] = p.wind.y;
    f->wind[2] = p.wind.z;
    f->time = p.time;
    f->density = p.density;
    f->filter = BRUME_GRID_NEAREST;
}

brume_status brume_density_new_fractal(brume_context *ctx, const brume_fractal *f, brume_density **out)
{
    static const char fn[] = "brume_density_new_fractal";
    err_clear();
    if (!out)
        return ctx_report(ctx, build_null(fn, "out"));
    *out = NULL;
    if (!f)
        return ctx_report(ctx, build_null(fn, "fractal"));
    fractal_params p;
    fractal_params_default(&p);
    brume_status st = BRUME_OK;
    for (int k = 0; k < 3 && !st; k++) {
        char arg[32];
        snprintf(arg, sizeof arg, "fractal.dims[%d]", k);
        st = build_number(fn, arg, f->dims[k], 1, 1024);
        p.n[k] = f->dims[k];
    }
    if (!st && (int)f->method != BRUME_FRACTAL_MIDPOINT && f->method != BRUME_FRACTAL_SPECTRAL &&
        f->method != BRUME_FRACTAL_PERLIN)
        st = err_set(BRUME_ERROR_RANGE, "%s: fractal.method: unknown method %d", fn, (int)f->method);
    if (!st && (int)f->shape != BRUME_FRACTAL_SHAPE_NONE && f->shape != BRUME_FRACTAL_SHAPE_ELLIPSOID &&
        f->shape != BRUME_FRACTAL_SHAPE_SLAB)
        st = err_set(BRUME_ERROR_RANGE, "%s: fractal.shape: unknown shape %d", fn, (int)f->shape);
    vec3 wind = v3(0, 0, 0);
    if (st || (st = build_number(fn, "fractal.hurst", f->hurst, 1e-3, 0.999)) ||
        (st = build_number(fn, "fractal.octaves", f->octaves, 1, 16)) ||
        (st = build_number(fn, "fractal.frequency", f->frequency, 1e-3, 1e3)) ||
        (st = build_number(fn, "fractal.falloff", f->falloff, 1e-3, 1.0)) ||
        (st = build_number(fn, "fractal.threshold", f->threshold, 0.0, 0.99)) ||
        (st = build_number(fn, "fractal.threshold_rate", f->threshold_rate, -1e3, 1e3)) ||
        (st = build_number(fn, "fractal.turbulence", f->turbulence, 0.0, 1e3)) ||
        (st = build_number(fn, "fractal.turbulence_frequency", f->turbulence_frequency, 1e-3, 1e3)) ||
        (st = build_point(fn, "fractal.wind", f->wind, &wind)) ||
        (st = build_number(fn, "fractal.time", f->time, -1e12, 1e12)) ||
        (st = build_number(fn, "fractal.density", f->density, 1e-9, 1e9)) || (st = check_filter(fn, f->filter)))
        return ctx_report(ctx, st);
    fractal_params_from_api(f, &p); /* checked above; wind is finite */
    /* bounds all zero: unit voxels centred on the origin, as in the paper */
    box3 b = {v3(-0.5 * p.n[0], -0.5 * p.n[1], -0.5 * p.n[2]), v3(0.5 * p.n[0], 0.5 * p.n[1], 0.5 * p.n[2])};
    bool zero = true;
    for (int i = 0; i < 6; i++)
        zero = zero && f->bounds[i] == 0.0;
    if (!zero && (st = build_box(fn, "fractal.bounds", f->bounds, &b)))
        return ctx_report(ctx, st);
    bool evolves = p.threshold_rate != 0.0 || (p.turbulence > 0.0 && v3_length(p.wind) > 0.0);
    return ctx_report(ctx, wrap(fn, fractal_cloud(&p, b, to_filter(f->filter)), evolves, out));
}

void brume_blob_generator_default(brume_blob_generator *g, brume_blob_generator_type type)
{
    if (!g)
        return;
    memset(g, 0, sizeof *g);
    g->type = type;
    g->radii[0] = g->radii[1] = g->radii[2] = 1.0;
    g->bounds_min[0] = g->bounds_min[1] = g->bounds_min[2] = -1.0;
    g->bounds_max[0] = g->bounds_max[1] = g->bounds_max[2] = 1.0;
    g->radii_min[0] = g->radii_min[1] = g->radii_min[2] = 0.2;
    g->radii_max[0] = g->radii_max[1] = g->radii_max[2] = 0.5;
    g->clouds = 4;
    g->count = type == BRUME_BLOBS_FIRE ? 14 : 100;
    g->h[0] = 0.1;
    g->h[1] = 0.3;
    g->density = 1.0;
    g->falloff = 1.0;
    g->up[1] = 1.0;
    g->height = 1.0;
    g->radius = 0.2;
    g->fire_h = 0.15;
    g->band[1] = 1.0;
    g->seed = 1;
}

static brume_status check_radii(const char *fn, const char *arg, const double *r, vec3 *out)
{
    brume_status st = build_point(fn, arg, r, out);
    if (!st && !(out->x > 0.0 && out->y > 0.0 && out->z > 0.0))
        st = err_set(BRUME_ERROR_RANGE, "%s: %s: every semi-axis must be > 0", fn, arg);
    return st;
}

/* One generator's blobs appended to list. */
static brume_status generate(const char *fn, int i, const brume_blob_generator *g, blob_list *list)
{
    char a[12][48];
    static const char *const names[12] = {"count", "h", "density", "falloff", "center", "radii", "bounds_min",
                                          "bounds_max", "radii_min", "radii_max", "clouds", "height"};
    for (int k = 0; k < 12; k++)
        snprintf(a[k], sizeof a[k], "gens[%d].%s", i, names[k]);
    brume_status st;
    if ((st = build_number(fn, a[0], g->count, 1, 1 << 22)) || (st = build_number(fn, a[2], g->density, 0.0, BIG)))
        return st;
    if (g->type == BRUME_BLOBS_CLOUD || g->type == BRUME_BLOBS_CLUSTER) {
        blob_cloud_params p = {.count = g->count, .h_min = g->h[0], .h_max = g->h[1], .density = g->density,
                               .falloff = g->falloff, .seed = g->seed};
        if (!(g->h[0] >= 1e-9 && g->h[1] <= BIG && g->h[0] <= g->h[1]))
            return err_set(BRUME_ERROR_RANGE, "%s: %s: need 1e-09 <= min <= max, got [%.17g, %.17g]", fn, a[1], g->h[0],
                           g->h[1]);
        if ((st = build_number(fn, a[3], g->falloff, 0.0, 100.0)))
            return st;
        if (g->type == BRUME_BLOBS_CLOUD) {
            if ((st = build_point(fn, a[4], g->center, &p.center)) || (st = check_radii(fn, a[5], g->radii, &p.radii)))
                return st;
            st = blob_gen_cloud(&p, list);
        } else {
            box3 box;
            vec3 rmin, rmax;
            if ((st = build_point(fn, a[6], g->bounds_min, &box.lo)) ||
                (st = build_point(fn, a[7], g->bounds_max, &box.hi)) ||
                (st = check_radii(fn, a[8], g->radii_min, &rmin)) || (st = check_radii(fn, a[9], g->radii_max, &rmax)) ||
                (st = build_number(fn, a[10], g->clouds, 1, 100000)))
                return st;
            if (!(box.lo.x <= box.hi.x && box.lo.y <= box.hi.y && box.lo.z <= box.hi.z))
                return err_set(BRUME_ERROR_RANGE, "%s: gens[%d]: need bounds_min <= bounds_max", fn, i);
            if ((double)g->clouds * g->count > BLOB_MAX_COUNT) /* refused before generating any */
                return err_set(BRUME_ERROR_RANGE, "%s: gens[%d]: clouds x count = %d x %d blobs, more than the limit of %d",
                               fn, i, g->clouds, g->count, BLOB_MAX_COUNT);
            st = blob_gen_cluster(&p, box, rmin, rmax, g->clouds, list);
        }
    } else if (g->type == BRUME_BLOBS_FIRE) {
        blob_fire_params p = {.height = g->height, .radius = g->radius, .count = g->count, .h = g->fire_h,
                              .density = g->density, .seed = g->seed};
        char b1[48], b2[48], b3[48], b4[48];
        snprintf(b1, sizeof b1, "gens[%d].base", i);
        snprintf(b2, sizeof b2, "gens[%d].up", i);
        snprintf(b3, sizeof b3, "gens[%d].radius", i);
        snprintf(b4, sizeof b4, "gens[%d].fire_h", i);
        if ((st = build_point(fn, b1, g->base, &p.base)) || (st = build_point(fn, b2, g->up, &p.up)) ||
            (st = build_number(fn, a[11], g->height, 1e-9, BIG)) || (st = build_number(fn, b3, g->radius, 0.0, BIG)) ||
            (st = build_number(fn, b4, g->fire_h, 1e-9, BIG)))
            return st;
        if (!(g->band[0] >= 0.0 && g->band[1] <= 1.0 && g->band[0] <= g->band[1]))
            return err_set(BRUME_ERROR_RANGE, "%s: gens[%d].band: need 0 <= min <= max <= 1, got [%.17g, %.17g]", fn, i,
                           g->band[0], g->band[1]);
        p.band_lo = g->band[0];
        p.band_hi = g->band[1] >= 1.0 ? 1.0 + 1e-9 : g->band[1];
        st = blob_gen_fire(&p, list);
    } else {
        return err_set(BRUME_ERROR_RANGE, "%s: gens[%d].type: unknown generator %d", fn, i, (int)g->type);
    }
    return st ? err_prefix("%s: gens[%d]", fn, i) : BRUME_OK;
}

brume_status brume_density_new_blobs(brume_context *ctx, const double *blobs, int n,
                                     const brume_blob_generator *gens, int ngens, double cutoff,
                                     const double velocity[3], brume_density **out)
{
    static const char fn[] = "brume_density_new_blobs";
    err_clear();
    if (!out)
        return ctx_report(ctx, build_null(fn, "out"));
    *out = NULL;
    if (n > 0 && !blobs)
        return ctx_report(ctx, build_null(fn, "blobs"));
    if (ngens > 0 && !gens)
        return ctx_report(ctx, build_null(fn, "gens"));
    brume_status st;
    if ((st = build_number(fn, "n", n, 0, 1 << 24)) || (st = build_number(fn, "ngens", ngens, 0, 1 << 16)))
        return ctx_report(ctx, st);
    if (cutoff == 0.0)
        cutoff = BLOB_DEFAULT_CUTOFF;
    vec3 v = v3(0, 0, 0);
    if ((st = build_number(fn, "cutoff", cutoff, 1.0, 10.0)) || (velocity && (st = build_point(fn, "velocity", velocity, &v))))
        return ctx_report(ctx, st);
    blob_list list = {0};
    for (int i = 0; i < n && !st; i++) {
        const double *b = blobs + 5 * (size_t)i;
        if (!isfinite(b[0] + b[1] + b[2] + b[3] + b[4]) || b[3] < 0.0 || !(b[4] > 0.0))
            st = err_set(BRUME_ERROR_RANGE, "%s: blobs[%d]: expected finite x, y, z, mass >= 0, h > 0", fn, i);
        else
            st = blob_list_push(&list, (blob){v3(b[0], b[1], b[2]), b[3], b[4]});
    }
    for (int i = 0; i < ngens && !st; i++)
        st = generate(fn, i, &gens[i], &list);
    if (!st && list.n == 0)
        st = err_set(BRUME_ERROR_RANGE, "%s: no blobs (give blobs or generators)", fn);
    if (!st) {
        /* the work of the majorant grid, counted in O(n) before any of it is done */
        double pairs = blob_majorant_pairs(list.b, list.n, cutoff, BLOB_MAJORANT_CELLS);
        if (pairs > BLOB_MAX_PAIRS)
            st = err_set(BRUME_ERROR_RANGE,
                         "%s: %d blobs cover %.3g cells of the %d^3 majorant grid, more than the limit of %.3g "
                         "(fewer or smaller blobs; docs/scene-format.md#limits)",
                         fn, list.n, pairs, BLOB_MAJORANT_CELLS, BLOB_MAX_PAIRS);
    }
    if (st) {
        blob_list_free(&list);
        return ctx_report(ctx, st);
    }
    blob_field *f = blob_field_new(list.b, list.n, cutoff, fn);
    blob_list_free(&list);
    if (!f)
        return ctx_report(ctx, err_status());
    f->velocity = v;
    density *d = density_new_blobs(f, BLOB_MAJORANT_CELLS);
    if (!d)
        blob_field_release(f);
    return ctx_report(ctx, wrap(fn, d, false, out));
}

void brume_density_release(brume_density *d)
{
    if (!d)
        return;
    density_release(d->d);
    free(d);
}

/* ---- phase functions ---------------------------------------------------------------------- */

static brume_status wrap_phase(const char *fn, phase *p, brume_phase **out)
{
    if (!p)
        return err_prefix("%s", fn);
    brume_phase *h = malloc(sizeof *h);
    if (!h) {
        phase_release(p);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn);
    }
    h->p = p;
    *out = h;
    return BRUME_OK;
}

#define PHASE_BEGIN(name)                                                                                        \
    static const char fn[] = name;                                                                               \
    err_clear();                                                                                                 \
    if (!out)                                                                                                    \
        return ctx_report(ctx, build_null(fn, "out"));                                                           \
    *out = NULL

brume_status brume_phase_new_preset(brume_context *ctx, brume_phase_preset preset, brume_phase **out)
{
    PHASE_BEGIN("brume_phase_new_preset");
    phase *p = NULL;
    switch (preset) {
    case BRUME_PHASE_ISOTROPIC: p = phase_new_isotropic(); break;
    case BRUME_PHASE_RAYLEIGH: p = phase_new_rayleigh(); break;
    case BRUME_PHASE_HAZY: p = phase_new_mie_hazy(); break;
    case BRUME_PHASE_MURKY: p = phase_new_mie_murky(); break;
    default:
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: preset: %d is not a brume_phase_preset", fn, (int)preset));
    }
    return ctx_report(ctx, wrap_phase(fn, p, out));
}

brume_status brume_phase_new_hg(brume_context *ctx, double g, brume_phase **out)
{
    PHASE_BEGIN("brume_phase_new_hg");
    brume_status st = build_number(fn, "g", g, -0.999999, 0.999999);
    return ctx_report(ctx, st ? st : wrap_phase(fn, phase_new_hg(g), out));
}

brume_status brume_phase_new_schlick(brume_context *ctx, double k, brume_phase **out)
{
    PHASE_BEGIN("brume_phase_new_schlick");
    brume_status st = build_number(fn, "k", k, -0.999999, 0.999999);
    return ctx_report(ctx, st ? st : wrap_phase(fn, phase_new_schlick(k), out));
}

brume_status brume_phase_new_schlick_mix(brume_context *ctx, double r, double k, double kprime, brume_phase **out)
{
    PHASE_BEGIN("brume_phase_new_schlick_mix");
    brume_status st;
    if ((st = build_number(fn, "r", r, 0.0, 1.0)) || (st = build_number(fn, "k", k, -0.999999, 0.999999)) ||
        (st = build_number(fn, "kprime", kprime, -0.999999, 0.999999)))
        return ctx_report(ctx, st);
    return ctx_report(ctx, wrap_phase(fn, phase_new_schlick_mix(r, k, kprime), out));
}

brume_status brume_phase_new_tabulated(brume_context *ctx, const double *angle, const double *value, int n,
                                       brume_phase **out)
{
    PHASE_BEGIN("brume_phase_new_tabulated");
    if (!angle)
        return ctx_report(ctx, build_null(fn, "angle"));
    if (!value)
        return ctx_report(ctx, build_null(fn, "value"));
    brume_status st = build_number(fn, "n", n, 2, 1 << 20);
    return ctx_report(ctx, st ? st : wrap_phase(fn, phase_new_tabulated(n, angle, value), out));
}

brume_status brume_phase_load(brume_context *ctx, const char *path, brume_phase **out)
{
    PHASE_BEGIN("brume_phase_load");
    if (!path)
        return ctx_report(ctx, build_null(fn, "path"));
    phase *p = phase_load_tabulated(path);
    if (!p)
        return ctx_report(ctx, err_status()); /* names the file */
    return ctx_report(ctx, wrap_phase(fn, p, out));
}

brume_status brume_phase_new_mixture(brume_context *ctx, const double *weights, brume_phase *const *lobes, int n,
                                     brume_phase **out)
{
    PHASE_BEGIN("brume_phase_new_mixture");
    if (!weights)
        return ctx_report(ctx, build_null(fn, "weights"));
    if (!lobes)
        return ctx_report(ctx, build_null(fn, "lobes"));
    brume_status st = build_number(fn, "n", n, 1, 16);
    if (st)
        return ctx_report(ctx, st);
    phase *ph[16];
    for (int i = 0; i < n; i++) {
        char arg[32];
        snprintf(arg, sizeof arg, "weights[%d]", i);
        if ((st = build_number(fn, arg, weights[i], 0.0, BIG)))
            return ctx_report(ctx, st);
        if (!lobes[i]) {
            snprintf(arg, sizeof arg, "lobes[%d]", i);
            return ctx_report(ctx, build_null(fn, arg));
        }
        ph[i] = lobes[i]->p;
    }
    brume_phase *h = malloc(sizeof *h);
    if (!h)
        return ctx_report(ctx, err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn));
    h->p = phase_new_mixture(n, weights, ph); /* on success it owns the lobes */
    if (!h->p) {
        free(h);
        return ctx_report(ctx, err_prefix("%s", fn));
    }
    for (int i = 0; i < n; i++)
        free(lobes[i]);
    *out = h;
    return ctx_report(ctx, BRUME_OK);
}

void brume_phase_release(brume_phase *p)
{
    if (!p)
        return;
    phase_release(p->p);
    free(p);
}
