/* blasi_options.c - the table of the blasi integrator's options. */
#include "method/blasi_options.h"

#include <math.h>

#include "method/option_table.h"

static void exit_given(void *opts, int choice)
{
    (void)choice;
    ((blasi_options *)opts)->exit_given = true;
}

static void view_given(void *opts, int choice)
{
    (void)choice;
    ((blasi_options *)opts)->view_given = true;
}

/* blasi.variant (0 paper, 1 physical): both exit_deposit and view_attenuation, except one
 * set by its own key, before or after. */
static void variant(void *opts, int physical)
{
    blasi_options *o = opts;
    if (!o->exit_given)
        o->exit_deposit = physical ? BLASI_EXIT_NONE : BLASI_EXIT_PAPER;
    if (!o->view_given)
        o->view_attenuation = physical ? BLASI_VIEW_EXTINCTION : BLASI_VIEW_ABSORPTION;
}

static const method_option options[] = {
    {.key = "blasi.light_rays", .kind = OPTION_INTEGER, .lo = 1.0, .hi = 1e12, .what = "an integer in [1, 1e12]",
     OPTION_FIELD(blasi_options, light_rays), .def = "2097152", /* 2^21, "2 million rays" (Section 5) */
     .doc = "first-pass rays over all lights, split evenly between them"},
    {.key = "blasi.r", .kind = OPTION_NUMBER, .lo = 0.0, .hi = 1.0, .what = "a number in [0, 1]",
     OPTION_FIELD(blasi_options, r), .def_doc = "from the phase function",
     .doc = "fraction of a ray's energy stored isotropically at an interception (Eq. 22); the rest goes on along "
            "the directional lobe. Default: 1 for `isotropic`, 0 for `schlick`, the weight of the backward (or "
            "isotropic) lobe of a two-lobe `schlick_mix`/`mixture`, else 0.1 (\"r ~ 0.1\", Section 4.2)"},
    {.key = "blasi.kprime", .kind = OPTION_NUMBER, .lo = -0.999999, .hi = 0.999999, .what = "a number in (-1, 1)",
     OPTION_FIELD(blasi_options, kprime), .def_doc = "from the phase function",
     .doc = "Schlick k' of the directional lobe, sampled by Eq. 23. Default: the forward lobe of a two-lobe "
            "mixture, else the medium's phase function itself"},
    {.key = "blasi.step", .kind = OPTION_NUMBER, .lo = 0.0, .hi = OPTION_BIG,
     .what = "a length >= 0 (0 = voxel by voxel)", OPTION_FIELD(blasi_options, step), .def = "0",
     .doc = "first pass: 0 walks exactly voxel by voxel; > 0 marches in uniform steps of this length (world "
            "units), the paper's \"distance sampling\""},
    {.key = "blasi.threshold", .kind = OPTION_NUMBER, .flags = OPTION_HI_OPEN, .lo = 0.0, .hi = 1.0,
     .what = "a number in [0, 1)", OPTION_FIELD(blasi_options, threshold), .def = "0.001",
     .doc = "light rays stop below this fraction of their initial weight, view rays when their attenuation falls "
            "below it"},
    {.key = "blasi.sources", .kind = OPTION_INTEGER, .lo = 1.0, .hi = 65536.0, .what = "an integer in [1, 65536]",
     OPTION_FIELD(blasi_options, sources), .def = "16",
     .doc = "elementary disk-shaped sources per area light (strata of its surface)"},
    {.key = "blasi.exit_deposit", .kind = OPTION_ENUM, OPTION_NAMES2("paper", "none"),
     OPTION_FIELD(blasi_options, exit_deposit), .def = "paper", .effect = exit_given,
     .doc = "where a light ray's energy goes when it leaves the media: the last non-empty voxel it crossed (the "
            "paper) or nowhere (physics; docs/errata.md, erratum 5)"},
    {.key = "blasi.view_attenuation", .kind = OPTION_ENUM, OPTION_NAMES2("absorption", "extinction"),
     OPTION_FIELD(blasi_options, view_attenuation), .def = "absorption", .effect = view_given,
     .doc = "view rays attenuated by sigma_a (the paper's pseudo-code) or by sigma_a + sigma_s (physics)"},
    {.key = "blasi.gather", .kind = OPTION_ENUM, OPTION_NAMES2("path_length", "printed"),
     OPTION_FIELD(blasi_options, gather), .def = "path_length",
     .doc = "how a view ray gathers a voxel's stored source S_V: integrated over the length it crosses, or, as the "
            "paper's second pass prints it, A L_V once per voxel visited with L_V = S_V times the voxel's mean "
            "chord 4 |V| / area (docs/blasi.md); `variant` does not set it"},
    {.key = "blasi.interpolate", .kind = OPTION_ENUM, OPTION_NAMES2("trilinear", "voxel"),
     OPTION_FIELD(blasi_options, interpolate), .def = "trilinear",
     .doc = "the density both passes see along their rays: trilinear between the voxels' centres (as the path "
            "tracer reads a trilinear grid; the light grid stays one value per voxel), or constant over each "
            "voxel, the paper's model and its stepped look (docs/blasi.md); `variant` does not set it"},
    {.key = "blasi.variant", .kind = OPTION_ENUM, OPTION_NAMES2("paper", "physical"), .effect = variant,
     .doc = "sets both exit_deposit and view_attenuation at once; keys given beside it win, in any order"},
    {.key = "blasi.voxels", .kind = OPTION_INTEGER, .flags = OPTION_ZERO_OR, .lo = 2.0, .hi = 2048.0,
     .what = "0 or an integer in [2, 2048]", OPTION_FIELD(blasi_options, voxels), .def = "0",
     .doc = "a blob field (Stam) is rendered as a dense trilinear grid of this many cells along its longest axis "
            "holding one realization of its perturbation (`stam.eps`, `stam.eta`, Q); 0: `--method blasi` "
            "refuses blob fields with a message"},
    {.key = "blasi.save_light", .kind = OPTION_PATH, .flags = OPTION_WRITES, .what = "a file name",
     OPTION_FIELD(blasi_options, save_light),
     .doc = "write the first pass's radiance grid to this file, relative to the scene file and inside its folder "
            "(docs/scene-format.md, \"Paths\"); `--save-light` on the command line may name any path"},
    {.key = "blasi.load_light", .kind = OPTION_PATH, .what = "a file name", OPTION_FIELD(blasi_options, load_light),
     .doc = "read it instead of running the first pass; a file made for another scene is an error naming it"},
};

/* NAN: from each medium's phase function at prepare (docs/blasi.md) */
static void computed_defaults(void *opts)
{
    blasi_options *o = opts;
    o->r = (double)NAN;
    o->kprime = (double)NAN;
}

const method_options_def blasi_options_def = {.method = "blasi",
                                              .size = sizeof(blasi_options),
                                              .options = options,
                                              .count = sizeof options / sizeof options[0],
                                              .defaults = computed_defaults};
