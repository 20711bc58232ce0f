/* progress.c - progress reports on stderr: a bar with the figures and the ETA on a terminal,
 * a line every few seconds in a log (stderr redirected to a file or a pipe). */
#include "core/progress.h"

#include <stdio.h>
#include <time.h>
#include <unistd.h>

double progress_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* "12.3 s", "4 min 05 s", "1 h 02 min": a duration as a person reads it. */
static void fmt_seconds(char *out, size_t n, double s)
{
    if (s < 60.0)
        snprintf(out, n, "%.1f s", s);
    else if (s < 3600.0)
        snprintf(out, n, "%d min %02d s", (int)(s / 60.0), (int)s % 60);
    else
        snprintf(out, n, "%d h %02d min", (int)(s / 3600.0), ((int)s / 60) % 60);
}

/* Under p->lock. */
static void progress_draw(progress *p, double now, bool final)
{
    const progress_figures *f = &p->last;
    char what[160] = "", el[32], eta[48];
    int len = 0;
    if (f->spp >= 0.0)
        len += snprintf(what + len, sizeof what - (size_t)len, "%.1f spp, ", f->spp);
    if (f->noise >= 0.0 && len < (int)sizeof what)
        len += snprintf(what + len, sizeof what - (size_t)len, "noise %.2f%%, ", 100.0 * f->noise);
    fmt_seconds(el, sizeof el, f->elapsed);
    if (final)
        snprintf(eta, sizeof eta, "done");
    else if (f->eta < 0.0)
        snprintf(eta, sizeof eta, "ETA not known yet");
    else {
        char t[32];
        fmt_seconds(t, sizeof t, f->eta);
        snprintf(eta, sizeof eta, "ETA %s", t);
    }
    char pct[16] = "  ?%";
    if (f->frac >= 0.0)
        snprintf(pct, sizeof pct, "%3d%%", (int)(f->frac * 100.0));
    if (p->tty) {
        enum { WIDTH = 30 };
        char bar[WIDTH + 1];
        int filled = f->frac > 0.0 ? (int)(f->frac * WIDTH) : 0;
        for (int i = 0; i < WIDTH; i++)
            bar[i] = i < filled ? '#' : '.';
        bar[WIDTH] = '\0';
        fprintf(stderr, "\r%s [%s] %s  %s%s elapsed, %s   ", p->label, bar, pct, what, el, eta);
    } else {
        fprintf(stderr, "brume: %s %s: %s%s elapsed, %s\n", p->label, pct, what, el, eta);
    }
    fflush(stderr);
    p->t_last_draw = now;
}

static bool due(const progress *p, double now)
{
    return now - p->t_last_draw >= (p->tty ? 0.1 : p->interval);
}

void progress_begin(progress *p, const char *label, size_t total, bool enabled, double log_seconds)
{
    p->label = label;
    p->total = total;
    p->done = 0;
    p->tty = isatty(STDERR_FILENO);
    p->interval = log_seconds > 0.0 ? log_seconds : PROGRESS_LOG_SECONDS;
    p->active = enabled && (p->tty || log_seconds >= 0.0);
    p->t_start = progress_now();
    p->t_last_draw = p->t_start; /* a log's first line comes one interval in */
    p->last = (progress_figures){-1.0, 0.0, -1.0, -1.0, -1.0};
    pthread_mutex_init(&p->lock, NULL);
    if (p->active && p->tty)
        progress_draw(p, p->t_start, false);
}

/* Figures of a count of work items; under p->lock. */
static void count_figures(progress *p, double now)
{
    double frac = p->total ? (double)p->done / (double)p->total : 0.0;
    frac = frac > 1.0 ? 1.0 : frac;
    double elapsed = now - p->t_start;
    p->last = (progress_figures){frac, elapsed, frac > 0.0 ? elapsed * (1.0 - frac) / frac : -1.0, -1.0, -1.0};
}

void progress_add(progress *p, size_t n)
{
    if (!p->active)
        return;
    pthread_mutex_lock(&p->lock);
    p->done += n;
    double now = progress_now();
    if (due(p, now)) {
        count_figures(p, now);
        progress_draw(p, now, false);
    }
    pthread_mutex_unlock(&p->lock);
}

void progress_update(progress *p, size_t done, size_t total)
{
    if (!p->active)
        return;
    pthread_mutex_lock(&p->lock);
    p->done = done;
    p->total = total;
    double now = progress_now();
    if (due(p, now)) {
        count_figures(p, now);
        progress_draw(p, now, false);
    }
    pthread_mutex_unlock(&p->lock);
}

void progress_show(progress *p, const progress_figures *f)
{
    if (!p->active)
        return;
    pthread_mutex_lock(&p->lock);
    p->last = *f;
    double now = progress_now();
    if (due(p, now))
        progress_draw(p, now, false);
    pthread_mutex_unlock(&p->lock);
}

void progress_end(progress *p, bool complete)
{
    if (p->active && p->tty) {
        if (p->last.spp < 0.0) /* a count: its figures now */
            count_figures(p, progress_now());
        if (complete) {
            p->last.frac = 1.0;
            p->last.eta = 0.0;
        }
        progress_draw(p, progress_now(), complete);
        fputc('\n', stderr);
    }
    pthread_mutex_destroy(&p->lock);
}
