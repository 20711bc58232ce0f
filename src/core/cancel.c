/* cancel.c - the progress callback asked from phases without tiles (cancel.h). */
#include "core/cancel.h"

#include <time.h>

#include "core/context.h"
#include "core/error.h"

static long long now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (long long)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

void cancel_poll_init(cancel_poll *c, const brume_render_settings *rs)
{
    c->fn = rs ? rs->progress_fn : NULL;
    c->user = rs ? rs->progress_user : NULL;
    atomic_init(&c->stop, false);
    atomic_init(&c->next_ns, now_ns() + (long long)(CANCEL_POLL_SECONDS * 1e9));
    atomic_init(&c->out_of_time, false);
    c->deadline_ns = rs && rs->time_budget > 0.0 ? now_ns() + (long long)(rs->time_budget * 1e9) : 0;
    pthread_mutex_init(&c->lock, NULL);
}

bool cancel_poll_stop(cancel_poll *c)
{
    if (atomic_load_explicit(&c->stop, memory_order_relaxed))
        return true;
    if (!c->fn && !c->deadline_ns)
        return false;
    long long t = now_ns();
    if (c->deadline_ns && t >= c->deadline_ns) {
        atomic_store(&c->out_of_time, true);
        atomic_store(&c->stop, true);
        return true;
    }
    if (!c->fn)
        return false;
    if (t < atomic_load_explicit(&c->next_ns, memory_order_relaxed))
        return false;
    if (pthread_mutex_trylock(&c->lock) != 0)
        return false; /* another thread is asking */
    if (t >= atomic_load(&c->next_ns) && !atomic_load(&c->stop)) {
        if (!c->fn(c->user, 0, 1))
            atomic_store(&c->stop, true);
        atomic_store(&c->next_ns, now_ns() + (long long)(CANCEL_POLL_SECONDS * 1e9));
    }
    pthread_mutex_unlock(&c->lock);
    return atomic_load(&c->stop);
}

bool cancel_poll_cancelled(const cancel_poll *c) { return atomic_load((atomic_bool *)&c->stop); }

bool cancel_poll_out_of_time(const cancel_poll *c) { return atomic_load((atomic_bool *)&c->out_of_time); }

void cancel_poll_finish(cancel_poll *c) { pthread_mutex_destroy(&c->lock); }

static _Thread_local atomic_uint *g_load_cancels; /* the loading context's count, NULL: none */
static _Thread_local unsigned g_load_start;        /* the count when this thread's load began */

/* An atomic add on a lock-free atomic: async-signal-safe. */
void brume_context_cancel_loads(brume_context *ctx)
{
    if (ctx)
        atomic_fetch_add(&ctx->load_cancels, 1u);
}

void cancel_load_begin(brume_context *ctx)
{
    g_load_cancels = ctx ? &ctx->load_cancels : NULL;
    g_load_start = ctx ? atomic_load(&ctx->load_cancels) : 0u;
}

void cancel_load_end(void) { g_load_cancels = NULL; }

static _Thread_local cancel_poll *g_watch; /* a render's callback, asked too (cancel_load_watch) */

void cancel_load_watch(cancel_poll *c) { g_watch = c; }

bool cancel_load_requested(void)
{
    return g_load_cancels && atomic_load_explicit(g_load_cancels, memory_order_relaxed) != g_load_start;
}

brume_status cancel_load_check(const char *what)
{
    if (g_watch && cancel_poll_stop(g_watch))
        return cancel_poll_out_of_time(g_watch)
                   ? err_set(BRUME_ERROR_RANGE, "%s: render.time: the time budget was spent before the first sample", what)
                   : err_set(BRUME_ERROR_CANCELLED, "%s: cancelled by the render's progress callback", what);
    if (!g_load_cancels || atomic_load_explicit(g_load_cancels, memory_order_relaxed) == g_load_start)
        return BRUME_OK;
    return err_set(BRUME_ERROR_CANCELLED, "%s: loading cancelled (brume_context_cancel_loads)", what);
}
