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

/* Writes an RGB PNG of npanels panels (each 460 x 340 pixels) under a title to path,
 * atomically (a temporary file beside it, renamed when whole). Errors name path. */
brume_status chart_png(const char *path, const char *title, int npanels, const chart_panel *panels);

#endif
