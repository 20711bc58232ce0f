/* stam.h - Stam 1994, "Stochastic Rendering of Density Fields": the stochastic renderer of
 * Section 6.3 inside a ray tracer with solid objects.
 *
 * For each camera ray (each ray with its own direction; docs/errata.md, erratum 9):
 *   I_b    radiance of what lies behind the media: a surface shaded by direct light (shadow
 *          rays through the clouds carry their transparency only, Section 6.3), plus
 *          albedo x background as sky light; or the background; or an area light
 *   T      per blob field, sum over the blobs on the segment of T_mean + sigma_T Q(x_ui)
 *          (Eq. 13 with the variance of docs/stam.md), clamped to >= 0
 *   tau    exp(-kappa_t T) per channel, kappa_t = sigma_a + sigma_s
 *   J_avg  the average source function (Eq. 8) from the mean density, Section 6.2: steps
 *          over the blobs' span of the ray; on each, the exact mean optical depth (erf) and
 *          J = (1 - Omega) E + Omega (sum over lights of p E_l tau_l + ambient) at its
 *          midpoint; tau_l from a cache of light transparencies or an exact shadow ray
 *   I      = tau I_b + (1 - tau) J_avg   (Eq. 9)
 * Every medium of the scene must be a blob field (density type "blobs"). */
#ifndef BRUME_RENDER_STAM_H
#define BRUME_RENDER_STAM_H

#include "core/rng.h"
#include "density/randfield.h"
#include "scene/scene.h"
#include "method/stam_params.h"
#include "scene/stam_media.h"

/* Builds Q and the light caches; fails (err_set) when a medium is not a blob field. */
brume_status stam_prepare(const brume_scene *s, void **state);
void stam_finish(void *state);
/* Radiance along r (unit direction); *hit_surface as integrator_Li. */
color stam_Li(const void *state, ray r, rng *g, bool *hit_surface);
/* The realized transparency of the media (and 0 behind a surface) along o + t d, t in
 * (0, tmax): exp(-kappa_t T) per channel. */
color stam_transmittance(const void *state, vec3 o, vec3 d, double tmax);

#endif
