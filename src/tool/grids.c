/* grids.c - the public grid-file calls of `brume info`, `convert` and `gen cloud` (brume.h,
 * "Grid files") over io/grid_io.h. */
#include "brume.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/error.h"
#include "core/regular_file.h"
#include "io/grid_io.h"
#include "io/grid_sequence.h"
#include "scene/scene_build.h"
#include "tool/tool_grid.h"

bool brume_grid_have_openvdb(void) { return grid_have_openvdb(); }

bool brume_grid_format_from_name(const char *name, brume_grid_format *out)
{
    if (!name || !out)
        return false;
    grid_format f = grid_format_from_name(name);
    if (f == GRID_FORMAT_AUTO && strcmp(name, "auto") != 0)
        return false;
    *out = (brume_grid_format)f; /* one enum (scene/scene_media.c asserts it) */
    return true;
}

const char *brume_grid_format_name(brume_grid_format format)
{
    return (unsigned)format <= (unsigned)BRUME_GRID_FORMAT_VDB ? grid_format_name((grid_format)format) : NULL;
}

brume_grid_format brume_grid_format_of(const char *path)
{
    if (!path)
        return BRUME_GRID_FORMAT_AUTO;
    grid_format f = grid_format_detect(path, NULL, 0);
    if (f != GRID_FORMAT_AUTO)
        return (brume_grid_format)f;
    unsigned char head[16];
    size_t n = 0;
    FILE *fp = NULL;
    if (io_open_regular(path, &fp) == BRUME_OK) { /* never blocks on a FIFO, never reads a device */
        n = fread(head, 1, sizeof head, fp);
        fclose(fp);
    }
    err_clear(); /* a file that cannot be read has no magic number: the caller's load says why */
    return (brume_grid_format)grid_format_detect(path, head, n);
}

brume_status tool_grid_options(const char *fn, const brume_grid_file_options *in, density_load_options *out)
{
    density_load_options_default(out);
    if (!in)
        return BRUME_OK;
    if ((unsigned)in->format > (unsigned)BRUME_GRID_FORMAT_VDB)
        return err_set(BRUME_ERROR_RANGE, "%s: opts.format: %d is not a brume_grid_format", fn, (int)in->format);
    if (!(in->max_memory_mb >= 0.0 && in->max_memory_mb <= 1e9))
        return err_set(BRUME_ERROR_RANGE, "%s: opts.max_memory_mb: %g outside [0, 1e9]", fn, in->max_memory_mb);
    if (!memchr(in->grid, '\0', sizeof in->grid))
        return err_set(BRUME_ERROR_RANGE, "%s: opts.grid: not NUL-terminated within 128 bytes", fn);
    out->format = (grid_format)in->format;
    if (in->max_memory_mb > 0.0)
        out->max_memory = (size_t)fmax(1.0, in->max_memory_mb * 1048576.0); /* exact: bytes / 2^20 * 2^20 */
    snprintf(out->grid, sizeof out->grid, "%s", in->grid);
    return BRUME_OK;
}

brume_status brume_grid_file_list(brume_context *ctx, const char *path, const brume_grid_file_options *opts,
                                  brume_grid_entry *out, int max, int *count)
{
    static const char fn[] = "brume_grid_file_list";
    err_clear();
    brume_status st = build_need(fn, 2, "path", path, "count", count);
    density_load_options lo;
    if (!st && max < 0)
        st = err_set(BRUME_ERROR_RANGE, "%s: max: %d is negative", fn, max);
    if (!st && max > 0 && !out)
        st = build_null(fn, "out");
    if (st || (st = tool_grid_options(fn, opts, &lo)))
        return ctx_report(ctx, st);
    gridvdb_info *gi = NULL;
    int n = 0;
    if ((st = grid_list_file(path, lo.max_memory, &gi, &n)) != BRUME_OK)
        return ctx_report(ctx, st);
    for (int g = 0; g < n && g < max; g++) {
        brume_grid_entry *e = &out[g];
        memset(e, 0, sizeof *e);
        snprintf(e->name, sizeof e->name, "%s", gi[g].name);
        snprintf(e->type, sizeof e->type, "%s", gi[g].type);
        snprintf(e->grid_class, sizeof e->grid_class, "%s", gi[g].cls);
        memcpy(e->index_min, gi[g].bbmin, sizeof e->index_min);
        memcpy(e->index_max, gi[g].bbmax, sizeof e->index_max);
        e->active_voxels = gi[g].active;
        e->value_min = gi[g].vmin;
        e->value_max = gi[g].vmax;
        e->nanovdb_bytes = gi[g].nano_bytes;
    }
    free(gi);
    *count = n;
    return ctx_report(ctx, BRUME_OK);
}

brume_status brume_density_get_info(brume_context *ctx, const brume_density *dens, brume_density_info *out)
{
    static const char fn[] = "brume_density_get_info";
    err_clear();
    brume_status st = build_need(fn, 2, "density", dens, "out", out);
    if (st)
        return ctx_report(ctx, st);
    density_info in;
    density_get_info(dens->d, &in);
    memset(out, 0, sizeof *out);
    out->sparse = in.kind == DENSITY_NANOVDB;
    memcpy(out->dims, in.n, sizeof out->dims);
    const double b[6] = {in.bounds.lo.x, in.bounds.lo.y, in.bounds.lo.z, in.bounds.hi.x, in.bounds.hi.y, in.bounds.hi.z};
    memcpy(out->bounds, b, sizeof b);
    memcpy(out->voxel_to_world, in.voxel_to_world.m, sizeof out->voxel_to_world);
    out->rho_min = in.rho_min;
    out->rho_max = in.rho_max;
    out->memory_bytes = in.memory_bytes;
    out->active_voxels = in.active_voxels;
    out->majorant_tree = in.majorant_tree;
    memcpy(out->majorant_dims, in.majorant_n, sizeof out->majorant_dims);
    out->majorant_cell = in.majorant_cell;
    return ctx_report(ctx, BRUME_OK);
}

brume_status brume_density_write(brume_context *ctx, const brume_density *dens, const char *path,
                                 brume_grid_format format)
{
    static const char fn[] = "brume_density_write";
    err_clear();
    brume_status st = build_need(fn, 2, "density", dens, "path", path);
    if (!st && (unsigned)format > (unsigned)BRUME_GRID_FORMAT_VDB)
        st = err_set(BRUME_ERROR_RANGE, "%s: format: %d is not a brume_grid_format", fn, (int)format);
    return ctx_report(ctx, st ? st : density_write_file(dens->d, path, (grid_format)format));
}

brume_status brume_grid_convert_vdb_to_nvdb(brume_context *ctx, const char *in, const char *out, const char *grid)
{
    err_clear();
    brume_status st = build_need("brume_grid_convert_vdb_to_nvdb", 2, "in", in, "out", out);
    return ctx_report(ctx, st ? st : grid_convert_vdb_to_nvdb(in, out, grid ? grid : ""));
}

brume_status brume_grid_sequence_extent(brume_context *ctx, const char *pattern, long first, long last,
                                        const brume_grid_file_options *opts, double bounds[6], double *rho_max)
{
    static const char fn[] = "brume_grid_sequence_extent";
    err_clear();
    brume_status st = build_need(fn, 3, "pattern", pattern, "bounds", bounds, "rho_max", rho_max);
    if (!st && !(first >= 0 && first <= last))
        st = err_set(BRUME_ERROR_RANGE, "%s: first..last: %ld..%ld is not a range of frames", fn, first, last);
    int is = st ? 0 : seq_is_pattern(pattern);
    if (!st && is <= 0)
        st = is < 0 ? err_status() : err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s: no frame pattern", fn, pattern);
    if (st)
        return ctx_report(ctx, st);
    box3 b = box3_empty();
    double rmax = 0.0;
    for (long n = first; n <= last; n++) {
        char name[4096];
        seq_name(pattern, n, name, sizeof name);
        brume_density *d = NULL;
        if ((st = brume_density_load(NULL, name, opts, &d)) != BRUME_OK)
            return ctx_report(ctx, st); /* the message stands: "PATH: reason" */
        box3 a = density_bounds(d->d);
        b.lo = v3_min(b.lo, a.lo);
        b.hi = v3_max(b.hi, a.hi);
        rmax = fmax(rmax, density_max(d->d));
        brume_density_release(d);
    }
    const double v[6] = {b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z};
    memcpy(bounds, v, sizeof v);
    *rho_max = rmax;
    return ctx_report(ctx, BRUME_OK);
}
