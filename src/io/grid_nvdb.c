/* grid_nvdb.c - NanoVDB files (.nvdb, uncompressed), read in C: the file's header and each
 * grid's metadata (nanovdb/util/IO.h: Header 16 bytes, MetaData 176 bytes + name, then the
 * grids), a grid chosen by name, kept sparse (density/nanovdb.c). Writing goes through
 * OpenVDB (grid_openvdb.c). */
#include "io/grid_formats.h"

#include <math.h>
#include <stdlib.h>

#include "core/error.h"

#define NVDB_HEADER 16
#define NVDB_META 176
#define NVDB_MAJOR 32 /* NanoVDB file format (ABI) version of libnanovdb-dev 10.0 */

/* NanoVDB grid type codes (NanoVDB.h GridType) and class codes (GridClass), for listings. */
static const char *nvdb_type_name(uint32_t t)
{
    static const char *const n[] = {"unknown", "float", "double", "int16", "int32", "int64", "vec3s", "vec3d", "mask",
                                    "half", "uint32", "bool", "rgba8", "fp4", "fp8", "fp16", "fpn", "vec4s", "vec4d",
                                    "index", "onindex"};
    return t < sizeof n / sizeof *n ? n[t] : "unknown";
}
static const char *nvdb_class_name(uint32_t c)
{
    static const char *const n[] = {"unknown", "level set", "fog volume", "staggered", "point index", "point data",
                                    "topology", "voxel volume", "index grid"};
    return c < sizeof n / sizeof *n ? n[c] : "unknown";
}

/* One grid's place in a NanoVDB file, from its metadata. */
typedef struct nvdb_entry {
    size_t at;       /* byte offset of its grid data */
    uint64_t size;   /* bytes */
    uint32_t type, cls;
    uint64_t voxels;
    int32_t bbox[6];
    char name[128];
} nvdb_entry;

/* Reads the file header and every grid's metadata; *out malloc'd. */
static bool nvdb_entries(const unsigned char *b, size_t size, const char *name, nvdb_entry **out, unsigned *count)
{
    *out = NULL;
    *count = 0;
    if (size < NVDB_HEADER) {
        err_set(BRUME_ERROR_PARSE, "%s: truncated NanoVDB header (%zu of 16 bytes)", name, size);
        return false;
    }
    if (memcmp(b, "NanoVDB0", 8) != 0) {
        err_set(BRUME_ERROR_PARSE, "%s: not a NanoVDB file (wrong magic number)", name);
        return false;
    }
    uint32_t version = rd_le32(b + 8);
    unsigned grids = (unsigned)(b[12] | b[13] << 8), codec = (unsigned)(b[14] | b[15] << 8);
    if (version >> 21 != NVDB_MAJOR) {
        err_set(BRUME_ERROR_UNSUPPORTED, "%s: NanoVDB file version %u.%u, this reader knows %d.x", name,
                (unsigned)(version >> 21), (unsigned)(version >> 10 & 2047), NVDB_MAJOR);
        return false;
    }
    if (codec != 0) {
        err_set(BRUME_ERROR_UNSUPPORTED, "%s: compressed NanoVDB (codec %u) unsupported; write it uncompressed", name,
                codec);
        return false;
    }
    nvdb_entry *e = calloc(grids + 1u, sizeof *e);
    if (!e) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
        return false;
    }
    /* metadata of every grid first, then the grids in the same order */
    size_t at = NVDB_HEADER;
    for (unsigned g = 0; g < grids; g++) {
        if (size - at < NVDB_META) {
            err_set(BRUME_ERROR_PARSE, "%s: truncated metadata of grid %u", name, g);
            goto fail;
        }
        const unsigned char *m = b + at;
        uint64_t gsize = rd_le64(m), fsize = rd_le64(m + 8);
        uint32_t nsize = rd_le32(m + 136);
        if (nsize > size - at - NVDB_META) {
            err_set(BRUME_ERROR_PARSE, "%s: truncated name of grid %u", name, g);
            goto fail;
        }
        if (fsize != gsize) {
            err_set(BRUME_ERROR_PARSE, "%s: grid %u stored in %llu bytes, expected %llu", name, g,
                    (unsigned long long)fsize, (unsigned long long)gsize);
            goto fail;
        }
        e[g].size = gsize;
        e[g].voxels = rd_le64(m + 24);
        e[g].type = rd_le32(m + 32);
        e[g].cls = rd_le32(m + 36);
        for (int k = 0; k < 6; k++)
            e[g].bbox[k] = (int32_t)rd_le32(m + 88 + 4 * k);
        size_t nl = nsize < sizeof e[g].name ? nsize : sizeof e[g].name - 1;
        const unsigned char *nul = memchr(m + NVDB_META, 0, nl); /* the stored size counts the NUL */
        nl = nul ? (size_t)(nul - (m + NVDB_META)) : nl;
        memcpy(e[g].name, m + NVDB_META, nl);
        e[g].name[nl] = '\0';
        for (size_t k = 0; k < nl; k++) /* names are shown in one-line messages */
            if ((unsigned char)e[g].name[k] < 32 || e[g].name[k] == 127)
                e[g].name[k] = '?';
        at += NVDB_META + nsize;
    }
    for (unsigned g = 0; g < grids; g++) {
        if (e[g].size > size - at) {
            err_set(BRUME_ERROR_PARSE, "%s: truncated: grid %u needs %llu bytes, %zu remain", name, g,
                    (unsigned long long)e[g].size, size - at);
            goto fail;
        }
        e[g].at = at;
        at += (size_t)e[g].size;
    }
    *out = e;
    *count = grids;
    return true;
fail:
    free(e);
    return false;
}

static void nvdb_names(const nvdb_entry *e, unsigned n, char *out, size_t cap)
{
    size_t used = 0;
    out[0] = '\0';
    for (unsigned g = 0; g < n && used < cap; g++) {
        int w = snprintf(out + used, cap - used, "%s\"%s\" (%s)", g ? ", " : "", e[g].name, nvdb_type_name(e[g].type));
        used += w > 0 ? (size_t)w : 0;
    }
    if (n == 0)
        snprintf(out, cap, "none");
}

/* The grid asked for, by the rule of density_load_options.grid; -1 with err_set. */
static int nvdb_pick(const nvdb_entry *e, unsigned n, const char *name, const char *grid, int count)
{
    char names[512];
    nvdb_names(e, n, names, sizeof names);
    bool want_vec3 = count == 3;
    if (grid[0]) {
        for (unsigned g = 0; g < n; g++)
            if (strcmp(e[g].name, grid) == 0) {
                if (e[g].type != 1 && !(want_vec3 && e[g].type == 6)) {
                    err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: grid \"%s\" holds %s values; %s grid is needed", name,
                            grid, nvdb_type_name(e[g].type), want_vec3 ? "a float or vec3s" : "a float");
                    return -1;
                }
                return (int)g;
            }
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: no grid named \"%s\"; grids: %s", name, grid, names);
        return -1;
    }
    int only = -1, nfloat = 0;
    for (unsigned g = 0; g < n; g++) {
        if (e[g].type == 1 && strcmp(e[g].name, "density") == 0)
            return (int)g;
        if (e[g].type == 1) {
            only = (int)g;
            nfloat++;
        }
    }
    if (nfloat == 1)
        return only;
    if (nfloat == 0)
        err_set(BRUME_ERROR_UNSUPPORTED, "%s: no float grid; grids: %s", name, names);
    else
        err_set(BRUME_ERROR_INVALID_ARGUMENT,
                "%s: several float grids and none named \"density\": pick one with \"grid\" (--grid); grids: %s", name,
                names);
    return -1;
}

bool grid_nvdb_read(const unsigned char *b, size_t size, const char *name, const density_load_options *o, int count,
                    density **out)
{
    nvdb_entry *e;
    unsigned n;
    if (!nvdb_entries(b, size, name, &e, &n))
        return false;
    int g = nvdb_pick(e, n, name, o->grid, count);
    if (g < 0) {
        free(e);
        return false;
    }
    size_t gbytes = (size_t)e[g].size, at = e[g].at;
    free(e);
    if (gbytes > o->max_memory) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: grid of %zu bytes exceeds the memory limit of %zu", name, gbytes,
                o->max_memory);
        return false;
    }
    void *buf = aligned_alloc(32, (gbytes + 31) / 32 * 32 + 32);
    if (!buf) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu bytes", name, gbytes);
        return false;
    }
    memcpy(buf, b + at, gbytes);
    if (!density_new_nanovdb_fields(buf, gbytes, count, o->filter, NULL, o->scale, o->max_memory, o->any_sign,
                                    o->edge_zero, name, out)) {
        free(buf);
        return false;
    }
    return true;
}

brume_status grid_nvdb_list(const unsigned char *b, size_t n, const char *path, size_t max_memory, gridvdb_info **out,
                            int *count)
{
    nvdb_entry *e;
    unsigned ng;
    if (!nvdb_entries(b, n, path, &e, &ng))
        return err_status();
    gridvdb_info *in = calloc(ng + 1u, sizeof *in);
    if (!in) {
        free(e);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    for (unsigned g = 0; g < ng; g++) {
        snprintf(in[g].name, sizeof in[g].name, "%s", e[g].name);
        snprintf(in[g].type, sizeof in[g].type, "%s", nvdb_type_name(e[g].type));
        snprintf(in[g].cls, sizeof in[g].cls, "%s", nvdb_class_name(e[g].cls));
        for (int a = 0; a < 3; a++) {
            in[g].bbmin[a] = e[g].bbox[a];
            in[g].bbmax[a] = e[g].bbox[3 + a];
        }
        in[g].active = e[g].voxels;
        in[g].nano_bytes = e[g].size;
        /* the value range: of the field brume would build (float and vec3s grids), of any
         * sign (a velocity's components are negative too) */
        if (e[g].type == 1 || e[g].type == 6) {
            int k = e[g].type == 1 ? 1 : 3;
            void *buf = aligned_alloc(32, ((size_t)e[g].size + 31) / 32 * 32 + 32);
            density *d[3];
            if (buf) {
                memcpy(buf, b + e[g].at, (size_t)e[g].size);
                if (density_new_nanovdb_fields(buf, (size_t)e[g].size, k, GRID_NEAREST, NULL, 1.0, max_memory, true,
                                               false, path, d)) {
                    in[g].vmin = INFINITY;
                    for (int c = 0; c < k; c++) {
                        density_info di;
                        density_get_info(d[c], &di);
                        in[g].vmin = fmin(in[g].vmin, di.rho_min);
                        in[g].vmax = fmax(in[g].vmax, di.rho_max);
                    }
                    for (int c = 0; c < k; c++)
                        density_release(d[c]);
                } else {
                    char gname[128];
                    snprintf(gname, sizeof gname, "%s", e[g].name);
                    free(buf);
                    free(in);
                    free(e);
                    return err_prefix("grid \"%s\"", gname);
                }
            }
        }
    }
    free(e);
    *out = in;
    *count = (int)ng;
    return BRUME_OK;
}
