/* stats.c - per-thread counters of a render, merged after it (stats.h). */
#include "core/stats.h"

_Thread_local stats_counters *stats_tls;

void stats_merge(stats_counters *a, const stats_counters *b)
{
    a->camera_rays += b->camera_rays;
    a->path_vertices += b->path_vertices;
    a->path_tentative += b->path_tentative;
    a->path_scatterings += b->path_scatterings;
    a->majorant_cells += b->majorant_cells;
    a->density_lookups += b->density_lookups;
    a->blob_queries += b->blob_queries;
    a->blob_nodes += b->blob_nodes;
    a->blob_visits += b->blob_visits;
    a->stam_camera_blobs += b->stam_camera_blobs;
    a->t_li += b->t_li;
    a->t_tracking += b->t_tracking;
    a->t_nee += b->t_nee;
}
