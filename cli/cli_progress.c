/* cli_progress.c - `brume render`'s progress display (cli_progress.h): a bar with the figures
 * and the ETA on a terminal, a line every few seconds in a log (stderr redirected to a file
 * or a pipe), and the reason a render stopped. The library computes the figures once
 * (brume_render_job_progress: a fraction that never goes back, a smoothed ETA), so the bar,
 * the log, the live view and Python show the same; one render is shown at a time. */
#include "cli_progress.h"

#include <stdio.h>
#include <time.h>
#include <unistd.h>

static struct {
    bool active;     /* drawing: enabled, and a terminal or log lines asked */
    bool tty;        /* stderr is a terminal: a bar redrawn in place */
    bool drawn;      /* a bar is on the terminal's line: the end adds a newline */
    double interval; /* seconds between two log lines */
    double t_start, t_last;
} g;

static double now_seconds(void)
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

/* One bar or line from the figures p (NULL: no job yet, only the time since the start). */
static void draw(const brume_render_progress *p, double now)
{
    char what[160] = "", el[32], eta[48] = "ETA not known yet", pct[16] = "  ?%";
    double frac = -1.0;
    if (p) {
        int len = snprintf(what, sizeof what, "%.1f spp, ", p->spp_mean);
        if (p->noise > 0.0)
            snprintf(what + len, sizeof what - (size_t)len, "noise %.2f%%, ", 100.0 * p->noise);
        fmt_seconds(el, sizeof el, p->elapsed);
        frac = p->fraction;
        if (p->finished) {
            snprintf(eta, sizeof eta, "done");
        } else if (p->eta >= 0.0) {
            char t[32];
            fmt_seconds(t, sizeof t, p->eta);
            snprintf(eta, sizeof eta, "ETA %s", t);
        }
    } else {
        snprintf(what, sizeof what, "preparing, ");
        fmt_seconds(el, sizeof el, now - g.t_start);
    }
    if (frac >= 0.0)
        snprintf(pct, sizeof pct, "%3d%%", (int)(frac * 100.0));
    if (g.tty) {
        enum { WIDTH = 30 };
        char bar[WIDTH + 1];
        int filled = frac > 0.0 ? (int)(frac * WIDTH) : 0;
        for (int i = 0; i < WIDTH; i++)
            bar[i] = i < filled ? '#' : '.';
        bar[WIDTH] = '\0';
        fprintf(stderr, "\rrender [%s] %s  %s%s elapsed, %s   ", bar, pct, what, el, eta);
        g.drawn = true;
    } else {
        fprintf(stderr, "brume: render %s: %s%s elapsed, %s\n", pct, what, el, eta);
    }
    fflush(stderr);
    g.t_last = now;
}

void cli_progress_begin(bool enabled, double log_seconds)
{
    g.tty = isatty(STDERR_FILENO);
    g.interval = log_seconds > 0.0 ? log_seconds : CLI_PROGRESS_LOG_SECONDS;
    g.active = enabled && (g.tty || log_seconds >= 0.0);
    g.drawn = false;
    g.t_start = now_seconds();
    g.t_last = g.t_start; /* a log's first line comes one interval in */
    if (g.active && g.tty)
        draw(NULL, g.t_start);
}

void cli_progress_tick(const brume_render_job *job)
{
    if (!g.active)
        return;
    double now = now_seconds();
    if (now - g.t_last < (g.tty ? 0.1 : g.interval))
        return;
    brume_render_progress p;
    if (job)
        brume_render_job_progress(job, &p);
    draw(job ? &p : NULL, now);
}

void cli_progress_end(const brume_render_job *job)
{
    if (g.active && g.tty) {
        brume_render_progress p;
        if (job)
            brume_render_job_progress(job, &p);
        draw(job ? &p : NULL, now_seconds());
    }
    if (g.drawn)
        fputc('\n', stderr);
    g.active = g.drawn = false;
}

void cli_progress_stop_reason(const brume_render_progress *p, const brume_render_settings *rs, char *buf, size_t n)
{
    switch (p->stopped) {
    case BRUME_STOP_NOISE:
        snprintf(buf, n, "every pixel met the %.3g%% noise target", 100.0 * rs->noise_target);
        break;
    case BRUME_STOP_SPP:
        if (rs->noise_target > 0.0)
            snprintf(buf, n, "the sample maximum, %d spp (render.spp or --spp), before the noise target: %.1f%% of "
                             "the pixels met it", rs->spp, 100.0 * p->converged);
        else if (rs->time_budget > 0.0)
            snprintf(buf, n, "the sample maximum, %d spp (render.spp or --spp), before the time budget", rs->spp);
        else
            snprintf(buf, n, "the %d spp asked", rs->spp);
        break;
    case BRUME_STOP_TIME:
        snprintf(buf, n, "the %.3g s time budget ran out", rs->time_budget);
        break;
    case BRUME_STOP_CANCELLED:
        snprintf(buf, n, "interrupted");
        break;
    default:
        snprintf(buf, n, "%s", "");
        break;
    }
}
