/* eta.h - which pixels a job's part holds, and the cost model behind the ETA (eta.c), for
 * render.c (job_refresh, job_pass, job_figures) and render_api.c. */
#ifndef BRUME_JOB_ETA_H
#define BRUME_JOB_ETA_H

#include <stdbool.h>
#include <stddef.h>

#include "render/job.h"

/* Whether pixel i belongs to the job's part (its tile, dealt round-robin to the parts). */
bool job_in_part(const brume_render_job *job, size_t i);
/* The mean cost per sample of the tiles whose cost is known, 0 if none. */
double job_mean_tile_cost(const brume_render_job *job);
/* The tile of the job's part that holds pixel i (job_in_part(job, i)). */
size_t job_pixel_task(const brume_render_job *job, size_t i);
/* Under job->lock at a pass's start: the wall seconds the cost model gives the pass. */
double job_pass_model(const brume_render_job *job);

#endif
