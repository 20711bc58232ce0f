/* scene_sequence.c - brume_scene_check_frames: every grid file a sequence of frames will
 * read is checked before the first frame renders (io/grid_sequence.h, docs/grids.md
 * "Sequences"), so that frame 97 of 100 does not fail after hours. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/error.h"
#include "io/grid_sequence.h"
#include "io/json.h"
#include "scene/scene.h"
#include "scene/scene_override.h"

/* The first frame in [first, last] whose file a grid object with a pattern cannot give;
 * recurses through the document. Values the reader would refuse are left to it. */
static brume_status check(const cJSON *j, const char *source, long first, long last)
{
    if (cJSON_IsObject(j)) {
        const cJSON *file = cJSON_GetObjectItemCaseSensitive(j, "file");
        if (cJSON_IsString(file) && seq_is_pattern(file->valuestring) == 1) {
            char pattern[2048], path[2048];
            json_resolve_path(source, file->valuestring, pattern, sizeof pattern);
            seq_options so = {0, 1, SEQ_REFUSE};
            const cJSON *v = cJSON_GetObjectItemCaseSensitive(j, "frame_offset");
            if (cJSON_IsNumber(v) && fabs(v->valuedouble) <= 1e9)
                so.offset = (long)v->valuedouble;
            v = cJSON_GetObjectItemCaseSensitive(j, "frame_step");
            if (cJSON_IsNumber(v) && v->valuedouble >= 1 && v->valuedouble <= 1e6)
                so.step = (long)v->valuedouble;
            v = cJSON_GetObjectItemCaseSensitive(j, "beyond");
            if (cJSON_IsString(v))
                seq_beyond_from_name(v->valuestring, &so.beyond);
            for (long f = first; f <= last; f++)
                if (seq_file(pattern, &so, f, path, sizeof path) != BRUME_OK)
                    return err_prefix("%s", source);
        }
    }
    for (const cJSON *c = j ? j->child : NULL; c; c = c->next)
        if (check(c, source, first, last) != BRUME_OK)
            return err_status();
    return BRUME_OK;
}

brume_status brume_scene_check_frames(brume_context *ctx, const brume_source *src, const brume_load_options *opts,
                                      long first, long last)
{
    err_clear();
    const char *path = scene_source_name(src);
    if (first < 0 || last < first)
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "%s: frames %ld to %ld: need 0 <= first <= last", path, first,
                                       last));
    char *text = NULL;
    if (scene_load_text(src, opts, &text) != BRUME_OK)
        return ctx_report(ctx, err_status());
    cJSON *root = NULL;
    brume_status st = json_parse(text, path, &root);
    free(text);
    if (st == BRUME_OK && opts && opts->noverrides > 0)
        st = scene_apply_overrides(root, path, opts->overrides, opts->noverrides);
    if (st == BRUME_OK)
        st = check(root, path, first, last);
    cJSON_Delete(root);
    return ctx_report(ctx, st);
}
