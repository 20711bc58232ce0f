/* render_impl.h - what render.c (the job, its tiles and passes) gives render_api.c (the
 * public render calls and the job's image); the job's parts and the ETA's cost model are
 * eta.h's. */
#ifndef BRUME_JOB_RENDER_IMPL_H
#define BRUME_JOB_RENDER_IMPL_H

#include <stdbool.h>

#include "brume.h"
#include "job/eta.h"
#include "render/job.h"

/* render.c */
void job_figures(brume_render_job *job, bool finished, brume_render_progress *out);
int job_next_pass(const brume_render_job *job, bool unwatched);
brume_status job_add(brume_render_job *job, int spp, bool unwatched);
brume_status job_run(brume_render_job *job, bool unwatched);

#endif
