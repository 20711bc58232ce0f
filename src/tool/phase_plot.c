/* phase_plot.c - polar and cartesian plots of phase functions with cairo. */
#include "brume.h"

#include <math.h>

#include <cairo.h>
#include <stdio.h>
#include <string.h>

#include "core/context.h"
#include "core/error.h"
#include "io/atomic.h"
#include "phase/phase.h"
#include "io/cairo_lib.h"
#include "io/chart.h"
#include "scene/scene_build.h"

#define PLOT_WIDTH 900
#define ROW_HEIGHT 300 /* panels */
#define TITLE_HEIGHT 26
#define POLAR_SIZE 300
#define CURVE_POINTS 721 /* angle steps of a quarter degree over [0, 180] */

/* phi = 4 pi p, the paper's quantity (integral 2 over t). */
static double plot_phi(const phase *p, double theta) { return 4.0 * PI * phase_eval(p, cos(theta)); }

/* The value plotted for phi: itself, or its decimal log. */
static double plot_value(double phi, bool log_scale) { return log_scale ? log10(fmax(phi, 1e-300)) : phi; }

/* The curves of a row: truth and approx, or the overlay's. */
static int row_count(const brume_phase_plot_row *row) { return row->ncurves > 0 ? row->ncurves : 2; }
static const phase *row_curve(const brume_phase_plot_row *row, int c)
{
    const brume_phase *h = row->ncurves > 0 ? row->curves[c] : c ? row->approx : row->truth;
    return h ? h->p : NULL;
}

static void set_color(cairo_t *cr, int approx);

static void set_style(cairo_t *cr, const brume_phase_plot_row *row, int c)
{
    if (row->ncurves <= 0) {
        set_color(cr, c);
        return;
    }
    static const double dash[] = {7.0, 4.0};
    const double *rgb = chart_color(c);
    bool d = row->dashed && row->dashed[c];
    cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
    cairo_set_dash(cr, d ? dash : NULL, d ? 2 : 0, 0.0);
    cairo_set_line_width(cr, 1.8);
}

static void set_color(cairo_t *cr, int approx)
{
    if (approx) {
        static const double dash[] = {7.0, 4.0};
        cairo_set_source_rgb(cr, 0.85, 0.33, 0.10);
        cairo_set_dash(cr, dash, 2, 0.0);
    } else {
        cairo_set_source_rgb(cr, 0.10, 0.25, 0.60);
        cairo_set_dash(cr, NULL, 0, 0.0);
    }
    cairo_set_line_width(cr, 1.8);
}

/* The range [*lo, *hi] of plot_value over the curves of one row. */
static void row_range(const brume_phase_plot_row *row, bool log_scale, double *lo, double *hi)
{
    *lo = INFINITY;
    *hi = -INFINITY;
    for (int c = 0; c < row_count(row); c++) {
        const phase *p = row_curve(row, c);
        if (!p)
            continue;
        for (int i = 0; i < CURVE_POINTS; i++) {
            double v = plot_value(plot_phi(p, PI * i / (CURVE_POINTS - 1)), log_scale);
            *lo = fmin(*lo, v);
            *hi = fmax(*hi, v);
        }
    }
}

/* Polar plot in the square [x0, x0 + POLAR_SIZE] x [y0, y0 + ROW_HEIGHT]: the point at angle
 * theta from the forward direction (+x) lies at radius phi(theta) / max phi, on a linear
 * scale whatever log_scale says (a log radius turns every lobe into a shifted circle: the
 * cartesian panel beside it is the log companion). The dotted circle is phi = 1 (isotropic
 * scattering). */
static void draw_polar(cairo_t *cr, const brume_phase_plot_row *row, bool log_scale, double x0, double y0)
{
    double lo, hi;
    (void)log_scale;
    row_range(row, false, &lo, &hi);
    double norm = hi > 0.0 ? hi : 1.0;
    /* Bounding box of the curves in plot units, then a uniform scale into the panel. */
    double xmin = 0.0, xmax = 0.0, ymax = 0.0;
    for (int c = 0; c < row_count(row); c++) {
        const phase *p = row_curve(row, c);
        if (!p)
            continue;
        for (int i = 0; i < CURVE_POINTS; i++) {
            double th = PI * i / (CURVE_POINTS - 1);
            double rad = plot_phi(p, th) / norm;
            xmin = fmin(xmin, rad * cos(th));
            xmax = fmax(xmax, rad * cos(th));
            ymax = fmax(ymax, rad * sin(th));
        }
    }
    double unit = 1.0 / norm; /* radius of phi = 1 */
    xmin = fmin(xmin, -unit);
    xmax = fmax(xmax, unit);
    ymax = fmax(ymax, unit);
    double margin = 14.0;
    double scale = fmin((POLAR_SIZE - 2.0 * margin) / (xmax - xmin), (ROW_HEIGHT - 2.0 * margin) / (2.0 * ymax));
    double cx = x0 + margin - xmin * scale + 0.5 * ((POLAR_SIZE - 2.0 * margin) - (xmax - xmin) * scale);
    double cy = y0 + 0.5 * ROW_HEIGHT;

    cairo_set_dash(cr, NULL, 0, 0.0);
    cairo_set_source_rgb(cr, 0.75, 0.75, 0.75);
    cairo_set_line_width(cr, 1.0);
    cairo_move_to(cr, x0 + 4.0, cy);
    cairo_line_to(cr, x0 + POLAR_SIZE - 4.0, cy);
    cairo_move_to(cr, cx, y0 + 4.0);
    cairo_line_to(cr, cx, y0 + ROW_HEIGHT - 4.0);
    cairo_stroke(cr);
    static const double dots[] = {2.0, 3.0};
    cairo_set_dash(cr, dots, 2, 0.0);
    cairo_arc(cr, cx, cy, unit * scale, 0.0, 2.0 * PI);
    cairo_stroke(cr);

    for (int c = 0; c < row_count(row); c++) {
        const phase *p = row_curve(row, c);
        if (!p)
            continue;
        set_style(cr, row, c);
        for (int i = 0; i < 2 * (CURVE_POINTS - 1) + 1; i++) {
            double th = PI * i / (CURVE_POINTS - 1); /* 0 .. 2 pi; phi is symmetric */
            double rad = plot_phi(p, th) / norm * scale;
            double x = cx + rad * cos(th), y = cy - rad * sin(th);
            if (i == 0)
                cairo_move_to(cr, x, y);
            else
                cairo_line_to(cr, x, y);
        }
        cairo_close_path(cr);
        cairo_stroke(cr);
    }
    cairo_set_dash(cr, NULL, 0, 0.0);
    cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
    chart_text(cr, x0 + 6.0, y0 + ROW_HEIGHT - 6.0, "polar, phi / max phi (linear)", 0.0);
}

/* The overlay's legend, its first line at (right - 150, ly). */
static void draw_legend(cairo_t *cr, const brume_phase_plot_row *row, double right, double ly)
{
    for (int c = 0; c < row->ncurves; c++) {
        if (!row->labels || !row->labels[c])
            continue;
        set_style(cr, row, c);
        cairo_move_to(cr, right - 150.0, ly - 4.0);
        cairo_line_to(cr, right - 126.0, ly - 4.0);
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
        chart_text(cr, right - 120.0, ly, row->labels[c], 0.0);
        ly += 14.0;
    }
}

/* phi against theta in degrees, in [x0, x0 + w] x [y0, y0 + ROW_HEIGHT]. */
static void draw_cartesian(cairo_t *cr, const brume_phase_plot_row *row, bool log_scale, double x0, double y0, double w)
{
    double lo, hi;
    row_range(row, log_scale, &lo, &hi);
    if (log_scale) {
        lo = floor(lo);
        hi = ceil(hi);
        if (hi <= lo)
            hi = lo + 1.0;
    } else {
        lo = 0.0;
        hi = hi > 0.0 ? hi * 1.05 : 1.0;
    }
    double left = x0 + 52.0, right = x0 + w - 12.0, top = y0 + 8.0, bottom = y0 + ROW_HEIGHT - 30.0;
    char label[32];

    cairo_set_dash(cr, NULL, 0, 0.0);
    cairo_set_line_width(cr, 1.0);
    for (int a = 0; a <= 180; a += 30) { /* angle grid */
        double x = left + (right - left) * a / 180.0;
        cairo_set_source_rgb(cr, 0.85, 0.85, 0.85);
        cairo_move_to(cr, x, top);
        cairo_line_to(cr, x, bottom);
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
        snprintf(label, sizeof label, "%d", a);
        chart_text(cr, x, bottom + 15.0, label, 0.5);
    }
    chart_text(cr, 0.5 * (left + right), bottom + 28.0, "scattering angle (degrees)", 0.5);
    /* Value grid: decades on a log scale, about five round steps otherwise. */
    double step = log_scale ? 1.0 : pow(10.0, floor(log10(hi / 5.0)));
    if (!log_scale && hi / step > 10.0)
        step *= hi / step > 20.0 ? 5.0 : 2.0;
    for (double v = lo; v <= hi + 1e-9 * step; v += step) {
        double y = bottom - (bottom - top) * (v - lo) / (hi - lo);
        cairo_set_source_rgb(cr, 0.85, 0.85, 0.85);
        cairo_move_to(cr, left, y);
        cairo_line_to(cr, right, y);
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
        snprintf(label, sizeof label, "%g", log_scale ? pow(10.0, v) : v);
        chart_text(cr, left - 4.0, y + 4.0, label, 1.0);
    }
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    cairo_rectangle(cr, left, top, right - left, bottom - top);
    cairo_stroke(cr);

    cairo_save(cr);
    cairo_rectangle(cr, left, top, right - left, bottom - top);
    cairo_clip(cr);
    for (int c = 0; c < row_count(row); c++) {
        const phase *p = row_curve(row, c);
        if (!p)
            continue;
        set_style(cr, row, c);
        for (int i = 0; i < CURVE_POINTS; i++) {
            double th = PI * i / (CURVE_POINTS - 1);
            double v = plot_value(plot_phi(p, th), log_scale);
            double x = left + (right - left) * i / (CURVE_POINTS - 1.0);
            double y = bottom - (bottom - top) * (v - lo) / (hi - lo);
            if (i == 0)
                cairo_move_to(cr, x, y);
            else
                cairo_line_to(cr, x, y);
        }
        cairo_stroke(cr);
    }
    cairo_restore(cr);
    draw_legend(cr, row, right, top + 16.0);
}

static brume_status phase_plot_png(const char *path, int n, const brume_phase_plot_row *rows, bool log_scale)
{
    if (n < 1)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: nothing to plot", path);
    brume_status opened = cairo_lib_open(path);
    if (opened != BRUME_OK)
        return opened;
    int height = n * (ROW_HEIGHT + TITLE_HEIGHT) + 6;
    cairo_surface_t *s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, PLOT_WIDTH, height);
    cairo_t *cr = cairo_create(s);
    cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
    cairo_paint(cr);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 11.0);
    for (int i = 0; i < n; i++) {
        double y0 = i * (ROW_HEIGHT + TITLE_HEIGHT) + 4.0;
        cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
        cairo_set_font_size(cr, 13.0);
        chart_text(cr, 8.0, y0 + 16.0, rows[i].title ? rows[i].title : "", 0.0);
        cairo_set_font_size(cr, 11.0);
        draw_polar(cr, &rows[i], log_scale, 0.0, y0 + TITLE_HEIGHT);
        draw_cartesian(cr, &rows[i], log_scale, POLAR_SIZE, y0 + TITLE_HEIGHT, PLOT_WIDTH - POLAR_SIZE);
    }
    return chart_write_png(s, cr, path);
}

brume_status brume_phase_plot_png(brume_context *ctx, const char *path, int n, const brume_phase_plot_row *rows,
                                  bool log_scale)
{
    err_clear();
    if (!path || !rows)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_phase_plot_png: %s: NULL",
                                       !path ? "path" : "rows"));
    if (n < 1 || n > 64)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_phase_plot_png: n: %d outside [1, 64]", n));
    for (int i = 0; i < n; i++) {
        const brume_phase_plot_row *r = &rows[i];
        if (r->ncurves > 16 || (r->ncurves > 0 && !r->curves) || (r->ncurves <= 0 && !r->truth))
            return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT,
                                           "brume_phase_plot_png: rows[%d]: %s", i,
                                           r->ncurves > 16 ? "more than 16 curves" : r->ncurves > 0 ? "curves: NULL"
                                                                                                : "truth: NULL"));
        for (int c = 0; c < r->ncurves; c++)
            if (!r->curves[c])
                return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT,
                                               "brume_phase_plot_png: rows[%d].curves[%d]: NULL", i, c));
    }
    const void *owner = atomic_owner(ctx);
    brume_status st = phase_plot_png(path, n, rows, log_scale);
    atomic_owner(owner);
    return ctx_report(ctx, st);
}
