/* chart.c - line and point charts with cairo (chart.h). */
#include "io/chart.h"

#include <cairo.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "core/vec.h"
#include "io/atomic.h"
#include "io/cairo_lib.h"

#define PANEL_W 460
#define PANEL_H 340
#define TITLE_H 28

static const double palette[8][3] = {{0.10, 0.25, 0.60}, {0.85, 0.33, 0.10}, {0.20, 0.60, 0.25},
                                     {0.60, 0.20, 0.60}, {0.75, 0.60, 0.05}, {0.10, 0.60, 0.70},
                                     {0.45, 0.45, 0.45}, {0.80, 0.10, 0.30}};

const double *chart_color(int i) { return palette[(unsigned)i % 8u]; }

void chart_text(cairo_t *cr, double x, double y, const char *s, double align)
{
    cairo_text_extents_t e;
    cairo_text_extents(cr, s, &e);
    cairo_move_to(cr, x - align * e.x_advance, y);
    cairo_show_text(cr, s);
}

/* A round step giving about five intervals over span. */
static double nice_step(double span)
{
    double s = pow(10.0, floor(log10(span / 5.0)));
    if (span / s > 20.0)
        s *= 5.0;
    else if (span / s > 10.0)
        s *= 2.0;
    return s;
}

static void style(cairo_t *cr, const chart_series *s)
{
    const double *c = palette[(unsigned)s->color % 8u];
    static const double dash[] = {7.0, 4.0};
    if (s->style == CHART_THIN) {
        cairo_set_source_rgba(cr, c[0], c[1], c[2], 0.55);
        cairo_set_line_width(cr, 1.0);
    } else {
        cairo_set_source_rgb(cr, c[0], c[1], c[2]);
        cairo_set_line_width(cr, 1.8);
    }
    cairo_set_dash(cr, s->style == CHART_DASHED ? dash : NULL, s->style == CHART_DASHED ? 2 : 0, 0.0);
}

/* A panel's plot area on the page and the data range it shows. */
typedef struct panel_frame {
    double left, right, top, bottom; /* page units */
    double xlo, xhi, ylo, yhi;       /* data units */
} panel_frame;

/* The data range of p's finite points (error bars included), padded above. */
static void panel_range(const chart_panel *p, panel_frame *f)
{
    double xlo = INFINITY, xhi = -INFINITY, ylo = INFINITY, yhi = -INFINITY;
    for (int k = 0; k < p->nseries; k++)
        for (int i = 0; i < p->series[k].n; i++) {
            const chart_series *s = &p->series[k];
            double e = s->err ? s->err[i] : 0.0;
            if (!isfinite(s->x[i]) || !isfinite(s->y[i]))
                continue;
            xlo = fmin(xlo, s->x[i]);
            xhi = fmax(xhi, s->x[i]);
            ylo = fmin(ylo, s->y[i] - e);
            yhi = fmax(yhi, s->y[i] + e);
        }
    if (!(xhi > xlo)) {
        xlo = 0.0;
        xhi = 1.0;
    }
    if (p->y_from_zero)
        ylo = fmin(0.0, ylo);
    if (!(yhi > ylo)) {
        ylo = isfinite(ylo) ? ylo - 1.0 : 0.0;
        yhi = ylo + 2.0;
    }
    yhi += 0.05 * (yhi - ylo);
    f->xlo = xlo;
    f->xhi = xhi;
    f->ylo = ylo;
    f->yhi = yhi;
}

/* Title, grid lines with their numbers, axis labels and the frame. */
static void panel_axes(cairo_t *cr, const chart_panel *p, const panel_frame *f, double x0, double y0)
{
    double left = f->left, right = f->right, top = f->top, bottom = f->bottom;
    double xlo = f->xlo, xhi = f->xhi, ylo = f->ylo, yhi = f->yhi;
    char label[64];
    cairo_set_font_size(cr, 12.0);
    cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
    chart_text(cr, 0.5 * (left + right), y0 + 15.0, p->title ? p->title : "", 0.5);
    cairo_set_font_size(cr, 10.5);
    cairo_set_line_width(cr, 1.0);
    cairo_set_dash(cr, NULL, 0, 0.0);
    double xs = nice_step(xhi - xlo), ys = nice_step(yhi - ylo);
    for (double v = ceil(xlo / xs) * xs; v <= xhi + 1e-9 * xs; v += xs) {
        double x = left + (right - left) * (v - xlo) / (xhi - xlo);
        cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
        cairo_move_to(cr, x, top);
        cairo_line_to(cr, x, bottom);
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
        snprintf(label, sizeof label, "%g", fabs(v) < 1e-12 * xs ? 0.0 : v);
        chart_text(cr, x, bottom + 14.0, label, 0.5);
    }
    for (double v = ceil(ylo / ys) * ys; v <= yhi + 1e-9 * ys; v += ys) {
        double y = bottom - (bottom - top) * (v - ylo) / (yhi - ylo);
        cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
        cairo_move_to(cr, left, y);
        cairo_line_to(cr, right, y);
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
        snprintf(label, sizeof label, "%g", fabs(v) < 1e-12 * ys ? 0.0 : v);
        chart_text(cr, left - 4.0, y + 4.0, label, 1.0);
    }
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    chart_text(cr, 0.5 * (left + right), bottom + 30.0, p->xlabel ? p->xlabel : "", 0.5);
    cairo_save(cr);
    cairo_move_to(cr, x0 + 14.0, 0.5 * (top + bottom));
    cairo_rotate(cr, -PI / 2.0);
    chart_text(cr, 0.0, 0.0, p->ylabel ? p->ylabel : "", 0.5);
    cairo_restore(cr);
    cairo_rectangle(cr, left, top, right - left, bottom - top);
    cairo_stroke(cr);
}

/* Every series, clipped to the plot area: lines broken at non-finite points, or dots with
 * error bars. */
static void panel_series(cairo_t *cr, const chart_panel *p, const panel_frame *f)
{
    double left = f->left, right = f->right, top = f->top, bottom = f->bottom;
    double xlo = f->xlo, xhi = f->xhi, ylo = f->ylo, yhi = f->yhi;
    cairo_save(cr);
    cairo_rectangle(cr, left, top, right - left, bottom - top);
    cairo_clip(cr);
    for (int k = 0; k < p->nseries; k++) {
        const chart_series *s = &p->series[k];
        style(cr, s);
        bool pen = false;
        for (int i = 0; i < s->n; i++) {
            if (!isfinite(s->x[i]) || !isfinite(s->y[i])) {
                pen = false;
                continue;
            }
            double x = left + (right - left) * (s->x[i] - xlo) / (xhi - xlo);
            double y = bottom - (bottom - top) * (s->y[i] - ylo) / (yhi - ylo);
            if (s->style == CHART_POINTS) {
                cairo_new_sub_path(cr);
                cairo_arc(cr, x, y, 3.0, 0.0, 2.0 * PI);
                cairo_fill(cr);
                if (s->err) {
                    double e = (bottom - top) * s->err[i] / (yhi - ylo);
                    cairo_move_to(cr, x, y - e);
                    cairo_line_to(cr, x, y + e);
                    cairo_stroke(cr);
                }
            } else if (!pen) {
                cairo_move_to(cr, x, y);
                pen = true;
            } else {
                cairo_line_to(cr, x, y);
            }
        }
        if (s->style != CHART_POINTS)
            cairo_stroke(cr);
    }
    cairo_restore(cr);
}

/* The labelled series' legend, top right. */
static void panel_legend(cairo_t *cr, const chart_panel *p, const panel_frame *f)
{
    double right = f->right, ly = f->top + 14.0;
    for (int k = 0; k < p->nseries; k++) {
        const chart_series *s = &p->series[k];
        if (!s->label)
            continue;
        style(cr, s);
        if (s->style == CHART_POINTS) {
            cairo_arc(cr, right - 150.0, ly - 4.0, 3.0, 0.0, 2.0 * PI);
            cairo_fill(cr);
        } else {
            cairo_move_to(cr, right - 162.0, ly - 4.0);
            cairo_line_to(cr, right - 138.0, ly - 4.0);
            cairo_stroke(cr);
        }
        cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
        chart_text(cr, right - 132.0, ly, s->label, 0.0);
        ly += 14.0;
    }
}

static void draw_panel(cairo_t *cr, const chart_panel *p, double x0, double y0)
{
    panel_frame f;
    panel_range(p, &f);
    f.left = x0 + 58.0;
    f.right = x0 + PANEL_W - 12.0;
    f.top = y0 + 24.0;
    f.bottom = y0 + PANEL_H - 40.0;
    panel_axes(cr, p, &f, x0, y0);
    panel_series(cr, p, &f);
    panel_legend(cr, p, &f);
}

static cairo_status_t png_to_file(void *closure, const unsigned char *data, unsigned int length)
{
    return fwrite(data, 1, length, (FILE *)closure) == length ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

brume_status chart_write_png(cairo_surface_t *s, cairo_t *cr, const char *path)
{
    cairo_status_t cst = cairo_status(cr);
    cairo_destroy(cr);
    if (cst != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(s);
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: drawing failed: %s", path, cairo_status_to_string(cst));
    }
    atomic_file f;
    brume_status st = atomic_open_kind(&f, path, BRUME_FILE_IMAGE);
    if (st != BRUME_OK) {
        cairo_surface_destroy(s);
        return st;
    }
    cst = cairo_surface_write_to_png_stream(s, png_to_file, f.fp);
    cairo_surface_destroy(s);
    if (cst != CAIRO_STATUS_SUCCESS) {
        atomic_abort(&f);
        return err_set(BRUME_ERROR_IO, "%s: cannot write: %s", path, cairo_status_to_string(cst));
    }
    return atomic_commit(&f);
}

brume_status chart_png(const char *path, const char *title, int npanels, const chart_panel *panels)
{
    if (npanels < 1)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: nothing to plot", path);
    brume_status st = cairo_lib_open(path);
    if (st != BRUME_OK)
        return st;
    int w = npanels * PANEL_W, h = PANEL_H + TITLE_H;
    cairo_surface_t *s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
    cairo_t *cr = cairo_create(s);
    cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
    cairo_paint(cr);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 13.5);
    cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
    chart_text(cr, 10.0, 19.0, title ? title : "", 0.0);
    for (int i = 0; i < npanels; i++)
        draw_panel(cr, &panels[i], (double)i * PANEL_W, TITLE_H);
    return chart_write_png(s, cr, path);
}
