/* render_impl.h - what render.c (the job, its tiles and passes) gives render_api.c (the
 * public render calls and the job's image). */
#ifndef BRUME_JOB_RENDER_IMPL_H
#define BRUME_JOB_RENDER_IMPL_H

#include <stdbool.h>

#include "brume.h"
#include "render/job.h"

/* render.c */
bool job_in_part(const brume_render_job *job, size_t i);
void job_figures(brume_render_job *job, bool finished, brume_render_progress *out);
int job_next_pass(const brume_render_job *job, bool unwatched);
brume_status job_add(brume_render_job *job, int spp, bool unwatched);
brume_status job_run(brume_render_job *job, bool unwatched);

#endif
