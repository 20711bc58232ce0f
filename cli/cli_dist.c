/* cli_dist.c - MPI ranks for `brume render` (compiled against MPI when BRUME_HAVE_MPI). */
#include "cli_dist.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>

#include "commands.h"

#if BRUME_HAVE_MPI
#include <mpi.h>
#endif

/* The process count a launcher announces (Open MPI, MPICH/Hydra, PMIx), or 0. */
static int launcher_size(void)
{
    static const char *const vars[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE", NULL};
    for (int i = 0; vars[i]; i++) {
        const char *v = getenv(vars[i]);
        if (v && *v)
            return atoi(v);
    }
    return 0;
}

bool dist_begin(dist *d)
{
    d->rank = 0;
    d->size = 1;
    d->mpi = false;
    int n = launcher_size();
    if (n <= 1)
        return true;
#if BRUME_HAVE_MPI
    if (MPI_Init(NULL, NULL) != MPI_SUCCESS) {
        cli_error("MPI_Init failed");
        return false;
    }
    d->mpi = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &d->rank);
    MPI_Comm_size(MPI_COMM_WORLD, &d->size);
    return true;
#else
    cli_error("started by mpirun with %d processes, but this brume was built without MPI "
              "(install libopenmpi-dev and rebuild; see README)", n);
    return false;
#endif
}

void dist_end(dist *d)
{
#if BRUME_HAVE_MPI
    if (d->mpi)
        MPI_Finalize();
#endif
    d->mpi = false;
}

void dist_abort(const dist *d, int code)
{
#if BRUME_HAVE_MPI
    if (d->mpi && d->size > 1)
        MPI_Abort(MPI_COMM_WORLD, code);
#else
    (void)d;
    (void)code;
#endif
}

#if BRUME_HAVE_MPI
static bool count_ok(size_t n) { return n <= (size_t)INT_MAX; }
#endif

bool dist_reduce_to_root(const dist *d, float *buf, size_t n)
{
#if BRUME_HAVE_MPI
    if (!d->mpi || d->size == 1)
        return true;
    if (!count_ok(n))
        return false;
    /* every pixel has one nonzero contributor (brume_render_part), so the sum is exact */
    void *send = d->rank == 0 ? MPI_IN_PLACE : (void *)buf;
    return MPI_Reduce(send, d->rank == 0 ? buf : NULL, (int)n, MPI_FLOAT, MPI_SUM, 0, MPI_COMM_WORLD) == MPI_SUCCESS;
#else
    (void)d;
    (void)buf;
    (void)n;
    return true;
#endif
}

bool dist_send_to_root(const dist *d, const float *buf, size_t n, int tag)
{
#if BRUME_HAVE_MPI
    if (!d->mpi || !count_ok(n))
        return false;
    return MPI_Send(buf, (int)n, MPI_FLOAT, 0, tag, MPI_COMM_WORLD) == MPI_SUCCESS;
#else
    (void)d;
    (void)buf;
    (void)n;
    (void)tag;
    return false;
#endif
}

bool dist_recv_at_root(const dist *d, float *buf, size_t n, int from, int tag)
{
#if BRUME_HAVE_MPI
    if (!d->mpi || !count_ok(n))
        return false;
    return MPI_Recv(buf, (int)n, MPI_FLOAT, from, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE) == MPI_SUCCESS;
#else
    (void)d;
    (void)buf;
    (void)n;
    (void)from;
    (void)tag;
    return false;
#endif
}

const char *dist_build_info(void)
{
#if BRUME_HAVE_MPI
    static char info[128];
    char lib[MPI_MAX_LIBRARY_VERSION_STRING];
    int len = 0;
    MPI_Get_library_version(lib, &len);
    int k = 0;
    while (k < len && k < 40 && lib[k] != ',' && lib[k] != '\n')
        k++;
    snprintf(info, sizeof info, "MPI (%.*s)", k, lib);
    return info;
#else
    return "no MPI";
#endif
}
