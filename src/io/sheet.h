/* sheet.h - a contact sheet: images on a grid of columns and rows, each column and row
 * labelled, under a title, written as a PNG with cairo (`brume sweep`, `brume figures
 * --compare`). */
#ifndef BRUME_IO_SHEET_H
#define BRUME_IO_SHEET_H

#include "brume.h"

/* cells[r * ncols + c] is drawn at column c, row r, tone mapped as a PNG of it would be
 * (opts: exposure and curve; NULL = exposure 0, clamp); a NULL cell is left blank. Cells may
 * differ in size: each column is as wide as its widest cell, each row as tall as its tallest.
 * col_labels[ncols] go above the columns, row_labels[nrows] left of the rows (either array
 * NULL: none), captions (NULL, or one per cell, NULL entries allowed) under each cell; title
 * (may be NULL) on top. Written atomically; errors name path. */
brume_status sheet_png(const char *path, const char *title, int ncols, int nrows, const brume_image *const *cells,
                       const char *const *col_labels, const char *const *row_labels, const char *const *captions,
                       const brume_write_options *opts);

#endif
