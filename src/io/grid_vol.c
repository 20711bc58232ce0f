/* grid_vol.c - Mitsuba 0.6 grid volumes (.vol): "VOL" 3, encoding, dims, channels, the
 * bounding box (a header of 48 bytes, little-endian), then the voxels (Mitsuba 0.6
 * documentation, "gridvolume"). */
#include "io/grid_formats.h"

#include "core/error.h"

bool grid_vol_read(const unsigned char *b, size_t size, const char *name, size_t max_memory, dense_read *out)
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
    size_t count = grid_voxel_count(name, n, max_memory);
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
    if (!grid_dense_alloc(out, n, count, name))
        return false;
    for (size_t i = 0; i < count; i++)
        out->data[i] = enc == 1 ? rd_lef(b + 48 + 4 * i) : (float)(b[48 + i] / 255.0);
    out->v2w = grid_box_map(box, out->n);
    return true;
}

brume_status grid_vol_write(const density *d, const density_info *in, const char *path)
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
    FILE *f = grid_open_tmp(&af, path);
    if (!f)
        return err_status();
    bool ok = fwrite(h, 1, 48, f) == 48 && grid_write_floats(f, d, in->n);
    return grid_commit_tmp(&af, ok);
}
