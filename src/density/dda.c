/* dda.c - setting up the 3-D DDA (see dda.h): the whole grid's walk, and a walk again over a
 * part of its interval (box clipping and the first cell are in dda.h, inline). */
#include "density/dda.h"

bool grid_dda_restart(grid_dda *g, double t0, double t1)
{
    t0 = t0 > g->t_in ? t0 : g->t_in;
    t1 = t1 < g->t_out ? t1 : g->t_out;
    g->done = true;
    if (!(t0 < t1))
        return false;
    g->tmax = t1; /* t_in, t_out stay: a later run may lie anywhere in them */
    return dda_seed(g, t0);
}

bool grid_dda_begin(grid_dda *g, const int n[3], vec3 o, vec3 d, double tmin, double tmax)
{
    static const int zero[3] = {0, 0, 0};
    return grid_dda_begin_box(g, n, zero, n, o, d, tmin, tmax);
}

