/* grid_raw.c - raw grids: float32 little-endian, x fastest, no header; dims and placement
 * from the sidecar FILE.hdr (docs/grids.md), else from the options or a cube's size. */
#include "io/grid_formats.h"

#include <math.h>
#include <sys/stat.h>

#include "core/error.h"
#include "core/number.h"
#include "core/regular_file.h"

/* Centred on the origin, cubic voxels, the longest axis spanning [-0.5, 0.5]. */
static box3 centred_box(const int n[3])
{
    int m = n[0] > n[1] ? n[0] : n[1];
    m = n[2] > m ? n[2] : m;
    vec3 h = v3(0.5 * n[0] / m, 0.5 * n[1] / m, 0.5 * n[2] / m);
    return (box3){v3_neg(h), h};
}

/* True when s holds nothing but white space: a line's numbers are all of it. */
static bool only_space(const char *s)
{
    while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n')
        s++;
    return *s == '\0';
}

/* grid_raw_sidecar in the "C" locale (its sscanf calls read "0.5" in every locale). */
static int sidecar_read(const char *path, int n[3], bool *has_v2w, affine3 *v2w)
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
        size_t len = strlen(line);
        if (len + 1 < sizeof line && line[len - (len > 0)] != '\n' && !feof(f)) { /* fgets stopped at a NUL byte */
            fclose(f);
            err_set(BRUME_ERROR_PARSE, "%s:%d: a NUL byte in a text file", hdr, lineno);
            return -1;
        }
        char *hash = strchr(line, '#');
        if (hash)
            *hash = '\0';
        char key[32];
        int used = 0;
        if (sscanf(line, "%31s%n", key, &used) != 1)
            continue;
        const char *rest = line + used;
        int end = 0;
        if (strcmp(key, "dims") == 0 && !got_dims && sscanf(rest, "%d %d %d%n", &n[0], &n[1], &n[2], &end) == 3 &&
            only_space(rest + end)) {
            got_dims = 1;
        } else if (strcmp(key, "bounds") == 0 && sscanf(rest, "%lf %lf %lf %lf %lf %lf%n", &b.lo.x, &b.lo.y, &b.lo.z,
                                                          &b.hi.x, &b.hi.y, &b.hi.z, &end) == 6 && only_space(rest + end)) {
            if (!v3_isfinite(b.lo) || !v3_isfinite(b.hi) || !(b.lo.x < b.hi.x && b.lo.y < b.hi.y && b.lo.z < b.hi.z)) {
                fclose(f);
                err_set(BRUME_ERROR_RANGE, "%s:%d: bounds need finite min < max on every axis (a mirrored grid "
                        "is a voxel_to_world with a negative scale)", hdr, lineno);
                return -1;
            }
            if (got_dims) {
                *v2w = grid_box_map(b, n);
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
            err_set(BRUME_ERROR_PARSE, "%s:%d: expected dims, bounds or voxel_to_world, each once with its "
                    "numbers alone (dims NX NY NZ, bounds X0 Y0 Z0 X1 Y1 Z1)", hdr, lineno);
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

/* Reads the optional sidecar PATH.hdr: "dims NX NY NZ", "bounds X0 Y0 Z0 X1 Y1 Z1" or
 * "voxel_to_world" and 12 numbers; '#' starts a comment. Returns 1 if read, 0 if absent,
 * -1 on error (err_set). */
int grid_raw_sidecar(const char *path, int n[3], bool *has_v2w, affine3 *v2w)
{
    locale_t old = num_c_begin();
    int r = sidecar_read(path, n, has_v2w, v2w);
    num_c_end(old);
    return r;
}

bool grid_raw_read(const unsigned char *b, size_t size, const char *name, const int dims[3], bool has_v2w,
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
    size_t count = grid_voxel_count(name, n, max_memory);
    if (!count)
        return false;
    if (size != count * 4) {
        err_set(BRUME_ERROR_PARSE, "%s: %zu bytes, but %lld x %lld x %lld float32 voxels need %zu", name, size,
                (long long)n[0], (long long)n[1], (long long)n[2], count * 4);
        return false;
    }
    if (!grid_dense_alloc(out, n, count, name))
        return false;
    for (size_t i = 0; i < count; i++)
        out->data[i] = rd_lef(b + 4 * i);
    out->v2w = has_v2w ? *v2w : grid_box_map(centred_box(out->n), out->n);
    return true;
}

/* The sidecar is committed first, then the data: a reader never finds a whole-looking
 * raw file without its sidecar (it would guess a cube), and a sidecar whose raw file did
 * not follow names sizes that the old or missing data contradict (read_raw refuses). */
brume_status grid_raw_write(const density *d, const density_info *in, const char *path)
{
    char hdr[4200];
    atomic_file af, ah;
    if (snprintf(hdr, sizeof hdr, "%s.hdr", path) >= (int)sizeof hdr)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: path too long", path);
    FILE *h = grid_open_tmp(&ah, hdr);
    if (!h)
        return err_status();
    const double *m = in->voxel_to_world.m;
    bool ok = fprintf(h,
                      "# brume raw grid sidecar: float32 little-endian, x fastest\n"
                      "dims %d %d %d\n"
                      "voxel_to_world %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n",
                      in->n[0], in->n[1], in->n[2], m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9],
                      m[10], m[11]) > 0;
    brume_status s = grid_commit_tmp(&ah, ok);
    if (s != BRUME_OK)
        return s;
    FILE *f = grid_open_tmp(&af, path);
    if (!f)
        return err_status();
    ok = grid_write_floats(f, d, in->n);
    return grid_commit_tmp(&af, ok);
}
