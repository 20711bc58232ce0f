/* grid_openvdb.c - grids through OpenVDB: .vdb reading (in a child process under resource
 * limits, io/grid_sandbox.h), .vdb and .nvdb writing and .vdb to .nvdb conversion (the
 * OpenVDB module, io/grid_vdb.h), when the build found OpenVDB. */
#include "io/grid_formats.h"

#include <stdlib.h>

#include "core/error.h"
#include "io/grid_sandbox.h"
#include "io/grid_vdb.h"

#ifndef BRUME_HAVE_OPENVDB
#define BRUME_HAVE_OPENVDB 0
#endif

/* A .vdb: the chosen grid straight into a NanoVDB buffer, in a child process. From the
 * file at `path` when given (brume never holds the file's bytes), else from the bytes. */
bool grid_vdb_read(const char *path, const unsigned char *b, size_t size, const char *name,
                   const density_load_options *o, int count, density **out)
{
    void *buf = NULL;
    size_t n = 0;
    if (grid_sandbox_to_nano(path, b, size, name, o->grid, count == 3, o->max_memory, &buf, &n) != BRUME_OK)
        return false;
    if (!density_new_nanovdb_fields(buf, n, count, o->filter, NULL, o->scale, o->max_memory, o->any_sign, o->edge_zero,
                                    name, out)) {
        free(buf);
        return false;
    }
    return true;
}

#if BRUME_HAVE_OPENVDB
brume_status grid_openvdb_write(const density *d, const density_info *in, const char *path, int nano)
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
    if (!grid_open_tmp(&af, path)) {
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
