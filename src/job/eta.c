/* eta.c - the pixels of a job's part, and the cost model behind a render's ETA (eta.h): what
 * a sample costs in each tile, and what the model gives a pass before it runs, so that
 * job_figures can correct the model by how far it missed the passes it priced. */
#include "job/eta.h"

bool job_in_part(const brume_render_job *job, size_t i)
{
    size_t x = i % (size_t)job->rs.width, y = i / (size_t)job->rs.width;
    size_t tile = (y / JOB_TILE) * (size_t)job->tiles_x + x / JOB_TILE;
    return tile % (size_t)job->nparts == (size_t)job->part;
}

/* The mean cost per sample of the tiles whose cost is known, 0 if none: the cost of a tile
 * that has not been measured yet. */
double job_mean_tile_cost(const brume_render_job *job)
{
    double sum = 0.0;
    size_t known = 0;
    for (size_t t = 0; t < job->ntiles; t++)
        if (job->tile_cost[t] > 0.0) {
            sum += job->tile_cost[t];
            known++;
        }
    return known ? sum / (double)known : 0.0;
}

/* The tile of the job's part that holds pixel i (job_in_part(job, i)). */
size_t job_pixel_task(const brume_render_job *job, size_t i)
{
    size_t x = i % (size_t)job->rs.width, y = i / (size_t)job->rs.width;
    return ((y / JOB_TILE) * (size_t)job->tiles_x + x / JOB_TILE) / (size_t)job->nparts;
}

/* Each active pixel's samples to job->target at its tile's cost (the mean cost where the
 * tile has none yet), turned into wall seconds as the last pass ran them; 0 before any
 * tile's cost is known. */
double job_pass_model(const brume_render_job *job)
{
    double mean_cost = job_mean_tile_cost(job), cost = 0.0;
    if (!(mean_cost > 0.0) || !(job->wall_per_cost > 0.0))
        return 0.0;
    for (size_t i = 0; i < job->npix; i++) {
        if (!job->active[i] || (job->nparts > 1 && !job_in_part(job, i)) || (int64_t)job->n[i] >= job->target)
            continue;
        double c = job->tile_cost[job_pixel_task(job, i)];
        cost += (double)(job->target - (int64_t)job->n[i]) * (c > 0.0 ? c : mean_cost);
    }
    return cost * job->wall_per_cost;
}
