/* grid_formats.c - what the grid formats share (io/grid_formats.h): voxel counts within the
 * memory limit, placements, dense buffers and the atomic writes. */
#include "io/grid_formats.h"

#include <errno.h>
#include <stdlib.h>

#include "core/error.h"

/* ---- shared by the formats -------------------------------------------------------------------- */

/* n0 n1 n2 voxels of `bytes_per` bytes each: the total, or 0 when it overflows size_t or
 * exceeds max_memory as floats (err_set). */
size_t grid_voxel_count(const char *name, const int64_t n[3], size_t max_memory)
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
affine3 grid_box_map(box3 b, const int n[3])
{
    vec3 e = v3_sub(b.hi, b.lo);
    return (affine3){{e.x / n[0], 0, 0, b.lo.x, 0, e.y / n[1], 0, b.lo.y, 0, 0, e.z / n[2], b.lo.z}};
}

bool grid_dense_alloc(dense_read *out, const int64_t n[3], size_t count, const char *name)
{
    out->data = malloc(count * sizeof(float));
    if (!out->data) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
        return false;
    }
    for (int a = 0; a < 3; a++)
        out->n[a] = (int)n[a];
    return true;
}

/* Writes go through io/atomic.h: a temporary file beside the destination, renamed over it
 * when complete. These two wrap it for the writers below. */
FILE *grid_open_tmp(atomic_file *af, const char *path)
{
    /* a raw grid's .hdr sidecar is text */
    size_t n = strlen(path);
    bool sidecar = n > 4 && strcmp(path + n - 4, ".hdr") == 0;
    return atomic_open_kind(af, path, sidecar ? BRUME_FILE_TEXT : BRUME_FILE_GRID) == BRUME_OK ? af->fp : NULL;
}

brume_status grid_commit_tmp(atomic_file *af, bool ok)
{
    if (!ok) {
        atomic_abort(af);
        return err_set(BRUME_ERROR_IO, "%s: write failed: %s", af->path, strerror(errno));
    }
    return atomic_commit(af);
}

bool grid_write_floats(FILE *f, const density *d, const int n[3])
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

