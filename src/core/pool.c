/* pool.c - a fork-join pool over an atomic task counter (pthreads). */
#include "core/pool.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <unistd.h>

typedef struct pool_job {
    atomic_size_t next;
    size_t ntasks;
    pool_fn fn;
    void *user;
} pool_job;

typedef struct pool_worker {
    pool_job *job;
    int thread;
} pool_worker;

static void pool_drain(pool_job *job, int thread)
{
    for (;;) {
        size_t t = atomic_fetch_add(&job->next, 1);
        if (t >= job->ntasks)
            return;
        job->fn(t, thread, job->user);
    }
}

static void *pool_main(void *arg)
{
    pool_worker *w = arg;
    pool_drain(w->job, w->thread);
    return NULL;
}

int pool_default_threads(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : (int)n;
}

int pool_run(int nthreads, size_t ntasks, pool_fn fn, void *user)
{
    if (nthreads <= 0)
        nthreads = pool_default_threads();
    if ((size_t)nthreads > ntasks)
        nthreads = ntasks > 0 ? (int)ntasks : 1;
    pool_job job;
    atomic_init(&job.next, 0);
    job.ntasks = ntasks;
    job.fn = fn;
    job.user = user;

    pthread_t *tid = NULL;
    pool_worker *workers = NULL;
    int started = 0;
    if (nthreads > 1) {
        tid = malloc(sizeof *tid * (size_t)nthreads);
        workers = malloc(sizeof *workers * (size_t)nthreads);
        if (tid && workers) {
            for (int i = 1; i < nthreads; i++) {
                workers[i] = (pool_worker){&job, i};
                if (pthread_create(&tid[i], NULL, pool_main, &workers[i]) != 0)
                    break;
                started = i;
            }
        }
    }
    pool_drain(&job, 0); /* if threads could not start, the caller does all the work */
    for (int i = 1; i <= started; i++)
        pthread_join(tid[i], NULL);
    free(tid);
    free(workers);
    return started + 1;
}
