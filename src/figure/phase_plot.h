/* phase_plot.h - polar and cartesian plots of phase functions (cairo), as Blasi's
 * Figures 2 to 6: one row per function, the polar plot of phi(theta) on the left (light
 * arrives from the left, forward scattering points right), phi against the angle in
 * degrees on the right; the true function solid, an optional approximation dashed. */
#ifndef BRUME_FIGURE_PHASE_PLOT_H
#define BRUME_FIGURE_PHASE_PLOT_H

#include <stdbool.h>

#include "brume.h"
#include "phase/phase.h"

typedef struct phase_plot_row {
    const char *title; /* printed above the row, borrowed */
    const phase *truth; /* drawn solid, borrowed */
    const phase *approx; /* drawn dashed, or NULL; borrowed */
    /* An overlay instead (Blasi's Figures 5 and 6): ncurves > 0 functions on the same axes,
     * each in its own colour (solid; dashed where dashed[i]), named in a legend. */
    int ncurves;
    const phase *const *curves;  /* borrowed */
    const char *const *labels;   /* borrowed, NULL entries: no legend line */
    const bool *dashed;          /* may be NULL */
} phase_plot_row;

/* Writes an 8-bit RGB PNG of n >= 1 rows to path, atomically (a temporary file beside it,
 * renamed when complete). The polar panel is always linear, phi / max phi; log_scale plots
 * log10(phi) on the cartesian panel (the polar plot's log companion). Errors name path. */
brume_status phase_plot_png(const char *path, int n, const phase_plot_row *rows, bool log_scale);

#endif
