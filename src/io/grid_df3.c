/* grid_df3.c - POV-Ray density files: 3 big-endian uint16 dims, then 1, 2 or 4-byte
 * big-endian samples, x fastest, on the unit cube (POV-Ray 3.7 documentation,
 * "density_file"). */
#include "io/grid_formats.h"

#include <math.h>

#include "core/error.h"

bool grid_df3_read(const unsigned char *b, size_t size, const char *name, size_t max_memory, dense_read *out)
{
    if (size < 6) {
        err_set(BRUME_ERROR_PARSE, "%s: truncated df3 header (%zu of 6 bytes)", name, size);
        return false;
    }
    int64_t n[3];
    for (int a = 0; a < 3; a++)
        n[a] = (int64_t)b[2 * a] << 8 | b[2 * a + 1];
    size_t count = grid_voxel_count(name, n, max_memory);
    if (!count)
        return false;
    size_t body = size - 6, width = body / count;
    if (body % count != 0 || (width != 1 && width != 2 && width != 4)) {
        err_set(BRUME_ERROR_PARSE, "%s: %zu data bytes for %lld x %lld x %lld voxels: need 1, 2 or 4 bytes each", name,
                body, (long long)n[0], (long long)n[1], (long long)n[2]);
        return false;
    }
    if (!grid_dense_alloc(out, n, count, name))
        return false;
    const unsigned char *p = b + 6;
    for (size_t i = 0; i < count; i++, p += width) {
        if (width == 1)
            out->data[i] = (float)(p[0] / 255.0);
        else if (width == 2)
            out->data[i] = (float)((p[0] << 8 | p[1]) / 65535.0);
        else
            out->data[i] = (float)(((uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3]) / 4294967295.0);
    }
    out->v2w = grid_box_map((box3){v3(0, 0, 0), v3(1, 1, 1)}, out->n); /* POV-Ray: the unit cube */
    return true;
}

brume_status grid_df3_write(const density *d, const density_info *in, const char *path)
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
    FILE *f = grid_open_tmp(&af, path);
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
    return grid_commit_tmp(&af, ok);
}
