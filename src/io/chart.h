/* chart.h - line and point charts drawn with cairo into PNG files: one or more panels side
 * by side, each with several series on one pair of axes and a legend (the plots of
 * `brume figures`: Stam's Figures 1 and 4). */
#ifndef BRUME_IO_CHART_H
#define BRUME_IO_CHART_H

#include <stdbool.h>

#include "brume.h"

typedef enum chart_style {
    CHART_LINE,   /* solid line through the points */
    CHART_DASHED, /* dashed line */
    CHART_POINTS, /* a marker at each point, with an error bar when err is given */
    CHART_THIN    /* thin grey line (a realization behind the others) */
} chart_style;

typedef struct chart_series {
    const char *label; /* legend text, or NULL for none; borrowed */
    int n;
    const double *x, *y; /* n values each; borrowed */
    const double *err;   /* CHART_POINTS: half-length of the error bar per point, or NULL */
    chart_style style;
    int color;           /* index into a fixed palette of 8 colours */
} chart_series;

typedef struct chart_panel {
    const char *title, *xlabel, *ylabel; /* borrowed */
    int nseries;
    const chart_series *series;
    bool y_from_zero; /* the y axis starts at 0 (else at the data's minimum) */
} chart_panel;

/* What every plot of brume shares (chart_png here, phase_plot_png in src/phase/). */
typedef struct _cairo cairo_t;
typedef struct _cairo_surface cairo_surface_t;
/* The i-th colour of the fixed palette of 8 (i taken modulo 8), as RGB in [0, 1]. */
const double *chart_color(int i);
/* Draws s with its baseline at y, x at the fraction align of its width (0 left, 0.5 centre). */
void chart_text(cairo_t *cr, double x, double y, const char *s, double align);
/* Ends a drawing: destroys cr, writes surface s as a PNG to path atomically (a temporary
 * file beside it, renamed when whole: io/atomic.h) and destroys s. Errors name path. */
brume_status chart_write_png(cairo_surface_t *s, cairo_t *cr, const char *path);

/* Writes an RGB PNG of npanels panels (each 460 x 340 pixels) under a title to path,
 * atomically (a temporary file beside it, renamed when whole). Errors name path. */
brume_status chart_png(const char *path, const char *title, int npanels, const chart_panel *panels);

#endif
