/* image_file.c - brume_image files: dispatch by extension to the OpenEXR, PNG and PFM
 * readers and writers (io/image_exr.c, image_png.c, image_pfm.c). */
#include "io/image_formats.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/error.h"
#include "io/atomic.h"

/* ---- files ------------------------------------------------------------------------------- */

typedef enum image_format { FORMAT_UNKNOWN, FORMAT_EXR, FORMAT_PNG, FORMAT_PFM } image_format;

/* The extension of the last path component, including the dot ("" when none). */
static const char *path_extension(const char *path)
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    const char *dot = strrchr(base, '.');
    return dot && dot != base ? dot : "";
}

static int ext_is(const char *ext, const char *want)
{
    for (; *ext && *want; ext++, want++) {
        char c = *ext;
        if (c >= 'A' && c <= 'Z')
            c = (char)(c - 'A' + 'a');
        if (c != *want)
            return 0;
    }
    return *ext == *want;
}

static image_format format_of(const char *path, brume_status *st)
{
    const char *ext = path_extension(path);
    if (ext_is(ext, ".exr"))
        return FORMAT_EXR;
    if (ext_is(ext, ".png"))
        return FORMAT_PNG;
    if (ext_is(ext, ".pfm"))
        return FORMAT_PFM;
    *st = err_set(BRUME_ERROR_UNSUPPORTED, "%s: unknown image format '%s' (use .exr, .png or .pfm)",
                  path, ext);
    return FORMAT_UNKNOWN;
}

brume_status brume_image_write(brume_context *ctx, const brume_image *image, const char *path,
                               const brume_write_options *opts)
{
    err_clear();
    brume_status st = BRUME_OK;
    if (!path)
        st = err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_image_write: path: NULL");
    else if (!image)
        st = err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_image_write: image: NULL");
    else if (!*path)
        st = err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_image_write: no path");
    else if (!image->rgba)
        st = err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: no image to write", path);
    else if (opts && !isfinite(opts->exposure))
        st = err_set(BRUME_ERROR_RANGE, "%s: exposure: expected a finite number of stops, got %g",
                     path, opts->exposure);
    else if (opts && opts->tonemap != BRUME_TONEMAP_CLAMP && opts->tonemap != BRUME_TONEMAP_FILMIC)
        st = err_set(BRUME_ERROR_RANGE, "%s: tonemap: unknown curve %d", path, (int)opts->tonemap);
    if (st != BRUME_OK)
        return ctx_report(ctx, st);

    const void *owner = atomic_owner(ctx); /* its temporary file is ctx's (io/atomic.h) */
    switch (format_of(path, &st)) {
    case FORMAT_EXR: st = image_write_exr(path, image); break;
    case FORMAT_PNG: st = image_write_png(path, image, opts); break;
    case FORMAT_PFM: st = image_write_pfm(path, image); break;
    case FORMAT_UNKNOWN: break;
    }
    atomic_owner(owner);
    return ctx_report(ctx, st);
}

brume_status brume_image_encode_png(brume_context *ctx, const brume_image *image, const brume_write_options *opts,
                                    unsigned char **data, size_t *size)
{
    err_clear();
    if (data)
        *data = NULL;
    if (size)
        *size = 0;
    if (!image || !image->rgba || !data || !size)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_image_encode_png: %s: NULL",
                                       !image || !image->rgba ? "image" : !data ? "data" : "size"));
    if (opts && !isfinite(opts->exposure))
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "brume_image_encode_png: exposure: expected a finite number of stops, got %g",
                                       opts->exposure));
    return ctx_report(ctx, image_encode_png(image, opts, data, size));
}

brume_status brume_image_read(brume_context *ctx, const char *path, brume_image **out)
{
    err_clear();
    if (!out)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_image_read: out: NULL"));
    *out = NULL;
    if (!path)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_image_read: path: NULL"));
    if (!*path)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_image_read: no path"));

    brume_status st = BRUME_OK;
    switch (format_of(path, &st)) {
    case FORMAT_EXR: st = image_read_exr(path, out); break;
    case FORMAT_PNG: st = image_read_png(path, out); break;
    case FORMAT_PFM: st = image_read_pfm(path, out); break;
    case FORMAT_UNKNOWN: break;
    }
    if (st != BRUME_OK && *out) {
        brume_image_release(*out);
        *out = NULL;
    }
    return ctx_report(ctx, st);
}
