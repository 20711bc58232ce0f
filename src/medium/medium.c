/* medium.c - medium lifecycle and derived coefficients. */
#include "medium/medium.h"

#include <stdlib.h>

void medium_init(medium *m) { m->sigma_t_max = col_max(col_add(m->sigma_a, m->sigma_s)); }

void medium_release(medium *m)
{
    density_release(m->rho);
    phase_release(m->ph);
    free(m->motion);
    m->motion = NULL;
    m->rho = NULL;
    m->ph = NULL;
}
