/* integrator.h - estimators of the radiance arriving along a camera ray.
 *   path    unbiased volumetric path tracing: spectral tracking for free flights,
 *           next-event estimation with ratio-tracked shadow rays, Russian roulette
 *   single  the same estimator stopped after one scattering event: single scattering
 *           of every light and of the background */
#ifndef BRUME_RENDER_INTEGRATOR_H
#define BRUME_RENDER_INTEGRATOR_H

#include "core/rng.h"
#include "render/scene.h"

typedef enum integrator_kind {
    INTEGRATOR_PATH,
    INTEGRATOR_SINGLE
} integrator_kind;

/* Parses a method name ("path", "single"); false if unknown. */
bool integrator_from_name(const char *name, integrator_kind *out);
/* Comma-separated list of the names, for messages. */
const char *integrator_names(void);

/* Radiance along r (unit direction) for the given kind. */
color integrator_Li(integrator_kind kind, const brume_scene *s, ray r, rng *g);

/* The path estimator with an explicit cap on scattering events (>= 1). */
color path_Li(const brume_scene *s, ray r, int max_depth, rng *g);

#endif
