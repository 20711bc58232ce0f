/* cairo_lib.c - the cairo functions brume draws with, forwarded to libcairo opened by its
 * SONAME (BRUME_CAIRO_SONAME, read from the library CMake found) at the first picture, not
 * linked: libcairo brings pixman, fontconfig, FreeType, libX11 and xcb, whose loading and
 * relocation took about 6 ms of every brume process's start on the project's machine, for
 * the few commands that draw (figures, charts, sheets, phase plots, compare;
 * docs/performance.md "Start-up"), through core/lazylib.h as every optional library.
 *
 * Each forwarder keeps cairo.h's declaration, so the drawing code reads as cairo's
 * documentation. A drawing function calls cairo_lib_open first and reports its failure;
 * a cairo call without it is a bug in brume, which stops with a message rather than call
 * through a null pointer. */
#include "io/cairo_lib.h"

#include <cairo.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/error.h"
#include "core/lazylib.h"

#ifndef BRUME_CAIRO_SONAME
#define BRUME_CAIRO_SONAME "libcairo.so.2"
#endif

/* R: returns a value, V: void; (return type, name, parameters, arguments) */
#define CAIRO_FUNCTIONS(R, V)                                                                                 \
    V(void, cairo_arc, (cairo_t * cr, double xc, double yc, double radius, double angle1, double angle2),     \
      (cr, xc, yc, radius, angle1, angle2))                                                                   \
    V(void, cairo_clip, (cairo_t * cr), (cr))                                                                 \
    V(void, cairo_close_path, (cairo_t * cr), (cr))                                                           \
    R(cairo_t *, cairo_create, (cairo_surface_t * target), (target))                                          \
    V(void, cairo_destroy, (cairo_t * cr), (cr))                                                              \
    V(void, cairo_fill, (cairo_t * cr), (cr))                                                                 \
    R(cairo_surface_t *, cairo_image_surface_create, (cairo_format_t format, int width, int height),          \
      (format, width, height))                                                                                \
    R(unsigned char *, cairo_image_surface_get_data, (cairo_surface_t * surface), (surface))                  \
    R(int, cairo_image_surface_get_stride, (cairo_surface_t * surface), (surface))                            \
    V(void, cairo_line_to, (cairo_t * cr, double x, double y), (cr, x, y))                                    \
    V(void, cairo_move_to, (cairo_t * cr, double x, double y), (cr, x, y))                                    \
    V(void, cairo_new_sub_path, (cairo_t * cr), (cr))                                                         \
    V(void, cairo_paint, (cairo_t * cr), (cr))                                                                \
    V(void, cairo_rectangle, (cairo_t * cr, double x, double y, double width, double height),                 \
      (cr, x, y, width, height))                                                                              \
    V(void, cairo_restore, (cairo_t * cr), (cr))                                                              \
    V(void, cairo_rotate, (cairo_t * cr, double angle), (cr, angle))                                          \
    V(void, cairo_save, (cairo_t * cr), (cr))                                                                 \
    V(void, cairo_select_font_face,                                                                           \
      (cairo_t * cr, const char *family, cairo_font_slant_t slant, cairo_font_weight_t weight),               \
      (cr, family, slant, weight))                                                                            \
    V(void, cairo_set_dash, (cairo_t * cr, const double *dashes, int num_dashes, double offset),              \
      (cr, dashes, num_dashes, offset))                                                                       \
    V(void, cairo_set_font_size, (cairo_t * cr, double size), (cr, size))                                     \
    V(void, cairo_set_line_width, (cairo_t * cr, double width), (cr, width))                                  \
    V(void, cairo_set_source_rgb, (cairo_t * cr, double red, double green, double blue), (cr, red, green, blue)) \
    V(void, cairo_set_source_rgba, (cairo_t * cr, double red, double green, double blue, double alpha),       \
      (cr, red, green, blue, alpha))                                                                          \
    V(void, cairo_show_text, (cairo_t * cr, const char *utf8), (cr, utf8))                                    \
    R(cairo_status_t, cairo_status, (cairo_t * cr), (cr))                                                     \
    R(const char *, cairo_status_to_string, (cairo_status_t status), (status))                                \
    V(void, cairo_stroke, (cairo_t * cr), (cr))                                                               \
    V(void, cairo_surface_destroy, (cairo_surface_t * surface), (surface))                                    \
    V(void, cairo_surface_flush, (cairo_surface_t * surface), (surface))                                      \
    V(void, cairo_surface_mark_dirty, (cairo_surface_t * surface), (surface))                                 \
    R(cairo_status_t, cairo_surface_status, (cairo_surface_t * surface), (surface))                           \
    R(cairo_status_t, cairo_surface_write_to_png_stream,                                                      \
      (cairo_surface_t * surface, cairo_write_func_t write_func, void *closure), (surface, write_func, closure)) \
    V(void, cairo_text_extents, (cairo_t * cr, const char *utf8, cairo_text_extents_t *extents), (cr, utf8, extents))

#define CAIRO_POINTER(ret, f, params, args) LAZYLIB_POINTER(f)
#define CAIRO_NAME(ret, f, params, args) LAZYLIB_NAME(f)
static struct {
    CAIRO_FUNCTIONS(CAIRO_POINTER, CAIRO_POINTER)
} lib;
static const char *const lib_names[] = {CAIRO_FUNCTIONS(CAIRO_NAME, CAIRO_NAME) NULL};
static const char *const lib_sonames[] = {BRUME_CAIRO_SONAME, NULL};
static lazylib lib_so = LAZYLIB("cairo", lib_sonames, lib_names, &lib, sizeof lib);

brume_status cairo_lib_open(const char *path)
{
    if (!lazylib_open(&lib_so))
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: %s", path, lib_so.error);
    return BRUME_OK;
}

/* Before a forwarded call: the library is open, or brume has a bug (see the file's comment). */
static void lib_need(const char *f)
{
    if (!lazylib_open(&lib_so)) {
        fprintf(stderr, "brume: internal error: %s called without cairo (%s)\n", f, lib_so.error);
        abort();
    }
}

#define CAIRO_FORWARD_R(ret, f, params, args)                                                                 \
    ret f params                                                                                              \
    {                                                                                                         \
        lib_need(#f);                                                                                         \
        return lib.f args;                                                                                    \
    }
#define CAIRO_FORWARD_V(ret, f, params, args)                                                                 \
    ret f params                                                                                              \
    {                                                                                                         \
        lib_need(#f);                                                                                         \
        lib.f args;                                                                                           \
    }
CAIRO_FUNCTIONS(CAIRO_FORWARD_R, CAIRO_FORWARD_V)
