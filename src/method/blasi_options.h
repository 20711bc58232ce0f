/* blasi_options.h - the settings of the `blasi` integrator (Blasi, Le Saec and Schlick
 * 1993, Section 4), set by name through brume_scene_set_option ("blasi.KEY"; a scene
 * file's "blasi" object is read through it). Their keys, ranges, defaults and meanings: the
 * table in blasi_options.c (`brume help options`, docs/scene-format.md, "Method options");
 * the method: docs/blasi.md. */
#ifndef BRUME_METHOD_BLASI_OPTIONS_H
#define BRUME_METHOD_BLASI_OPTIONS_H

#include <stdbool.h>
#include <stdint.h>

#include "brume.h"

/* docs/errata.md, erratum 5, first point: where a light ray's energy goes when it leaves. */
typedef enum blasi_exit {
    BLASI_EXIT_PAPER, /* stored in the last non-empty voxel crossed (the paper) */
    BLASI_EXIT_NONE   /* lost, as in physics */
} blasi_exit;

/* docs/errata.md, erratum 5, second point: what attenuates a view ray. */
typedef enum blasi_view_atten {
    BLASI_VIEW_ABSORPTION, /* A *= exp(-alpha rho delta), the paper's pseudo-code */
    BLASI_VIEW_EXTINCTION  /* A *= exp(-(alpha + sigma) rho delta), physics */
} blasi_view_atten;

/* How a view ray gathers a voxel's stored source S_V (radiance per unit length). */
typedef enum blasi_gather {
    BLASI_GATHER_PATH_LENGTH, /* integral of A S_V over the length crossed: A S_V (1 - e^-kappa d) / kappa */
    BLASI_GATHER_PRINTED      /* "L_P = L_P + A L_V" per voxel visited, whatever the length crossed, with
                                 L_V = S_V times the voxel's mean chord 4 |V| / area (docs/blasi.md) */
} blasi_gather;

/* How both passes read the density between the voxels' values. */
typedef enum blasi_interpolate {
    BLASI_INTERPOLATE_TRILINEAR, /* trilinear between the voxels' centres, as the path tracer reads a
                                    trilinear grid: no steps at voxel faces (docs/blasi.md) */
    BLASI_INTERPOLATE_VOXEL      /* constant over each voxel, the paper's model and look */
} blasi_interpolate;

#define BLASI_PATH_MAX 1024

typedef struct blasi_options {
    uint64_t light_rays;    /* first-pass rays over all lights, split evenly, >= 1 */
    double r;               /* fraction stored isotropically at an interception, [0, 1];
                               NAN = from each medium's phase function (docs/blasi.md) */
    double kprime;          /* Schlick k' of the directional lobe, (-1, 1); NAN = from the phase */
    double step;            /* first-pass step, world units; 0 = exact voxel-by-voxel walk */
    double threshold;       /* rays stop below this fraction of their initial weight
                               (light rays) or of 1 (view attenuation), [0, 1) */
    int sources;            /* elementary sources per area light (strata of its surface) */
    blasi_exit exit_deposit;
    blasi_view_atten view_attenuation;
    blasi_gather gather;    /* not set by `variant`: path_length unless given */
    blasi_interpolate interpolate; /* not set by `variant`: trilinear unless given */
    int voxels;             /* a blob field (Stam) is rendered as a dense grid of this many cells
                               along its longest axis, one realization of the perturbation
                               (stam.eps, stam.eta, Q); 0 = blob fields are refused */
    char save_light[BLASI_PATH_MAX]; /* write the first pass's radiance grid here ("" = no) */
    char load_light[BLASI_PATH_MAX]; /* read it from here instead of running the pass */
    bool exit_given, view_given; /* set by their own keys: `variant` leaves them alone */
} blasi_options;

/* The table of "blasi.KEY" options (blasi_options.c; method/method_options.h). */
extern const struct method_options_def blasi_options_def;

#endif
