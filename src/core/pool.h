/* pool.h - run independent tasks (image tiles, batches of light rays) on worker threads.
 *
 * Tasks are handed out through one atomic counter, so the work split adapts to load, and
 * results must not depend on which thread ran a task: write to per-task storage, or draw
 * random numbers from the task's own counter-based stream (core/rng.h). */
#ifndef BRUME_CORE_POOL_H
#define BRUME_CORE_POOL_H

#include <stddef.h>

/* fn(task, thread, user) for task in [0, ntasks), thread in [0, nthreads). */
typedef void (*pool_fn)(size_t task, int thread, void *user);

/* Runs every task once on nthreads threads (0 = one per online core) and returns when all
 * are done. The calling thread works too. Returns the number of threads used. */
int pool_run(int nthreads, size_t ntasks, pool_fn fn, void *user);

/* Number of online cores (at least 1). */
int pool_default_threads(void);

#endif
