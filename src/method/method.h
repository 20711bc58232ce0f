/* method.h - the rendering methods brume has, by name: the closed set that render.method
 * names (docs/scene-format.md). Their options are method/method_options.h's; their
 * estimators are render/'s (integrator.h dispatches on integrator_kind). */
#ifndef BRUME_METHOD_METHOD_H
#define BRUME_METHOD_METHOD_H

#include <stdbool.h>

typedef enum integrator_kind {
    INTEGRATOR_PATH,
    INTEGRATOR_SINGLE,
    INTEGRATOR_BLASI,
    INTEGRATOR_STAM /* Stam 1994's stochastic renderer (render/stam.h) */
} integrator_kind;

/* Parses a method name ("path", "single", "blasi", "stam"); false if unknown. */
bool integrator_from_name(const char *name, integrator_kind *out);
/* The name of kind ("path" ...), or NULL outside the enum. */
const char *integrator_name(integrator_kind kind);
/* Comma-separated list of the names, for messages. */
const char *integrator_names(void);

#endif
