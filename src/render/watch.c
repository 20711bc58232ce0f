/* watch.c - the bound on one camera sample's work, and its stop (watch.h). */
#include "render/watch.h"

#include <math.h>

#include "scene/scene.h"

_Thread_local sample_watch *watch_tls;

uint64_t watch_bound(const brume_scene *s, int max_depth)
{
    double tau = 0.0;
    for (int m = 0; m < s->nmedia; m++) {
        const medium *md = &s->media[m];
        if (!md->rho)
            continue;
        density_info in;
        density_get_info(md->rho, &in);
        tau += md->sigma_t_max * in.rho_max * v3_length(v3_sub(in.bounds.hi, in.bounds.lo));
    }
    double n = WATCH_MARGIN * (double)(max_depth + 1) * (tau + 1.0); /* inf for an unbounded medium */
    if (!(n >= 0x1p24))
        n = isnan(n) ? 0x1p40 : 0x1p24;
    return n < 0x1p40 ? (uint64_t)n : (uint64_t)1 << 40;
}

static void watch_arm(sample_watch *w)
{
    uint64_t end = w->sample_start + w->bound;
    w->check_at = end < w->next_poll ? end : w->next_poll;
}

void watch_sample(sample_watch *w)
{
    w->sample_start = w->collisions;
    w->cut = false;
    if (w->stopped)
        w->check_at = 0;
    else
        watch_arm(w);
}

bool watch_slow(sample_watch *w)
{
    if (w->cut || w->stopped) /* every later walk of the sample ends at its first collision */
        return true;
    if (w->collisions - w->sample_start >= w->bound) {
        w->cut = true;
        w->check_at = 0;
        return true;
    }
    if (w->collisions >= w->next_poll) {
        w->next_poll = w->collisions + WATCH_POLL;
        if (w->poll && w->poll(w->user)) {
            w->stopped = true;
            w->check_at = 0;
            return true;
        }
    }
    watch_arm(w);
    return false;
}
