/* sheet.c - contact sheets of images with labels, drawn with cairo (tool.h). */
#include "tool/tool.h"

#include <cairo.h>
#include <stdint.h>
#include <string.h>

#include "core/error.h"
#include "io/cairo_lib.h"
#include "io/chart.h"
#include "image/image.h"

#define PAD 8
#define LABEL_H 18  /* a line of text */
#define MAX_SIDE 16384

brume_status sheet_png(const char *path, const char *title, int ncols, int nrows, const brume_image *const *cells,
                       const char *const *col_labels, const char *const *row_labels, const char *const *captions,
                       const brume_write_options *opts)
{
    if (ncols < 1 || nrows < 1 || ncols > 256 || nrows > 256)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: a sheet of %d x %d cells", path, ncols, nrows);
    if (cairo_lib_open(path) != BRUME_OK)
        return err_status();
    int cw[256] = {0}, rh[256] = {0};
    for (int r = 0; r < nrows; r++)
        for (int c = 0; c < ncols; c++) {
            const brume_image *im = cells[r * ncols + c];
            if (!im)
                continue;
            cw[c] = cw[c] > im->width ? cw[c] : im->width;
            rh[r] = rh[r] > im->height ? rh[r] : im->height;
        }
    int x0 = PAD;
    if (row_labels) { /* as wide as the widest row label */
        cairo_surface_t *m = cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 1);
        cairo_t *mc = cairo_create(m);
        cairo_select_font_face(mc, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
        cairo_set_font_size(mc, 12.0);
        for (int r = 0; r < nrows; r++) {
            cairo_text_extents_t e;
            if (!row_labels[r])
                continue;
            cairo_text_extents(mc, row_labels[r], &e);
            if (e.x_advance + 2 * PAD > x0)
                x0 = (int)(e.x_advance + 2 * PAD);
        }
        cairo_destroy(mc);
        cairo_surface_destroy(m);
        if (x0 > MAX_SIDE)
            x0 = MAX_SIDE;
    }
    int y0 = (title ? LABEL_H + PAD : PAD) + (col_labels ? LABEL_H : 0);
    int cap_h = captions ? LABEL_H : 0;
    long W = x0, H = y0;
    for (int c = 0; c < ncols; c++)
        W += cw[c] + PAD;
    for (int r = 0; r < nrows; r++)
        H += rh[r] + cap_h + PAD;
    if (W > MAX_SIDE || H > MAX_SIDE)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: the sheet would be %ld x %ld pixels (at most %d a side)", path,
                       W, H, MAX_SIDE);
    cairo_surface_t *sf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, (int)W, (int)H);
    if (cairo_surface_status(sf) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(sf);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: cannot make a %ld x %ld picture", path, W, H);
    }
    cairo_surface_flush(sf);
    unsigned char *px = cairo_image_surface_get_data(sf);
    int stride = cairo_image_surface_get_stride(sf);
    for (long y = 0; y < H; y++)
        memset(px + (size_t)y * (size_t)stride, 0xff, (size_t)W * 4);
    int y = y0;
    for (int r = 0; r < nrows; r++) {
        int x = x0;
        for (int c = 0; c < ncols; c++) {
            const brume_image *im = cells[r * ncols + c];
            for (int j = 0; im && j < im->height; j++)
                for (int i = 0; i < im->width; i++) {
                    const float *p = im->rgba + 4 * ((size_t)j * (size_t)im->width + (size_t)i);
                    uint32_t v = 0;
                    for (int k = 0; k < 3; k++)
                        v = v << 8 | image_encode_srgb8((double)p[k], opts);
                    memcpy(px + (size_t)(y + j) * (size_t)stride + 4 * (size_t)(x + i), &v, 4);
                }
            x += cw[c] + PAD;
        }
        y += rh[r] + cap_h + PAD;
    }
    cairo_surface_mark_dirty(sf);
    cairo_t *cr = cairo_create(sf);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 12.0);
    if (title)
        chart_text(cr, PAD, LABEL_H, title, 0.0);
    int x = x0;
    for (int c = 0; c < ncols; c++) {
        if (col_labels && col_labels[c])
            chart_text(cr, x + cw[c] / 2.0, y0 - 5, col_labels[c], 0.5);
        x += cw[c] + PAD;
    }
    y = y0;
    for (int r = 0; r < nrows; r++) {
        if (row_labels && row_labels[r])
            chart_text(cr, PAD, y + rh[r] / 2.0 + 4, row_labels[r], 0.0);
        x = x0;
        for (int c = 0; captions && c < ncols; c++) {
            if (captions[r * ncols + c])
                chart_text(cr, x + cw[c] / 2.0, y + rh[r] + LABEL_H - 4, captions[r * ncols + c], 0.5);
            x += cw[c] + PAD;
        }
        y += rh[r] + cap_h + PAD;
    }
    return chart_write_png(sf, cr, path);
}
