/* scene_blasi.c - the scene file's "blasi" options. */
#include "io/scene_blasi.h"

#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "density/fractal.h"

brume_status scene_parse_blasi(const cJSON *root, jloc top, blasi_options *o)
{
    const cJSON *b = cJSON_GetObjectItemCaseSensitive(root, "blasi");
    if (!b)
        return BRUME_OK;
    static const char *const keys[] = {"light_rays", "r", "kprime", "step", "threshold", "sources", "exit_deposit",
                                       "view_attenuation", "variant", "voxels", "save_light", "load_light", NULL};
    jloc at = {top.file, "blasi"};
    if (!cJSON_IsObject(b))
        return err_set(BRUME_ERROR_PARSE, "%s: blasi: expected an object", top.file);
    brume_status st = json_check_object(b, at, keys);
    if (st)
        return st;
    /* "variant" first, so that exit_deposit and view_attenuation given beside it win */
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(b, "variant");
    for (int pass = 0; pass < 2; pass++)
        for (const cJSON *it = b->child; it; it = it->next) {
            if (strcmp(it->string, "comment") == 0 || (it == v) != (pass == 0))
                continue;
            char text[2 * BLASI_PATH_MAX];
            if (cJSON_IsNumber(it)) {
                snprintf(text, sizeof text, "%.17g", it->valuedouble);
            } else if (cJSON_IsString(it)) {
                bool is_path = strcmp(it->string, "save_light") == 0 || strcmp(it->string, "load_light") == 0;
                if (is_path)
                    json_resolve_path(top.file, it->valuestring, text, sizeof text);
                else
                    snprintf(text, sizeof text, "%s", it->valuestring);
            } else {
                return err_set(BRUME_ERROR_PARSE, "%s: blasi.%s: expected a number or a string", top.file, it->string);
            }
            if ((st = blasi_options_set(o, it->string, text)))
                return err_prefix("%s", top.file);
        }
    return BRUME_OK;
}
