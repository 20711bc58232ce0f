/* fuzz_seeds.c - writes a small grid in every format into DIR/<format>/, the seed corpora
 * of the fuzz targets (fuzz/run.sh). Usage: fuzz_seeds DIR */
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>

#include "core/error.h"
#include "io/grid_io.h"

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: fuzz_seeds DIR\n");
        return 2;
    }
    float *v = malloc(5 * 4 * 3 * sizeof *v);
    for (int i = 0; i < 60; i++)
        v[i] = (float)((i * 37) % 11) / 10.0f;
    density *d = density_new_grid(5, 4, 3, v, (box3){v3(-1, -1, 0), v3(1, 0.5, 1)}, GRID_TRILINEAR);
    const char *fmts[] = {"raw", "df3", "vol", "nvdb", "vdb"};
    for (int f = 0; f < 5; f++) {
        char dir[1024], path[1100];
        snprintf(dir, sizeof dir, "%s/%s", argv[1], fmts[f]);
        mkdir(argv[1], 0777);
        mkdir(dir, 0777);
        snprintf(path, sizeof path, "%s/seed.%s", dir, fmts[f]);
        if (f >= 3 && !grid_have_openvdb())
            continue;
        if (density_write_file(d, path, GRID_FORMAT_AUTO) != BRUME_OK) {
            fprintf(stderr, "fuzz_seeds: %s\n", err_message());
            return 1;
        }
    }
    density_release(d);
    return 0;
}
