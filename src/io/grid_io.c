/* grid_io.c - grid files by format: names and detection (extension, else magic number), loading
 * (the file's bytes, the reader of its format, the values' checks, the placement) and writing,
 * dispatched to one file per format: grid_raw.c, grid_df3.c, grid_vol.c, grid_nvdb.c,
 * grid_openvdb.c (.vdb, and .nvdb writing). */
#include "io/grid_io.h"

#include "io/grid_formats.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <strings.h>

#include "core/error.h"
#include "core/regular_file.h"
#include "io/grid_sandbox.h"
#include "io/grid_vdb.h"

#ifndef BRUME_HAVE_OPENVDB
#define BRUME_HAVE_OPENVDB 0
#endif

/* ---- names and detection ----------------------------------------------------------------- */

static const char *const format_names[] = {"auto", "raw", "df3", "vol", "nvdb", "vdb"};

const char *grid_format_name(grid_format f)
{
    return (unsigned)f < sizeof format_names / sizeof *format_names ? format_names[f] : "auto";
}

grid_format grid_format_from_name(const char *s)
{
    for (int i = 1; i < (int)(sizeof format_names / sizeof *format_names); i++)
        if (strcasecmp(s, format_names[i]) == 0)
            return (grid_format)i;
    return GRID_FORMAT_AUTO;
}

bool grid_have_openvdb(void) { return BRUME_HAVE_OPENVDB; }

void grid_before_fork(void)
{
#if BRUME_HAVE_OPENVDB
    gridvdb_before_fork();
#endif
}

grid_format grid_format_detect(const char *path, const unsigned char *head, size_t n)
{
    const char *dot = path ? strrchr(path, '.') : NULL;
    if (dot && !strchr(dot, '/')) {
        grid_format f = grid_format_from_name(dot + 1);
        if (f != GRID_FORMAT_AUTO)
            return f;
    }
    if (n >= 4 && memcmp(head, "VOL", 3) == 0)
        return GRID_FORMAT_VOL;
    if (n >= 8 && memcmp(head, "NanoVDB0", 8) == 0)
        return GRID_FORMAT_NVDB;
    if (n >= 8 && memcmp(head, " BDV\0\0\0\0", 8) == 0)
        return GRID_FORMAT_VDB;
    return GRID_FORMAT_AUTO;
}

void density_load_options_default(density_load_options *o)
{
    memset(o, 0, sizeof *o);
    o->format = GRID_FORMAT_AUTO;
    o->filter = GRID_TRILINEAR;
    o->scale = 1.0;
    o->max_memory = DENSITY_DEFAULT_MAX_MEMORY;
}

/* ---- loading ---------------------------------------------------------------------------------- */

/* Checks values with the file's name, then builds the dense grid. */
static density *finish_dense(dense_read *r, const char *name, const density_load_options *o)
{
    size_t count = (size_t)r->n[0] * (size_t)r->n[1] * (size_t)r->n[2];
    for (size_t i = 0; i < count; i++) {
        float v = (float)((double)r->data[i] * o->scale);
        if (!isfinite(r->data[i]) || !isfinite(v) || v < 0.0f) {
            err_set(BRUME_ERROR_RANGE, "%s: voxel %zu (%zu, %zu, %zu) has density %g: need finite and >= 0", name, i,
                    i % (size_t)r->n[0], i / (size_t)r->n[0] % (size_t)r->n[1],
                    i / ((size_t)r->n[0] * (size_t)r->n[1]), (double)r->data[i]);
            free(r->data);
            return NULL;
        }
        r->data[i] = v;
    }
    density *d = density_new_grid_affine(r->n[0], r->n[1], r->n[2], r->data, &r->v2w, o->filter);
    if (!d) {
        char msg[512];
        snprintf(msg, sizeof msg, "%s", err_message());
        err_set(err_status(), "%s: %.500s", name, msg);
        free(r->data);
    }
    return d;
}

/* The fields out[0 .. count) placed by the options' bounds or transform, when given; false
 * with err_set, the fields released, when the placement is degenerate. */
static bool place_fields(density **out, int count, const char *name, const density_load_options *o)
{
    if (!o->has_bounds && !o->has_transform)
        return true;
    if (o->has_bounds && !(o->bounds.hi.x > o->bounds.lo.x && o->bounds.hi.y > o->bounds.lo.y &&
                           o->bounds.hi.z > o->bounds.lo.z)) {
        for (int c = 0; c < count; c++)
            density_release(out[c]);
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: placement bounds must have lo < hi", name);
        return false;
    }
    for (int c = 0; c < count; c++) {
        density_info info;
        density_get_info(out[c], &info);
        affine3 v2w = o->has_bounds ? grid_box_map(o->bounds, info.n) : info.voxel_to_world;
        if (o->has_transform)
            v2w = affine3_compose(&o->transform, &v2w);
        if (!density_place(out[c], &v2w)) {
            for (int k = 0; k < count; k++)
                density_release(out[k]);
            err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: placement transform is singular or not finite", name);
            return false;
        }
    }
    return true;
}

static bool load_fields(const unsigned char *b, size_t size, const char *name, const char *path,
                        const density_load_options *opts, int count, density **out)
{
    density_load_options o;
    if (opts)
        o = *opts;
    else
        density_load_options_default(&o);
    o.grid[sizeof o.grid - 1] = '\0';
    if (o.scale == 0.0)
        o.scale = 1.0;
    if (o.max_memory == 0)
        o.max_memory = DENSITY_DEFAULT_MAX_MEMORY;
    if (!(o.scale > 0.0) || !isfinite(o.scale)) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: density scale %g must be finite and > 0", name, o.scale);
        return false;
    }
    grid_format f = o.format != GRID_FORMAT_AUTO ? o.format : grid_format_detect(name, b, b ? size : 0);
    if (count != 1 && f != GRID_FORMAT_NVDB && f != GRID_FORMAT_VDB) {
        err_set(BRUME_ERROR_UNSUPPORTED, "%s: a colour (vec3) field needs a .vdb or .nvdb grid", name);
        return false;
    }
    if (o.grid[0] && f != GRID_FORMAT_NVDB && f != GRID_FORMAT_VDB) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: grid \"%s\": only .vdb and .nvdb files hold named grids", name,
                o.grid);
        return false;
    }
    if (o.edge_zero && ((f != GRID_FORMAT_NVDB && f != GRID_FORMAT_VDB) || o.has_bounds)) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: edge zero (pbrt-v4's NanoVDB lookup) takes a .vdb or .nvdb grid in "
                "its own placement (no bounds)", name);
        return false;
    }
    dense_read r = {{0, 0, 0}, NULL, affine3_identity()};
    out[0] = NULL;
    switch (f) {
    case GRID_FORMAT_AUTO:
        err_set(BRUME_ERROR_UNSUPPORTED, "%s: unknown grid format (extension or magic number)", name);
        return false;
    case GRID_FORMAT_RAW: {
        int dims[3] = {o.raw_dims[0], o.raw_dims[1], o.raw_dims[2]};
        bool has_v2w = false;
        affine3 v2w = affine3_identity();
        if (path && (dims[0] | dims[1] | dims[2]) == 0 && grid_raw_sidecar(path, dims, &has_v2w, &v2w) < 0)
            return false;
        if (!grid_raw_read(b, size, name, dims, has_v2w, &v2w, o.max_memory, &r))
            return false;
        out[0] = finish_dense(&r, name, &o);
        break;
    }
    case GRID_FORMAT_DF3:
        if (!grid_df3_read(b, size, name, o.max_memory, &r))
            return false;
        out[0] = finish_dense(&r, name, &o);
        break;
    case GRID_FORMAT_VOL:
        if (!grid_vol_read(b, size, name, o.max_memory, &r))
            return false;
        out[0] = finish_dense(&r, name, &o);
        break;
    case GRID_FORMAT_NVDB:
        if (!grid_nvdb_read(b, size, name, &o, count, out))
            return false;
        break;
    case GRID_FORMAT_VDB:
        if (!grid_vdb_read(b ? NULL : path, b, size, name, &o, count, out))
            return false;
        break;
    }
    if (!out[0])
        return false;
    return place_fields(out, count, name, &o);
}

density *density_load_memory(const void *bytes, size_t size, const char *name, const density_load_options *opts)
{
    density *d[1];
    return load_fields(bytes, size, name, NULL, opts, 1, d) ? d[0] : NULL;
}

/* Opens the regular file path as *f, with *len its size in bytes, and reads its first bytes
 * into head (what grid_format_detect reads); false with err_set naming path. */
static bool grid_file_open(const char *path, FILE **f, long *len, unsigned char head[16], size_t *nhead)
{
    if (io_open_regular(path, f) != BRUME_OK)
        return false;
    *len = -1;
    if (fseek(*f, 0, SEEK_END) == 0)
        *len = ftell(*f);
    if (*len < 0 || fseek(*f, 0, SEEK_SET) != 0) {
        fclose(*f);
        err_set(BRUME_ERROR_IO, "%s: cannot determine the file size", path);
        return false;
    }
    memset(head, 0, 16);
    *nhead = fread(head, 1, 16, *f);
    return true;
}

/* The whole of f (grid_file_open's, len bytes) into *out (malloc'd), and closes f: a file
 * larger than the voxel budget (plus headers) cannot fit once decoded and is refused. false
 * with err_set naming path. */
static bool grid_file_read(FILE *f, const char *path, long len, size_t max_memory, unsigned char **out)
{
    *out = NULL;
    if ((size_t)len > max_memory + ((size_t)1 << 20)) {
        fclose(f);
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: file of %ld bytes exceeds the memory limit of %zu", path, len,
                max_memory);
        return false;
    }
    unsigned char *b = malloc((size_t)len + 1);
    if (!b || fseek(f, 0, SEEK_SET) != 0) {
        free(b);
        fclose(f);
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory reading %ld bytes", path, len);
        return false;
    }
    size_t got = fread(b, 1, (size_t)len, f);
    fclose(f);
    if (got != (size_t)len) {
        free(b);
        err_set(BRUME_ERROR_IO, "%s: read %zu of %ld bytes", path, got, len);
        return false;
    }
    *out = b;
    return true;
}

/* Reads the whole file (not for .vdb, which the child process reads itself). */
static bool load_path(const char *path, const density_load_options *opts, int count, density **out)
{
    size_t max_memory = opts && opts->max_memory ? opts->max_memory : DENSITY_DEFAULT_MAX_MEMORY;
    FILE *f = NULL;
    long len;
    unsigned char head[16];
    size_t nhead;
    if (!grid_file_open(path, &f, &len, head, &nhead))
        return false;
    grid_format fmt = opts && opts->format != GRID_FORMAT_AUTO ? opts->format : grid_format_detect(path, head, nhead);
    if (fmt == GRID_FORMAT_VDB) {
        fclose(f);
        return load_fields(NULL, (size_t)len, path, path, opts, count, out);
    }
    unsigned char *b;
    if (!grid_file_read(f, path, len, max_memory, &b))
        return false;
    bool ok = load_fields(b, (size_t)len, path, path, opts, count, out);
    free(b);
    return ok;
}

density *density_load_file(const char *path, const density_load_options *opts)
{
    density *d[1];
    return load_path(path, opts, 1, d) ? d[0] : NULL;
}

bool density_load_file_fields(const char *path, const density_load_options *opts, int count, density **out)
{
    if (count != 1 && count != 3) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %d fields (1 or 3)", path, count);
        return false;
    }
    return load_path(path, opts, count, out);
}

brume_status grid_list_file(const char *path, size_t max_memory, gridvdb_info **out, int *count)
{
    *out = NULL;
    *count = 0;
    if (max_memory == 0)
        max_memory = DENSITY_DEFAULT_MAX_MEMORY;
    FILE *f = NULL;
    long len;
    unsigned char head[16];
    size_t nhead;
    if (!grid_file_open(path, &f, &len, head, &nhead))
        return err_status();
    grid_format fmt = grid_format_detect(path, head, nhead);
    if (fmt != GRID_FORMAT_NVDB) {
        fclose(f);
        if (fmt == GRID_FORMAT_VDB)
            return grid_sandbox_list(path, NULL, 0, path, max_memory, out, count);
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: only .vdb and .nvdb files hold named grids", path);
    }
    unsigned char *b;
    if (!grid_file_read(f, path, len, max_memory, &b))
        return err_status();
    brume_status st = grid_nvdb_list(b, (size_t)len, path, max_memory, out, count);
    free(b);
    return st;
}

/* ---- writing ---------------------------------------------------------------------------------- */

brume_status density_write_file(const density *d, const char *path, grid_format format)
{
    grid_format f = format != GRID_FORMAT_AUTO ? format : grid_format_detect(path, NULL, 0);
    density_info in;
    density_get_info(d, &in);
    switch (f) {
    case GRID_FORMAT_RAW: return grid_raw_write(d, &in, path);
    case GRID_FORMAT_DF3: return grid_df3_write(d, &in, path);
    case GRID_FORMAT_VOL: return grid_vol_write(d, &in, path);
    case GRID_FORMAT_NVDB:
    case GRID_FORMAT_VDB:
#if BRUME_HAVE_OPENVDB
        return grid_openvdb_write(d, &in, path, f == GRID_FORMAT_NVDB);
#else
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: writing .%s needs OpenVDB, and brume was built without OpenVDB",
                       path, grid_format_name(f));
#endif
    case GRID_FORMAT_AUTO: break;
    }
    return err_set(BRUME_ERROR_UNSUPPORTED, "%s: unknown grid format (use .raw, .df3, .vol, .nvdb or .vdb)", path);
}

/* .vdb to .nvdb through OpenVDB in the sandbox, written atomically. */
brume_status grid_convert_vdb_to_nvdb(const char *in, const char *out, const char *grid)
{
#if BRUME_HAVE_OPENVDB
    atomic_file af;
    if (!grid_open_tmp(&af, out))
        return err_status();
    fclose(af.fp); /* the converter writes the temporary file by name */
    af.fp = NULL;
    if (grid_sandbox_vdb_to_nvdb(in, af.tmp_path, grid, DENSITY_DEFAULT_MAX_MEMORY) != BRUME_OK) {
        brume_status st = err_status();
        atomic_abort(&af);
        return st;
    }
    return atomic_commit(&af);
#else
    (void)out;
    (void)grid;
    return err_set(BRUME_ERROR_UNSUPPORTED, "%s: .vdb needs OpenVDB, and brume was built without OpenVDB", in);
#endif
}
