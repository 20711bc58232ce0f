/* medium.c - medium lifecycle and derived coefficients. */
#include "medium/medium.h"

#include <stdlib.h>

#include "core/error.h"
#include "medium/blackbody.h"

bool medium_emits(const medium *m)
{
    if (col_is_black(m->sigma_a) && !m->emit_per_length)
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
    m->sigma_t_min = m->albedo[0] ? 0.0 : col_min(col_add(m->sigma_a, m->sigma_s));
    if (m->temperature)
        blackbody_init();
    m->sigma_flight = m->sigma_t_max;
    if (m->emit_per_length && m->rho && medium_emits(m)) {
        /* Emission per unit length is gathered at a flight's tentative collisions, which
         * must come where the medium is, however clear: at least some 16 along the field's
         * diagonal where the density is at its maximum (the estimate's relative deviation
         * over a path of n expected collisions is 1 / sqrt(n)). */
        density_info in;
        density_get_info(m->rho, &in);
        double diag = v3_length(v3_sub(in.bounds.hi, in.bounds.lo));
        double rate = in.rho_max > 0.0 && diag > 0.0 ? 16.0 / (in.rho_max * diag) : 0.0;
        if (isfinite(rate) && rate > m->sigma_flight)
            m->sigma_flight = rate;
    }
    /* |v| = |M u| <= medium_velocity_map_norm |u|, and |u| <= the norm of the components'
     * bounds: a lookup (nearest, or trilinear: a convex combination of voxels) lies within
     * each component's range of values */
    double u2 = 0.0;
    for (int c = 0; m->velocity[0] && c < 3; c++) {
        density_info in;
        density_get_info(m->velocity[c], &in);
        double b = fmax(fabs(in.rho_min), fabs(in.rho_max));
        u2 += b * b;
    }
    m->velocity_max = m->velocity[0] ? sqrt(u2) * medium_velocity_map_norm(m) : 0.0;
}

brume_status medium_check_range(const medium *m, const char *source, int index)
{
    if (!m->rho)
        return BRUME_OK;
    density_info in;
    density_get_info(m->rho, &in);
    /* a majorant cell's world size: at most mcell voxels along each voxel-space axis, and
     * never more than the whole field */
    const double *a = in.voxel_to_world.m;
    double edge = 0.0;
    for (int c = 0; c < 3; c++)
        edge += sqrt(a[c] * a[c] + a[4 + c] * a[4 + c] + a[8 + c] * a[8 + c]);
    double cell = fmin(edge * in.majorant_cell, v3_length(v3_sub(in.bounds.hi, in.bounds.lo)));
    double sigma_hi = m->sigma_t_max * in.rho_max, spread = m->sigma_t_max * (in.rho_max - in.rho_min) * cell;
    if (!isfinite(sigma_hi))
        return err_set(BRUME_ERROR_RANGE,
                       "%s: media[%d]: sigma_t %g times density up to %g is not a finite extinction "
                       "(docs/scene-format.md#limits)",
                       source, index, m->sigma_t_max, in.rho_max);
    if (!(spread <= MEDIUM_TAU_SPREAD_MAX))
        return err_set(BRUME_ERROR_RANGE,
                       "%s: media[%d]: sigma_t %g times densities from %g to %g over a majorant cell %g wide varies "
                       "by an optical depth of %.3g, more than the %.0f brume can track "
                       "(docs/scene-format.md#limits)",
                       source, index, m->sigma_t_max, in.rho_min, in.rho_max, cell, spread, MEDIUM_TAU_SPREAD_MAX);
    /* Channels of unequal extinction: tentative collisions come at the largest channel's rate,
     * and the flight's ratio tracking goes on while the smallest channel's transmittance
     * stays up, about sigma_t_max / sigma_t_min collisions for each e-fold of it (some 10 of
     * them before the roulette ends it), unless the ray leaves the field first (its optical
     * depth at the largest rate across the field). The smaller of the two is the flight's
     * cost: at most the same optical depth brume tracks in a cell. */
    double diag = v3_length(v3_sub(in.bounds.hi, in.bounds.lo));
    double tau_across = sigma_hi * diag, ratio = m->sigma_t_max / m->sigma_t_min; /* inf for a clear channel */
    if (m->sigma_t_min < m->sigma_t_max && !(fmin(tau_across, 10.0 * ratio) <= MEDIUM_TAU_SPREAD_MAX))
        return err_set(BRUME_ERROR_RANGE,
                       "%s: media[%d]: sigma_t from %.17g to %.17g across the colour channels, times density up to "
                       "%.17g over a field %.3g wide: a free flight would take some %.3g tentative collisions, more than "
                       "the %.0f brume can track (docs/scene-format.md#limits)",
                       source, index, m->sigma_t_min, m->sigma_t_max, in.rho_max, diag, fmin(tau_across, 10.0 * ratio),
                       MEDIUM_TAU_SPREAD_MAX);
    return BRUME_OK;
}

void medium_release(medium *m)
{
    density_release(m->rho);
    phase_release(m->ph);
    for (int c = 0; c < 3; c++) {
        density_release(m->albedo[c]);
        density_release(m->emission[c]);
        density_release(m->velocity[c]);
        m->albedo[c] = m->emission[c] = m->velocity[c] = NULL;
    }
    density_release(m->moved);
    m->moved = NULL;
    density_release(m->temperature);
    m->temperature = NULL;
    free(m->motion);
    m->motion = NULL;
    m->rho = NULL;
    m->ph = NULL;
}
