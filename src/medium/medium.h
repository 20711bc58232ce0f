/* medium.h - a participating medium: a density field with optical properties.
 *
 * Units: sigma_a and sigma_s are per world unit of length per unit density, so at x
 *   sigma_t(x) = (sigma_a + sigma_s) rho(x)   [1 / world unit]
 * and the albedo is sigma_s / (sigma_a + sigma_s). Emission Le is a radiance added along a
 * ray at the rate sigma_a rho(x) Le per unit length (Stam's (1 - Omega) E term).
 * Blasi's alpha and sigma are sigma_a and sigma_s; Stam's kappa_t is sigma_a + sigma_s. */
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
    color Le;           /* emitted radiance (W sr^-1 m^-2 in world units), >= 0 */
    double sigma_t_max; /* max over channels of sigma_a + sigma_s (set by medium_init) */
    char name[64];
    motion *motion;     /* owned; NULL = fixed. Else the field is placed in world space at
                           time t by motion_at(motion, t) applied after its own placement:
                           rays are moved into the field's frame at their own time */
} medium;

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

#endif
