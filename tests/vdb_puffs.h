/* vdb_puffs.h - the .vdb files the sparse tests write through OpenVDB: two puffs far
 * apart (density, temperature and a Cd colour, each a function of the voxel), three single
 * voxels, a box at 3000 K. Shared by test_sparse*.c; static, so each test keeps its own. */
#ifndef BRUME_TEST_VDB_PUFFS_H
#define BRUME_TEST_VDB_PUFFS_H

#include "test.h"

#include <sys/wait.h>
#include <unistd.h>

#include "core/vec.h"
#include "io/grid_io.h"
#include "io/grid_vdb.h"

/* Two puffs far apart: centres (8, 8, 8) and (1213, 1213, 1213), radius 6 voxels, so the
 * active index box spans about 1218^3 voxels. Voxel size 0.01, centre of voxel 0 at 0. */
#define PUFF_R 6
static const int puff_c[2][3] __attribute__((unused)) = {{8, 8, 8}, {1213, 1213, 1213}};
#define VOXEL 0.01

/* The density of voxel (i, j, k): 0 outside the puffs. */
static inline double puff_density(int i, int j, int k)
{
    for (int p = 0; p < 2; p++) {
        double dx = i - puff_c[p][0], dy = j - puff_c[p][1], dz = k - puff_c[p][2];
        double r = sqrt(dx * dx + dy * dy + dz * dz);
        if (r <= PUFF_R)
            return (float)(0.25 + (p + 1) * 0.5 * (1.0 - r / PUFF_R));
    }
    return 0.0;
}
static inline double puff_temperature(int i, int j, int k)
{
    return puff_density(i, j, k) > 0 ? 1000.0 + 10.0 * i + k : 0;
}
static inline void puff_colour(int i, int j, int k, float c[3])
{
    c[0] = 0.2f + 0.001f * (float)i;
    c[1] = 0.5f;
    c[2] = 0.9f - 0.0005f * (float)k;
    (void)j;
}

/* Writes path through OpenVDB (as NanoVDB if nanovdb): fill adds the grids and their voxels.
 * In a child process: OpenVDB (and TBB) stay out of the test's own process, which later
 * forks the sandboxed reader. */
static inline void write_vdb(const char *path, int nanovdb, void (*fill)(gridvdb_writer *w, const void *user),
                             const void *user)
{
    grid_before_fork(); /* no idle library thread holds a lock the child needs */
    pid_t pid = fork();
    ASSERT_TRUE(pid >= 0);
    if (pid == 0) {
        gridvdb_writer *w = gridvdb_writer_new();
        fill(w, user);
        _exit(gridvdb_writer_save(w, path, nanovdb) == BRUME_OK ? 0 : 1);
    }
    int st = 0;
    waitpid(pid, &st, 0);
    ASSERT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0);
}

static const double origin0[3] __attribute__((unused)) = {0, 0, 0};

/* The puffs, in the grids named by names ([0] density (float), [1] temperature (float),
 * [2] Cd (vec3); NULL skips one). */
static inline void fill_puffs(gridvdb_writer *w, const void *user)
{
    const char *const *names = user;
    int g[3];
    for (int q = 0; q < 3; q++)
        g[q] = names[q] ? gridvdb_writer_add(w, names[q], q == 2, VOXEL, origin0) : -1;
    for (int p = 0; p < 2; p++)
        for (int k = puff_c[p][2] - PUFF_R; k <= puff_c[p][2] + PUFF_R; k++)
            for (int j = puff_c[p][1] - PUFF_R; j <= puff_c[p][1] + PUFF_R; j++)
                for (int i = puff_c[p][0] - PUFF_R; i <= puff_c[p][0] + PUFF_R; i++) {
                    float v = (float)puff_density(i, j, k), t = (float)puff_temperature(i, j, k), c[3];
                    puff_colour(i, j, k, c);
                    if (v <= 0.0f)
                        continue;
                    if (g[0] >= 0)
                        gridvdb_writer_set(w, g[0], i, j, k, &v);
                    if (g[1] >= 0)
                        gridvdb_writer_set(w, g[1], i, j, k, &t);
                    if (g[2] >= 0)
                        gridvdb_writer_set(w, g[2], i, j, k, c);
                }
}

/* The puffs as .vdb (nanovdb 0) or .nvdb (1). */
static inline void write_puffs(const char *path, const char *const names[3], int nanovdb)
{
    write_vdb(path, nanovdb, fill_puffs, names);
}

/* "density": A (1 at (12, 12, 12)), B (0.5 at (23, 15, 15)), C (0.25 at (31, 23, 23)) */
static inline void fill_three_voxels(gridvdb_writer *w, const void *user)
{
    (void)user;
    int g = gridvdb_writer_add(w, "density", 0, VOXEL, origin0);
    const float a = 1.0f, b = 0.5f, c = 0.25f;
    gridvdb_writer_set(w, g, 12, 12, 12, &a);
    gridvdb_writer_set(w, g, 23, 15, 15, &b);
    gridvdb_writer_set(w, g, 31, 23, 23, &c);
}

/* "temperature": 3000 K over [-7, 7]^3 voxels of size 1 (a box covering the density's) */
static inline void fill_3000K(gridvdb_writer *w, const void *user)
{
    (void)user;
    int g = gridvdb_writer_add(w, "temperature", 0, 1.0, origin0);
    float t = 3000.0f;
    for (int k = -7; k <= 7; k++)
        for (int j = -7; j <= 7; j++)
            for (int i = -7; i <= 7; i++)
                gridvdb_writer_set(w, g, i, j, k, &t);
}

static const char *const all_names[3] __attribute__((unused)) = {"density", "temperature", "Cd"};

/* world centre of voxel (i, j, k) */
static inline vec3 centre(int i, int j, int k) { return v3(VOXEL * i, VOXEL * j, VOXEL * k); }

#endif
