/* path_options.c - the table of the path integrator's options (`path` and `single`). */
#include "method/path_options.h"

#include "method/option_table.h"

static const method_option options[] = {
    {.key = "path.sun_lobe", .kind = OPTION_NUMBER, .lo = 0.0, .hi = 100.0, .what = "a number in [0, 100]",
     OPTION_FIELD(path_options, sun_lobe),
     /* measured on the comparison clouds of bench/cloud64_vs_cycles.sh (docs/performance.md,
      * "Sun-lobe sampling") */
     .def = "2",
     .doc = "sun-lobe sampling: at a scattering event a delta sun (`distant` without `angular_radius`) gets a "
            "second direction sample from its own scattering lobe with probability min(1, sun_lobe S), S in [0, 1] "
            "from the phase function and the angle to the sun, weighed against phase sampling by multiple importance "
            "sampling (docs/path-tracer.md, \"Sun-lobe sampling\"). Unbiased for any value; 0 turns it off. It pays "
            "in forward-scattering media (HG g above about 0.4) and is not drawn for flatter phase functions"},
    {.key = "path.sun_roulette", .kind = OPTION_NUMBER, .lo = 0.0, .hi = 1.0, .what = "a number in [0, 1]",
     OPTION_FIELD(path_options, sun_roulette),
     .def = "0.03", /* measured the same way (docs/performance.md, "Sun rays deep in a cloud") */
     .doc = "the sun roulette (`path` and `single`): a shadow ray or sun-lobe sample towards a delta sun from a "
            "point where the sun's transmittance, predicted at prepare on a grid over the media, is T < "
            "sun_roulette, is made with probability T / sun_roulette (at least 1e-6) and weighed by its inverse "
            "(docs/path-tracer.md, \"Sun rays deep in a cloud\"). Unbiased for any value; 0 turns it off. Built only "
            "when at least 10 % of the media's extinction lies where it acts (dense clouds) and no medium moves"},
    {.key = "path.split", .kind = OPTION_INTEGER, .lo = 1.0, .hi = PATH_SPLIT_MAX,
     .what = "a whole number in [1, " OPTION_STR(PATH_SPLIT_MAX) "]", OPTION_FIELD(path_options, split), .def = "1",
     .doc = "splitting at the camera vertex (`path` only): a camera path that scatters first in a medium continues "
            "`split` times from there, each continuation weighed 1 / split, its roulette against that share "
            "(docs/path-tracer.md, \"Splitting at the camera vertex\"). Unbiased for any value; pays in dense, "
            "bright clouds where the variance lies after the first event (1.1-1.2 x the efficiency at 3 or 4 on "
            "`scenes/wdas-dense.json`), loses where it does not (0.89 x at 2 on cloud64)"},
};

const method_options_def path_options_def = {
    .method = "path", .size = sizeof(path_options), .options = options, .count = sizeof options / sizeof options[0]};
