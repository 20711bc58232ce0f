/* cli_dist.h - rendering over several processes started by mpirun: which process this
 * is, and moving images to rank 0. Built on MPI when CMake finds it (BRUME_HAVE_MPI);
 * otherwise every call behaves as a single process, and a run under mpirun stops with a
 * clear message instead of rendering the same image N times. MPI is initialised only when
 * a launcher started the process, so a plain `brume render` never touches MPI. */
#ifndef BRUME_CLI_DIST_H
#define BRUME_CLI_DIST_H

#include <stdbool.h>
#include <stddef.h>

typedef struct dist {
    int rank, size; /* this process and the number of processes (1, 0 alone) */
    bool mpi;       /* MPI was initialised (dist_end finalises it) */
} dist;

/* Joins the launcher's processes, or stands alone. False (with a message printed) when
 * started by mpirun with N > 1 in a build without MPI, or when MPI fails to start. */
bool dist_begin(dist *d);
void dist_end(dist *d);
/* Stops every process with exit status `code` (a failure on one rank would otherwise
 * leave the others waiting); returns only when alone. */
void dist_abort(const dist *d, int code);
/* Sums n floats of every rank into rank 0's buf (other ranks' buf unchanged). */
bool dist_reduce_to_root(const dist *d, float *buf, size_t n);
/* Sends n floats to rank 0 / receives them on rank 0 from rank `from`; tag = frame. */
bool dist_send_to_root(const dist *d, const float *buf, size_t n, int tag);
bool dist_recv_at_root(const dist *d, float *buf, size_t n, int from, int tag);
/* "MPI (Open MPI v4.1.4)" or "no MPI": for --version. */
const char *dist_build_info(void);

#endif
