/* light_file.h - Blasi's light files: the first pass's radiance grid saved to disk
 * (blasi.save_light) and read back instead of running the pass (blasi.load_light).
 *
 * The format (docs/blasi.md, "Light files"), little-endian:
 *   8 bytes "BRUMEBL1", u32 version (1), u32 number of media, u64 scene hash,
 *   per medium: u32 nx, ny, nz, u32 0; then per medium nx ny nz x 3 float32: the source
 *   S (RGB radiance per unit length, world units), x fastest.
 * The hash is the caller's key for what the grid was made from (render/blasi_setup.c's
 * blasi_scene_hash): a file made for another scene or other options is refused. */
#ifndef BRUME_IO_LIGHT_FILE_H
#define BRUME_IO_LIGHT_FILE_H

#include <stddef.h>
#include <stdint.h>

#include "core/error.h"

/* What a light file holds besides its data: the hash and each medium's grid size. */
typedef struct light_file_layout {
    uint64_t hash;
    int nmedia;
    const int (*n)[3]; /* nmedia: voxels per axis of each medium */
    size_t nvox;       /* the sum over media of nx ny nz */
} light_file_layout;

/* Writes the layout and S (3 nvox floats) to path, whole or not at all (io/atomic.h).
 * Errors name the path and blasi.save_light. */
brume_status light_file_write(const char *path, const light_file_layout *l, const float *S);

/* Reads path into S (3 nvox floats, owned by the caller) when its header matches the
 * layout, its data is whole with nothing after it, and every value is finite and >= 0.
 * On failure err_set() names the path, blasi.load_light and what is wrong; S may hold
 * part of the file. */
brume_status light_file_read(const char *path, const light_file_layout *l, float *S);

#endif
