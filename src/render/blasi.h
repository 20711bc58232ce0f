/* blasi.h - the `blasi` integrator: the two-pass Monte-Carlo method of Blasi, Le Saec and
 * Schlick, "A Rendering Algorithm for Discrete Volume Density Objects" (Eurographics 1993,
 * Section 4). Derivations, variants and measurements: docs/blasi.md.
 *
 *   first pass (view-independent, blasi_prepare): rays leave every light towards the
 *     media, walk the voxels, are attenuated by absorption between interceptions, are
 *     intercepted with the average scattering coefficient (Eq. 10-11; docs/errata.md, erratum 4),
 *     store the fraction r isotropically in the voxel and carry 1 - r on along a direction
 *     drawn from the directional lobe (Eq. 23). The stored power becomes an isotropic
 *     source per unit length in each voxel (docs/errata.md, erratum 6).
 *   second pass (view-dependent, blasi_Li): a view ray walks the voxels, adds each voxel's
 *     source scaled by its current attenuation, stops under a threshold, and adds the
 *     background L-infinity; surfaces occlude and are lit directly.
 *
 * Every medium must be a voxel grid (dense or NanoVDB; procedural clouds are grids too) or a
 * blob field voxelized at blasi.voxels;
 * each is read as constant per voxel (its stored voxel values, the paper's model). The
 * state is immutable after blasi_prepare and read by every render thread. */
#ifndef BRUME_RENDER_BLASI_H
#define BRUME_RENDER_BLASI_H

#include <stdint.h>

#include "core/rng.h"
#include "method/blasi_options.h"
#include "scene/scene.h"

typedef struct blasi_state blasi_state;

/* Runs the first pass (or loads its result, s->blasi.load_light) and, if asked
 * (s->blasi.save_light), writes it. On success *out is a new state owned by the caller;
 * on failure *out is NULL and err_set() names the medium, option or file. */
brume_status blasi_prepare(const brume_scene *s, blasi_state **out);
void blasi_finish(blasi_state *st);

/* The second pass along camera ray r (unit direction). g is used only to sample area
 * lights when shading a surface. */
color blasi_Li(const brume_scene *s, const blasi_state *st, ray r, rng *g, bool *hit_surface);

/* exp(-integral of sigma_t rho) along r through the voxels as blasi sees them (constant
 * per voxel): the transmittance behind a pixel's alpha. Surfaces are not considered. */
color blasi_transmittance(const brume_scene *s, const blasi_state *st, ray r);

/* What the first pass did, for benchmarks and tests. */
typedef struct blasi_stats {
    double light_seconds;   /* wall time of the first pass (or of loading it) */
    uint64_t light_rays;    /* rays sent from the lights, blasi.light_rays (0 when loaded) */
    uint64_t traced_rays;   /* of them, those that can reach a non-empty voxel and were traced */
    uint64_t interceptions; /* scattering events in the first pass */
    uint64_t deposits;      /* voxel deposits: interceptions and exit deposits */
    double emitted_power;   /* sum over rays and channels of the power they start with / 3 */
    bool loaded;            /* true when the radiance grid came from a file */
    double stored_power;    /* sum over voxels and channels of the stored power / 3 */
} blasi_stats;
void blasi_get_stats(const blasi_state *st, blasi_stats *out);

#endif
