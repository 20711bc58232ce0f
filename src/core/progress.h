/* progress.h - progress reports on stderr: a bar redrawn in place when stderr is a terminal,
 * else one line every few seconds (a log), each with the work's figures and its ETA. */
#ifndef BRUME_CORE_PROGRESS_H
#define BRUME_CORE_PROGRESS_H

#include <pthread.h>
#include <stdbool.h>
#include <stddef.h>

#define PROGRESS_LOG_SECONDS 10.0 /* between two log lines by default (Cycles and pbrt log alike) */

/* What a report shows. A negative frac or eta means "not known yet" (a noise target before
 * any pixel has an error estimate); frac stays below 1 until the work is complete. */
typedef struct progress_figures {
    double frac;     /* fraction of the work done, [0, 1], or < 0 */
    double elapsed;  /* seconds */
    double eta;      /* seconds left, or < 0 */
    double spp;      /* mean samples per pixel, < 0: not a render */
    double noise;    /* largest relative standard error over the signal pixels, < 0: not shown */
} progress_figures;

typedef struct progress {
    const char *label;
    size_t total, done;  /* progress_add and progress_update: a count of work items */
    bool active;         /* false: disabled, or interval < 0 off a terminal */
    bool tty;            /* stderr is a terminal: a bar redrawn in place */
    double interval;     /* seconds between log lines off a terminal */
    double t_start, t_last_draw;
    progress_figures last;
    pthread_mutex_t lock;
} progress;

/* Starts a report when enabled: a bar on a terminal, else a line every log_seconds (0: the
 * default PROGRESS_LOG_SECONDS; < 0: none off a terminal). */
void progress_begin(progress *p, const char *label, size_t total, bool enabled, double log_seconds);
/* A count of work items (done of total): thread-safe; the ETA extrapolates the rate. */
void progress_add(progress *p, size_t n);
void progress_update(progress *p, size_t done, size_t total);
/* The figures of a render; drawn when a redraw is due (ten a second on a terminal, one
 * per interval in a log). Thread-safe. */
void progress_show(progress *p, const progress_figures *f);
/* Ends the report: drawn complete when the work is, else as far as it got (an interrupted
 * or failed run must not end on 100 %). */
void progress_end(progress *p, bool complete);

/* Monotonic wall-clock seconds. */
double progress_now(void);

#endif
