/* path_options.h - the settings of the `path` and `single` integrators, set by name through
 * brume_scene_set_option ("path.KEY"; a scene file's "path" object is read through it).
 * Their keys, ranges, defaults and meanings: the table in path_options.c (`brume help
 * options`, docs/scene-format.md, "Method options"); the methods: docs/path-tracer.md. */
#ifndef BRUME_METHOD_PATH_OPTIONS_H
#define BRUME_METHOD_PATH_OPTIONS_H

#include "brume.h"

/* The most continuations path.split may ask for. */
#define PATH_SPLIT_MAX 8

typedef struct path_options {
    /* Sun-lobe sampling (docs/path-tracer.md, "Sun-lobe sampling"): at a scattering event
     * with arriving direction d, a delta sun at direction wi gets a second direction
     * sample from its own scattering lobe with probability min(1, sun_lobe S(d . wi)),
     * weighed against phase sampling by multiple importance sampling. Unitless, in
     * [0, 100]; 0 turns it off. */
    double sun_lobe;
    /* Sun roulette (docs/path-tracer.md, "Sun rays deep in a cloud"): a shadow ray or a
     * sun-lobe sample towards a delta sun from a point where the sun's transmittance is
     * predicted at T < sun_roulette is made with probability T / sun_roulette (times any
     * other roulette's) and weighed by its inverse. Unitless, in [0, 1]; 0 turns it off. */
    double sun_roulette;
    /* Splitting at the camera vertex (docs/path-tracer.md, "Splitting at the camera
     * vertex"): a camera path continues `split` times from its first scattering event in a
     * medium, each continuation weighed 1 / split (and rouletted against that share). A
     * whole number in [1, PATH_SPLIT_MAX]; 1, the default, does not split. */
    double split;
} path_options;

/* The table of "path.KEY" options (path_options.c; method/method_options.h). */
extern const struct method_options_def path_options_def;

#endif
