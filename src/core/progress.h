/* progress.h - a progress bar with ETA on a terminal (stderr), silent otherwise. */
#ifndef BRUME_CORE_PROGRESS_H
#define BRUME_CORE_PROGRESS_H

#include <pthread.h>
#include <stdbool.h>
#include <stddef.h>

typedef struct progress {
    const char *label;
    size_t total, done;
    bool active; /* false: not a terminal, or quiet */
    double t_start, t_last_draw;
    pthread_mutex_t lock;
} progress;

/* active only when enabled and stderr is a terminal. */
void progress_begin(progress *p, const char *label, size_t total, bool enabled);
/* Thread-safe; redraws at most ten times a second. */
void progress_add(progress *p, size_t n);
/* Sets both figures (a total that is an estimate may change); thread-safe. */
void progress_update(progress *p, size_t done, size_t total);
/* Ends the bar: drawn full when the work is complete, else as far as it got (an interrupted
 * or failed run must not end on 100 %). */
void progress_end(progress *p, bool complete);

/* Monotonic wall-clock seconds. */
double progress_now(void);

#endif
