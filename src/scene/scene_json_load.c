/* scene_json_load.c - brume_scene_load and brume_scene_text: a scene source (file, text,
 * pbrt file, studio) as JSON text, then read by scene_parse_json_with (scene_json.c). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/budget.h"
#include "core/cancel.h"
#include "core/context.h"
#include "core/error.h"
#include "core/regular_file.h"
#include "io/grid_io.h"
#include "io/grid_sequence.h"
#include "io/json.h"
#include "method/method.h"
#include "scene/scene_methods.h"
#include "scene/scene_stam.h"
#include "scene/scene_pbrt.h"
#include "scene/scene_studio.h"
#include "scene/scene_keys.h"
#include "scene/scene_override.h"
#include "scene/scene_surfaces.h"
#include "scene/scene.h"
#include "scene/scene_build.h"
#include "scene/scene_json_common.h"

#define SCENE_FILE_MAX_BYTES (64L << 20)

static brume_status read_text_file(const char *path, char **out)
{
    *out = NULL;
    FILE *fp = NULL; /* a regular file: a FIFO would block, /dev/zero never end */
    if (io_open_regular(path, &fp) != BRUME_OK)
        return err_status();
    if (io_check_size(fp, path, "a scene file", SCENE_FILE_MAX_BYTES) != BRUME_OK) {
        fclose(fp);
        return err_status();
    }
    char *buf = NULL;
    size_t len = 0, cap = 0;
    for (;;) {
        if (len + 4096 + 1 > cap) {
            cap = cap ? 2 * cap : 65536;
            if (cap > (size_t)SCENE_FILE_MAX_BYTES + 4096 + 1) {
                free(buf);
                fclose(fp);
                return err_set(BRUME_ERROR_RANGE, "%s: larger than %ld MiB; not a scene file", path,
                               SCENE_FILE_MAX_BYTES >> 20);
            }
            char *nb = realloc(buf, cap);
            if (!nb) {
                free(buf);
                fclose(fp);
                return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
            }
            buf = nb;
        }
        size_t got = fread(buf + len, 1, 4096, fp);
        len += got;
        if (got < 4096)
            break;
    }
    int bad = ferror(fp);
    fclose(fp);
    if (bad) {
        free(buf);
        return err_set(BRUME_ERROR_IO, "%s: read error", path);
    }
    buf[len] = '\0';
    if (strlen(buf) != len) {
        free(buf);
        return err_set(BRUME_ERROR_PARSE, "%s: contains a NUL byte; not a JSON scene file", path);
    }
    *out = buf;
    return BRUME_OK;
}

/* The source's name in messages (and, for a text, the folder its file names resolve against). */
const char *scene_source_name(const brume_source *src)
{
    if (src && src->text)
        return src->path ? src->path : "<json>";
    if (src && src->path)
        return src->path;
    return "<default scene>";
}

static brume_status copy_text(const char *text, const char *name, char **out)
{
    if (!(*out = strdup(text)))
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
    return BRUME_OK;
}

/* The one dispatch from a source to the scene description the reader takes: a text is
 * itself, a grid file becomes its studio scene (scene/scene_studio.c), a .pbrt file its
 * translation (scene/scene_pbrt.c), any other file is read as JSON, no source is the
 * default scene. */
static brume_status scene_source_text(const brume_source *src, const brume_load_options *o, char **text)
{
    *text = NULL;
    if (src && src->text)
        return copy_text(src->text, scene_source_name(src), text);
    if (!src || !src->path)
        return copy_text(scene_default_json, scene_source_name(src), text);
    if (scene_studio_is_grid(src->path))
        return scene_studio_json(src->path, o ? o->studio : NULL, text);
    if (scene_pbrt_is_pbrt(src->path))
        return scene_pbrt_read(src->path, o && o->lenient, text);
    return read_text_file(src->path, text);
}

/* Checks opts (NULL: the defaults) into *o; the message names the source. */
static brume_status load_options(const brume_source *src, const brume_load_options *opts, const char *fn,
                                 brume_load_options *o)
{
    *o = (brume_load_options){0.0, 0, NULL, 0, NULL, 0, false};
    if (opts)
        *o = *opts;
    if (o->noverrides < 0 || (o->noverrides > 0 && !o->overrides))
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: opts.overrides: NULL or noverrides < 0", fn);
    if (o->frame < 0)
        return err_set(BRUME_ERROR_RANGE, "%s: frame %ld is negative", scene_source_name(src), o->frame);
    if (!isfinite(o->time))
        return err_set(BRUME_ERROR_RANGE, "%s: load time %g is not finite", scene_source_name(src), o->time);
    return BRUME_OK;
}

brume_status brume_scene_load(brume_context *ctx, const brume_source *src, const brume_load_options *opts,
                              brume_scene **out)
{
    err_clear();
    if (!out)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_scene_load: out: NULL"));
    *out = NULL;
    brume_load_options o;
    brume_status st = load_options(src, opts, "brume_scene_load", &o);
    if (st)
        return ctx_report(ctx, st);
    char *text = NULL;
    cancel_load_begin(ctx); /* brume_context_cancel_loads(ctx) ends it */
    budget_hold(o.memory_held);
    if ((st = scene_source_text(src, &o, &text)) == BRUME_OK)
        st = scene_parse_json_with(text, scene_source_name(src), o.time, o.frame > 0 ? o.frame : -1, o.overrides,
                                   o.noverrides, out);
    budget_hold(0);
    cancel_load_end();
    if (st == BRUME_OK)
        (*out)->memory_held = o.memory_held; /* commit counts them too */
    free(text);
    return ctx_report(ctx, st);
}

brume_status scene_load_text(const brume_source *src, const brume_load_options *opts, char **json)
{
    err_clear();
    if (!json)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_scene_text: json: NULL");
    *json = NULL;
    return scene_source_text(src, opts, json);
}

brume_status brume_scene_text(brume_context *ctx, const brume_source *src, const brume_load_options *opts,
                              char **json)
{
    return ctx_report(ctx, scene_load_text(src, opts, json));
}
