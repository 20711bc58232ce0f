/* budget.c - the per-thread memory budget of a scene load (budget.h). */
#include "core/budget.h"

#include "core/error.h"

static _Thread_local bool open_;
static _Thread_local size_t limit_, used_;
static _Thread_local double work_limit_;
static _Thread_local size_t held_; /* budget_hold: another scene's bytes, kept across begin/end */

void budget_begin(size_t limit)
{
    open_ = true;
    limit_ = limit ? limit : BUDGET_DEFAULT_BYTES;
    used_ = 0;
    work_limit_ = BUDGET_DEFAULT_WORK;
}

void budget_set_work_limit(double units)
{
    if (open_)
        work_limit_ = units > 0.0 ? units : BUDGET_DEFAULT_WORK;
}

double budget_work_limit(void) { return open_ ? work_limit_ : BUDGET_DEFAULT_WORK; }

brume_status budget_work(double units, const char *who, const char *how)
{
    double limit = budget_work_limit();
    if (!(units <= limit))
        return err_set(BRUME_ERROR_RANGE, "%s: %s are %.3g units of work, over render.max_work (%.3g)", who, how,
                       units, limit);
    return BRUME_OK;
}

void budget_set_limit(size_t limit)
{
    if (open_)
        limit_ = limit ? limit : BUDGET_DEFAULT_BYTES;
#ifdef BUDGET_MAX_BYTES
    if (limit_ > BUDGET_MAX_BYTES)
        limit_ = BUDGET_MAX_BYTES;
#endif
}

void budget_resume(size_t limit, size_t used)
{
    budget_begin(limit);
    used_ = used;
}

size_t budget_used(void) { return open_ ? used_ : 0; }

void budget_end(void)
{
    open_ = false;
    used_ = 0;
}

size_t budget_limit(void) { return open_ ? limit_ : BUDGET_DEFAULT_BYTES; }

size_t budget_left(void)
{
    if (!open_)
        return BUDGET_DEFAULT_BYTES;
    return used_ < limit_ ? limit_ - used_ : 0;
}

void budget_hold(size_t bytes) { held_ = bytes; }

brume_status budget_take(size_t bytes, const char *who)
{
    size_t left = budget_left();
    if (open_ && held_ > 0) /* another scene's bytes count here, not in budget_left (budget.h) */
        left = left > held_ ? left - held_ : 0;
    if (bytes > left) {
        double mib = 1.0 / 1048576.0;
        if (open_ && held_ > 0)
            return err_set(BRUME_ERROR_OUT_OF_MEMORY,
                           "%s: needs %.1f MiB, more than the %.1f MiB left of the memory limit of %.0f MiB "
                           "(render.max_memory_mb) while another scene holds %.1f MiB of it",
                           who, (double)bytes * mib, (double)left * mib, (double)limit_ * mib, (double)held_ * mib);
        if (open_)
            return err_set(BRUME_ERROR_OUT_OF_MEMORY,
                           "%s: needs %.1f MiB, more than the %.1f MiB left of the memory limit of %.0f MiB "
                           "(render.max_memory_mb)",
                           who, (double)bytes * mib, (double)left * mib, (double)limit_ * mib);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: needs %.1f MiB, more than the memory limit of %.0f MiB", who,
                       (double)bytes * mib, (double)left * mib);
    }
    if (open_)
        used_ += bytes;
    return BRUME_OK;
}

void budget_give(size_t bytes)
{
    if (open_)
        used_ = bytes < used_ ? used_ - bytes : 0;
}
