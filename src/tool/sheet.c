/* sheet.c - contact sheets of images with labels, drawn with cairo (brume_image_sheet_png). */
#include "brume.h"

#include <cairo.h>
#include <stdint.h>
#include <string.h>

#include "core/context.h"
#include "core/error.h"
#include "io/atomic.h"
#include "io/cairo_lib.h"
#include "io/chart.h"
#include "image/image.h"

#define PAD 8
#define LABEL_H 18  /* a line of text */
#define MAX_SIDE 16384

/* The layout of a sheet: column widths, row heights, where the first cell starts. */
typedef struct sheet_layout {
    int ncols, nrows;
    int cw[256], rh[256];
    int x0, y0, cap_h;
    long W, H;
} sheet_layout;

/* As wide as the widest row label (at least PAD), at most MAX_SIDE. */
static int row_label_width(const char *const *row_labels, int nrows)
{
    int x0 = PAD;
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
    return x0 > MAX_SIDE ? MAX_SIDE : x0;
}

static void sheet_measure(sheet_layout *L, const brume_image *const *cells, const char *title,
                          const char *const *col_labels, const char *const *row_labels, const char *const *captions)
{
    memset(L->cw, 0, sizeof L->cw);
    memset(L->rh, 0, sizeof L->rh);
    for (int r = 0; r < L->nrows; r++)
        for (int c = 0; c < L->ncols; c++) {
            const brume_image *im = cells[r * L->ncols + c];
            if (!im)
                continue;
            L->cw[c] = L->cw[c] > im->width ? L->cw[c] : im->width;
            L->rh[r] = L->rh[r] > im->height ? L->rh[r] : im->height;
        }
    L->x0 = row_labels ? row_label_width(row_labels, L->nrows) : PAD;
    L->y0 = (title ? LABEL_H + PAD : PAD) + (col_labels ? LABEL_H : 0);
    L->cap_h = captions ? LABEL_H : 0;
    L->W = L->x0;
    L->H = L->y0;
    for (int c = 0; c < L->ncols; c++)
        L->W += L->cw[c] + PAD;
    for (int r = 0; r < L->nrows; r++)
        L->H += L->rh[r] + L->cap_h + PAD;
}

/* White background, then each cell's pixels tone mapped as a PNG of it would be. */
static void sheet_paint_cells(cairo_surface_t *sf, const sheet_layout *L, const brume_image *const *cells,
                              const brume_write_options *opts)
{
    cairo_surface_flush(sf);
    unsigned char *px = cairo_image_surface_get_data(sf);
    int stride = cairo_image_surface_get_stride(sf);
    for (long y = 0; y < L->H; y++)
        memset(px + (size_t)y * (size_t)stride, 0xff, (size_t)L->W * 4);
    int y = L->y0;
    for (int r = 0; r < L->nrows; r++) {
        int x = L->x0;
        for (int c = 0; c < L->ncols; c++) {
            const brume_image *im = cells[r * L->ncols + c];
            for (int j = 0; im && j < im->height; j++)
                for (int i = 0; i < im->width; i++) {
                    const float *p = im->rgba + 4 * ((size_t)j * (size_t)im->width + (size_t)i);
                    uint32_t v = 0;
                    for (int k = 0; k < 3; k++)
                        v = v << 8 | image_encode_srgb8((double)p[k], opts);
                    memcpy(px + (size_t)(y + j) * (size_t)stride + 4 * (size_t)(x + i), &v, 4);
                }
            x += L->cw[c] + PAD;
        }
        y += L->rh[r] + L->cap_h + PAD;
    }
    cairo_surface_mark_dirty(sf);
}

static void sheet_draw_labels(cairo_t *cr, const sheet_layout *L, const char *title, const char *const *col_labels,
                              const char *const *row_labels, const char *const *captions)
{
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 12.0);
    if (title)
        chart_text(cr, PAD, LABEL_H, title, 0.0);
    int x = L->x0;
    for (int c = 0; c < L->ncols; c++) {
        if (col_labels && col_labels[c])
            chart_text(cr, x + L->cw[c] / 2.0, L->y0 - 5, col_labels[c], 0.5);
        x += L->cw[c] + PAD;
    }
    int y = L->y0;
    for (int r = 0; r < L->nrows; r++) {
        if (row_labels && row_labels[r])
            chart_text(cr, PAD, y + L->rh[r] / 2.0 + 4, row_labels[r], 0.0);
        x = L->x0;
        for (int c = 0; captions && c < L->ncols; c++) {
            if (captions[r * L->ncols + c])
                chart_text(cr, x + L->cw[c] / 2.0, y + L->rh[r] + LABEL_H - 4, captions[r * L->ncols + c], 0.5);
            x += L->cw[c] + PAD;
        }
        y += L->rh[r] + L->cap_h + PAD;
    }
}

static brume_status sheet_png(const char *path, const char *title, int ncols, int nrows, const brume_image *const *cells,
                       const char *const *col_labels, const char *const *row_labels, const char *const *captions,
                       const brume_write_options *opts)
{
    if (ncols < 1 || nrows < 1 || ncols > 256 || nrows > 256)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: a sheet of %d x %d cells", path, ncols, nrows);
    if (cairo_lib_open(path) != BRUME_OK)
        return err_status();
    sheet_layout L = {.ncols = ncols, .nrows = nrows};
    sheet_measure(&L, cells, title, col_labels, row_labels, captions);
    if (L.W > MAX_SIDE || L.H > MAX_SIDE)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: the sheet would be %ld x %ld pixels (at most %d a side)", path,
                       L.W, L.H, MAX_SIDE);
    cairo_surface_t *sf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, (int)L.W, (int)L.H);
    if (cairo_surface_status(sf) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(sf);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: cannot make a %ld x %ld picture", path, L.W, L.H);
    }
    sheet_paint_cells(sf, &L, cells, opts);
    cairo_t *cr = cairo_create(sf);
    sheet_draw_labels(cr, &L, title, col_labels, row_labels, captions);
    return chart_write_png(sf, cr, path);
}

brume_status brume_image_sheet_png(brume_context *ctx, const char *path, const char *title, int ncols, int nrows,
                                   const brume_image *const *cells, const char *const *col_labels,
                                   const char *const *row_labels, const char *const *captions,
                                   const brume_write_options *opts)
{
    err_clear();
    if (!path || !cells)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_image_sheet_png: %s: NULL",
                                       !path ? "path" : "cells"));
    const void *owner = atomic_owner(ctx);
    brume_status st = sheet_png(path, title, ncols, nrows, cells, col_labels, row_labels, captions, opts);
    atomic_owner(owner);
    return ctx_report(ctx, st);
}
