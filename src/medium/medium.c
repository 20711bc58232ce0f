/* medium.c - medium lifecycle and derived coefficients. */
#include "medium/medium.h"

#include <stdlib.h>

#include "medium/blackbody.h"

bool medium_has_fields(const medium *m) { return m->albedo[0] || m->temperature || m->emission[0]; }

bool medium_emits(const medium *m)
{
    if (col_is_black(m->sigma_a))
        return false;
    return !col_is_black(m->Le) || m->temperature || (m->emission[0] && !col_is_black(m->emission_color));
}

void medium_init(medium *m)
{
    color st = m->sigma_a;
    for (int c = 0; c < BRUME_NSAMPLES; c++) {
        m->albedo_max[c] = m->albedo[c] ? density_max(m->albedo[c]) : 1.0;
        st.c[c] += m->sigma_s.c[c] * m->albedo_max[c];
    }
    m->sigma_t_max = col_max(st);
    if (m->temperature)
        blackbody_init();
}

void medium_release(medium *m)
{
    density_release(m->rho);
    phase_release(m->ph);
    for (int c = 0; c < 3; c++) {
        density_release(m->albedo[c]);
        density_release(m->emission[c]);
        m->albedo[c] = m->emission[c] = NULL;
    }
    density_release(m->temperature);
    m->temperature = NULL;
    free(m->motion);
    m->motion = NULL;
    m->rho = NULL;
    m->ph = NULL;
}
