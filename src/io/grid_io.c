/* grid_io.c - grid file formats: readers (raw, df3, .vol, .nvdb in C; .vdb through
 * grid_vdb.cpp), writers (raw + sidecar, df3, .vol; .nvdb and .vdb through grid_vdb.cpp),
 * placement and limits. Format references:
 *   df3: POV-Ray 3.7 documentation, "density_file" (big-endian, x fastest, unit cube);
 *   .vol: Mitsuba 0.6 documentation, "gridvolume" (header of 48 bytes, little-endian);
 *   .nvdb: nanovdb/util/IO.h (Header 16 bytes, MetaData 176 bytes + name, then grids);
 *   raw: float32 little-endian, x fastest; sidecar FILE.hdr (docs/grids.md). */
#include "io/atomic.h"
#include "io/grid_io.h"

#include <ctype.h>
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <strings.h>
#include <unistd.h>

#include "core/error.h"
#include "io/grid_sandbox.h"
#include "core/regular_file.h"
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

/* ---- little helpers ------------------------------------------------------------------------- */

static uint32_t rd_le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static uint64_t rd_le64(const unsigned char *p) { return (uint64_t)rd_le32(p) | (uint64_t)rd_le32(p + 4) << 32; }
static float rd_lef(const unsigned char *p)
{
    uint32_t u = rd_le32(p);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}
static void wr_le32(unsigned char *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (unsigned char)(v >> (8 * i));
}

/* n0 n1 n2 voxels of `bytes_per` bytes each: the total, or 0 when it overflows size_t or
 * exceeds max_memory as floats (err_set). */
static size_t voxel_count(const char *name, const int64_t n[3], size_t max_memory)
{
    size_t count = 1;
    for (int a = 0; a < 3; a++) {
        if (n[a] < 1 || n[a] > INT32_MAX) {
            err_set(BRUME_ERROR_PARSE, "%s: dimension %lld out of range [1, %d]", name, (long long)n[a], INT32_MAX);
            return 0;
        }
        if (count > SIZE_MAX / (size_t)n[a] / sizeof(float)) {
            err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: dimensions %lld x %lld x %lld overflow", name, (long long)n[0],
                    (long long)n[1], (long long)n[2]);
            return 0;
        }
        count *= (size_t)n[a];
    }
    if (count > max_memory / sizeof(float)) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: %lld x %lld x %lld voxels need %zu bytes, over the memory limit of %zu",
                name, (long long)n[0], (long long)n[1], (long long)n[2], count * sizeof(float), max_memory);
        return 0;
    }
    return count;
}

/* Voxel box [0, n) onto the axis-aligned box b. */
static affine3 box_map(box3 b, const int n[3])
{
    vec3 e = v3_sub(b.hi, b.lo);
    return (affine3){{e.x / n[0], 0, 0, b.lo.x, 0, e.y / n[1], 0, b.lo.y, 0, 0, e.z / n[2], b.lo.z}};
}

/* Centred on the origin, cubic voxels, the longest axis spanning [-0.5, 0.5]. */
static box3 centred_box(const int n[3])
{
    int m = n[0] > n[1] ? n[0] : n[1];
    m = n[2] > m ? n[2] : m;
    vec3 h = v3(0.5 * n[0] / m, 0.5 * n[1] / m, 0.5 * n[2] / m);
    return (box3){v3_neg(h), h};
}

/* A dense grid being read: voxels and placement. */
typedef struct dense_read {
    int n[3];
    float *data;
    affine3 v2w;
} dense_read;

/* ---- raw ------------------------------------------------------------------------------------ */

/* Reads the optional sidecar PATH.hdr: "dims NX NY NZ", "bounds X0 Y0 Z0 X1 Y1 Z1" or
 * "voxel_to_world" and 12 numbers; '#' starts a comment. Returns 1 if read, 0 if absent,
 * -1 on error (err_set). */
static int raw_sidecar(const char *path, int n[3], bool *has_v2w, affine3 *v2w)
{
    char hdr[4096];
    if (snprintf(hdr, sizeof hdr, "%s.hdr", path) >= (int)sizeof hdr)
        return 0;
    struct stat hs;
    if (stat(hdr, &hs) != 0)
        return 0; /* no sidecar */
    FILE *f = NULL;
    if (io_open_regular(hdr, &f) != BRUME_OK)
        return -1;
    char line[512];
    int lineno = 0, got_dims = 0;
    box3 b;
    while (fgets(line, sizeof line, f)) {
        lineno++;
        char *hash = strchr(line, '#');
        if (hash)
            *hash = '\0';
        char key[32];
        int used = 0;
        if (sscanf(line, "%31s%n", key, &used) != 1)
            continue;
        const char *rest = line + used;
        if (strcmp(key, "dims") == 0 && sscanf(rest, "%d %d %d", &n[0], &n[1], &n[2]) == 3) {
            got_dims = 1;
        } else if (strcmp(key, "bounds") == 0 && sscanf(rest, "%lf %lf %lf %lf %lf %lf", &b.lo.x, &b.lo.y, &b.lo.z,
                                                          &b.hi.x, &b.hi.y, &b.hi.z) == 6) {
            if (!v3_isfinite(b.lo) || !v3_isfinite(b.hi) || !(b.lo.x < b.hi.x && b.lo.y < b.hi.y && b.lo.z < b.hi.z)) {
                fclose(f);
                err_set(BRUME_ERROR_RANGE, "%s:%d: bounds need finite min < max on every axis (a mirrored grid "
                        "is a voxel_to_world with a negative scale)", hdr, lineno);
                return -1;
            }
            if (got_dims) {
                *v2w = box_map(b, n);
                *has_v2w = true;
            } else {
                fclose(f);
                err_set(BRUME_ERROR_PARSE, "%s:%d: bounds before dims", hdr, lineno);
                return -1;
            }
        } else if (strcmp(key, "voxel_to_world") == 0) {
            double *m = v2w->m;
            if (sscanf(rest, "%lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf", &m[0], &m[1], &m[2], &m[3], &m[4],
                       &m[5], &m[6], &m[7], &m[8], &m[9], &m[10], &m[11]) != 12) {
                fclose(f);
                err_set(BRUME_ERROR_PARSE, "%s:%d: voxel_to_world needs 12 numbers", hdr, lineno);
                return -1;
            }
            *has_v2w = true;
        } else {
            fclose(f);
            err_set(BRUME_ERROR_PARSE, "%s:%d: expected dims, bounds or voxel_to_world", hdr, lineno);
            return -1;
        }
    }
    fclose(f);
    if (!got_dims) {
        err_set(BRUME_ERROR_PARSE, "%s: no dims line", hdr);
        return -1;
    }
    return 1;
}

static bool read_raw(const unsigned char *b, size_t size, const char *name, const int dims[3], bool has_v2w,
                     const affine3 *v2w, size_t max_memory, dense_read *out)
{
    int64_t n[3] = {dims[0], dims[1], dims[2]};
    if (n[0] == 0 && n[1] == 0 && n[2] == 0) {
        /* no dims: a cube if the size is 4 n^3 */
        size_t v = size / 4;
        int64_t c = (int64_t)llround(cbrt((double)v));
        if (size % 4 != 0 || c < 1 || (size_t)(c * c * c) != v) {
            err_set(BRUME_ERROR_INVALID_ARGUMENT,
                    "%s: raw grid of %zu bytes needs dimensions (--dims NXxNYxNZ or a sidecar %s.hdr)", name, size,
                    name);
            return false;
        }
        n[0] = n[1] = n[2] = c;
    }
    size_t count = voxel_count(name, n, max_memory);
    if (!count)
        return false;
    if (size != count * 4) {
        err_set(BRUME_ERROR_PARSE, "%s: %zu bytes, but %lld x %lld x %lld float32 voxels need %zu", name, size,
                (long long)n[0], (long long)n[1], (long long)n[2], count * 4);
        return false;
    }
    out->data = malloc(count * sizeof(float));
    if (!out->data) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
        return false;
    }
    for (size_t i = 0; i < count; i++)
        out->data[i] = rd_lef(b + 4 * i);
    for (int a = 0; a < 3; a++)
        out->n[a] = (int)n[a];
    out->v2w = has_v2w ? *v2w : box_map(centred_box(out->n), out->n);
    return true;
}

/* ---- df3 ------------------------------------------------------------------------------------ */

static bool read_df3(const unsigned char *b, size_t size, const char *name, size_t max_memory, dense_read *out)
{
    if (size < 6) {
        err_set(BRUME_ERROR_PARSE, "%s: truncated df3 header (%zu of 6 bytes)", name, size);
        return false;
    }
    int64_t n[3];
    for (int a = 0; a < 3; a++)
        n[a] = (int64_t)b[2 * a] << 8 | b[2 * a + 1];
    size_t count = voxel_count(name, n, max_memory);
    if (!count)
        return false;
    size_t body = size - 6, width = body / count;
    if (body % count != 0 || (width != 1 && width != 2 && width != 4)) {
        err_set(BRUME_ERROR_PARSE, "%s: %zu data bytes for %lld x %lld x %lld voxels: need 1, 2 or 4 bytes each", name,
                body, (long long)n[0], (long long)n[1], (long long)n[2]);
        return false;
    }
    out->data = malloc(count * sizeof(float));
    if (!out->data) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
        return false;
    }
    const unsigned char *p = b + 6;
    for (size_t i = 0; i < count; i++, p += width) {
        if (width == 1)
            out->data[i] = (float)(p[0] / 255.0);
        else if (width == 2)
            out->data[i] = (float)((p[0] << 8 | p[1]) / 65535.0);
        else
            out->data[i] = (float)(((uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3]) / 4294967295.0);
    }
    for (int a = 0; a < 3; a++)
        out->n[a] = (int)n[a];
    out->v2w = box_map((box3){v3(0, 0, 0), v3(1, 1, 1)}, out->n); /* POV-Ray: the unit cube */
    return true;
}

/* ---- Mitsuba .vol --------------------------------------------------------------------------- */

static bool read_vol(const unsigned char *b, size_t size, const char *name, size_t max_memory, dense_read *out)
{
    if ((size >= 3 && memcmp(b, "VOL", 3) != 0) || (size >= 4 && b[3] != 3)) {
        err_set(BRUME_ERROR_PARSE, "%s: not a Mitsuba .vol version 3 file (wrong magic number)", name);
        return false;
    }
    if (size < 48) {
        err_set(BRUME_ERROR_PARSE, "%s: truncated .vol header (%zu of 48 bytes)", name, size);
        return false;
    }
    if (memcmp(b, "VOL", 3) != 0 || b[3] != 3) {
        err_set(BRUME_ERROR_PARSE, "%s: not a Mitsuba .vol version 3 file (wrong magic number)", name);
        return false;
    }
    uint32_t enc = rd_le32(b + 4), channels = rd_le32(b + 20);
    if (enc != 1 && enc != 3) {
        err_set(BRUME_ERROR_UNSUPPORTED, "%s: .vol encoding %u unsupported (1 = float32 and 3 = uint8 are)", name,
                (unsigned)enc);
        return false;
    }
    if (channels != 1) {
        err_set(BRUME_ERROR_UNSUPPORTED, "%s: .vol has %u channels; a density needs 1", name, (unsigned)channels);
        return false;
    }
    int64_t n[3] = {(int32_t)rd_le32(b + 8), (int32_t)rd_le32(b + 12), (int32_t)rd_le32(b + 16)};
    size_t count = voxel_count(name, n, max_memory);
    if (!count)
        return false;
    size_t width = enc == 1 ? 4 : 1;
    if ((size - 48) / width != count || (size - 48) % width != 0) {
        err_set(BRUME_ERROR_PARSE, "%s: %s: %zu data bytes, %lld x %lld x %lld voxels need %zu", name,
                (size - 48) / width < count ? "truncated" : "trailing bytes", size - 48, (long long)n[0],
                (long long)n[1], (long long)n[2], count * width);
        return false;
    }
    box3 box = {v3((double)rd_lef(b + 24), (double)rd_lef(b + 28), (double)rd_lef(b + 32)),
                v3((double)rd_lef(b + 36), (double)rd_lef(b + 40), (double)rd_lef(b + 44))};
    if (!v3_isfinite(box.lo) || !v3_isfinite(box.hi) || !(box.hi.x > box.lo.x && box.hi.y > box.lo.y && box.hi.z > box.lo.z)) {
        err_set(BRUME_ERROR_PARSE, "%s: .vol bounding box is empty or not finite", name);
        return false;
    }
    out->data = malloc(count * sizeof(float));
    if (!out->data) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
        return false;
    }
    for (size_t i = 0; i < count; i++)
        out->data[i] = enc == 1 ? rd_lef(b + 48 + 4 * i) : (float)(b[48 + i] / 255.0);
    for (int a = 0; a < 3; a++)
        out->n[a] = (int)n[a];
    out->v2w = box_map(box, out->n);
    return true;
}

/* ---- NanoVDB file --------------------------------------------------------------------------- */

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

static bool read_nvdb(const unsigned char *b, size_t size, const char *name, const density_load_options *o, int count,
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
    if (!density_new_nanovdb_fields(buf, gbytes, count, o->filter, NULL, o->scale, o->max_memory, name, out)) {
        free(buf);
        return false;
    }
    return true;
}

/* A .vdb: the chosen grid straight into a NanoVDB buffer, in a child process. From the
 * file at `path` when given (brume never holds the file's bytes), else from the bytes. */
static bool read_vdb(const char *path, const unsigned char *b, size_t size, const char *name,
                     const density_load_options *o, int count, density **out)
{
    void *buf = NULL;
    size_t n = 0;
    if (grid_sandbox_to_nano(path, b, size, name, o->grid, count == 3, o->max_memory, &buf, &n) != BRUME_OK)
        return false;
    if (!density_new_nanovdb_fields(buf, n, count, o->filter, NULL, o->scale, o->max_memory, name, out)) {
        free(buf);
        return false;
    }
    return true;
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
        if (path && (dims[0] | dims[1] | dims[2]) == 0 && raw_sidecar(path, dims, &has_v2w, &v2w) < 0)
            return false;
        if (!read_raw(b, size, name, dims, has_v2w, &v2w, o.max_memory, &r))
            return false;
        out[0] = finish_dense(&r, name, &o);
        break;
    }
    case GRID_FORMAT_DF3:
        if (!read_df3(b, size, name, o.max_memory, &r))
            return false;
        out[0] = finish_dense(&r, name, &o);
        break;
    case GRID_FORMAT_VOL:
        if (!read_vol(b, size, name, o.max_memory, &r))
            return false;
        out[0] = finish_dense(&r, name, &o);
        break;
    case GRID_FORMAT_NVDB:
        if (!read_nvdb(b, size, name, &o, count, out))
            return false;
        break;
    case GRID_FORMAT_VDB:
        if (!read_vdb(b ? NULL : path, b, size, name, &o, count, out))
            return false;
        break;
    }
    if (!out[0])
        return false;
    if (o.has_bounds || o.has_transform) {
        if (o.has_bounds && !(o.bounds.hi.x > o.bounds.lo.x && o.bounds.hi.y > o.bounds.lo.y &&
                              o.bounds.hi.z > o.bounds.lo.z)) {
            for (int c = 0; c < count; c++)
                density_release(out[c]);
            err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: placement bounds must have lo < hi", name);
            return false;
        }
        for (int c = 0; c < count; c++) {
            density_info info;
            density_get_info(out[c], &info);
            affine3 v2w = o.has_bounds ? box_map(o.bounds, info.n) : info.voxel_to_world;
            if (o.has_transform)
                v2w = affine3_compose(&o.transform, &v2w);
            if (!density_place(out[c], &v2w)) {
                for (int k = 0; k < count; k++)
                    density_release(out[k]);
                err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: placement transform is singular or not finite", name);
                return false;
            }
        }
    }
    return true;
}

density *density_load_memory(const void *bytes, size_t size, const char *name, const density_load_options *opts)
{
    density *d[1];
    return load_fields(bytes, size, name, NULL, opts, 1, d) ? d[0] : NULL;
}

/* Reads the whole file (not for .vdb, which the child process reads itself). */
static bool load_path(const char *path, const density_load_options *opts, int count, density **out)
{
    size_t max_memory = opts && opts->max_memory ? opts->max_memory : DENSITY_DEFAULT_MAX_MEMORY;
    FILE *f = NULL;
    if (io_open_regular(path, &f) != BRUME_OK)
        return false;
    long len = -1;
    if (fseek(f, 0, SEEK_END) == 0)
        len = ftell(f);
    if (len < 0 || fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        err_set(BRUME_ERROR_IO, "%s: cannot determine the file size", path);
        return false;
    }
    unsigned char head[16] = {0};
    size_t nhead = fread(head, 1, sizeof head, f);
    grid_format fmt = opts && opts->format != GRID_FORMAT_AUTO ? opts->format : grid_format_detect(path, head, nhead);
    if (fmt == GRID_FORMAT_VDB) {
        fclose(f);
        return load_fields(NULL, (size_t)len, path, path, opts, count, out);
    }
    /* a file larger than the voxel budget (plus headers) cannot fit once decoded */
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
    bool ok = load_fields(b, got, path, path, opts, count, out);
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
    unsigned char head[16] = {0};
    size_t nhead = 0;
    FILE *f = NULL;
    if (io_open_regular(path, &f) != BRUME_OK)
        return err_status();
    nhead = fread(head, 1, sizeof head, f);
    fclose(f);
    grid_format fmt = grid_format_detect(path, head, nhead);
    if (fmt == GRID_FORMAT_VDB)
        return grid_sandbox_list(path, NULL, 0, path, max_memory, out, count);
    if (fmt != GRID_FORMAT_NVDB)
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: only .vdb and .nvdb files hold named grids", path);
    size_t n = 0;
    unsigned char *b = NULL;
    {
        FILE *g = NULL;
        long len = -1;
        if (io_open_regular(path, &g) != BRUME_OK)
            return err_status();
        if (g && fseek(g, 0, SEEK_END) == 0)
            len = ftell(g);
        if (!g || len < 0 || fseek(g, 0, SEEK_SET) != 0 || (size_t)len > max_memory + ((size_t)1 << 20) ||
            !(b = malloc((size_t)len + 1)) || (n = fread(b, 1, (size_t)len, g)) != (size_t)len) {
            if (g)
                fclose(g);
            free(b);
            return err_set(BRUME_ERROR_IO, "%s: cannot read the file (or over the memory limit)", path);
        }
        fclose(g);
    }
    nvdb_entry *e;
    unsigned ng;
    if (!nvdb_entries(b, n, path, &e, &ng)) {
        free(b);
        return err_status();
    }
    gridvdb_info *in = calloc(ng + 1u, sizeof *in);
    if (!in) {
        free(e);
        free(b);
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
        /* the value range: of the field brume would build (float and vec3s grids) */
        if (e[g].type == 1 || e[g].type == 6) {
            int k = e[g].type == 1 ? 1 : 3;
            void *buf = aligned_alloc(32, ((size_t)e[g].size + 31) / 32 * 32 + 32);
            density *d[3];
            if (buf) {
                memcpy(buf, b + e[g].at, (size_t)e[g].size);
                if (density_new_nanovdb_fields(buf, (size_t)e[g].size, k, GRID_NEAREST, NULL, 1.0, max_memory, path,
                                               d)) {
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
                    free(b);
                    return err_prefix("grid \"%s\"", gname);
                }
            }
        }
    }
    free(e);
    free(b);
    *out = in;
    *count = (int)ng;
    return BRUME_OK;
}

/* ---- writing ---------------------------------------------------------------------------------- */

/* Writes go through io/atomic.h: a temporary file beside the destination, renamed over it
 * when complete. These two wrap it for the writers below. */
static FILE *open_tmp(atomic_file *af, const char *path)
{
    return atomic_open(af, path) == BRUME_OK ? af->fp : NULL;
}

static brume_status commit_tmp(atomic_file *af, bool ok)
{
    if (!ok) {
        atomic_abort(af);
        return err_set(BRUME_ERROR_IO, "%s: write failed: %s", af->path, strerror(errno));
    }
    return atomic_commit(af);
}

static bool write_floats(FILE *f, const density *d, const int n[3])
{
    unsigned char buf[4 * 256];
    size_t k = 0;
    for (int z = 0; z < n[2]; z++)
        for (int y = 0; y < n[1]; y++)
            for (int x = 0; x < n[0]; x++) {
                float v = (float)density_voxel(d, x, y, z);
                uint32_t u;
                memcpy(&u, &v, sizeof u);
                wr_le32(buf + 4 * k, u);
                if (++k == 256) {
                    if (fwrite(buf, 4, k, f) != k)
                        return false;
                    k = 0;
                }
            }
    return fwrite(buf, 4, k, f) == k;
}

/* The sidecar is committed first, then the data: a reader never finds a whole-looking
 * raw file without its sidecar (it would guess a cube), and a sidecar whose raw file did
 * not follow names sizes that the old or missing data contradict (read_raw refuses). */
static brume_status write_raw(const density *d, const density_info *in, const char *path)
{
    char hdr[4200];
    atomic_file af, ah;
    if (snprintf(hdr, sizeof hdr, "%s.hdr", path) >= (int)sizeof hdr)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: path too long", path);
    FILE *h = open_tmp(&ah, hdr);
    if (!h)
        return err_status();
    const double *m = in->voxel_to_world.m;
    bool ok = fprintf(h,
                      "# brume raw grid sidecar: float32 little-endian, x fastest\n"
                      "dims %d %d %d\n"
                      "voxel_to_world %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n",
                      in->n[0], in->n[1], in->n[2], m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9],
                      m[10], m[11]) > 0;
    brume_status s = commit_tmp(&ah, ok);
    if (s != BRUME_OK)
        return s;
    FILE *f = open_tmp(&af, path);
    if (!f)
        return err_status();
    ok = write_floats(f, d, in->n);
    return commit_tmp(&af, ok);
}

static brume_status write_df3(const density *d, const density_info *in, const char *path)
{
    for (int a = 0; a < 3; a++)
        if (in->n[a] > 65535)
            return err_set(BRUME_ERROR_RANGE, "%s: df3 dimensions are at most 65535, got %d", path, in->n[a]);
    /* the fewest bytes per sample that hold every value exactly */
    int width = 1;
    for (int z = 0; z < in->n[2]; z++)
        for (int y = 0; y < in->n[1]; y++)
            for (int x = 0; x < in->n[0]; x++) {
                float v = (float)density_voxel(d, x, y, z);
                if (v > 1.0f)
                    return err_set(BRUME_ERROR_RANGE,
                                   "%s: df3 holds densities in [0, 1]; voxel (%d, %d, %d) is %g (rescale with --scale)",
                                   path, x, y, z, (double)v);
                if (width == 1 && (float)(round((double)v * 255.0) / 255.0) != v)
                    width = 2;
                if (width == 2 && (float)(round((double)v * 65535.0) / 65535.0) != v)
                    width = 4;
            }
    atomic_file af;
    FILE *f = open_tmp(&af, path);
    if (!f)
        return err_status();
    unsigned char h[6];
    for (int a = 0; a < 3; a++) {
        h[2 * a] = (unsigned char)(in->n[a] >> 8);
        h[2 * a + 1] = (unsigned char)in->n[a];
    }
    bool ok = fwrite(h, 1, 6, f) == 6;
    for (int z = 0; z < in->n[2] && ok; z++)
        for (int y = 0; y < in->n[1] && ok; y++)
            for (int x = 0; x < in->n[0] && ok; x++) {
                double v = density_voxel(d, x, y, z);
                double q = round(v * (width == 1 ? 255.0 : width == 2 ? 65535.0 : 4294967295.0));
                uint32_t u = (uint32_t)q;
                unsigned char s[4] = {(unsigned char)(u >> 24), (unsigned char)(u >> 16), (unsigned char)(u >> 8),
                                      (unsigned char)u};
                ok = fwrite(s + 4 - width, 1, (size_t)width, f) == (size_t)width;
            }
    return commit_tmp(&af, ok);
}

static brume_status write_vol(const density *d, const density_info *in, const char *path)
{
    unsigned char h[48] = {'V', 'O', 'L', 3};
    wr_le32(h + 4, 1);
    for (int a = 0; a < 3; a++)
        wr_le32(h + 8 + 4 * a, (uint32_t)in->n[a]);
    wr_le32(h + 20, 1);
    float bb[6] = {(float)in->bounds.lo.x, (float)in->bounds.lo.y, (float)in->bounds.lo.z,
                   (float)in->bounds.hi.x, (float)in->bounds.hi.y, (float)in->bounds.hi.z};
    for (int i = 0; i < 6; i++) {
        uint32_t u;
        memcpy(&u, &bb[i], sizeof u);
        wr_le32(h + 24 + 4 * i, u);
    }
    atomic_file af;
    FILE *f = open_tmp(&af, path);
    if (!f)
        return err_status();
    bool ok = fwrite(h, 1, 48, f) == 48 && write_floats(f, d, in->n);
    return commit_tmp(&af, ok);
}

#if BRUME_HAVE_OPENVDB
static brume_status write_vdb(const density *d, const density_info *in, const char *path, int nano)
{
    size_t count = (size_t)in->n[0] * (size_t)in->n[1] * (size_t)in->n[2];
    float *data = malloc(count * sizeof *data);
    if (!data)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    size_t o = 0;
    for (int z = 0; z < in->n[2]; z++)
        for (int y = 0; y < in->n[1]; y++)
            for (int x = 0; x < in->n[0]; x++)
                data[o++] = (float)density_voxel(d, x, y, z);
    atomic_file af;
    if (!open_tmp(&af, path)) {
        free(data);
        return err_status();
    }
    fclose(af.fp); /* OpenVDB writes the temporary file by name */
    af.fp = NULL;
    const char *tmp = af.tmp_path;
    brume_status s = gridvdb_write_dense(tmp, nano, in->n, data, in->voxel_to_world.m);
    free(data);
    if (s != BRUME_OK) {
        /* the message names the temporary file: name the destination instead */
        char msg[1024];
        const char *m = err_message();
        size_t tl = strlen(tmp);
        snprintf(msg, sizeof msg, "%s", strncmp(m, tmp, tl) == 0 && m[tl] == ':' ? m + tl + 2 : m);
        atomic_abort(&af);
        return err_set(s, "%s: %.1000s", path, msg);
    }
    return atomic_commit(&af);
}
#endif

brume_status density_write_file(const density *d, const char *path, grid_format format)
{
    grid_format f = format != GRID_FORMAT_AUTO ? format : grid_format_detect(path, NULL, 0);
    density_info in;
    density_get_info(d, &in);
    switch (f) {
    case GRID_FORMAT_RAW: return write_raw(d, &in, path);
    case GRID_FORMAT_DF3: return write_df3(d, &in, path);
    case GRID_FORMAT_VOL: return write_vol(d, &in, path);
    case GRID_FORMAT_NVDB:
    case GRID_FORMAT_VDB:
#if BRUME_HAVE_OPENVDB
        return write_vdb(d, &in, path, f == GRID_FORMAT_NVDB);
#else
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: writing .%s needs OpenVDB, and brume was built without OpenVDB",
                       path, grid_format_name(f));
#endif
    case GRID_FORMAT_AUTO: break;
    }
    return err_set(BRUME_ERROR_UNSUPPORTED, "%s: unknown grid format (use .raw, .df3, .vol, .nvdb or .vdb)", path);
}

brume_status grid_convert_vdb_to_nvdb(const char *in, const char *out, const char *grid)
{
#if BRUME_HAVE_OPENVDB
    atomic_file af;
    if (!open_tmp(&af, out))
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

