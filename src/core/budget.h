/* budget.h - the one memory limit that every reader and generator counts against.
 *
 * Loading a scene opens a budget (budget_begin) of render.max_memory_mb (default 4 GiB);
 * each reader or generator asks budget_take for the bytes it is about to allocate, before
 * allocating, and fails with a one-line message naming what wanted the memory, the key
 * and the limit when the scene's total would exceed it. Outside a scene load (a grid read
 * by `brume info`, an image read through the API) there is no running total: each request
 * alone is checked against the default limit. The state is per thread: a scene loads on
 * one thread. docs/scene-format.md, "Limits". */
#ifndef BRUME_CORE_BUDGET_H
#define BRUME_CORE_BUDGET_H

#include <stdbool.h>
#include <stddef.h>

#include "brume.h"

/* 4 GiB: the default of render.max_memory_mb (4096). A build may lower it, and cap what a
 * scene may ask for with BUDGET_MAX_BYTES (the fuzz targets do: fuzz/run.sh). */
#ifndef BUDGET_DEFAULT_BYTES
#define BUDGET_DEFAULT_BYTES ((size_t)4 << 30)
#endif

/* 1e12: the default of render.max_work, the one work limit (units of work: a step of a ray,
 * a noise value or a lattice point generated; about 3 hours of Blasi's light pass on 2 cores). */
#define BUDGET_DEFAULT_WORK 1e12

/* Opens this thread's budget with `limit` bytes (0 = the default) and the default work
 * limit; nests by replacing. */
void budget_begin(size_t limit);
/* Changes the open budget's limit (render.max_memory_mb); bytes already taken stay taken. */
void budget_set_limit(size_t limit);
void budget_end(void);
/* Opens this thread's budget again for an object that took `used` of `limit` before (a
 * scene read earlier and committed now). */
void budget_resume(size_t limit, size_t used);
/* Changes the open budget's work limit (render.max_work, units of work; 0 = the default). */
void budget_set_work_limit(double units);
/* The open budget's work limit, or the default when none is open. */
double budget_work_limit(void);
/* A generator about to do `units` of work asks first (`how` says how they were counted,
 * e.g. "64^3 voxels x 5 octaves"): BRUME_OK, or BRUME_ERROR_RANGE with err_set() naming who,
 * the figure and the limit when they pass it. Work is not summed: each phase is bounded
 * alone, as each phase is interruptible alone. */
brume_status budget_work(double units, const char *who, const char *how);
/* Bytes taken from the open budget (0 when none is open). */
size_t budget_used(void);
/* Takes `bytes` for `who` (e.g. "scene.json: media[0].phase.file"): BRUME_OK, or
 * BRUME_ERROR_OUT_OF_MEMORY with err_set() when they exceed what is left. */
brume_status budget_take(size_t bytes, const char *who);
/* Bytes of the same limit that another object holds while this thread loads (a sequence's
 * frame being rendered while the next frame is read ahead, brume_load_options.memory_held);
 * 0 ends it. budget_take refuses what would pass the limit with them; budget_left does not
 * count them, so that what a reader chooses by the memory left (a small grid's dense copy)
 * is what it chooses alone: a load under a hold makes the same scene as without it, or fails
 * with BRUME_ERROR_OUT_OF_MEMORY. Per thread, kept across budget_begin and budget_end. */
void budget_hold(size_t bytes);
/* Gives back bytes taken for something freed while loading. */
void budget_give(size_t bytes);
/* Bytes left in the open budget, or the default limit when none is open. */
size_t budget_left(void);
/* The open budget's limit, or the default when none is open. */
size_t budget_limit(void);

#endif
