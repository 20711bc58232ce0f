/* progress.c - progress bar with elapsed time and ETA, drawn on stderr when it is a tty. */
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

static void progress_draw(progress *p, double now)
{
    double frac = p->total ? (double)p->done / (double)p->total : 1.0;
    double elapsed = now - p->t_start;
    double eta = frac > 0.0 ? elapsed * (1.0 - frac) / frac : 0.0;
    enum { WIDTH = 40 };
    char bar[WIDTH + 1];
    int filled = (int)(frac * WIDTH);
    for (int i = 0; i < WIDTH; i++)
        bar[i] = i < filled ? '#' : '.';
    bar[WIDTH] = '\0';
    fprintf(stderr, "\r%s [%s] %3d%%  %.1fs elapsed, ETA %.1fs ", p->label, bar, (int)(frac * 100.0), elapsed, eta);
    fflush(stderr);
    p->t_last_draw = now;
}

void progress_begin(progress *p, const char *label, size_t total, bool enabled)
{
    p->label = label;
    p->total = total;
    p->done = 0;
    p->active = enabled && isatty(STDERR_FILENO);
    p->t_start = progress_now();
    p->t_last_draw = 0.0;
    pthread_mutex_init(&p->lock, NULL);
    if (p->active)
        progress_draw(p, p->t_start);
}

void progress_add(progress *p, size_t n)
{
    if (!p->active)
        return;
    pthread_mutex_lock(&p->lock);
    p->done += n;
    double now = progress_now();
    if (now - p->t_last_draw > 0.1 || p->done >= p->total)
        progress_draw(p, now);
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
    if (now - p->t_last_draw > 0.1 || p->done >= p->total)
        progress_draw(p, now);
    pthread_mutex_unlock(&p->lock);
}

void progress_end(progress *p, bool complete)
{
    if (p->active) {
        if (complete)
            p->done = p->total;
        progress_draw(p, progress_now());
        fputc('\n', stderr);
    }
    pthread_mutex_destroy(&p->lock);
}
