/* light_file.c - Blasi's light files (io/light_file.h: the format). */
#include "io/light_file.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "core/regular_file.h"
#include "io/atomic.h"

#define LIGHT_FILE_MAGIC "BRUMEBL1"
#define LIGHT_FILE_VERSION 1u

static bool host_is_little_endian(void)
{
    uint32_t one = 1;
    unsigned char b;
    memcpy(&b, &one, 1);
    return b == 1;
}

brume_status light_file_write(const char *path, const light_file_layout *l, const float *S)
{
    if (!host_is_little_endian())
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: blasi.save_light: light files are little-endian", path);
    atomic_file f;
    brume_status rc = atomic_open_kind(&f, path, BRUME_FILE_LIGHT);
    if (rc != BRUME_OK)
        return err_prefix("blasi.save_light");
    uint32_t head[2] = {LIGHT_FILE_VERSION, (uint32_t)l->nmedia};
    bool ok = fwrite(LIGHT_FILE_MAGIC, 1, 8, f.fp) == 8 && fwrite(head, sizeof head, 1, f.fp) == 1 &&
              fwrite(&l->hash, sizeof l->hash, 1, f.fp) == 1;
    for (int m = 0; ok && m < l->nmedia; m++) {
        uint32_t dims[4] = {(uint32_t)l->n[m][0], (uint32_t)l->n[m][1], (uint32_t)l->n[m][2], 0};
        ok = fwrite(dims, sizeof dims, 1, f.fp) == 1;
    }
    if (ok && l->nvox > 0)
        ok = fwrite(S, sizeof(float) * 3, l->nvox, f.fp) == l->nvox;
    if (!ok) {
        atomic_abort(&f);
        return err_set(BRUME_ERROR_IO, "%s: blasi.save_light: write error: %s", path, strerror(errno));
    }
    if (atomic_commit(&f) != BRUME_OK)
        return err_prefix("blasi.save_light");
    return BRUME_OK;
}

/* The header: magic, version, media count, each medium's size, and the hash. */
static brume_status read_header(FILE *fp, const char *path, const light_file_layout *l)
{
    char magic[8];
    uint32_t head[2];
    uint64_t hash;
    brume_status rc = BRUME_OK;
    if (fread(magic, 1, 8, fp) != 8 || memcmp(magic, LIGHT_FILE_MAGIC, 8) != 0 || fread(head, sizeof head, 1, fp) != 1 ||
        fread(&hash, sizeof hash, 1, fp) != 1) {
        rc = err_set(BRUME_ERROR_PARSE, "%s: blasi.load_light: not a brume light file", path);
    } else if (head[0] != LIGHT_FILE_VERSION) {
        rc = err_set(BRUME_ERROR_PARSE, "%s: blasi.load_light: version %u, this brume reads %u", path, head[0],
                     LIGHT_FILE_VERSION);
    } else if (head[1] != (uint32_t)l->nmedia) {
        rc = err_set(BRUME_ERROR_PARSE, "%s: blasi.load_light: made for %u media, the scene has %d", path, head[1],
                     l->nmedia);
    }
    for (int m = 0; rc == BRUME_OK && m < l->nmedia; m++) {
        uint32_t dims[4];
        if (fread(dims, sizeof dims, 1, fp) != 1)
            rc = err_set(BRUME_ERROR_PARSE, "%s: blasi.load_light: truncated header", path);
        else if (dims[0] != (uint32_t)l->n[m][0] || dims[1] != (uint32_t)l->n[m][1] || dims[2] != (uint32_t)l->n[m][2])
            rc = err_set(BRUME_ERROR_PARSE, "%s: blasi.load_light: medium %d is %u x %u x %u voxels, the scene's %d x %d x %d",
                         path, m, dims[0], dims[1], dims[2], l->n[m][0], l->n[m][1], l->n[m][2]);
    }
    if (rc == BRUME_OK && hash != l->hash)
        rc = err_set(BRUME_ERROR_PARSE,
                     "%s: blasi.load_light: made for another scene or other first-pass options (hash %016llx, this "
                     "scene %016llx)",
                     path, (unsigned long long)hash, (unsigned long long)l->hash);
    return rc;
}

brume_status light_file_read(const char *path, const light_file_layout *l, float *S)
{
    if (!host_is_little_endian())
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: blasi.load_light: light files are little-endian", path);
    FILE *fp = NULL;
    if (io_open_input(path, "blasi.load_light", &fp) != BRUME_OK)
        return err_status();
    /* no size check: what is read is the layout's size, and one byte more says "trailing" */
    brume_status rc = read_header(fp, path, l);
    if (rc == BRUME_OK && l->nvox > 0 && fread(S, sizeof(float) * 3, l->nvox, fp) != l->nvox)
        rc = err_set(BRUME_ERROR_PARSE, "%s: blasi.load_light: truncated data", path);
    if (rc == BRUME_OK && fgetc(fp) != EOF)
        rc = err_set(BRUME_ERROR_PARSE, "%s: blasi.load_light: trailing bytes after the data", path);
    for (size_t i = 0; rc == BRUME_OK && i < 3 * l->nvox; i++)
        if (!(isfinite(S[i]) && S[i] >= 0.0f))
            rc = err_set(BRUME_ERROR_PARSE, "%s: blasi.load_light: value %zu is negative or not finite", path, i);
    fclose(fp);
    return rc;
}
