/* medium.h - a participating medium: a density field with optical properties.
 *
 * Units: sigma_a and sigma_s are per world unit of length per unit density, so at x
 *   sigma_t(x) = (sigma_a + sigma_s) rho(x)   [1 / world unit]
 * and the albedo is sigma_s / (sigma_a + sigma_s). Blasi's alpha and sigma are sigma_a and
 * sigma_s; Stam's kappa_t is sigma_a + sigma_s.
 *
 * Emission, in one of two units for the whole medium (emit_per_length):
 *   false (pbrt-v4's): Le is a radiance [W m^-2 sr^-1] added along a ray at the rate
 *     sigma_a rho(x) Le(x) per unit length (Stam's (1 - Omega) E term);
 *   true (Cycles'): Le is a radiance per unit length [W m^-2 sr^-1 / world unit] added as it
 *     is wherever rho(x) > 0, whatever the density (Principled Volume's emission).
 *
 * Optional fields (docs/grids.md, "Media with several fields"), each a grid with its own
 * placement, evaluated at the same medium-local point as rho:
 *   albedo A(x) (3 fields, one per channel): sigma_s(x) = sigma_s rho(x) A(x) per channel;
 *   temperature T(x) (kelvin): with T' = (T(x) - bb_offset) bb_tscale > bb_cutoff, adds
 *     pbrt-v4's  Le_bb = bb_scale blackbody(T')  (peak-normalized, medium/blackbody.h), or
 *     Cycles'    Le_bb = bb_tint (sigma_SB 1e-6 / pi) ((1 - bb_intensity) + bb_intensity T'^4)
 *                        blackbody_rgb_blender(T')  (luminance 1, Principled Volume's);
 *   emission E(x) (1 field, or 3 for a vec3 grid): adds emission_color E(x).
 * The emitted Le(x) = Le + Le_bb(x) + emission_color E(x) is added in the medium's units,
 * as the constant Le is. */
#ifndef BRUME_MEDIUM_MEDIUM_H
#define BRUME_MEDIUM_MEDIUM_H

#include "core/color.h"
#include "core/motion.h"
#include "density/density.h"
#include "phase/phase.h"

typedef struct medium {
    density *rho;       /* owned */
    phase *ph;          /* owned */
    color sigma_a;      /* absorption per unit length per unit density, >= 0 */
    color sigma_s;      /* scattering per unit length per unit density, >= 0 */
    color Le;           /* emitted radiance, or radiance per unit length (emit_per_length), >= 0 */
    bool emit_per_length; /* every Le term is a radiance per unit length, emitted where rho > 0 */
    double sigma_t_max; /* max over channels of sigma_a + sigma_s (set by medium_init) */
    double sigma_flight; /* the rate per unit density of a flight's tentative collisions: sigma_t_max,
                            or more for a medium emitting per unit length, whose emission the
                            collisions gather where sigma_t is small or 0 (medium_init) */
    double sigma_t_min; /* min over channels of sigma_a + sigma_s, the control's scale; 0 with an
                           albedo field, whose sigma_t varies otherwise than rho (medium_init) */
    density *albedo[3];      /* NULL, or per-channel factors of sigma_s (owned, >= 0) */
    density *temperature;    /* NULL, or the temperature grid (owned), kelvin before scale/offset */
    bool bb_blender;         /* Cycles' blackbody (intensity, tint, Stefan-Boltzmann) instead of pbrt-v4's */
    double bb_scale;         /* pbrt-v4's blackbody radiance scale, > 0 (radiance units) */
    double bb_intensity;     /* Cycles' blackbody intensity in [0, 1]: the weight of T'^4 */
    color bb_tint;           /* Cycles' blackbody tint, >= 0 */
    double bb_tscale;        /* temperature scale, > 0 */
    double bb_offset;        /* temperature offset, kelvin */
    double bb_cutoff;        /* kelvin: nothing glows at or below it, >= 0 */
    density *emission[3];    /* NULL, or an emission field: [0] alone (float grid) or [0..2] */
    color emission_color;    /* multiplies the emission field (radiance units), >= 0 */
    double albedo_max[3];    /* max of each albedo field (set by medium_init; 1 without) */
    density *velocity[3];    /* NULL, or the sampled vectors' x, y, z components u (owned); the
                                velocity v = velocity_map u is in world units per second in the
                                field's frame (before `motion`). A lookup at time t
                                reads every field at x - v(x) (t - t_f), t_f the frame time and
                                t - t_f clamped to the shutter (medium_coeffs_at) */
    double velocity_map[9];  /* v = M u, u the components' values: 3 x 3, row-major (the linear
                                part of the grid's placement; the identity by default) */
    double velocity_max;     /* bound of |v| over the field, world units per second (medium_init;
                                0 without velocity) */
    density *moved;          /* owned: rho's majorants moved by up to velocity_max times the
                                shutter's reach from t_f (density_new_moved_majorant, built at
                                commit), walked instead of rho's; NULL: rho's own */
    char name[64];
    motion *motion;     /* owned; NULL = fixed. Else the field is placed in world space at
                           time t by motion_at(motion, t) applied after its own placement:
                           rays are moved into the field's frame at their own time */
} medium;

/* Whether the medium has any field besides rho (albedo, temperature, emission) or emits per
 * unit length: what only the path tracer's general lookup renders; a velocity moves the
 * fields and is not counted. */
static inline bool medium_has_fields(const medium *m)
{
    return m->albedo[0] || m->temperature || m->emission[0] || m->emit_per_length;
}
/* A bound of the velocity map's norm |M|_2 <= sqrt(|M|_1 |M|_inf), exact for the identity,
 * axis scalings and axis swaps: |v| = |M u| <= it times |u|. */
static inline double medium_velocity_map_norm(const medium *m)
{
    const double *M = m->velocity_map;
    double col_max = 0.0, row_max = 0.0;
    for (int k = 0; k < 3; k++) {
        col_max = fmax(col_max, fabs(M[k]) + fabs(M[3 + k]) + fabs(M[6 + k]));
        row_max = fmax(row_max, fabs(M[3 * k]) + fabs(M[3 * k + 1]) + fabs(M[3 * k + 2]));
    }
    return sqrt(col_max * row_max);
}
/* Whether it can emit: constant Le, a temperature or an emission field (with sigma_a > 0,
 * or per unit length). */
bool medium_emits(const medium *m);
/* Fills the derived fields; call after setting the others. */
void medium_init(medium *m);
/* The range a medium really supports (docs/scene-format.md, "Limits"): extinction
 * sigma_t rho finite, and within one majorant cell sigma_t (rho_max - rho_min) times the
 * cell's width at most MEDIUM_TAU_SPREAD_MAX, which bounds the null collisions a ray makes
 * crossing a cell. A constant medium (rho_max = rho_min) is tracked at any density: its
 * collisions are real and end the walk. err_set names source and media[index]; call after
 * medium_init. */
#define MEDIUM_TAU_SPREAD_MAX 1e5
brume_status medium_check_range(const medium *m, const char *source, int index);
void medium_release(medium *m);

/* ---- one medium at a point and along a ray (medium_eval.c), what the trackers call ---- */

/* The medium's coefficients at a point [1 / world unit] and its emitted radiance there. */
typedef struct medium_coeffs {
    color sigma_a, sigma_s; /* sigma_t = sigma_a + sigma_s */
    color emission;         /* emitted radiance per unit length [radiance / world unit]: sigma_a Le,
                               or Le for a medium emitting per unit length */
} medium_coeffs;

/* At the world point p at time `time` (seconds; a moving medium is taken where it is
 * then), its fields read dt seconds back along the velocity (dt: time minus the frame's,
 * clamped to the shutter). false: rho <= 0 there, or the motion is singular (mc unset). */
bool medium_coeffs_at(const medium *md, vec3 p, double time, double dt, medium_coeffs *mc);
/* Begins the walk of the medium's majorant cells along r (unit direction) over [0, tmax]
 * at the ray's time, the moved majorants for a velocity-blurred medium. false: its motion
 * is singular then, and there is nothing to walk. */
bool medium_majorant_begin(const medium *md, ray r, double tmax, majorant_iter *it);

#endif
