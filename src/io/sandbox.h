/* sandbox.h - what the readers that run in a child process share (io/grid_sandbox.c for
 * OpenVDB, io/mesh.c for assimp): the child's limits and the pipe between the two.
 *
 * A reader of a library that is not hardened against hostile files forks; the child sets
 * RLIMIT_CPU, RLIMIT_AS (not under AddressSanitizer, whose shadow memory needs terabytes of
 * address space) and RLIMIT_CORE, silences stdout and stderr, reads, and writes its answer on
 * a pipe; the parent reads the pipe under a wall-clock deadline, never trusting a size before
 * checking it, then reaps the child, killing it on a timeout. A crash, an abort, a timeout or
 * an exhausted limit becomes one line naming the file (sandbox_failure). */
#ifndef BRUME_IO_SANDBOX_H
#define BRUME_IO_SANDBOX_H

#include <stdbool.h>
#include <stddef.h>
#include <sys/types.h>

#include "brume.h"

#if defined(__SANITIZE_ADDRESS__)
#define SANDBOX_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SANDBOX_ASAN 1
#endif
#endif
#ifndef SANDBOX_ASAN
#define SANDBOX_ASAN 0
#endif

double sandbox_now(void);
/* In the child: CPU seconds, address space (bytes, 0 = unchanged; ignored under ASan), no
 * core files, stdout and stderr to /dev/null. */
void sandbox_child_limits(double cpu_seconds, size_t address_space);
/* 0 when all n bytes were written; -1 otherwise. */
int sandbox_write_all(int fd, const void *p, size_t n);
/* Reads exactly n bytes before the deadline (sandbox_now() time): 0 ok, -1 closed or error,
 * -2 timeout, -3 this thread's load was cancelled (brume_context_cancel_loads, core/cancel.h). */
int sandbox_read_all(int fd, void *p, size_t n, double deadline);
/* In the child: the thread's last error (err_message, err_status) as an 'E' record. */
void sandbox_child_error(int fd);
/* In the parent, after an 'E' tag: reads the record and sets it as this thread's error
 * (one line). The read_all result. */
int sandbox_read_error(int fd, double deadline);
/* Reaps pid (killed first when rr is -2, a timeout, or -3, a cancel) and, when rr is not 0, sets the one-line
 * error of what happened: "NAME: WHAT gave no answer within N s", "... exceeded its CPU limit",
 * "... crashed (signal N)", "... failed (exit N)"; `what` names the reader ("the mesh reader"),
 * `hint` what the file may be ("malformed or hostile .vdb"). Returns err_status() or BRUME_OK. */
brume_status sandbox_reap(pid_t pid, int rr, const char *name, const char *what, const char *hint, double cpu_seconds,
                          double wall_seconds);

#endif
