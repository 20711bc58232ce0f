/* progress.h - the figures every display of a render shows, computed once: a fraction done
 * that never goes back and a smoothed ETA. The library prints nothing; the figures reach a
 * caller through brume_render_job_progress (job/), and the bar and the log lines are drawn
 * by the caller (cli/cli_progress.c, python/brume). */
#ifndef BRUME_CORE_PROGRESS_H
#define BRUME_CORE_PROGRESS_H

#include <stdbool.h>

/* Monotonic wall-clock seconds. */
double progress_now(void);

/* How a render's passes grow under a noise target: from s samples a pixel to
 * s + min(max(1, s / divisor), max_step). */
typedef struct progress_passes {
    int divisor, max_step;
} progress_passes;

/* The samples a pixel will have taken when adaptive sampling stops it, predicted from the
 * estimate err of its relative standard error after n samples: it needs n (err / target)^2
 * (the error falls as 1 / sqrt(n)), and gets its samples in passes, so it stops at the first
 * count of the passes from `from` (the last pass's count) that meets its need, not at the
 * need itself; at most spp (the maximum). */
double progress_samples_needed(double n, double err, double target, int from, progress_passes passes, int spp);

/* A render's own estimate of the time left jumps: under a noise target the samples each
 * pixel still needs are estimated again after every pass. A meter turns those readings
 * into what a person can trust: a fraction that never goes back and an ETA that moves
 * smoothly. job/ feeds it from brume_render_job_progress, so that the CLI's bar and log,
 * the live view and Python show the same figures. */

#define PROGRESS_SMOOTHING 0.25 /* the ETA's time constant, a fraction of the time spent or left */
#define PROGRESS_FRAC_MAX 0.99  /* the largest fraction shown before the work is finished */

/* What the work says of itself at one moment. */
typedef struct progress_reading {
    double elapsed;     /* seconds spent so far, >= 0 */
    double left;        /* seconds the work's own estimate leaves, < 0: not known yet */
    double budget_left; /* seconds left of a time budget, < 0: no budget */
    bool finished;      /* nothing left to do */
} progress_reading;

/* What has been shown (progress_meter_init). */
typedef struct progress_meter {
    double frac; /* the largest fraction shown, < 0: none yet */
    double end;  /* the smoothed estimate of `elapsed` at the end, < 0: not known yet */
    double t;    /* elapsed at the last reading that knew the end */
} progress_meter;

void progress_meter_init(progress_meter *m);
/* The fraction done and the ETA (seconds) to show for reading r. The end the reading
 * predicts (elapsed + left, never past a time budget's end) is followed by a first-order
 * filter whose time constant is PROGRESS_SMOOTHING x the smaller of the time spent and the
 * time left: a jump in the estimate shows over a quarter of the run so far rather than at
 * once, and the end of the run is followed closely. The fraction is elapsed / (elapsed +
 * ETA), never below one shown before, at most PROGRESS_FRAC_MAX until the work is finished
 * (then 1, with an ETA of 0). Before the end is known: the last fraction (< 0 if none) and
 * an ETA of -1. Readings come in the order of their elapsed times. */
void progress_meter_read(progress_meter *m, const progress_reading *r, double *frac, double *eta);

#endif
