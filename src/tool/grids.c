/* grids.c - the grid files of `brume info`, `convert` and `gen cloud` over io/grid_io.h and
 * density/fractal.h (tool.h). */
#include "tool/tool.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "density/fractal.h"
#include "io/grid_io.h"
#include "io/grid_sequence.h"

/* The command line's options as the readers take them (no checks: the tool made them). */
static density_load_options load_options(const brume_grid_file_options *in)
{
    density_load_options o;
    density_load_options_default(&o);
    o.format = (grid_format)in->format; /* one enum (scene/scene_media.c checks it) */
    for (int k = 0; k < 3; k++)
        o.raw_dims[k] = in->dims[k];
    o.has_bounds = in->has_bounds;
    o.bounds = (box3){v3(in->bounds[0], in->bounds[1], in->bounds[2]), v3(in->bounds[3], in->bounds[4], in->bounds[5])};
    o.has_transform = in->has_transform;
    memcpy(o.transform.m, in->transform, sizeof o.transform.m);
    o.filter = in->filter == BRUME_GRID_NEAREST ? GRID_NEAREST : GRID_TRILINEAR;
    o.scale = in->scale;
    if (in->max_memory_mb > 0.0)
        o.max_memory = (size_t)(in->max_memory_mb * 1048576.0); /* exact: bytes / 2^20 * 2^20 */
    snprintf(o.grid, sizeof o.grid, "%s", in->grid);
    return o;
}

bool tool_grid_format_known(const char *name) { return grid_format_from_name(name) != GRID_FORMAT_AUTO; }

brume_grid_format tool_grid_format_parse(const char *name)
{
    return name ? (brume_grid_format)grid_format_from_name(name) : BRUME_GRID_FORMAT_AUTO;
}

const char *tool_grid_format_of(const char *path, brume_grid_format format, const unsigned char *head, size_t n)
{
    grid_format f = format != BRUME_GRID_FORMAT_AUTO ? (grid_format)format : grid_format_detect(path, head, n);
    return f == GRID_FORMAT_AUTO ? NULL : grid_format_name(f);
}

bool tool_grid_have_openvdb(void) { return grid_have_openvdb(); }

density *tool_grid_load(const char *path, const brume_grid_file_options *o)
{
    density_load_options lo = load_options(o);
    return density_load_file(path, &lo);
}

void tool_grid_release(density *d) { density_release(d); }

brume_status tool_grid_write(const density *d, const char *path, const char *format)
{
    return density_write_file(d, path, format && format[0] ? grid_format_from_name(format) : GRID_FORMAT_AUTO);
}

brume_status tool_grid_convert_vdb_to_nvdb(const char *in, const char *out, const char *grid)
{
    return grid_convert_vdb_to_nvdb(in, out, grid);
}

brume_status tool_grid_print_list(FILE *out, const char *path, const brume_grid_file_options *o, int *count)
{
    density_load_options lo = load_options(o);
    gridvdb_info *gi = NULL;
    int ngrids = 0;
    brume_status st = grid_list_file(path, lo.max_memory, &gi, &ngrids);
    if (st != BRUME_OK)
        return st;
    fprintf(out, "file:           %s\n", path);
    fprintf(out, "grids:          %d\n", ngrids);
    for (int g = 0; g < ngrids; g++) {
        fprintf(out, "  grid \"%s\": %s, %s, index box (%d, %d, %d) to (%d, %d, %d), %llu active voxels, values %.6g "
                     "to %.6g, NanoVDB %.2f MiB\n",
                gi[g].name, gi[g].type, gi[g].cls, gi[g].bbmin[0], gi[g].bbmin[1], gi[g].bbmin[2], gi[g].bbmax[0],
                gi[g].bbmax[1], gi[g].bbmax[2], gi[g].active, gi[g].vmin, gi[g].vmax,
                (double)gi[g].nano_bytes / 1048576.0);
    }
    free(gi);
    *count = ngrids;
    return BRUME_OK;
}

void tool_grid_print_info(FILE *out, const char *path, const char *format, const density *d)
{
    density_info in;
    density_get_info(d, &in);
    const double *m = in.voxel_to_world.m;
    fprintf(out, "file:           %s\n", path);
    fprintf(out, "format:         %s (%s grid)\n", format, in.kind == DENSITY_NANOVDB ? "sparse NanoVDB" : "dense");
    fprintf(out, "dimensions:     %d x %d x %d voxels\n", in.n[0], in.n[1], in.n[2]);
    fprintf(out, "world bounds:   (%.6g, %.6g, %.6g) to (%.6g, %.6g, %.6g)\n", in.bounds.lo.x, in.bounds.lo.y,
            in.bounds.lo.z, in.bounds.hi.x, in.bounds.hi.y, in.bounds.hi.z);
    fprintf(out, "voxel to world: [%.6g %.6g %.6g %.6g; %.6g %.6g %.6g %.6g; %.6g %.6g %.6g %.6g]\n", m[0], m[1], m[2],
            m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[11]);
    fprintf(out, "values:         %.6g to %.6g\n", in.rho_min, in.rho_max);
    fprintf(out, "memory:         %zu bytes (%.2f MiB)\n", in.memory_bytes, (double)in.memory_bytes / 1048576.0);
    fprintf(out, "active voxels:  %llu\n", (unsigned long long)in.active_voxels);
    if (in.majorant_tree)
        fprintf(out, "majorants:      from the tree: %d blocks of 128^3 voxels with bounds per 8^3 leaf cell\n",
                in.majorant_n[0]);
    else
        fprintf(out, "majorant grid:  %d x %d x %d cells of %d^3 voxels\n", in.majorant_n[0], in.majorant_n[1],
                in.majorant_n[2], in.majorant_cell);
}

brume_status tool_grid_sequence_extent(const char *pattern, long first, long last, const brume_grid_file_options *o,
                                       double bounds[6], double *rho_max)
{
    density_load_options lo = load_options(o);
    box3 b = box3_empty();
    double rmax = 0.0;
    for (long n = first; n <= last; n++) {
        char name[4096];
        seq_name(pattern, n, name, sizeof name);
        density *d = density_load_file(name, &lo);
        if (!d)
            return err_status() != BRUME_OK ? err_status() : BRUME_ERROR_IO;
        box3 a = density_bounds(d);
        b.lo = v3_min(b.lo, a.lo);
        b.hi = v3_max(b.hi, a.hi);
        rmax = fmax(rmax, density_max(d));
        density_release(d);
    }
    const double v[6] = {b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z};
    memcpy(bounds, v, sizeof v);
    *rho_max = rmax;
    return BRUME_OK;
}

density *tool_gen_cloud(const brume_fractal *f)
{
    fractal_params p;
    fractal_params_from_api(f, &p);
    box3 b = {v3(f->bounds[0], f->bounds[1], f->bounds[2]), v3(f->bounds[3], f->bounds[4], f->bounds[5])};
    return fractal_cloud(&p, b, f->filter == BRUME_GRID_NEAREST ? GRID_NEAREST : GRID_TRILINEAR);
}
