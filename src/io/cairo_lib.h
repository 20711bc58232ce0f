/* cairo_lib.h - cairo, opened by its SONAME at the first picture drawn (charts, contact
 * sheets, phase plots, comparisons) instead of linked: see cairo_lib.c. */
#ifndef BRUME_IO_CAIRO_LIB_H
#define BRUME_IO_CAIRO_LIB_H

#include "brume.h"

/* Opens libcairo if it is not open yet. BRUME_OK, or BRUME_ERROR_UNSUPPORTED with the
 * message "PATH: cannot open cairo: WHY" (path: the picture being made). Every function that
 * draws calls it before its first cairo call; the cairo functions assume it succeeded. */
brume_status cairo_lib_open(const char *path);

#endif
