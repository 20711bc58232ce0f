/* stam_figures.h - Stam 1994's Figures 1 and 4 as PNG plots (stam_figures.c; `brume figures`). */
#ifndef BRUME_FIGURE_STAM_FIGURES_H
#define BRUME_FIGURE_STAM_FIGURES_H

#include <stdbool.h>

#include "brume.h"

/* Figure 1: one random blob along a line through its centre, mean, mean +- sigma and one
 * realization, without clamping and with eta (Section 4). Errors name path. */
brume_status stam_figure1_png(const char *path, bool quick);

/* Figure 4: Var T_i against d_i for several eta, blob_T_var (lines) against the sample
 * variance over explicit realizations (points; 120 when quick, else 1200). *max_z (may be
 * NULL) receives the largest |sample - closed form| in standard errors of the sample
 * variance. Errors name path. */
brume_status stam_figure4_png(const char *path, bool quick, double *max_z);

#endif
