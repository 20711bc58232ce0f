/* cli_dist.c - MPI ranks for `brume render` (compiled against MPI when BRUME_HAVE_MPI).
 *
 * The MPI library is opened by its SONAME (BRUME_MPI_SONAME, read from the library CMake
 * found) when a launcher starts brume with several processes, or when --help names it, and
 * not linked: Open MPI's loading and relocation took about 6 ms of every brume process's
 * start on the project's machine, for the few runs under mpirun (the same way as
 * Embree and libmicrohttpd). It is opened RTLD_GLOBAL: Open MPI's plugins (mca_*.so), which
 * it opens in MPI_Init, resolve libmpi's symbols from the global scope. Open MPI's
 * predefined handles (MPI_COMM_WORLD, MPI_FLOAT, MPI_SUM) are the addresses of objects in
 * libmpi, so they are looked up too; MPICH's are integer constants. */
#include "cli_dist.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>

#include "commands.h"

#if BRUME_HAVE_MPI
#include <mpi.h>

#include "core/lazylib.h"

#ifndef BRUME_MPI_SONAME
#define BRUME_MPI_SONAME "libmpi.so.40"
#endif

#define MPI_FUNCTIONS(X)                                                                                \
    X(MPI_Init) X(MPI_Comm_rank) X(MPI_Comm_size) X(MPI_Finalize) X(MPI_Abort) X(MPI_Reduce) X(MPI_Send) \
    X(MPI_Recv) X(MPI_Get_library_version)

static struct {
    MPI_FUNCTIONS(LAZYLIB_POINTER)
} mpi;
static const char *const mpi_names[] = {MPI_FUNCTIONS(LAZYLIB_NAME) NULL};
static const char *const mpi_sonames[] = {BRUME_MPI_SONAME, NULL};
/* RTLD_GLOBAL: Open MPI's plug-ins (mca_*.so), which it opens in MPI_Init, resolve libmpi's
 * symbols from the global scope */
static lazylib mpi_so = LAZYLIB_GLOBAL("the MPI library", mpi_sonames, mpi_names, &mpi, sizeof mpi);
static struct {
    MPI_Comm world;
    MPI_Datatype float_type;
    MPI_Op sum;
} mpi_handles;

/* Opens the MPI library once and finds its predefined handles. */
static bool mpi_open(void)
{
    if (!lazylib_open(&mpi_so))
        return false;
#ifdef OPEN_MPI
    void *at[3] = {lazylib_symbol(&mpi_so, "ompi_mpi_comm_world"), lazylib_symbol(&mpi_so, "ompi_mpi_float"),
                   lazylib_symbol(&mpi_so, "ompi_mpi_op_sum")};
    if (!at[0] || !at[1] || !at[2])
        return false;
    mpi_handles.world = (MPI_Comm)at[0];
    mpi_handles.float_type = (MPI_Datatype)at[1];
    mpi_handles.sum = (MPI_Op)at[2];
#else
    mpi_handles.world = MPI_COMM_WORLD;
    mpi_handles.float_type = MPI_FLOAT;
    mpi_handles.sum = MPI_SUM;
#endif
    return true;
}
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
    if (!mpi_open()) {
        cli_error("started by mpirun with %d processes, but %s", n, mpi_so.error);
        return false;
    }
    if (mpi.MPI_Init(NULL, NULL) != MPI_SUCCESS) {
        cli_error("MPI_Init failed");
        return false;
    }
    d->mpi = true;
    mpi.MPI_Comm_rank(mpi_handles.world, &d->rank);
    mpi.MPI_Comm_size(mpi_handles.world, &d->size);
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
        mpi.MPI_Finalize();
#endif
    d->mpi = false;
}

void dist_abort(const dist *d, int code)
{
#if BRUME_HAVE_MPI
    if (d->mpi && d->size > 1)
        mpi.MPI_Abort(mpi_handles.world, code);
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
    return mpi.MPI_Reduce(send, d->rank == 0 ? buf : NULL, (int)n, mpi_handles.float_type, mpi_handles.sum, 0, mpi_handles.world) == MPI_SUCCESS;
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
    return mpi.MPI_Send(buf, (int)n, mpi_handles.float_type, 0, tag, mpi_handles.world) == MPI_SUCCESS;
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
    return mpi.MPI_Recv(buf, (int)n, mpi_handles.float_type, from, tag, mpi_handles.world, MPI_STATUS_IGNORE) == MPI_SUCCESS;
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
    static char info[600];
    if (!mpi_open()) {
        snprintf(info, sizeof info, "MPI (but %s)", mpi_so.error);
        return info;
    }
    char lib[MPI_MAX_LIBRARY_VERSION_STRING];
    int len = 0;
    mpi.MPI_Get_library_version(lib, &len);
    int k = 0;
    while (k < len && k < 40 && lib[k] != ',' && lib[k] != '\n')
        k++;
    snprintf(info, sizeof info, "MPI (%.*s)", k, lib);
    return info;
#else
    return "no MPI";
#endif
}
