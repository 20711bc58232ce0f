/* progress.c - a render's progress figures (progress.h): the samples a pixel needs, and the
 * meter that turns the render's estimates into a fraction that never goes back and a
 * smoothed ETA. Nothing here prints. */
#include "core/progress.h"

#include <math.h>
#include <time.h>

double progress_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double progress_samples_needed(double n, double err, double target, int from, progress_passes passes, int spp)
{
    double need = n * (err / target) * (err / target);
    long long s = from;
    while (s < spp && (double)s < need) {
        long long k = s / passes.divisor > 1 ? s / passes.divisor : 1;
        s += k < passes.max_step ? k : passes.max_step;
    }
    return (double)(s < spp ? s : spp);
}

void progress_meter_init(progress_meter *m) { *m = (progress_meter){-1.0, -1.0, 0.0}; }

void progress_meter_read(progress_meter *m, const progress_reading *r, double *frac, double *eta)
{
    if (r->finished) {
        *frac = 1.0;
        *eta = 0.0;
        return;
    }
    double left = r->left;
    if (r->budget_left >= 0.0)
        left = left < 0.0 ? r->budget_left : fmin(left, r->budget_left);
    if (left < 0.0) {
        *frac = m->frac;
        *eta = -1.0;
        return;
    }
    double end = r->elapsed + left;
    if (m->end < 0.0) {
        m->end = end;
    } else if (r->elapsed > m->t) {
        double tau = PROGRESS_SMOOTHING * fmin(r->elapsed, left);
        m->end = tau > 0.0 ? m->end + (end - m->end) * -expm1(-(r->elapsed - m->t) / tau) : end;
    }
    m->t = fmax(m->t, r->elapsed);
    if (r->budget_left >= 0.0) /* a budget's end is a fact, not an estimate */
        m->end = fmin(m->end, r->elapsed + r->budget_left);
    *eta = fmax(m->end - r->elapsed, 0.0);
    double f = r->elapsed > 0.0 ? r->elapsed / (r->elapsed + *eta) : 0.0;
    m->frac = fmax(m->frac, fmin(f, PROGRESS_FRAC_MAX));
    *frac = m->frac;
}
